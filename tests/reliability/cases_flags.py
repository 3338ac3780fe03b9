"""Errors the library raises with its own keys for arguments the user gave as command-line flags
(issue 30, item 2), as data in the form of cases.py: the command prints each as one line with
``command line`` and the FLAG as the key (tb_exudyn/cli/flags.py: FLAGS), and the library's
mentions of other arguments (``overwrite=True``, ``another out folder``, ``the max_memory of``) as
the flags a user can type.

Each case must end in exit status 2 with one line holding the texts of ``expect``, no traceback, and
nothing under the scratch folder written, moved or deleted (tests/reliability/test_flags.py; the
lead adds CASES_FLAGS to cases.CASES for measure.py). Runs that are refused after their output folder
is made (and removed again) are in tests/test_cli_flags.py.
"""

from __future__ import annotations

from pathlib import Path

from .cases import Case, Run, rr_arrays, rr_meta, write_result

GROUP = "flags"


def _plot_channel_matches_nothing(d: Path) -> Run:
    """plotting.data.select_channels refuses the pattern with its key ``channels``."""
    f = write_result(d / "out" / "pem", rr_arrays(), rr_meta())
    return Run(argv=("plot", str(f), "--channels", "nothing.*"),
               expect=("command line: key '--channels' = 'nothing.*'", "matches no channel"))


def _sweep_speeds_out_of_range(d: Path) -> Run:
    """The sweep's speeds are refused with the flag that gave them."""
    return Run(argv=("sweep", "quick", "--speeds-kmh", "0:10:1", "--out", str(d / "s"), "--no-progress"),
               expect=("command line: key '--speeds-kmh' = '0:10:1'", "out of range"))


CASES_FLAGS: list[Case] = [
    Case("plot --channels matching nothing", GROUP, _plot_channel_matches_nothing),
    Case("sweep --speeds-kmh 0:10:1", GROUP, _sweep_speeds_out_of_range),
]
