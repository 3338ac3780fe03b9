"""``tb-exudyn modes``: natural frequencies, damping ratios and what moves, of a scenario (at the start of
its run or with the train at given positions), a bridge alone, a vehicle or a train alone."""

from __future__ import annotations

import argparse
import math

from ..errors import SettingError
from ..structure.guards import check_scenario_size
from . import scenario as cli_scenario
from .lazy import methods as _methods
from .show import MODEL_HELP, bridge_modes_text, command_model, scenario_modes, vehicle_modes

EXIT_OK = 0


def _cmd_modes(args: argparse.Namespace) -> int:
    methods = _methods()
    if args.band is not None and not 0.0 <= args.band[0] < args.band[1]:
        raise SettingError("command line", "--band", args.band, "F_MIN F_MAX with 0 <= F_MIN < F_MAX [Hz]")
    for x in args.position or ():
        if not math.isfinite(x):
            raise SettingError("command line", "--position", x, "finite positions X [m] of the first axle along the "
                               "track (0: the bridge start)", "not finite")
    kind, scenario = command_model(args)
    if kind != "scenario" and args.position:
        raise SettingError("command line", "--position", args.position[0], "--position with a scenario (a train on "
                           f"its bridge)", f"{args.scenario!r} is a {kind}")
    if kind == "bridge":
        print(bridge_modes_text(scenario, args.band))
        return EXIT_OK
    if kind in ("vehicle", "train"):
        print("\n".join(vehicle_modes(args, kind, scenario, methods)))
        return EXIT_OK
    check_scenario_size(scenario)  # the run's checks (the damping guard follows the whole run), before the build
    print("\n".join(scenario_modes(args, scenario, methods)))
    return EXIT_OK


def add_parser(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("modes", help="natural frequencies, damping ratios and what moves (of a scenario, a bridge "
                                     "alone, a vehicle alone)")
    p.add_argument("scenario", metavar="MODEL", help=MODEL_HELP)
    p.add_argument("--set", dest="settings", action="append", metavar="KEY=VALUE",
                   help=cli_scenario.SET_HELP)
    p.add_argument("--position", type=float, nargs="+", default=None, metavar="X",
                   help="the train's first axle at X [m] along the track (0: bridge start), one table each; default: "
                        "the start of the run (vehicles on rigid track, the bridge alone)")
    p.add_argument("--band", type=float, nargs=2, default=None, metavar=("F_MIN", "F_MAX"),
                   help="only modes with undamped frequency in this band [Hz]")
    p.add_argument("--all", action="store_true", help="also the decoupled weak-spring modes")
    p.set_defaults(func=_cmd_modes)


__all__ = ["add_parser"]
