"""The command line's texts on the terminal: the run's channel table and short summary, the bridge's
frequencies for ``show`` (what the commands print)."""

from __future__ import annotations

import fnmatch
import math
import re
import textwrap

from ..codes.trains import list_trains
from ..results.caveats import unmet_requirement
from ..results.checks import default_limits, verdict_lines
from ..scenario import list_models
from ..track import get_spectrum, spectrum_names
from ..scenario import Scenario
from ..structure import StructureError, modal_bridge
from ..system.labels import default_patterns, display_unit, format_number
from ..system.modes import DIRECTIONS, nth_frequency


def bridge_frequency_rows(scenario: Scenario) -> list[tuple[str, str, str, str]]:
    """Rows with f1 and f3 of the bridge per direction (vertical, lateral, torsion) [Hz]: the
    finite-element modes of the bridge alone (no train), up to analysis.mode_max_frequency."""
    an = scenario.analysis
    try:
        mb = modal_bridge(scenario.bridge, an.mode_max_frequency, an.max_modes)
    except StructureError as exc:
        return [("(derived) bridge modes", "not available", "", str(exc))]
    rows = []
    source = "its modes tables" if getattr(scenario.bridge, "kind", "") == "modal_table" else "FE"
    for d in DIRECTIONS:
        f = [nth_frequency(mb.frequencies, mb.mode_types, d, n) for n in (1, 3)]
        text = ", ".join("-" if math.isnan(x) else f"{x:.4g}" for x in f)
        rows.append((f"(derived) bridge f1, f3 {d}", text, "Hz",
                     f"1st and 3rd {d} mode of the whole bridge alone ({source}; '-': none up to mode_max_frequency)"))
    return rows


#: channels listed on the terminal, the largest max |mean| + 3 sigma relative to max |mean| first
SHOWN_CHANNELS = 8
#: a value at most this fraction of the largest of its unit is round-off (a lateral mean of a vertical-only
#: load, 6e-19 mm): shown as 0
NOISE = 1e-9


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
    n_warn = len(result.provenance.get("warnings", []) or [])
    if n_warn:  # printed once as they came (tb-exudyn: warning: ...); here only where they are in full
        lines.append(f"{n_warn} warning{'s' if n_warn != 1 else ''} above, each in full in the report (Warnings)")
    rows = result.summary_rows(k)
    patterns = [p for _, group in default_patterns(result.channels) for p in group]
    key = [r for r in rows if any(fnmatch.fnmatchcase(r[0], p) for p in patterns)] or rows[:SHOWN_CHANNELS]
    width = max((len(r[0]) for r in key), default=10)
    lines.append(f"key channels (a screening, not the verdicts' statistic; all {len(rows)}: {table_path.name} in the "
                 "output folder):")
    lines.append(f"  {'channel':<{width}}  {'max |mean|':>12} {'max sigma':>12} {f'max |mean| + {k:g} sigma':>20}")
    unanswered = ""
    scale: dict[str, float] = {}  # per unit the largest value: what is 1e-9 of it is round-off, shown as 0
    for _, u, m, sd, p in rows:
        scale[u] = max(scale.get(u, 0.0), abs(m), abs(sd), abs(p))
    for n, u, m, sd, p in key:
        du = display_unit(u)
        m, sd, p = (0.0 if abs(x) <= NOISE * scale[u] else x for x in (m, sd, p))
        why = unmet_requirement(result, "axle_force_y", n) if fnmatch.fnmatchcase(n, "car*.axle*.force_y") else None
        unanswered = unanswered or (why or "").split(":")[0].split("; ")[-1]
        lines.append(f"  {n:<{width}}  {format_number(du.factor * m):>12} {format_number(du.factor * sd):>12} "
                     f"{format_number(du.factor * p):>14} {du.unit}" + (" *" if why else ""))
    if unanswered:  # the lateral forces of a car that cannot give running safety: no value to judge
        lines.append(f"  * not a running-safety value: {unanswered}")
    return "\n".join(lines)


#: a warning that asks for a scenario value ("use track.lead_in >= 110 m"): the --set that makes it
_ASKS = re.compile(r"use ((?:track|analysis|bridge|train)\.[A-Za-z0-9_.]+) (?:>=|<=|=) '?([A-Za-z0-9.eE+_-]+)'?")


#: a terminal line's width and a warning's lines on it (the report has the whole text)
TERMINAL_WIDTH, WARNING_LINES = 100, 2
#: no line a command prints is longer
LINE_MAX = 200


def kmh(v: float) -> str:
    """A speed [km/h] to 0.1 km/h, what a speed means on a line (204.724 -> '204.7', 250.0 -> '250')."""
    return f"{v:.1f}".removesuffix(".0")


def fitted(text: str, width: int = LINE_MAX) -> str:
    """``text`` with every line longer than ``width`` wrapped at words, the rest of it indented two
    more than the line (tables wrap their own columns; this is the bound for any other line)."""
    out = []
    for line in text.split("\n"):
        if len(line) <= width:
            out.append(line)
            continue
        lead = " " * (len(line) - len(line.lstrip()) + 2)
        out += textwrap.wrap(line, width, subsequent_indent=lead, break_on_hyphens=False, break_long_words=True)
    return "\n".join(out)


def terminal_warning(text: str, width: int = TERMINAL_WIDTH, lines: int = WARNING_LINES) -> list[str]:
    """A warning as at most ``lines`` lines of at most ``width`` characters, "tb-exudyn: warning: "
    first, the rest indented; a longer text is cut at a word and ends with a pointer to the report."""
    head, indent = "tb-exudyn: warning: ", "  "
    hint = re.search(r" \((--set [^()]*)\)$", text)  # the change it asks for is never cut
    if hint:
        text = text[: hint.start()]
    words, out, line = text.split(), [], head
    tail = " ... (report)" + (f" {hint.group(1)}" if hint else "")
    if hint and len(head) + len(text) + len(hint.group(0)) <= width * lines - len(indent):
        words += hint.group(0).split()
        hint, tail = None, " ... (in full in the report)"
    for i, word in enumerate(words):
        if len(line) + 1 + len(word) > width and line.strip():
            if len(out) == lines - 1:  # the last line: cut here, with the pointer
                while len(line) + len(tail) > width and " " in line.strip():
                    line = line[: line.rstrip().rfind(" ")]
                out.append(line.rstrip() + tail)
                return out
            out.append(line.rstrip())
            line = indent
        line += ("" if line in (head, indent) else " ") + word
    out.append(line.rstrip())
    return out


def with_set_hint(text: str) -> str:
    """A warning's text with the ``--set KEY=VALUE`` that makes the change it asks for."""
    hints = [f"--set {k}={v}" for k, v in _ASKS.findall(text)]
    return text + (f" ({', '.join(hints)})" if hints else "")


def _listed(rows: list[tuple[str, str]], width: int = 160) -> list[str]:
    """Name and description rows, the names aligned and each description wrapped beside its name."""
    w = max((len(n) for n, _ in rows), default=0)
    out = []
    for name, text in rows:
        wrapped = textwrap.wrap(" ".join(text.split()), width - w - 4, break_on_hyphens=False) or [""]
        out.append(f"  {name:<{w}}  {wrapped[0]}".rstrip())
        out += [" " * (w + 4) + rest for rest in wrapped[1:]]
    return out


def library_listing() -> str:
    """The model library for ``tb-exudyn list``: vehicles, bridges, scenarios, trains, limits, spectra, each
    group's names aligned and the descriptions wrapped within 160 characters."""
    out: list[str] = []
    entries = list_models()
    for category in ("vehicles", "bridges", "scenarios"):
        out.append(f"{category}:")
        out += _listed([(e.name, e.description) for e in entries if e.category == category])
    out.append("trains (moving forces for `tb-exudyn check`; hslm_a: all ten HSLM-A):")
    out += _listed(list(list_trains()))
    out.append("limits (criteria of the code checks, models/limits; docs/verdicts.md):")
    out += _listed([(f"{ls.name}/{c.id}", c.title) for ls in default_limits() for c in ls.criteria])
    out.append("spectra (track irregularities; one-sided, spatial frequency in rad/m):")
    out += _listed([(name, get_spectrum(name).describe()) for name in spectrum_names()])
    return "\n".join(out)


__all__ = ["LINE_MAX", "fitted", "kmh", "library_listing", "SHOWN_CHANNELS", "bridge_frequency_rows", "short_summary", "summary_table", "terminal_warning", "with_set_hint"]
