"""The ``tb-exudyn`` command: a thin layer over the library, one module per command.

Parses arguments, loads the scenario, calls the methods, saves and prints. A user error (bad
scenario file, impossible setting) is printed as one message and exits with status 2; no traceback.
The commands: show.py (list, show), modes.py, run.py, sweep.py, check.py, uq.py, results.py (compare,
plot, export, report), export_modes.py; beside them scenario.py (the scenario a command line asks
for), text.py (what they print), flags.py (the one table of library keys and their flags) and lazy.py
(the methods, imported when a command runs one).
"""

from __future__ import annotations

import argparse
import sys
import warnings
from typing import Sequence

from .._version import __version__
from ..errors import SettingError, UserError
from . import check as cli_check, export_modes as cli_export_modes, flags as cli_flags, modes as cli_modes
from . import results as cli_results, run as cli_run, show as cli_show, sweep as cli_sweep, text as cli_text
from . import uq as cli_uq
from .flags import int_option
from .lazy import methods

EXIT_OK, EXIT_USER_ERROR = 0, 2


class _Parser(argparse.ArgumentParser):
    """argparse's parser with a one-line error (no usage block), naming the command's --help; exit 2."""

    def error(self, message: str):  # noqa: ANN201 - argparse's hook; never returns
        command = self.prog.partition(" ")[2]
        self.exit(EXIT_USER_ERROR, f"tb-exudyn: error: {command + ': ' if command else ''}{message} "
                                   f"(the options: {self.prog} --help)\n")


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(
        prog="tb-exudyn",
        description="Random vibration of a train crossing a bridge (Exudyn, pseudo-excitation method, Monte Carlo).",
        formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog="""examples:
  tb-exudyn run                        the reference study li_zhu_2011 (PEM, batched engine) and its report
  tb-exudyn run quick --out q          the small default scenario into ./q
  tb-exudyn run li_zhu_2011 --speed-kmh 300 --channels 'bridge.*' 'car1.*'
  tb-exudyn run li_zhu_2011_mc_check --method mc --samples 500
  tb-exudyn modes li_zhu_2011          natural frequencies, damping ratios, the damping guard
  tb-exudyn export tb_exudyn_out --format netcdf --output study.nc
""",
    )
    parser.add_argument("--version", action="version", version=f"tb-exudyn {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    cli_show.add_parsers(sub)  # list, show
    cli_modes.add_parser(sub)
    cli_run.add_parser(sub)
    cli_sweep.add_parser(sub)
    cli_check.add_parser(sub)
    cli_results.add_parsers(sub)
    cli_export_modes.add_parser(sub)
    cli_uq.add_parser(sub, methods)
    return parser


#: options naming a file or folder (an empty one would silently mean the current folder)
PATH_OPTIONS = {"scenario": "SCENARIO", "out": "--out", "folder": "FOLDER", "pem_dir": "PEM_DIR", "mc_dir": "MC_DIR",
                "html": "--html", "output": "--output"}


def check_arguments(args: argparse.Namespace) -> argparse.Namespace:
    """Check the options argparse cannot (empty paths, numbers and their ranges, option pairs) and
    convert the numbers, then the command's own checks (``check`` of its parser's defaults);
    SettingError ``command line: key '--OPTION'`` naming the option, before any work."""
    for attr, option in PATH_OPTIONS.items():
        if getattr(args, attr, None) is not None and not str(getattr(args, attr)).strip():
            raise SettingError("command line", option, getattr(args, attr), "a file or folder path", "empty")
    if args.command in ("run", "sweep", "check"):
        args.workers = int_option(args.workers, "--workers", 1)
    return args.check(args) if hasattr(args, "check") else args


def _one_line_warning(message, category, filename, lineno, file=None, line=None) -> None:  # noqa: ANN001
    """Warnings and notices, each once, in at most two lines of 100 characters (no source line), with
    the --set a change needs; the report has them in full."""
    text = cli_text.with_set_hint(cli_flags.notice_as_flags(" ".join(str(message).split())))
    if text in _SHOWN:  # each warning once (a sweep repeats a speed's)
        return
    _SHOWN.add(text)
    print("\n".join(cli_text.terminal_warning(text)), file=sys.stderr if file is None else file)


#: the warnings printed by this command (each once)
_SHOWN: set[str] = set()


#: after a Ctrl-C the program ends within this many seconds, whatever an exit handler waits for
EXIT_WATCHDOG_S = 30.0


def _exit_within(seconds: float, code: int) -> None:
    """A daemon thread that ends the process with ``code`` if the interpreter's exit (its handlers join
    the worker pools' threads and processes, without a timeout) has not ended it ``seconds`` from now.
    Every output is already whole or absent by then: the blocks that write finished when the interrupt
    passed through them."""
    import os
    import threading
    import time

    def end() -> None:
        time.sleep(seconds)
        sys.stderr.flush()
        os._exit(code)

    threading.Thread(target=end, daemon=True, name="tb_exudyn-exit-watchdog").start()


def main(argv: Sequence[str] | None = None) -> int:
    _SHOWN.clear()  # each command shows each warning once (main may be called again in one process)
    parser = build_parser()
    args = parser.parse_args(argv)
    shown = warnings.showwarning
    warnings.showwarning = _one_line_warning
    try:
        code = int(args.func(check_arguments(args)))
        if code == cli_check.EXIT_INTERRUPTED and argv is None:  # check's own Ctrl-C path: the same bound
            _exit_within(EXIT_WATCHDOG_S, code)
        return code
    except UserError as exc:  # ScenarioError, SettingError, CheckpointError, ResultsError, ...
        print(f"tb-exudyn: error: {cli_flags.as_flags(exc)}", file=sys.stderr)  # library keys told as flags
        return EXIT_USER_ERROR
    except OSError as exc:  # a file or folder the user named cannot be read or written
        print(f"tb-exudyn: error: {exc}", file=sys.stderr)
        return EXIT_USER_ERROR
    except MemoryError as exc:  # the memory estimate's margin was not enough: the size, not a bug
        print(f"tb-exudyn: error: command {args.command!r}: out of memory ({exc or 'an allocation failed'}) "
              "(allowed: fewer --workers, a smaller analysis.n_freq or --psd-channels key; finished tasks kept: --resume)",
              file=sys.stderr)
        return EXIT_USER_ERROR
    except KeyboardInterrupt:  # a command without --resume has nothing to resume (check: cli_check says what is left)
        kept = "; finished tasks are kept (run again with --resume)" if hasattr(args, "resume") else ""
        print(f"tb-exudyn: interrupted{kept}", file=sys.stderr)
        if argv is None:  # the program, not a caller in this process: its exit must not hang
            _exit_within(EXIT_WATCHDOG_S, cli_check.EXIT_INTERRUPTED)
        return cli_check.EXIT_INTERRUPTED
    finally:
        warnings.showwarning = shown


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
