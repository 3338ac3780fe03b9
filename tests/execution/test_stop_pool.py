"""Ending a pool at once (Ctrl-C) must not leave the process unable to exit (issue 49).

Problem: a worker terminated while it sends a result leaves the pool's manager thread reading a
message that never ends (the parent holds the result pipe's other end open, so no end-of-file comes);
the interpreter joins that thread at exit without a timeout, so a Ctrl-C'd run printed its line and
then hung (seen once in about 20 CI runs, a 2-worker Exudyn-engine run). The state is made here
deterministically: the parent writes a message header announcing 1 MB and 10 bytes of it into the
result pipe, so the manager thread blocks in the read as it would on a half-sent result, while the
worker is busy. The reference is the process's own exit: with ``_stop_pool`` as it was (terminate and
join the workers only) this child never exits; the bound of 30 s only tells one that ends from one that
never does (it takes about 2 s).

The command's own safety net is tested beside it: after a Ctrl-C the program ends within
``EXIT_WATCHDOG_S`` whatever an exit handler waits for (here a thread that never ends).
"""

from __future__ import annotations

import subprocess
import sys
import textwrap
import time

CHILD = textwrap.dedent("""
    import multiprocessing, os, struct, sys, time
    from concurrent.futures import ProcessPoolExecutor
    from tb_exudyn.execution.tasks import _stop_pool

    def busy():
        time.sleep(120)

    if __name__ == "__main__":
        pool = ProcessPoolExecutor(1, mp_context=multiprocessing.get_context("spawn"))
        fut = pool.submit(busy)
        t0 = time.time()
        while not fut.running() and time.time() - t0 < 60:
            time.sleep(0.05)
        os.write(pool._result_queue._writer.fileno(), struct.pack("!i", 1_000_000) + b"x" * 10)
        time.sleep(0.5)  # the manager thread is in the read now
        _stop_pool(pool)
        print("stopped", flush=True)
""")


def test_a_pool_stopped_while_its_manager_reads_a_half_sent_result_lets_the_process_exit(tmp_path):
    script = tmp_path / "child.py"
    script.write_text(CHILD)
    t0 = time.monotonic()
    proc = subprocess.run([sys.executable, str(script)], check=False, capture_output=True, text=True, timeout=30)
    assert proc.returncode == 0 and "stopped" in proc.stdout, proc.stderr[-2000:]
    assert "Traceback" not in proc.stderr, proc.stderr[-2000:]
    assert time.monotonic() - t0 < 30


HANGING_EXIT = textwrap.dedent("""
    import threading, time
    from tb_exudyn.cli import _exit_within

    threading.Thread(target=time.sleep, args=(3600,), name="never ends").start()  # joined at exit
    _exit_within(1.0, 130)
""")


def test_the_exit_watchdog_ends_a_process_whose_exit_would_wait_forever(tmp_path):
    script = tmp_path / "hang.py"
    script.write_text(HANGING_EXIT)
    t0 = time.monotonic()
    proc = subprocess.run([sys.executable, str(script)], check=False, capture_output=True, text=True, timeout=30)
    assert proc.returncode == 130, proc.stderr[-2000:]
    assert time.monotonic() - t0 < 30
