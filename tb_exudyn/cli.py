"""The ``tb-exudyn`` command: a thin layer over the library.

Parses arguments, loads the scenario, calls the solvers, saves and prints. A user error (bad
scenario file, impossible setting) is printed as one message and exits with status 2; no traceback.
"""

from __future__ import annotations

import argparse
import sys
from typing import Sequence

from .scenario import ScenarioError, list_models, load_scenario
from .scenario.show import scenario_table

EXIT_OK, EXIT_USER_ERROR = 0, 2


def _cmd_list(args: argparse.Namespace) -> int:
    entries = list_models()
    width = max(len(e.name) for e in entries)
    for category in ("vehicles", "bridges", "scenarios"):
        print(f"{category}:")
        for e in (e for e in entries if e.category == category):
            print(f"  {e.name:<{width}}  {e.description}")
    from .track import get_spectrum, spectrum_names

    print("spectra (track irregularities; one-sided, spatial frequency in rad/m):")
    names = spectrum_names()
    width = max(len(n) for n in names)
    for name in names:
        print(f"  {name:<{width}}  {get_spectrum(name).describe()}")
    return EXIT_OK


def _cmd_show(args: argparse.Namespace) -> int:
    print(scenario_table(load_scenario(args.scenario)))
    return EXIT_OK


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="tb-exudyn",
        description="Random vibration of a train crossing a bridge (Exudyn, pseudo-excitation method, Monte Carlo).",
    )
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    p = sub.add_parser("list", help="named vehicles, bridges, scenarios and track spectra")
    p.set_defaults(func=_cmd_list)
    p = sub.add_parser("show", help="the resolved scenario as a table")
    p.add_argument("scenario", help="scenario name (see `tb-exudyn list`) or path to a .toml file")
    p.set_defaults(func=_cmd_show)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return int(args.func(args))
    except ScenarioError as exc:
        print(f"tb-exudyn: error: {exc}", file=sys.stderr)
        return EXIT_USER_ERROR
    except (ValueError, OSError) as exc:
        # user-caused problems that surface outside scenario loading (e.g. an unwritable folder)
        if getattr(exc, "user_error", False) or isinstance(exc, OSError):
            print(f"tb-exudyn: error: {exc}", file=sys.stderr)
            return EXIT_USER_ERROR
        raise


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
