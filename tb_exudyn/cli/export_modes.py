"""``tb-exudyn export-modes``: a bridge's finite-element modes written as a ``modal_table`` bridge (the CSV
tables of docs/modal_bridge.md and its bridge.toml), for the command line (cli/__init__.py adds the command)."""

from __future__ import annotations

import argparse

from .flags import flag
from ..errors import SettingError
from ..scenario.io import load_bridge
from ..scenario.model import ModalTable
from ..scenario.schema import source_file
from ..structure import StructureError
from ..structure.imported import export_modes

#: the modes exported by default: those a run keeps (analysis.mode_max_frequency's default)
DEFAULT_MAX_FREQUENCY = 100.0


def _cmd_export_modes(args: argparse.Namespace) -> int:
    if not 0.0 < args.max_frequency < float("inf"):
        raise SettingError("command line", "--max-frequency", args.max_frequency, "a finite frequency > 0 [Hz]")
    if args.max_modes < 0:
        raise SettingError("command line", "--max-modes", args.max_modes, "a whole number >= 0 (0: no limit)")
    bridge = load_bridge(args.bridge)
    if isinstance(bridge, ModalTable):
        raise SettingError("command line", "BRIDGE", args.bridge, "a simple_beam or frame bridge (its finite-element "
                           "modes are exported)", "a modal_table has no finite-element model")
    try:
        paths = export_modes(bridge, args.out, args.max_frequency, args.max_modes, overwrite=args.overwrite,
                             where="command line", key="--out")
    except StructureError as exc:  # the modes asked for name the option, the bridge's data its file
        if exc.key in ("max_frequency", "max_modes"):
            raise SettingError("command line", flag(exc.key), exc.value, exc.allowed, exc.reason) from None
        raise StructureError(source_file(bridge) or exc.file, exc.key, exc.value, exc.allowed,
                             f"{exc.file}: {exc.reason}" if exc.reason else exc.file) from None
    for path in paths.values():
        print(path)
    return 0


def add_parser(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("export-modes", help="a bridge's finite-element modes as CSV tables and a modal_table bridge "
                                            "(docs/modal_bridge.md)")
    p.add_argument("bridge", help="bridge name (see `tb-exudyn list`) or path to a .toml file")
    p.add_argument("--out", required=True, help="folder for bridge.toml, modes.csv, shapes.csv and stations.csv")
    p.add_argument("--max-frequency", type=float, default=DEFAULT_MAX_FREQUENCY,
                   help=f"modes up to this frequency [Hz] (default {DEFAULT_MAX_FREQUENCY:g}, as "
                        "analysis.mode_max_frequency)")
    p.add_argument("--max-modes", type=int, default=0, help="at most this many modes (0: no limit)")
    p.add_argument("--overwrite", action="store_true", help="replace those files if they exist")
    p.set_defaults(func=_cmd_export_modes)


__all__ = ["add_parser"]
