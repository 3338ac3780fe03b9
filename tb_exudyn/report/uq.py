"""The HTML report of an uncertainty study (``tb-exudyn uq``, issue 46): one self-contained page.

Read top-down:

- the verdict under uncertainty: per criterion of the limits, P_f = E_theta[P(exceed | theta)] (the
  result's ``pf``: the expansion's mean over the uncertain keys of the probability of exceeding the
  limit in one passage at the criterion's deciding location) against the target probability per
  passage, the largest P(exceed | theta) at any node, and the estimate (the level exceeded with the
  target probability) as mean and std over the keys (:func:`tb_exudyn.results.uq.pf_verdicts`);
- what the study was: the uncertain keys (distribution, mean, std, bounds), the order, the design,
  the nodes and the time;
- the surrogate's leave-one-out error per quantity, next to the warning threshold;
- the Sobol first-order and total indices of the key quantities, with the bars;
- the sigma(t) bands of the channels drawn;
- every warning (the surrogate's and the nodes' runs'), each once;
- the scenario.

The study is taken as a :class:`tb_exudyn.results.uq.UqResult`; no module of :mod:`tb_exudyn.methods`
is imported. Every piece of text is escaped; the figures are embedded as base64 PNG.
"""

from __future__ import annotations

import datetime as _dt
import html
import math
from pathlib import Path
from typing import Any, Sequence

from .._version import __version__
from ..atomic import write_text_atomic
from ..results.checks_table import SMALLEST_SHOWN
from ..results.uq import LOO_WARNING, pf_verdicts, warning_groups
from ..system.labels import format_number
from .sections import (
    STYLE,
    Raw,
    _img,
    html_table,
    link,
    scenario_section,
    verdict_class,
)

esc = html.escape

#: the study's page in its output folder
UQ_REPORT = "uq.html"


def _probability(p: float) -> str:
    if p is None or not math.isfinite(p):
        return "-"
    return f"< {SMALLEST_SHOWN:.0e}" if p < SMALLEST_SHOWN else f"{p:.3g}"


def _value(v: Any) -> float:
    return math.nan if v is None else float(v)


def _loo(e: float) -> str:
    return "not estimated" if not math.isfinite(e) else f"{100.0 * e:.2g} %"


def verdict_section(result: Any, target: float | None = None) -> str:
    rows = pf_verdicts(result, target)
    out = ['<section id="verdict"><h2>Verdict under uncertainty</h2>']
    if not rows:
        out.append("<p>No code criterion applies to the channels of this study.</p></section>")
        return "\n".join(out)
    t = rows[0]["target"]
    n_ex = sum(r["verdict"] == "EXCEEDS" for r in rows)
    n_ne = sum(r["verdict"] == "NOT EVALUATED" for r in rows)
    out.append(f'<p class="counts"><b>{n_ex} of {len(rows)} criteria EXCEED</b> the target probability {t:.3g} per '
               f"passage under the uncertain keys{f'; {n_ne} not evaluated' if n_ne else ''}.</p>")
    out.append("<p>P_f = E_theta[P(exceed | theta)]: the probability of exceeding the criterion's limit in one passage at "
               "its deciding location, averaged over the uncertain keys theta (the expansion's mean of that probability "
               "over the nodes; with a quadrature design the quadrature's weighted mean of the nodes' probabilities). "
               f"The criterion EXCEEDS when P_f is above the target {t:.3g}. Shown as &lt; {SMALLEST_SHOWN:.0e} below "
               "that. The estimate is the level exceeded with the target probability in one passage (in the unit shown), its "
               "mean and standard deviation over the keys and its 5, 50 and 95 % points over them (the surrogate at "
               "1024 Sobol points of the keys); the limit is the criterion's pass/fail value in the default "
               "limits, which the nodes were checked against ('-' where it depends on the run).</p>")
    body = []
    for r in rows:
        title, unit, limit = r["title"], r["unit"], r["limit"]
        body.append([r["criterion"], title, Raw(f'<span class="{verdict_class(r["verdict"])}">'
                                                f'{esc(r["verdict"].lower())}</span>'),
                     _probability(r["pf"]), f"{r['target']:.3g}", _probability(r["node_max"]),
                     format_number(r["estimate_mean"], 3), format_number(r["estimate_std"], 2),
                     " / ".join(format_number(v, 3) or "-" for v in r["estimate_band"]),
                     format_number(limit, 3) or "-", unit])
    out.append(html_table("uq-verdicts", ["criterion", "what it checks", "verdict", "P_f", "target",
                                          "largest P at a node", "estimate mean", "estimate std",
                                          "estimate 5 / 50 / 95 %", "limit", "unit"],
                          body, ["", "", "", "num", "num", "num", "num", "num", "num", "num", ""]))
    out.append("</section>")
    return "\n".join(out)


def study_section(result: Any) -> str:
    prov = result.provenance
    out = ['<section id="study"><h2>The study</h2>',
           f"<p>Polynomial chaos of total degree {esc(str(prov.get('order', '?')))} over "
           f"{esc(str(prov.get('n_nodes', '?')))} PEM runs ({esc(str(prov.get('design', '?')))} design), engine "
           f"{esc(str(prov.get('engine', '?')))}, {format_number(float(prov.get('seconds', math.nan)), 3)} s "
           f"({esc(str(prov.get('tasks_from_checkpoint', 0)))} nodes from the checkpoint).</p>"]
    body = [[k.get("key", ""), k.get("distribution", ""), format_number(_value(k.get("mean")), 4),
             format_number(_value(k.get("std")), 3), format_number(_value(k.get("low")), 4),
             format_number(_value(k.get("high")), 4)] for k in result.keys]
    out.append(html_table("uq-keys", ["key", "distribution", "mean", "std", "low", "high"], body,
                          ["", "", "num", "num", "num", "num"]))
    out.append("</section>")
    return "\n".join(out)


def loo_section(result: Any) -> str:
    out = ['<section id="loo"><h2>Surrogate error (leave-one-out)</h2>',
           "<p>Per quantity, the expansion's leave-one-out error relative to the quantity's variance over the keys: "
           f"above {100 * LOO_WARNING:g} % the surrogate's moments, Sobol indices and P_f are not accurate (raise "
           "--order or use more nodes). Not estimated when the design has no more nodes than basis terms (a quadrature "
           "of one key: order + 1 of each), when a node has leverage 1, or for a quantity that does not vary.</p>"]

    def shown(q: str, v: float, digits: int) -> str:  # a probability as the verdict shows it
        return _probability(float(v)) if q.startswith("probability:") else format_number(float(v), digits)

    body = [[q, shown(q, m, 3), shown(q, s, 2),
             Raw(f'<span class="exceeds">{esc(_loo(float(e)))}</span>') if math.isfinite(e) and e > LOO_WARNING
             else _loo(float(e))] for q, m, s, e in zip(result.quantities, result.quantity_mean, result.quantity_std,
                                                          result.loo)]
    out.append(html_table("uq-loo", ["quantity", "mean", "std", "leave-one-out error"], body, ["", "num", "num", "num"]))
    out.append("</section>")
    return "\n".join(out)


def sobol_section(result: Any, sobol_png: bytes | None) -> str:
    out = ['<section id="sobol"><h2>Sobol indices of the key quantities</h2>',
           "<p>Per quantity and uncertain key: the first-order index (the share of the quantity's variance over the keys "
           "that the key explains alone) and the total index (with its interactions). '-' for a quantity that was not "
           "evaluated at every node.</p>"]
    if sobol_png:
        out.append(_img(sobol_png, "Sobol indices"))
    keys = result.key_names
    body = []
    for name in result.quantities:
        q = result.quantity(name)
        body.append([name] + [f"{format_number(q['sobol_first'][k], 2) or '-'} / {format_number(q['sobol_total'][k], 2) or '-'}"
                              for k in keys])
    out.append(html_table("uq-sobol", ["quantity"] + [f"{k} (first / total)" for k in keys], body,
                          [""] + ["num"] * len(keys)))
    out.append("</section>")
    return "\n".join(out)


def bands_section(bands: Sequence[tuple[str, bytes]]) -> str:
    out = ['<section id="bands"><h2>sigma(t) over the crossing</h2>',
           "<p>Each channel's sigma(t): its mean over the keys, the median and the 5-95 % band (read from the "
           "surrogate).</p>"]
    out += [_img(png, f"sigma band of {ch}") for ch, png in bands] or ["<p>Not drawn (--no-figures).</p>"]
    out.append("</section>")
    return "\n".join(out)


def warnings_section(result: Any) -> str:
    """Every warning: those that differ only in their numbers (the same mode's growth at another node)
    once, as first raised, with the others folded below it."""
    out = ['<section id="warnings"><h2>Warnings</h2>']
    for first, texts in warning_groups(result):
        out.append(f'<p class="warn">{esc(first)}</p>')
        if len(texts) > 1:
            out.append(f"<details><summary>{len(texts)} messages like it (at other nodes)</summary>"
                       + "".join(f"<p><small>{esc(t)}</small></p>" for t in texts) + "</details>")
    if len(out) == 1:
        out.append("<p>None recorded.</p>")
    out.append("</section>")
    return "\n".join(out)


def render_uq_report(result: Any, sobol_png: bytes | None = None, bands: Sequence[tuple[str, bytes]] = (),
                     target: float | None = None) -> str:
    """The HTML text of the report on a study (module docstring); ``sobol_png``: the Sobol bars as PNG
    bytes or None; ``bands``: (channel, PNG bytes) of the sigma(t) bands; ``target``: the target
    probability per passage (default the checks')."""
    sc = result.scenario
    title = f"tb_exudyn uncertainty study: {sc.name}"
    now = _dt.datetime.now(_dt.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    nav = [("verdict", "Verdict"), ("study", "Study"), ("loo", "Surrogate error"), ("sobol", "Sobol indices"),
           ("bands", "sigma(t) bands"), ("warnings", "Warnings"), ("scenario", "Scenario")]
    body = [f"<h1>{esc(title)}</h1>", f'<p class="meta">{esc(sc.description)}</p>',
            f'<p class="meta">Uncertain keys: {esc(", ".join(result.key_names))}. Generated {esc(now)} by tb_exudyn '
            f"{esc(__version__)}. The result is in uq/.</p>",
            "<nav>" + " | ".join(link(a, t) for a, t in nav) + "</nav>",
            verdict_section(result, target), study_section(result), loo_section(result), sobol_section(result, sobol_png),
            bands_section(bands), warnings_section(result), scenario_section([sc])]
    return ("<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
            f"<meta name=\"viewport\" content=\"width=device-width\"><title>{esc(title)}</title>"
            f"<style>{STYLE}</style></head><body>\n" + "\n".join(body) + "\n</body></html>\n")


def write_uq_report(result: Any, folder: str | Path, sobol_png: bytes | None = None,
                    bands: Sequence[tuple[str, bytes]] = ()) -> Path:
    """Write :func:`render_uq_report` to ``folder/uq.html``, atomically."""
    out = Path(folder) / UQ_REPORT
    write_text_atomic(out, render_uq_report(result, sobol_png, bands))
    return out


__all__ = ["UQ_REPORT", "render_uq_report", "write_uq_report"]
