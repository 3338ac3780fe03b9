"""The test session's process: Ctrl-C (SIGINT) handled as in a terminal.

A shell without job control starts a command run in the background (``cmd &``, as CI scripts and
``nohup`` do) with SIGINT ignored, and Python then leaves it ignored: the tests that send the
process (or a child, which inherits the disposition across exec) a SIGINT to stand for a user's
Ctrl-C (tests/reliability/test_check_outputs.py, test_check_driver.py) would see nothing happen.
The handler a terminal gives is put back here, once, before any test runs; a process that did not
ignore SIGINT is not touched.
"""

from __future__ import annotations

import signal

if signal.getsignal(signal.SIGINT) == signal.SIG_IGN:
    signal.signal(signal.SIGINT, signal.default_int_handler)
if hasattr(signal, "pthread_sigmask"):
    signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT})
