"""The speed sweep's text on the terminal (what ``tb-exudyn sweep`` prints): the speed rule, the key
quantities by speed in display units (kN for forces) with their units in the headers, and per code
criterion its verdicts over the speeds (cli.py parses, runs and prints)."""

from __future__ import annotations

import math
import textwrap
from typing import Any

from .cli_text import TERMINAL_WIDTH
from .results.checks_table import VERDICTS
from .system.labels import display_unit, format_number


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
    for c in criteria:
        verdicts = [str(r.get(f"{c}_verdict", "")) for r in rows]
        us = [(float(r.get(f"{c}_utilisation", math.nan)), r["speed_kmh"]) for r in rows]
        known = [(u, v) for u, v in us if math.isfinite(u)]
        if not known:
            reason = next((str(r[f"{c}_reason"]) for r in rows if r.get(f"{c}_reason")), "")
            not_evaluated.setdefault(reason, []).append(c)
            continue
        u, v = max(known)
        counts = ", ".join(f"{name} {verdicts.count(name)}" for name in VERDICTS if verdicts.count(name))
        cond = sum(bool(r.get(f"{c}_caveats")) for r in rows)
        out += textwrap.wrap(f"  {c}: {counts} of {n}; largest utilisation {format_number(u, 3)} at "
                             f"{format_number(v)} km/h" + (f"; conditional at {cond}" if cond else ""), width,
                             subsequent_indent="    ", break_on_hyphens=False)
    for reason, names in not_evaluated.items():
        out += textwrap.wrap(f"  NOT EVALUATED: {', '.join(names)}" + (f" ({reason})" if reason else ""), width,
                             subsequent_indent="    ", break_on_hyphens=False)
    return out


__all__ = ["quantity_table", "rule_lines", "verdict_lines"]
