"""The command line's texts on the terminal: the run's channel table and short summary, the bridge's
frequencies for ``show`` (what cli.py prints; cli.py parses, loads, runs and prints)."""

from __future__ import annotations

import fnmatch
import math
import re

from .results.checks import verdict_lines
from .scenario import Scenario
from .structure import StructureError, modal_bridge
from .system.labels import default_patterns, display_unit, format_number
from .system.modes import DIRECTIONS, nth_frequency


def bridge_frequency_rows(scenario: Scenario) -> list[tuple[str, str, str, str]]:
    """Rows with f1 and f3 of the bridge per direction (vertical, lateral, torsion) [Hz]: the
    finite-element modes of the bridge alone (no train), up to analysis.mode_max_frequency."""
    an = scenario.analysis
    try:
        mb = modal_bridge(scenario.bridge, an.mode_max_frequency, an.max_modes)
    except StructureError as exc:
        return [("(derived) bridge modes", "not available", "", str(exc))]
    rows = []
    for d in DIRECTIONS:
        f = [nth_frequency(mb.frequencies, mb.mode_types, d, n) for n in (1, 3)]
        text = ", ".join("-" if math.isnan(x) else f"{x:.4g}" for x in f)
        rows.append((f"(derived) bridge f1, f3 {d}", text, "Hz",
                     f"1st and 3rd {d} mode of the whole bridge alone (FE; '-': none up to mode_max_frequency)"))
    return rows


#: channels listed on the terminal, the largest max |mean| + 3 sigma relative to max |mean| first
SHOWN_CHANNELS = 8


def summary_table(result, k: float = 3.0) -> str:
    """Per channel: max |mean|, max sigma, max |mean| + k sigma, with units."""
    rows = result.summary_rows(k)
    width = max(len(r[0]) for r in rows)
    band = f"{result.band[0]:.3g}-{result.band[1]:.3g} Hz"
    lines = [f"{'channel':<{width}}  {'unit':<8} {'max|mean|':>11} {'max sigma':>11} {f'max|mean|+{k:g}s':>13}"]
    lines += [f"{n:<{width}}  {u:<8} {m:>11.4e} {s:>11.4e} {p:>13.4e}" for n, u, m, s, p in rows]
    lines.append(f"(sigma over the band {band}; {result.method}, {result.n_samples or len(result.freq)} "
                 f"{'samples' if result.n_samples else 'frequencies'})")
    return "\n".join(lines)


def short_summary(result, table_path, k: float = 3.0) -> str:
    """What a user reads first on the terminal: the warnings (lightly damped modes, grid error,
    loss of contact), the channels whose random part is largest against their mean, and where the
    full table is."""
    lines = verdict_lines(result)
    warnings_ = [str(w) for w in result.provenance.get("warnings", [])]
    if warnings_:
        lines.append(f"{len(warnings_)} warning(s) (also in the report):")
        lines += [f"  - {w}" for w in warnings_[:6]]
        if len(warnings_) > 6:
            lines.append(f"  ... and {len(warnings_) - 6} more")
    rows = result.summary_rows(k)
    patterns = [p for _, group in default_patterns(result.channels) for p in group]
    key = [r for r in rows if any(fnmatch.fnmatchcase(r[0], p) for p in patterns)] or rows[:SHOWN_CHANNELS]
    width = max((len(r[0]) for r in key), default=10)
    lines.append(f"key channels ({len(rows)} channels in {table_path}):")
    lines.append(f"  {'channel':<{width}}  {'max |mean|':>12} {'max sigma':>12} {f'max |mean| + {k:g} sigma':>20}")
    for n, u, m, sd, p in key:
        du = display_unit(u)
        lines.append(f"  {n:<{width}}  {format_number(du.factor * m):>12} {format_number(du.factor * sd):>12} "
                     f"{format_number(du.factor * p):>14} {du.unit}")
    return "\n".join(lines)


#: a warning that asks for a scenario value ("use track.lead_in >= 110 m"): the --set that makes it
_ASKS = re.compile(r"use ((?:track|analysis|bridge|train)\.[A-Za-z0-9_.]+) (?:>=|<=) ([0-9.eE+-]+)")


def with_set_hint(text: str) -> str:
    """A warning's text with the ``--set KEY=VALUE`` that makes the change it asks for."""
    hints = [f"--set {k}={v}" for k, v in _ASKS.findall(text)]
    return text + (f" ({', '.join(hints)})" if hints else "")


__all__ = ["SHOWN_CHANNELS", "bridge_frequency_rows", "short_summary", "summary_table", "with_set_hint"]
