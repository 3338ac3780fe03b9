"""The HTML report of a speed sweep (``tb-exudyn sweep``): one self-contained page beside its table.

Read top-down, like the report of one run:

- what was swept: the scenario, the speeds, the engine, the run time;
- the verdicts by speed: per code criterion at its deciding location, the utilisation (estimate over
  limit) and the probability of exceeding the limit in one passage (the sweep's check columns,
  :func:`tb_exudyn.methods.sweep.check_columns`), and how many criteria EXCEED at each speed;
- the key quantities by speed: the largest max |mean| + 3 sigma of each (display units), then per
  quantity its largest |mean|, sigma, the channel and the estimated grid error of its channels;
- the figure (the table's quantities against speed, the resonance speeds marked), when drawn;
- the resonance speeds v = f_n d / i;
- the grid: per speed the band, the number of frequencies and the channels whose estimated grid
  error exceeds the tolerance, so that an unconverged grid is seen next to the numbers it affects;
- the warnings: each distinct message once, with the speeds it was raised at;
- the base scenario.

The sweep is taken as a :class:`tb_exudyn.methods.sweep.SweepResult` (its rows, summaries,
quantities, resonances, base scenario and provenance); no module of :mod:`tb_exudyn.methods` is
imported. Every piece of text is escaped; the figure is embedded as base64 PNG.
"""

from __future__ import annotations

import datetime as _dt
import html
import math
import re
from pathlib import Path
from typing import Any

import numpy as np

from .._version import __version__
from ..atomic import write_text_atomic
from ..system.labels import display_unit, format_number
from .sections import STYLE, Raw, _img, html_table, link, scenario_section, verdict_class

esc = html.escape

#: the sweep's report in its output folder
SWEEP_REPORT = "speed_sweep.html"
#: a warning raised at one speed ends with this (tb_exudyn.methods.sweep: "... (at 250 km/h)")
_AT_SPEED = re.compile(r"^(?P<text>.*) \(at (?P<speed>[0-9.]+) km/h\)$", re.S)


def _percent(x: float) -> str:
    return "not estimated" if x is None or not math.isfinite(x) else f"{100.0 * x:.2g} %"


def _criteria(rows: list[dict[str, Any]]) -> list[str]:
    """The code criteria of the check columns, in the order they first appear."""
    out: list[str] = []
    for row in rows:
        for key in row:
            if key.endswith("_utilisation"):
                name = key[: -len("_utilisation")]
                if name not in out:
                    out.append(name)
    return out


def _utilisation_cell(u: float, p: float) -> Raw:
    if u is None or not math.isfinite(u):
        return Raw("-")
    cls = "exceeds" if u > 1.0 else "ok"
    prob = "" if p is None or not math.isfinite(p) else f"<br><small>P = {esc(f'{p:.3g}')}</small>"
    return Raw(f'<span class="{verdict_class(cls)}">{esc(format_number(u, 3))}</span>{prob}')


def verdicts_by_speed(rows: list[dict[str, Any]]) -> str:
    """Per speed: the number of criteria that EXCEED, then per criterion the utilisation (estimate
    over limit; above 1 exceeds) with the probability of exceeding in one passage below it."""
    criteria = _criteria(rows)
    out = ['<section id="verdicts"><h2>Verdicts by speed</h2>']
    if not criteria:
        out.append("<p>No code check applies to the key quantities of this sweep.</p></section>")
        return "\n".join(out)
    out.append("<p>Per criterion at its deciding location: utilisation = estimate / limit (above 1: the "
               "limit is exceeded), and P, the probability of exceeding the limit in one passage.</p>")
    body = []
    for row in rows:
        n = row.get("checks_exceeding", math.nan)
        body.append([format_number(row["speed_kmh"]), "-" if not math.isfinite(n) else str(int(n))]
                    + [_utilisation_cell(row.get(f"{c}_utilisation", math.nan), row.get(f"{c}_probability", math.nan))
                       for c in criteria])
    heads = [Raw(esc(c).replace("/", "/<wbr>").replace("_", "_<wbr>")) for c in criteria]  # long names may wrap
    out.append(html_table("sweep-verdicts", ["speed [km/h]", "criteria exceeding"] + heads, body,
                          ["num", "num"] + ["num"] * len(criteria)))
    out.append("</section>")
    return "\n".join(out)


def quantities_by_speed(result: Any) -> str:
    """The key quantities: one overview table (max |mean| + 3 sigma of each) and one folded table per
    quantity (|mean|, sigma, |mean| + 3 sigma, the channel, its grid error)."""
    rows = result.rows()
    units = {key: display_unit(result.quantity_unit(key)) for key, _, _ in result.quantities}
    out = ['<section id="quantities"><h2>Key quantities by speed</h2>',
           "<p>The largest max |mean| + 3 sigma over each quantity's channels and the run; the grid error "
           "is the largest estimated grid error of the quantity's channels (not estimated: no grid-error "
           "sweep).</p>"]
    head = ["speed [km/h]"] + [f"{key} [{units[key].unit}]" for key, _, _ in result.quantities]
    body = [[format_number(r["speed_kmh"])] + [format_number(r[f"{key}_max_abs_mean_plus_3sigma"] * units[key].factor)
                                               for key, _, _ in result.quantities] for r in rows]
    out.append(html_table("sweep-quantities", head, body, ["num"] * len(head)))
    for key, pattern, _ in result.quantities:
        u = units[key]
        body = [[format_number(r["speed_kmh"]), format_number(r[f"{key}_max_abs_mean"] * u.factor),
                 format_number(r[f"{key}_max_sigma"] * u.factor),
                 format_number(r[f"{key}_max_abs_mean_plus_3sigma"] * u.factor), str(r[f"{key}_channel"]),
                 _percent(r.get(f"{key}_grid_error", math.nan))] for r in rows]
        out.append(f"<details><summary>{esc(key)}: {esc(result.quantity_text(key))} [{esc(u.unit)}] "
                   f"(channels {esc(pattern)})</summary>"
                   + html_table(f"sweep-{key}", ["speed [km/h]", f"max |mean| [{u.unit}]", f"max sigma [{u.unit}]",
                                                 f"max |mean| + 3 sigma [{u.unit}]", "channel", "grid error"],
                                body, ["num", "num", "num", "num", "", "num"]) + "</details>")
    out.append("</section>")
    return "\n".join(out)


def resonances_section(result: Any) -> str:
    out = ['<section id="resonances"><h2>Resonance speeds</h2>',
           "<p>v = f_n d / i: loads spaced d apart pass a bridge mode of frequency f_n every i-th period "
           "(the first vertical, lateral and torsion modes of the bridge alone).</p>"]
    rows = [[r.direction, format_number(r.frequency), f"{r.distance_name} {format_number(r.distance)} m", str(r.order),
             format_number(r.speed_kmh)] for r in sorted(result.resonances, key=lambda r: r.speed_kmh)]
    out.append(html_table("sweep-resonances", ["mode", "f_n [Hz]", "d", "i", "speed [km/h]"], rows,
                          ["", "num", "", "num", "num"]) if rows else "<p>None found.</p>")
    out.append("</section>")
    return "\n".join(out)


def grid_section(result: Any, tolerance: float) -> str:
    """Per speed the band, the number of frequencies and how many channels' grid error exceeds
    ``tolerance`` (with the largest)."""
    out = ['<section id="grid"><h2>Frequency grid by speed</h2>',
           f"<p>The grid follows the speed (the track's wavelength band). A channel whose estimated grid error "
           f"exceeds {100 * tolerance:g} % changes by more than that when the grid is refined: its numbers above "
           "depend on the grid.</p>"]
    body = []
    for r, s in zip(result.rows(), result.summaries):
        ge = np.asarray(s.get("grid_error", np.array([math.nan])), dtype=float)
        known = ge[np.isfinite(ge)]
        over = r.get("channels_grid_error_over_tolerance", math.nan)
        worst = "not estimated" if not known.size else f"{_percent(float(known.max()))} ({s['channels'][int(np.nanargmax(ge))]})"
        cls = "" if not known.size or known.max() <= tolerance else "exceeds"
        body.append([format_number(r["speed_kmh"]), f"{format_number(r['f_min_hz'])}-{format_number(r['f_max_hz'])}",
                     str(r["n_freq"]), "-" if not math.isfinite(over) else f"{int(over)} of {ge.size}",
                     Raw(f'<span class="{cls}">{esc(worst)}</span>' if cls else esc(worst))])
    out.append(html_table("sweep-grid", ["speed [km/h]", "band [Hz]", "frequencies", f"channels above {100 * tolerance:g} %",
                                         "largest grid error (channel)"], body, ["num", "", "num", "num", ""]))
    out.append("</section>")
    return "\n".join(out)


def warnings_by_message(result: Any) -> str:
    """Each distinct warning once, with the speeds it was raised at."""
    seen: dict[str, list[str]] = {}
    for v, s in zip(result.speeds, result.summaries):
        for w in s.get("warnings", ()):
            m = _AT_SPEED.match(str(w))
            text, speed = (m.group("text"), m.group("speed")) if m else (str(w), format_number(v))
            seen.setdefault(text, [])
            if speed not in seen[text]:
                seen[text].append(speed)
    out = ['<section id="warnings"><h2>Warnings</h2>']
    if not seen:
        out.append("<p>None recorded.</p>")
    for text, speeds in seen.items():
        where = "all speeds" if len(speeds) == len(result.speeds) else ", ".join(speeds) + " km/h"
        out.append(f'<p class="warn">{esc(text)} <small>(at {esc(where)})</small></p>')
    out.append("</section>")
    return "\n".join(out)


def render_sweep_report(result: Any, figure_png: bytes | None = None, tolerance: float = 0.01) -> str:
    """The HTML text of the report on a sweep (see the module docstring); ``figure_png``: the
    sweep's figure (:func:`tb_exudyn.plotting.plot_speed_sweep`) as PNG bytes, or None;
    ``tolerance``: the grid error above which a channel is counted (PEM's GRID_ERROR_TOLERANCE)."""
    sc = result.base
    prov = result.provenance
    title = f"tb_exudyn speed sweep: {sc.name}"
    now = _dt.datetime.now(_dt.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    speeds = result.speeds
    what = (f"{len(speeds)} speeds, {format_number(min(speeds))}-{format_number(max(speeds))} km/h; engine "
            f"{prov.get('engine', '?')}; {format_number(float(prov.get('seconds', math.nan)))} s "
            f"({prov.get('tasks_from_checkpoint', 0)} speeds from the checkpoint)")
    nav = [("verdicts", "Verdicts"), ("quantities", "Key quantities"), ("figure", "Figure"),
           ("resonances", "Resonance speeds"), ("grid", "Grid"), ("warnings", "Warnings"), ("scenario", "Scenario")]
    figure = ('<section id="figure"><h2>Figure</h2>'
              + (_img(figure_png, "key quantities against speed") if figure_png else "<p>Not drawn (--no-figures).</p>")
              + "</section>")
    body = [f"<h1>{esc(title)}</h1>", f'<p class="meta">{esc(sc.description)}</p>',
            f'<p class="meta">{esc(what)}. Generated {esc(now)} by tb_exudyn {esc(__version__)}. Each speed\'s '
            f"full result is in its folder (&lt;speed&gt;/pem).</p>",
            "<nav>" + " | ".join(link(a, t) for a, t in nav) + "</nav>",
            verdicts_by_speed(result.rows()), quantities_by_speed(result), figure, resonances_section(result),
            grid_section(result, tolerance), warnings_by_message(result), scenario_section([sc])]
    return ("<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
            f"<meta name=\"viewport\" content=\"width=device-width\"><title>{esc(title)}</title>"
            f"<style>{STYLE}</style></head><body>\n" + "\n".join(body) + "\n</body></html>\n")


def write_sweep_report(result: Any, folder: str | Path, figure_png: bytes | None = None, tolerance: float = 0.01) -> Path:
    """Write :func:`render_sweep_report` to ``folder/speed_sweep.html``, atomically."""
    out = Path(folder) / SWEEP_REPORT
    write_text_atomic(out, render_sweep_report(result, figure_png, tolerance))
    return out


__all__ = ["SWEEP_REPORT", "render_sweep_report", "write_sweep_report"]
