"""``tb-exudyn uq``: polynomial chaos over PEM runs under uncertain scenario keys (issue 46), for the
command line (cli/__init__.py adds the command and hands it the methods package, loaded when it runs).

Everything a user can get wrong (the scenario, the ``[uncertain]`` table or file, the options, every
node's scenario) is checked before ``--out`` is created or written: one line, exit 2."""

from __future__ import annotations

import argparse
import io
import math
from pathlib import Path
from typing import Any

from ..atomic import write_atomic_group
from .flags import WHERE
from .results import report_package
from ..errors import SettingError
from ..execution.output import removed_if_left_empty
from ..results.checks_table import SMALLEST_SHOWN
from ..results.uq import pf_verdicts, warning_groups
from ..scenario.io import parse_setting
from ..scenario.uncertain import load_study
from ..storage import check_writable
from ..system.labels import format_number

#: run_uq's arguments and the options that give them
UQ_FLAGS = {"order": "--order", "nodes": "--nodes", "design": "--design", "channels": "--channels",
            "keys": "--uncertain-file", "window": "--window", "workers": "--workers"}


def _int(text: Any, option: str, low: int) -> int | None:
    if text is None:
        return None
    try:
        value = int(text)
    except ValueError:
        raise SettingError(WHERE, option, text, f"a whole number >= {low}", "not a whole number") from None
    if value < low:
        raise SettingError(WHERE, option, value, f"a whole number >= {low}", "out of range")
    return value


def _settings(args: argparse.Namespace) -> list[tuple[str, Any]]:
    out = []
    for text in args.settings or ():
        try:
            out.append(parse_setting(text))
        except ValueError as exc:
            raise SettingError(WHERE, "--set", text, str(exc)) from None
    return out


def _study(args: argparse.Namespace) -> tuple[Any, Any]:
    try:
        return load_study(args.scenario, args.uncertain_file, _settings(args))
    except SettingError as exc:  # a --set the scenario refuses
        if exc.where != "load_study":
            raise
        raise exc.restated(WHERE, "--set") from None


def cmd_uq(args: argparse.Namespace, methods: Any) -> int:
    """The command: the study loaded and checked, then :func:`tb_exudyn.methods.uq.run_uq` into --out."""
    order, nodes, workers = _int(args.order, "--order", 1), _int(args.nodes, "--nodes", 2), _int(args.workers, "--workers", 1)
    scenario, keys = _study(args)
    design = args.design or ("sobol" if nodes is not None else "tensor")
    window = None if args.window is None else tuple(args.window)
    common = dict(order=order, design=design, nodes=nodes, channels=args.channels, window=window)
    try:  # every check of the study (design, keys, each node's scenario) before --out is touched
        methods.uq.UqMethod(scenario, tuple(keys), order, design, nodes, channels=args.channels,
                            window=window).plan_checks()
    except SettingError as exc:
        if exc.where != "run_uq" or exc.key not in UQ_FLAGS:
            raise
        raise exc.restated(WHERE, UQ_FLAGS[exc.key]) from None
    print(_clip(f"scenario {scenario.name}: {len(keys)} uncertain keys ({', '.join(k.key for k in keys)}), "
                f"order {order}, {design} design"))
    with removed_if_left_empty(args.out):
        out = check_writable(args.out)
        result = methods.uq.run_uq(scenario, keys, workers=workers, out=out, resume=args.resume,
                                   progress=not args.no_progress, overwrite=args.overwrite, **common)
    for line in summary_lines(result):
        print(line)
    written = save_figures(result, out, figures=not args.no_figures)
    print(_clip(f"written: {', '.join(p.name for p in written)}"))
    print(f"({result.provenance['n_nodes']} nodes in {result.provenance['seconds']:.1f} s, "
          f"{result.provenance.get('tasks_from_checkpoint', 0)} from the checkpoint) result in {(out / 'uq').resolve()}")
    return 0


#: the channels whose sigma(t) band is drawn (the first of the study's)
BAND_FIGURES = 4


def _png(fig: Any) -> bytes:
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=100)
    return buf.getvalue()


def save_figures(result: Any, out: Path, figures: bool = True) -> list[Path]:
    """``out/uq_sobol.png`` (the Sobol bars), ``out/uq_band.<channel>.png`` for the first
    :data:`BAND_FIGURES` channels (unless ``figures`` is False) and the page ``out/uq.html``
    (:func:`tb_exudyn.report.uq.render_uq_report`, the figures embedded), written as one group
    (:func:`tb_exudyn.atomic.write_atomic_group`, which removes an earlier study's figures that the group
    has no counterpart for; matplotlib loaded now, by the result)."""
    reporting = report_package()
    sobol = _png(result.plot_sobol()) if figures else None
    bands = [(ch, _png(result.plot_band(ch))) for ch in result.channels[:BAND_FIGURES]] if figures else []
    items = ([("uq_sobol.png", sobol)] if figures else []) + [(f"uq_band.{ch}.png", png) for ch, png in bands]
    items.append((reporting.UQ_REPORT, reporting.render_uq_report(result, sobol, bands).encode("utf-8")))
    stale = [p for pattern in ("uq_sobol.png", "uq_band.*.png") for p in out.glob(pattern)
             if p.name not in {name for name, _ in items}]  # an earlier study's figures (--overwrite)
    return write_atomic_group([(out / name, lambda path, b=data: Path(path).write_bytes(b)) for name, data in items],
                              remove=stale)


#: the rows of key quantities (max sigma per channel) the terminal shows; the rest are on the page
QUANTITY_ROWS = 16
#: the criteria and the warnings (those alike as one) the terminal shows; all are on the page. With the
#: command's other lines (8: headers, the "... more" lines, the files, the time), at most 16 + 20 + 6 + 8 = 50
#: lines, within issue 49's 60
CRITERION_ROWS, WARNING_ROWS = 20, 6
#: a terminal line's width (issue 49)
LINE_MAX = 200


def _probability(p: float) -> str:
    """As the run's report shows a probability: 3 digits, "< 1e-09" below SMALLEST_SHOWN, "-" if none."""
    if not math.isfinite(p):
        return "-"
    return f"< {SMALLEST_SHOWN:.0e}" if p < SMALLEST_SHOWN else f"{p:.3g}"


def loo_text(loo: float) -> str:
    """The leave-one-out error as a percentage (2 digits), "-" when not estimated."""
    return "-" if not math.isfinite(loo) else f"{100.0 * loo:.2g} %"


def _clip(line: str) -> str:
    return line if len(line) <= LINE_MAX else line[: LINE_MAX - 3] + "..."


def summary_lines(result: Any) -> list[str]:
    """The study on a screen: per key quantity (max sigma of each channel, the first
    :data:`QUANTITY_ROWS`) its mean, std, leave-one-out error and the key of the largest total Sobol
    index; then per criterion P_f against the target probability and its verdict; then each warning
    once. Every line at most :data:`LINE_MAX` characters."""
    shown = [q for q in result.quantities if q.startswith("max_sigma:")]
    lines = [f"{'max sigma over the run':<46} {'mean':>10} {'std':>9} {'LOO':>8}  most influential key (total Sobol)"]
    for name in shown[:QUANTITY_ROWS]:
        q = result.quantity(name)
        key, s = max(q["sobol_total"].items(), key=lambda kv: -1.0 if kv[1] != kv[1] else kv[1])
        unit = result.units[result.index(name.split(":", 1)[1])]
        why = f"{key} ({s:.2f})" if math.isfinite(s) and q["std"] > 0 else "- (no variance over the keys)"
        lines.append(f"{name.split(':', 1)[1] + ' [' + unit + ']':<46} {format_number(q['mean'], 3):>10} "
                     f"{format_number(q['std'], 2):>9} {loo_text(q['loo']):>8}  {why}")
    if len(shown) > QUANTITY_ROWS:
        lines.append(f"... and {len(shown) - QUANTITY_ROWS} more channels (uq.html)")
    rows = pf_verdicts(result)
    if rows:
        lines.append(f"verdict under uncertainty: P_f = E over the keys of P(exceed in one passage), against the target "
                     f"{rows[0]['target']:.3g} per passage")
    for r in rows[:CRITERION_ROWS]:
        est = ("" if not math.isfinite(r["estimate_mean"]) else
               f"; estimate {format_number(r['estimate_mean'], 3)} +- {format_number(r['estimate_std'], 2)}"
               + (f" (95 % {format_number(r['estimate_band'][-1], 3)})" if math.isfinite(r["estimate_band"][-1]) else "")
               + f" {r['unit']}"
               + (f" (limit {format_number(r['limit'], 3)})" if math.isfinite(r["limit"]) else ""))
        lines.append(_clip(f"  {r['criterion']:<44} {r['verdict']:<13} P_f {_probability(r['pf']):>9}"
                           f" (largest at a node {_probability(r['node_max'])}){est}"))
    if len(rows) > CRITERION_ROWS:
        lines.append(f"... and {len(rows) - CRITERION_ROWS} more criteria (uq.html)")
    groups = warning_groups(result)
    for first, texts in groups[:WARNING_ROWS]:
        more = f" ({len(texts)} messages like it)" if len(texts) > 1 else ""
        lines.append(_clip(f"warning{more}: {first}"))
    if len(groups) > WARNING_ROWS:
        lines.append(f"... and {len(groups) - WARNING_ROWS} more warnings (uq.html)")
    return lines


def add_parser(sub: Any, methods: Any) -> Any:
    """Add ``uq`` to the command line's subparsers; ``methods()``: the methods package (loaded when the
    command runs)."""
    p = sub.add_parser("uq", help="polynomial chaos over PEM runs: the response under uncertain scenario keys")
    p.add_argument("scenario", help="scenario name or .toml file (its [uncertain] table names the uncertain keys)")
    p.add_argument("--uncertain-file", dest="uncertain_file", default=None, metavar="FILE",
                   help="a TOML file whose [uncertain] table replaces the scenario's")
    p.add_argument("--set", dest="settings", action="append", metavar="KEY=VALUE",
                   help="set a scenario key, checked as in a file (repeatable)")
    p.add_argument("--order", default="3", help="the expansion's total degree (default 3; 1 ... 8)")
    p.add_argument("--design", choices=("tensor", "sparse", "sobol"), default=None,
                   help="tensor or sparse Gauss quadrature (order + 1 points per key; default tensor), or a Sobol "
                        "design fitted by least squares (the default with --nodes)")
    p.add_argument("--nodes", default=None, help="the Sobol design's node count (default twice the basis size)")
    p.add_argument("--channels", nargs="+", default=None, help="channel patterns (default the sweep's key quantities)")
    p.add_argument("--window", nargs=2, type=float, default=None, metavar=("T0", "T1"),
                   help="the times [s] over which a channel's max sigma is taken (default the whole run)")
    p.add_argument("--out", default="uq", help="output folder (default ./uq; the result in OUT/uq)")
    p.add_argument("--workers", default=None, help="worker processes (default all cores); the nodes are the tasks")
    p.add_argument("--resume", action="store_true", help="reuse the nodes finished in --out")
    p.add_argument("--overwrite", action="store_true", help="replace an earlier study's result and checkpoint in --out")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.add_argument("--no-figures", action="store_true", help="no figures (uq_sobol.png, uq_band.<channel>.png); uq.html is written without them")
    p.set_defaults(func=lambda a: cmd_uq(a, methods()))
    return p


__all__ = ["BAND_FIGURES", "CRITERION_ROWS", "LINE_MAX", "QUANTITY_ROWS", "UQ_FLAGS", "WARNING_ROWS", "add_parser", "cmd_uq", "loo_text", "save_figures", "summary_lines"]
