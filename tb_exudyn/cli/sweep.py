"""The speed sweep's text on the terminal (what ``tb-exudyn sweep`` prints): the speed rule, the key
quantities by speed in display units (kN for forces) with their units in the headers, and per code
criterion its verdicts over the speeds (and the command itself)."""

from __future__ import annotations

import argparse
import dataclasses
import math
import textwrap
from typing import Any

from ..errors import SettingError
from ..execution.output import SWEEP_FIGURE, removed_if_left_empty
from ..results.checks import default_limits
from ..scenario import Analysis, Scenario
from ..storage import check_writable
from . import scenario as cli_scenario, text as cli_text
from .flags import WHERE, flag, int_option
from .lazy import methods as _methods
from .results import folder_lock_of, report_package
from .text import TERMINAL_WIDTH

EXIT_OK = 0
from ..results.checks_table import VERDICTS
from ..system.labels import display_unit, format_number


def rule_lines(result: Any) -> list[str]:
    """The speed rule (each speed's scenario from the base's), and the default key quantities the
    model lacks, each wrapped to the terminal."""
    prov = result.provenance
    text = f"speed rule (as run --speed-kmh; v0 = {format_number(result.base.speed_kmh)} km/h): {prov.get('speed_rule', '')}"
    out = textwrap.wrap(text, TERMINAL_WIDTH, subsequent_indent="  ", break_on_hyphens=False)
    left = prov.get("quantities_left_out") or []
    if left:
        out += textwrap.wrap(f"key quantities without a channel in this model (left out): {', '.join(left)}",
                             TERMINAL_WIDTH, subsequent_indent="  ", break_on_hyphens=False)
    return out


#: at most this many speeds in the terminal's table (a longer sweep: evenly spaced ones and each quantity's
#: largest; every speed is in speed_sweep.csv)
TABLE_SPEEDS = 30


def _shown_speeds(result: Any, rows: list) -> list[int]:
    """The rows the table shows: all up to :data:`TABLE_SPEEDS`, else the first, the last, each key
    quantity's largest and evenly spaced ones between."""
    if len(rows) <= TABLE_SPEEDS:
        return list(range(len(rows)))
    keep = {0, len(rows) - 1}
    for key, _, _ in result.quantities:
        col = [float(r[f"{key}_max_abs_mean_plus_3sigma"]) for r in rows]
        keep.add(max(range(len(col)), key=lambda i: col[i] if math.isfinite(col[i]) else -math.inf))
    step = (len(rows) - 1) / max(TABLE_SPEEDS - len(keep), 1)
    keep.update(round(i * step) for i in range(TABLE_SPEEDS - len(keep) + 1))
    return sorted(keep)


def quantity_table(result: Any, width: int = TERMINAL_WIDTH) -> list[str]:
    """Per speed the largest max |mean| + 3 sigma of each key quantity in its display unit, the unit
    in the header's second line; split into blocks of columns that fit ``width``; at most about
    :data:`TABLE_SPEEDS` speeds (:func:`_shown_speeds`)."""
    every = result.rows()
    shown = _shown_speeds(result, every)
    rows = [every[i] for i in shown]
    columns = []
    for key, _, _ in result.quantities:
        du = display_unit(result.quantity_unit(key))
        values = [format_number(r[f"{key}_max_abs_mean_plus_3sigma"] * du.factor) for r in rows]
        columns.append((key, f"[{du.unit}]" if du.unit else "[-]", values))
    speeds = [format_number(r["speed_kmh"]) for r in rows]
    first = max(len("speed"), len("[km/h]"), *(len(s) for s in speeds))
    blocks: list[list[tuple[str, str, list[str]]]] = [[]]
    used = first
    for col in columns:
        w = max(len(col[0]), len(col[1]), *(len(v) for v in col[2])) + 1
        if blocks[-1] and used + w > width:
            blocks.append([])
            used = first
        blocks[-1].append(col)
        used += w
    out = ["max |mean| + 3 sigma per key quantity (largest over its channels and the run):"]
    for block in blocks:
        ws = [max(len(c[0]), len(c[1]), *(len(v) for v in c[2])) for c in block]
        out.append(f"{'speed':>{first}}" + "".join(f" {c[0]:>{w}}" for c, w in zip(block, ws)))
        out.append(f"{'[km/h]':>{first}}" + "".join(f" {c[1]:>{w}}" for c, w in zip(block, ws)))
        for i, s in enumerate(speeds):
            out.append(f"{s:>{first}}" + "".join(f" {c[2][i]:>{w}}" for c, w in zip(block, ws)))
    if len(rows) < len(every):
        out.append(f"({len(rows)} of {len(every)} speeds: evenly spaced and each quantity's largest; all in "
                   "speed_sweep.csv)")
    return out


def verdict_lines(result: Any, width: int = TERMINAL_WIDTH) -> list[str]:
    """Per code criterion checked at the sweep's speeds (those whose channels the sweep computes):
    at how many speeds it EXCEEDS and its largest utilisation with the speed; those not evaluated
    after them, one line per reason naming the criteria, wrapped (never cut) within ``width``."""
    rows = result.rows()
    criteria = result.criteria()
    if not criteria:
        return ["code checks: none applies to the key quantities of this sweep"]
    n = f"{len(rows)} speed{'s' if len(rows) != 1 else ''}"
    out = [f"code checks at {n} (utilisation: the estimate at the target probability over the limit):"]
    not_evaluated: dict[str, list[str]] = {}
    checks = result.criterion_values()
    for c in criteria:
        mine = [(at[c], r["speed_kmh"]) for at, r in zip(checks, rows) if c in at]
        verdicts = [x.verdict for x, _ in mine]
        known = [(x.utilisation, v) for x, v in mine if math.isfinite(x.utilisation)]
        if not known:
            reason = next((x.reason for x, _ in mine if x.reason), "")
            not_evaluated.setdefault(reason, []).append(c)
            continue
        u, v = max(known)
        counts = ", ".join(f"{name} {verdicts.count(name)}" for name in VERDICTS if verdicts.count(name))
        cond = sum(bool(x.caveats) for x, _ in mine)
        out += textwrap.wrap(f"  {c}: {counts} of {n}; largest utilisation {format_number(u, 3)} at "
                             f"{format_number(v)} km/h" + (f"; conditional at {cond}" if cond else ""), width,
                             subsequent_indent="    ", break_on_hyphens=False)
    for reason, names in not_evaluated.items():
        out += textwrap.wrap(f"  NOT EVALUATED: {', '.join(names)}" + (f" ({reason})" if reason else ""), width,
                             subsequent_indent="    ", break_on_hyphens=False)
    return out


def _cmd_sweep(args: argparse.Namespace) -> int:
    methods = _methods()
    sweep = methods.sweep
    scenario = cli_scenario.load(args)
    if (args.speeds_kmh is None) == (args.line_speed_kmh is None):
        raise SettingError("command line", "--speeds-kmh", args.speeds_kmh,
                           "exactly one of --speeds-kmh START:STOP:STEP and --line-speed-kmh V")
    if args.speeds_kmh is not None:  # both checked (range, count, distinct) before the series is made
        speeds = sweep.parse_speeds(args.speeds_kmh, where="command line")
    else:
        speeds = sweep.en1991_speeds(args.line_speed_kmh, args.speed_step_kmh, where="command line")
    if args.freq_spacing is not None and args.freq_spacing not in sweep.FREQ_SPACINGS:
        raise SettingError("command line", "--freq-spacing", args.freq_spacing, " or ".join(sweep.FREQ_SPACINGS))
    default_limits()  # the limit files of each speed's checks, before the folder is made
    options = None
    if args.precision != "float64":
        options = methods.BatchedOptions(precision=args.precision)
    # what the sweep would refuse, refused before --out is created or written, naming the option
    try:
        sweep.check_sweep(scenario, speeds, channels=args.channels, n_freq=args.n_freq, options=options,
                          freq_spacing=args.freq_spacing)
    except SettingError as exc:  # run_sweep's speeds came from --speeds-kmh or --line-speed-kmh: the typed one
        typed = {"speeds_kmh": ("speeds_kmh", args.speeds_kmh) if args.speeds_kmh is not None else
                 ("line_speed_kmh", args.line_speed_kmh), "channels": ("channels", args.channels)}
        if exc.where != "run_sweep" or exc.key not in typed:
            raise
        key, value = typed[exc.key]
        raise exc.restated(WHERE, flag(key), value) from None
    print(f"scenario {scenario.name}: {len(speeds)} speeds {cli_text.kmh(speeds[0])}-{cli_text.kmh(speeds[-1])} km/h")
    with removed_if_left_empty(args.out):  # one refused later (or interrupted) leaves no new empty --out
        out = check_writable(args.out)
        with folder_lock_of(out):
            return _sweep(args, methods, scenario, speeds, out, options)


def _sweep(args: argparse.Namespace, methods, scenario: Scenario, speeds, out, options) -> int:  # noqa: ANN001
    result = methods.sweep.run_sweep(scenario, speeds, workers=args.workers, out=out, resume=args.resume,
                                     progress=not args.no_progress, n_freq=args.n_freq, options=options,
                                     channels=args.channels, overwrite=args.overwrite,
                                     keep_checkpoint=args.keep_checkpoint, freq_spacing=args.freq_spacing)
    for line in rule_lines(result) + quantity_table(result) + verdict_lines(result):
        print(line)
    print(f"({len(speeds)} speed{'s' if len(speeds) != 1 else ''} in {result.provenance['seconds']:.1f} s, "
          f"{result.provenance['tasks_from_checkpoint']} from the checkpoint)")
    figure, png = "", None
    reporting = report_package()
    if not args.no_figures:
        reporting.save_figure(result.plot(), out / SWEEP_FIGURE)
        figure, png = f", {SWEEP_FIGURE}", (out / SWEEP_FIGURE).read_bytes()
    page = reporting.write_sweep_report(result, out, png)
    print(f"speed_sweep.csv{figure} and {page.name} (each speed's result in <speed>/pem) in {out.resolve()}")
    return EXIT_OK


def check_arguments(args: argparse.Namespace) -> argparse.Namespace:
    """--n-freq converted and checked against analysis.n_freq's range, before any work."""
    n_freq = next(f.metadata["check"] for f in dataclasses.fields(Analysis) if f.name == "n_freq")
    args.n_freq = int_option(args.n_freq, "--n-freq", 1, int(n_freq.high), "as analysis.n_freq")
    return args


def add_parser(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("sweep", help="PEM at a series of speeds (batched engine): table and figure of the key quantities")
    p.add_argument("scenario", help="scenario name (see `tb-exudyn list`) or path to a .toml file")
    p.add_argument("--set", dest="settings", action="append", metavar="KEY=VALUE",
                   help=cli_scenario.SET_HELP)
    p.add_argument("--speeds-kmh", default=None, metavar="START:STOP:STEP",
                   help="speeds [km/h], STOP included (or a comma list, e.g. 160,220,300); at most 1000 speeds, "
                        "each > 0 and <= 1000 km/h")
    p.add_argument("--line-speed-kmh", type=float, default=None, metavar="V",
                   help="EN 1991-2 (6.4.6.2): speeds up to 1.2 x the maximum line speed V, from V/2 in "
                        "--speed-step-kmh steps (instead of --speeds-kmh)")
    p.add_argument("--speed-step-kmh", type=float, default=10.0,
                   help="step of --line-speed-kmh (default 10; > 0, at most 1000 speeds)")
    p.add_argument("--out", default="sweep", help="output folder (default: ./sweep)")
    p.add_argument("--workers", default=None, help="worker processes (default: all cores)")
    p.add_argument("--resume", action="store_true", help="reuse finished speeds (and tasks) in --out")
    p.add_argument("--overwrite", action="store_true",
                   help="replace an earlier sweep's table, checkpoint and speeds in --out (without it or --resume such "
                        "a folder is refused)")
    p.add_argument("--keep-checkpoint", dest="keep_checkpoint", action="store_true",
                   help="keep --out/checkpoint-sweep after the table is written")
    p.add_argument("--n-freq", dest="n_freq", default=None,
                   help="PEM frequencies per speed (default: the scenario's n_freq; with --freq-spacing adaptive the "
                        "least, raised at each speed to what the grid's rules need)")
    p.add_argument("--freq-spacing", dest="freq_spacing", default=None, metavar="SPACING",
                   help="linear, log or adaptive (converged grids: fine at the system's modes and for the run's "
                        "length, docs/adaptive_grid.md; default: the scenario's freq_spacing)")
    p.add_argument("--channels", nargs="+", default=None,
                   help="channel patterns of the key quantities, each must match a channel, derived ones included "
                        "(default: deck accelerations, bridge.*.acc_z_en1990 with its EN 1990 check among them, car "
                        "body accelerations, wheel forces)")
    p.add_argument("--precision", choices=("float64", "float32"), default="float64",
                   help="float32: faster (measured in docs/speed.md), sigma within 1e-5 of each channel's largest")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.add_argument("--no-figures", action="store_true", help="no figure (the report is written without it)")
    p.set_defaults(func=_cmd_sweep, check=check_arguments)


__all__ = ["add_parser", "check_arguments", "quantity_table", "rule_lines", "verdict_lines"]
