"""The HTML report of a speed sweep (``tb-exudyn sweep``): one self-contained page beside its table.

Read top-down, like the report of one run:

- what was swept: the scenario, the speeds, the engine, the run time;
- the verdicts by speed: per code criterion at its deciding location, the utilisation (estimate over
  limit) and the probability of exceeding the limit in one passage (the sweep's check columns,
  :func:`tb_exudyn.methods.sweep.check_values`), and how many criteria EXCEED at each speed;
- the key quantities by speed: the largest max |mean| + 3 sigma of each (display units), then per
  quantity its largest |mean|, sigma, the channel and the estimated grid error of its channels;
- the figure (the table's quantities against speed, the resonance speeds marked), when drawn;
- the resonance speeds v = f_n d / i;
- the grid: the speed rule each speed's scenario follows (:mod:`tb_exudyn.scenario.speed_rule`, as
  ``run --speed-kmh``), per speed the band, the number of frequencies, the approach and the channels
  whose estimated grid error exceeds the tolerance, so that an unconverged grid is seen next to the
  numbers it affects;
- the warnings: each distinct message once, with the speeds it was raised at;
- the base scenario.

The sweep is taken as a :class:`tb_exudyn.results.sweep.SweepResult` (its rows, summaries,
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
from ..execution.output import SWEEP_PAGE
from ..system.labels import display_unit, format_number
from ..results.checks import GRID_ERROR_TOLERANCE
from ..results.checks_table import SMALLEST_SHOWN
from ..results.sweep import CriterionValues
from ..scenario.speed_rule import RULE
from .sections import STYLE, Raw, _img, html_table, link, scenario_section, verdict_class

esc = html.escape

#: the sweep's page in its output folder
SWEEP_REPORT = SWEEP_PAGE
#: a warning raised at one speed ends with this (tb_exudyn.methods.sweep: "... (at 250 km/h)")
#: a percentage in a message: the same warning at another speed differs in them (a mode's growth over the run)
_NUMBER = re.compile(r"[-+]?\d+(?:\.\d+)?(?:e[-+]?\d+)? %")
_AT_SPEED = re.compile(r"^(?P<text>.*) \(at (?P<speed>[0-9.]+) km/h\)$", re.S)


def _percent(x: float) -> str:
    return "not estimated" if x is None or not math.isfinite(x) else f"{100.0 * x:.2g} %"


def _probability(p: float) -> str:
    """As the run's report shows it: 3 digits, "< 1e-09" below SMALLEST_SHOWN."""
    if p is None or not math.isfinite(p):
        return "-"
    return f"< {SMALLEST_SHOWN:.0e}" if p < SMALLEST_SHOWN else f"{p:.3g}"


def _verdict_cell(values: CriterionValues | None, c: str) -> Raw:
    if values is None:
        return Raw('<span class="not-evaluated">not evaluated</span>')
    verdict, u, p = values.verdict, values.utilisation, values.probability
    mark = " &dagger;" if values.caveats else ""
    if verdict == "NOT EVALUATED" or u is None or not math.isfinite(u):
        return Raw(f'<span class="not-evaluated">not evaluated</span>{mark}')
    cls = verdict_class(verdict) if verdict else ("exceeds" if u > 1.0 else "ok")
    shown = _probability(p)
    prob = "" if p is None or not math.isfinite(p) else f"<br><small>P {esc(shown if shown.startswith('<') else '= ' + shown)}</small>"
    return Raw(f'<span class="{cls}">{esc(format_number(u, 3))}</span>{mark}{prob}')


def verdicts_by_speed(result: Any) -> str:
    """Per speed: the number of criteria that EXCEED, then per criterion the utilisation (estimate
    over limit; above 1 exceeds) with the probability of exceeding in one passage below it; per
    criterion a folded table of the estimate, the limit, the deciding channel and the caveats."""
    criteria, checks, speeds = result.criteria(), result.criterion_values(), result.speeds
    exceeding = [r.get("checks_exceeding", math.nan) for r in result.rows()]
    out = ['<section id="verdicts"><h2>Verdicts by speed</h2>']
    if not criteria:
        out.append("<p>No code check applies to the key quantities of this sweep.</p></section>")
        return "\n".join(out)
    out.append("<p>Per code criterion at its deciding location (the worst of its channels): the utilisation "
               "is the estimate, the level exceeded with the target probability in one passage (as in a run's "
               "report), over the limit; above 1 the criterion EXCEEDS. P is the probability of exceeding the "
               f"limit in one passage (shown as &lt; {SMALLEST_SHOWN:.0e} below that). &dagger;: conditional, a "
               "caveat could change the verdict (a lightly damped mode, a loss of contact: see the Warnings and "
               "the criterion's table below). Only the criteria whose channels are among the sweep's key "
               "quantities are checked: the deck acceleration by default (its channels bridge.*.acc_z_en1990 are a "
               "key quantity), no deck twist, derailment or unloading check without those channels; a run at "
               "one speed (tb-exudyn run --speed-kmh, the same scenario as the sweep's there) checks every "
               "criterion of its channels.</p>")
    body = []
    for v, n, at in zip(speeds, exceeding, checks):
        body.append([format_number(v), "-" if not math.isfinite(n) else f"{int(n)} of {len(criteria)}"]
                    + [_verdict_cell(at.get(c), c) for c in criteria])
    heads = [Raw(esc(c).replace("/", "/<wbr>").replace("_", "_<wbr>")) for c in criteria]  # long names may wrap
    out.append(html_table("sweep-verdicts", ["speed [km/h]", "criteria exceeding"] + heads, body,
                          ["num", "num"] + ["num"] * len(criteria)))
    for c in criteria:
        reasons = list(dict.fromkeys(at[c].reason for at in checks if c in at and at[c].reason))
        if reasons:
            out.append(f'<p class="meta">{esc(c)} not evaluated: {esc("; ".join(reasons))}</p>')
    for c in criteria:
        mine = [(v, at[c]) for v, at in zip(speeds, checks) if c in at]
        title = next((x.title for _, x in mine if x.title), "")
        unit = next((x.unit for _, x in mine if x.unit), "")
        du = display_unit(unit)
        detail = [[format_number(v), x.verdict, format_number(x.estimate * du.factor),
                   format_number(x.limit * du.factor), format_number(x.utilisation, 3), _probability(x.probability),
                   x.channel, x.caveats.replace("_", " ")] for v, x in mine]
        out.append(f"<details><summary>{esc(c)}: {esc(title)}</summary>"
                   + html_table(f"sweep-verdicts-{c.replace('/', '-')}",
                                ["speed [km/h]", "verdict", f"estimate [{du.unit}]", f"limit [{du.unit}]", "utilisation",
                                 "P", "deciding channel", "caveats that could change the verdict"],
                                detail, ["num", "", "num", "num", "num", "num", "", ""]) + "</details>")
    out.append("</section>")
    return "\n".join(out)


def quantities_by_speed(result: Any) -> str:
    """The key quantities: one overview table (max |mean| + 3 sigma of each) and one folded table per
    quantity (|mean|, sigma, |mean| + 3 sigma, the channel, its grid error)."""
    rows = result.rows()
    units = {key: display_unit(result.quantity_unit(key)) for key, _, _ in result.quantities}
    out = ['<section id="quantities"><h2>Key quantities by speed</h2>',
           "<p>The largest max |mean| + 3 sigma over each quantity's channels and the run (a screening value, "
           "not a verdict: the verdicts above use each criterion's own estimate). In each quantity's table the "
           "largest |mean|, sigma and |mean| + 3 sigma may come from different channels; the channel is that "
           "of the largest |mean| + 3 sigma, and the grid error the largest of the quantity's channels.</p>"]
    head = ["speed [km/h]"] + [f"{key} [{units[key].unit}]" for key, _, _ in result.quantities]
    body = [[format_number(r["speed_kmh"])] + [format_number(r[f"{key}_max_abs_mean_plus_3sigma"] * units[key].factor)
                                               for key, _, _ in result.quantities] for r in rows]
    out.append(html_table("sweep-quantities", head, body, ["num"] * len(head)))
    left = result.provenance.get("quantities_left_out") or []
    if left:
        out.append(f'<p class="meta">Default key quantities without a channel in this model (left out): '
                   f'{esc(", ".join(map(str, left)))}.</p>')
    for key, pattern, _ in result.quantities:
        u = units[key]
        body = [[format_number(r["speed_kmh"]), format_number(r[f"{key}_max_abs_mean"] * u.factor),
                 format_number(r[f"{key}_max_sigma"] * u.factor),
                 format_number(r[f"{key}_max_abs_mean_plus_3sigma"] * u.factor), str(r[f"{key}_channel"]),
                 _percent(r.get(f"{key}_grid_error", math.nan))] for r in rows]
        out.append(f"<details><summary>{esc(key)}: {esc(result.quantity_text(key))} [{esc(u.unit)}] "
                   f"(channels {esc(pattern)})</summary>"
                   + html_table(f"sweep-{key}", ["speed [km/h]", f"max |mean| [{u.unit}]", f"max sigma [{u.unit}]",
                                                 f"max |mean| + 3 sigma [{u.unit}]",
                                                 "channel (of the largest |mean| + 3 sigma)", "grid error"],
                                body, ["num", "num", "num", "num", "", "num"]) + "</details>")
    out.append("</section>")
    return "\n".join(out)


def resonances_section(result: Any) -> str:
    lo, hi = min(result.speeds), max(result.speeds)
    out = ['<section id="resonances"><h2>Resonance speeds</h2>',
           "<p>At v = f_n d / i, loads spaced d apart (the cars, the bogies) pass a bridge mode of frequency "
           "f_n once every i periods, so that their effects add up (the first vertical, lateral and torsion "
           f"modes of the bridge alone). Those within the swept {format_number(lo)}-{format_number(hi)} km/h "
           "are marked in the figure; all are listed below.</p>"]
    ordered = sorted(result.resonances, key=lambda r: r.speed_kmh)
    rows = [[r.direction, format_number(r.frequency), r.distance_name, format_number(r.distance), str(r.order),
             Raw(f"<b>{esc(format_number(r.speed_kmh))}</b>") if lo <= r.speed_kmh <= hi else format_number(r.speed_kmh),
             "yes" if lo <= r.speed_kmh <= hi else ""] for r in ordered]
    out.append(html_table("sweep-resonances", ["mode", "f_n [Hz]", "spacing", "d [m]", "i", "speed [km/h]",
                                               "within the sweep"], rows,
                          ["", "num", "", "num", "num", "num", ""]) if rows else "<p>None found.</p>")
    out.append("</section>")
    return "\n".join(out)


def grid_section(result: Any, tolerance: float) -> str:
    """Per speed the band, the number of frequencies and how many channels' grid error exceeds
    ``tolerance`` (with the largest)."""
    spacing = {str(s.get("freq_spacing", "")) for s in result.summaries} - {""}
    out = ['<section id="grid"><h2>Frequency grid by speed</h2>',
           f"<p>Each speed's scenario follows the speed rule, as tb-exudyn run --speed-kmh does, from the base at "
           f"v0 = {format_number(result.base.speed_kmh)} km/h: {esc(str(result.provenance.get('speed_rule', RULE)))}"
           f"{'; spacing ' + ', '.join(sorted(spacing)) if spacing else ''}. "
           f"The grid error of a channel is estimated from the same sweep on cell midpoints (by default those of the "
           f"cells wider than the adaptive grid's rules ask for, docs/adaptive_grid.md): a channel whose "
           f"estimate exceeds {100 * tolerance:g} % changes by more than that when the grid is refined, so its numbers "
           "above depend on the grid.</p>"]
    everywhere = [np.asarray(s.get("grid_error", np.array([math.nan])), dtype=float) for s in result.summaries]
    known = np.concatenate([g[np.isfinite(g)] for g in everywhere]) if everywhere else np.array([])
    bad = [format_number(v) for v, g in zip(result.speeds, everywhere) if np.any(g > tolerance)]
    if not known.size:
        out.append('<p class="warn">The grid error was not estimated: nothing says whether the grids are converged.</p>')
    elif not bad:
        out.append(f"<p><b>Converged at every speed</b>: the largest estimated grid error is {_percent(float(known.max()))}, "
                   f"below {100 * tolerance:g} %.</p>")
    else:
        out.append(f'<p class="warn"><b>Not converged at {len(bad)} of {len(result.speeds)} speeds</b> '
                   f"({', '.join(bad)} km/h): the largest estimated grid error is {_percent(float(known.max()))}. Use "
                   "--freq-spacing adaptive or more frequencies (--n-freq).</p>")
    body = []
    for r, s in zip(result.rows(), result.summaries):
        ge = np.asarray(s.get("grid_error", np.array([math.nan])), dtype=float)
        known = ge[np.isfinite(ge)]
        over = r.get("channels_grid_error_over_tolerance", math.nan)
        worst = "not estimated" if not known.size else f"{_percent(float(known.max()))} ({s['channels'][int(np.nanargmax(ge))]})"
        cls = "" if not known.size or known.max() <= tolerance else "exceeds"
        lead_in = float(np.asarray(s.get("lead_in", math.nan)))
        body.append([format_number(r["speed_kmh"]), f"{format_number(r['f_min_hz'])}-{format_number(r['f_max_hz'])}",
                     str(r["n_freq"]), format_number(lead_in) or "-", "-" if not math.isfinite(over) else f"{int(over)} of {ge.size}",
                     Raw(f'<span class="{cls}">{esc(worst)}</span>' if cls else esc(worst))])
    out.append(html_table("sweep-grid", ["speed [km/h]", "band [Hz]", "frequencies", "approach [m]",
                                         f"channels above {100 * tolerance:g} %", "largest grid error (channel)"], body,
                          ["num", "", "num", "num", "num", ""]))
    out.append("</section>")
    return "\n".join(out)


def warnings_by_message(result: Any) -> str:
    """Each warning once: messages that differ only in their percentages (the same mode's growth at
    another speed) are one, shown as first raised, with the speeds they were raised at."""
    seen: dict[str, tuple[str, list[str], list[bool]]] = {}
    for v, s in zip(result.speeds, result.summaries):
        for w in s.get("warnings", ()):
            m = _AT_SPEED.match(str(w))
            text, speed = (m.group("text"), m.group("speed")) if m else (str(w), format_number(v))
            first, speeds, varied = seen.setdefault(_NUMBER.sub("#", text), (text, [], [False]))
            varied[0] |= text != first
            if speed not in speeds:
                speeds.append(speed)
    out = ['<section id="warnings"><h2>Warnings</h2>']
    if not seen:
        out.append("<p>None recorded.</p>")
    for text, speeds, varied in seen.values():
        where = "all speeds" if len(speeds) == len(result.speeds) else ", ".join(speeds) + " km/h"
        note = f"; as raised at {speeds[0]} km/h: the percentages vary with the speed" if varied[0] else ""
        out.append(f'<p class="warn">{esc(text)} <small>(at {esc(where)}{esc(note)})</small></p>')
    out.append("</section>")
    return "\n".join(out)


def render_sweep_report(result: Any, figure_png: bytes | None = None, tolerance: float = GRID_ERROR_TOLERANCE) -> str:
    """The HTML text of the report on a sweep (see the module docstring); ``figure_png``: the
    sweep's figure (:func:`tb_exudyn.plotting.plot_speed_sweep`) as PNG bytes, or None;
    ``tolerance``: the grid error above which a channel is counted (default: the one the checks and PEM's
    warnings use)."""
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
            verdicts_by_speed(result), quantities_by_speed(result), figure, resonances_section(result),
            grid_section(result, tolerance), warnings_by_message(result),
            '<p class="meta" id="base-scenario">The scenario below is the sweep\'s base: at each speed the speed rule '
            "sets the speed, the band, the grid and the approach (the grid section above); each speed's own scenario, "
            "the rule's statement in its notes, is in its result.</p>", scenario_section([sc])]
    return ("<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
            f"<meta name=\"viewport\" content=\"width=device-width\"><title>{esc(title)}</title>"
            f"<style>{STYLE}</style></head><body>\n" + "\n".join(body) + "\n</body></html>\n")


def write_sweep_report(result: Any, folder: str | Path, figure_png: bytes | None = None,
                       tolerance: float = GRID_ERROR_TOLERANCE) -> Path:
    """Write :func:`render_sweep_report` to ``folder/speed_sweep.html``, atomically."""
    out = Path(folder) / SWEEP_REPORT
    write_text_atomic(out, render_sweep_report(result, figure_png, tolerance))
    return out


__all__ = ["SWEEP_REPORT", "render_sweep_report", "write_sweep_report"]
