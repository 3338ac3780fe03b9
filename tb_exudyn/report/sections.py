"""The report's HTML sections: tables, pieces and the sections, each a function returning escaped HTML."""

from __future__ import annotations

import base64
import html
import math
import re
from dataclasses import dataclass, fields, is_dataclass
from pathlib import Path
from typing import Any, Iterable, Sequence

import numpy as np

from ..plotting import data as pdata
from ..plotting.files import PALETTE_COLOURS, compact_png  # noqa: F401 (the page's figures)
from ..plotting.data import channel_group, channel_label, crossing_times, display_unit, format_number
from ..results import RandomResponse, TimeHistory
from ..results.checks_table import format_value
from ..scenario import Scenario
from ..scenario.show import run_label
from ..scenario.studies import MEASURES, Study, StudyQuantity
from .entries import FindingRow, ModeEntry, Result, code_limit, compare_findings, static_axle_load

esc = html.escape


# ============================================================================================ scenario tables
def _fmt(v: Any) -> str:
    if isinstance(v, float):
        return "inf" if math.isinf(v) else f"{v:.6g}"
    if isinstance(v, tuple):
        return ", ".join(getattr(x, "name", None) or _fmt(x) for x in v)
    return str(v)


def flat_rows(obj: Any, prefix: str = "") -> list[tuple[str, str, str, str]]:
    """(key, value, unit, meaning) of every field of a scenario dataclass, nested keys dotted;
    description, source and notes are left out (they go to the sources table)."""
    rows = []
    kind = getattr(type(obj), "kind", None)
    if isinstance(kind, str):
        rows.append((prefix + "kind", kind, "", "model kind"))
    for f in fields(obj):
        if f.name in ("description", "source", "notes"):
            continue
        v = getattr(obj, f.name)
        if is_dataclass(v):
            rows += flat_rows(v, f"{prefix}{f.name}.")
        else:
            rows.append((prefix + f.name, _fmt(v), f.metadata.get("unit", ""), f.metadata.get("doc", "")))
    return rows


def scenario_sections(sc: Scenario) -> list[tuple[str, str, list[str], list[Sequence[str]]]]:
    """(id, title, header, rows) of the scenario's tables: train, vehicles, bridge, track, settings,
    derived quantities and sources."""

    offsets = sc.train.axle_positions
    train, first = [], 0
    for k, v in enumerate(sc.train.vehicles):
        p = static_axle_load(sc, k + 1)
        train.append((f"car{k + 1}", v.name, v.kind, f"{offsets[first]:.6g}", str(len(v.axle_offsets)),
                      "" if p is None else f"{p / 1e3:.4g}", v.description))
        first += len(v.axle_offsets)
    sections = [("scenario-train", "Train (running order)",
                 ["channel prefix", "vehicle", "kind", "first axle behind the train's first [m]", "axles",
                  "static axle load [kN]", "description"], train)]
    seen = set()
    for v in sc.train.vehicles:
        if v.name not in seen:
            seen.add(v.name)
            sections.append((f"scenario-vehicle-{v.name}", f"Vehicle {v.name}", ["key", "value", "unit", "meaning"],
                             flat_rows(v)))
    head = ["key", "value", "unit", "meaning"]
    sections.append(("scenario-bridge", f"Bridge {sc.bridge.name}", head, flat_rows(sc.bridge)))
    sections.append(("scenario-track", "Track", head, flat_rows(sc.track)))
    sections.append(("scenario-settings", "Analysis settings", head,
                     [("speed_kmh", _fmt(sc.speed_kmh), "km/h", "train speed")] + flat_rows(sc.analysis)))
    derived = [
        ("speed", f"{sc.speed:.6g}", "m/s", "train speed"),
        ("train length", f"{sc.train.length:.6g}", "m", "first to last axle"),
        ("bridge length", f"{sc.bridge.length:.6g}", "m", "sum of spans"),
        ("duration", f"{sc.duration:.6g}", "s", "first axle at -lead_in until the last axle is run_out past the bridge"),
    ]
    derived += [(label, f"{t:.6g}", "s", "time t of the event (t = 0: first axle at -lead_in)")
                for _, label, t in crossing_times(sc).marks()]
    if len(sc.train.vehicles) > 1:
        for car in range(1, len(sc.train.vehicles) + 1):
            derived += [(label, f"{t:.6g}", "s", "time t of the event")
                        for _, label, t in crossing_times(sc, car).marks()]
    sections.append(("scenario-derived", "Derived quantities", head, derived))
    sources = [("scenario", sc.name, sc.source, sc.notes), ("bridge", sc.bridge.name, sc.bridge.source, sc.bridge.notes)]
    sources += [("vehicle", v.name, v.source, v.notes) for v in {v.name: v for v in sc.train.vehicles}.values()]
    sections.append(("scenario-sources", "Sources and notes", ["part", "name", "source", "notes"], sources))
    return sections


# ============================================================================================ HTML pieces
STYLE = """
body{font-family:system-ui,sans-serif;max-width:88rem;margin:.6rem auto;padding:0 1rem;color:#222;line-height:1.35}
h1{font-size:1.45rem;margin:.2rem 0} h2{font-size:1.2rem;margin:1.2rem 0 .4rem;border-bottom:1px solid #ddd}
h3{font-size:1.05rem;margin:.9rem 0 .3rem} h4{font-size:.95rem;margin:.8rem 0 .2rem}
p.meta{margin:.1rem 0;color:#555;font-size:.85rem} nav{font-size:.85rem;margin:.2rem 0 .4rem}
table{border-collapse:collapse;margin:.3rem 0 .8rem;font-size:.82rem}
th,td{border:1px solid #ccc;padding:.15rem .45rem;text-align:left;vertical-align:top}
th{background:#f0f0f0} td.num{text-align:right;font-variant-numeric:tabular-nums;white-space:nowrap}
.exceeds,.not-matched{color:#b00;font-weight:bold} .ok,.matched{color:#070;font-weight:bold} .check{color:#a60}
.undetermined{color:#a60;font-weight:bold} .not-evaluated{color:#555;font-weight:bold}
.placeholder{background:#fff8e0;border:1px solid #e6c200;padding:.3rem .6rem;margin:.3rem 0;font-size:.88rem}
.warn{background:#fdeaea;border-left:4px solid #b00;padding:.2rem .6rem;margin:.2rem 0;font-size:.88rem}
.figs{display:grid;grid-template-columns:repeat(auto-fill,minmax(34rem,1fr));gap:.4rem}
figure{margin:0} img{max-width:100%;height:auto} figcaption{font-size:.78rem;color:#555}
p.nums{font-size:.85rem;margin:.1rem 0 .3rem} code{font-size:.85em} small{color:#555}
details{margin:.2rem 0} summary{cursor:pointer;font-weight:600}
p.counts{margin:.2rem 0 .3rem;font-size:.92rem} .conditional{color:#a60;font-weight:600}
#verdicts td.notes{font-size:.78rem;white-space:nowrap}
#verdicts-table td{padding:.08rem .4rem;line-height:1.22} #verdicts-table tr.part th{background:#e6edf5;font-weight:600}
#verdicts-table .not-evaluated{white-space:nowrap} #verdicts-table td:first-child{min-width:20rem} #verdicts-table td.reason{color:#444}
p.terms{font-size:.8rem;margin:.1rem 0 .35rem;color:#333;max-width:80rem} h2 small{font-weight:normal;font-size:.8rem;color:#555} ol.notes{font-size:.78rem;margin:.1rem 0 .5rem;padding-left:2.4rem}
ol.notes li{margin:.05rem 0} #verdicts-all table{width:100%;table-layout:fixed}
#verdicts-all th:nth-child(1){width:46%} #verdicts-all th:nth-child(5){width:18%} #verdicts-all th:nth-child(6){width:9%}
"""

#: the page's script: a link opens the folded sections around its target; the channel filter, an
#: input box made by the script (without it the page reads the same)
FILTER_SCRIPT = """
document.addEventListener('click',function(e){var a=e.target.closest&&e.target.closest('a[href^="#"]');if(!a)return;
var t=document.getElementById(a.getAttribute('href').slice(1));
for(var d=t&&t.parentElement;d;d=d.parentElement){if(d.tagName==='DETAILS')d.open=true;}});
(function(){var box=document.getElementById('channel-filter');if(!box)return;
var input=document.createElement('input');input.type='search';input.size=40;
input.placeholder='filter channels: words, e.g. car2 lateral';box.appendChild(input);
input.addEventListener('input',function(){var words=input.value.toLowerCase().split(/\\s+/).filter(Boolean);
document.querySelectorAll('#channels details.group').forEach(function(d){var n=0;
d.querySelectorAll('tbody tr').forEach(function(tr){var t=tr.textContent.toLowerCase();
var ok=words.every(function(w){return t.indexOf(w)>=0;});tr.hidden=!ok;if(ok)n++;});
d.hidden=n===0;d.open=words.length>0&&n>0;});
var all=document.getElementById('channels-all');if(all&&words.length>0)all.open=true;});})();
"""


@dataclass(frozen=True)
class Raw:
    """Already escaped HTML for a table cell."""

    html: str


def html_table(tid: str, header: Sequence[Any], rows: Iterable[Sequence[Any]], classes: Sequence[str] = ()) -> str:
    out = [f'<table id="{esc(tid)}"><thead><tr>' + "".join(f"<th>{h.html if isinstance(h, Raw) else esc(h)}</th>"
                                                       for h in header) + "</tr></thead><tbody>"]
    for row in rows:
        cells = []
        for i, cell in enumerate(row):
            cls = classes[i] if i < len(classes) else ""
            cells.append(f'<td class="{cls}">' if cls else "<td>")
            cells.append((cell.html if isinstance(cell, Raw) else esc(str(cell))) + "</td>")
        out.append("<tr>" + "".join(cells) + "</tr>")
    return "".join(out) + "</tbody></table>"


def _shown(value: float, si_unit: str) -> str:
    """A value in its display unit (number only)."""
    return format_number(value * display_unit(si_unit).factor)


def verdict_class(word: str) -> str:
    return re.sub(r"[^a-z]+", "-", word.lower()).strip("-")


def _flatten(d: Any, prefix: str = "") -> list[tuple[str, str]]:
    if isinstance(d, dict):
        out = []
        for key in sorted(d):
            out += _flatten(d[key], f"{prefix}{key}.")
        return out
    if isinstance(d, (list, tuple)):
        text = "; ".join(str(x) for x in d) if d else "(none)"
    elif isinstance(d, float):
        text = f"{d:.6g}"
    else:
        text = str(d)
    return [(prefix.rstrip("."), text)]


def result_name(path: Path, result: Result) -> str:
    kind = result.method if isinstance(result, RandomResponse) else "time history"
    return kind if path.name == kind else f"{path.name} ({kind})"


def anchor(prefix: str, name: str) -> str:
    return f"{prefix}-{name}"


def link(target: str, text: str) -> str:
    return f'<a href="#{esc(target)}">{esc(text)}</a>'


# ============================================================================================ sections
def provenance_warnings(result: Result) -> list[str]:
    """A result's provenance ``warnings`` as text: a list of strings as the runs write it (and a loaded
    result must hold); a result built in Python with one string or another value gives that one line."""
    found = result.provenance.get("warnings") if isinstance(result.provenance, dict) else None
    if found is None:
        return []
    return [str(w) for w in found] if isinstance(found, (list, tuple)) else [str(found)]


def warnings_section(found: Sequence[tuple[Path, Result]], extra: Sequence[str] = ()) -> str:
    """Every result's provenance ``warnings`` (and the report's own), or "none recorded"."""
    items = [(None, w) for w in extra]
    for path, result in found:
        items += [(result_name(path, result), w) for w in provenance_warnings(result)]
    out = ['<section id="warnings"><h2>Warnings</h2>']
    if not items:
        out.append("<p>None recorded in the results' provenance.</p>")
    for where, text in items:
        out.append(f'<p class="warn">{esc(text)}' + (f" <small>({esc(where)})</small>" if where else "") + "</p>")
    out.append("</section>")
    return "\n".join(out)


def _ours_text(row: FindingRow) -> str:
    if row.ours is None:
        return ""
    unit = MEASURES[row.quantity.measure][0]
    if isinstance(row.ours, tuple):
        return f"{format_number(row.ours[0], 3)}-{format_number(row.ours[1], 3)} {unit}".strip()
    if row.quantity.measure == "band_across_zero_share":
        return f"{100 * row.ours:.0f} %"
    return f"{format_number(row.ours, 3)} {unit}".strip()


def _study_text(q: StudyQuantity) -> str:
    unit = MEASURES[q.measure][0]
    parts = []
    if not math.isnan(q.study):
        parts.append(f"{format_number(q.study, 3)} {unit}".strip())
    if q.study_range:
        parts.append(f"{format_number(q.study_range[0], 3)}-{format_number(q.study_range[1], 3)} {unit}".strip())
    if q.study_text:
        parts.append(f"“{q.study_text}”")
    return "; ".join(parts)


def _rule_text(q: StudyQuantity) -> str:
    unit = MEASURES[q.measure][0]
    if not math.isnan(q.tolerance):
        return f"within {format_number(q.tolerance, 3)} {unit}".strip()
    if not math.isnan(q.agree_below):
        return f"below {format_number(q.agree_below, 3)}"
    if not math.isnan(q.agree_above):
        return f"above {format_number(q.agree_above, 3)}"
    return ""


def _why(where: str) -> str:
    """A finding's ``explained`` ('docs/findings.md section 1') as a link to that file of this source tree
    (the docs are not installed with the package: plain text then)."""
    doc = Path(__file__).resolve().parents[2] / where.split(" ", 1)[0]
    text = f"why: {esc(where)}"
    return f'<a href="{esc(doc.as_uri())}">{text}</a>' if doc.is_file() else text


def findings_section(studies: Sequence[Study], resp: RandomResponse | None, figure_ids: set[str]) -> str:
    """The study's stated findings beside ours ("" when the scenario reproduces no study)."""
    if not studies:
        return ""
    out = ['<section id="findings"><h2>The study\'s findings beside ours</h2>']
    for study in studies:
        out.append(f"<p><b>{esc(study.title)}</b>. <small>{esc(study.source)} Data: models/studies/{esc(study.name)}.toml; "
                   "agreement rules marked [check] are our reading of the study's words.</small></p>")
        if resp is None:
            out.append('<p class="placeholder">Not computed: no PEM result with PSD maps in this folder.</p>')
            continue
        rows = []
        previous = None
        for r in compare_findings(study, resp):
            ch = r.quantity.channel
            where = link(anchor("fig", ch), channel_label(ch)) if anchor("fig", ch) in figure_ids else esc(channel_label(ch))
            agreement = r.agreement
            cls = verdict_class(agreement) if agreement in ("matched", "not matched") else ""
            rule = _rule_text(r.quantity)
            claim = (Raw("") if r.finding is previous else  # the claim once, on its first quantity
                     Raw(f"<b>{esc(r.finding.id)}</b>: {esc(r.finding.claim)}<br><small>{esc(r.finding.where)}</small>"))
            previous = r.finding
            rows.append((claim,
                         Raw(f"{where}<br><small><code>{esc(ch)}</code></small>"),
                         MEASURES[r.quantity.measure][1], _study_text(r.quantity), _ours_text(r),
                         Raw((f'<span class="{cls}">{esc(agreement)}</span>' if cls else esc(agreement))
                             + (f"<br><small>{_why(r.finding.explained)}</small>"
                                if agreement == "not matched" and r.finding.explained else "")
                              + (f"<br><small>{esc(rule)}: {esc(r.quantity.basis)}</small>" if rule else
                                 f"<small>{esc(r.quantity.basis)}</small>"))))
        head = ["finding (the study)", "channel", "measure", "the study", "ours", "agreement"]
        out.append(html_table(f"findings-{study.name}", head, rows, ("", "", "", "num", "num", "")))
    out.append("</section>")
    return "\n".join(out)


def _numbers(result: Result, ch: str, k: float) -> str:
    """The numbers a channel's figures explain, in one line."""
    if isinstance(result, TimeHistory):
        value, t = result.peak(ch)
        return f"max |value| {esc(format_value(abs(value), result.unit(ch)))} at t = {t:.3g} s"
    row = result.index(ch)
    unit = result.unit(ch)
    mean, std = result.mean[row], result.std[row]
    j = int(np.argmax(std))
    parts = [f"max |mean| {format_value(float(np.max(np.abs(mean))), unit)}",
             f"max sigma {format_value(float(std[j]), unit)} at t = {result.time[j]:.3g} s",
             f"max |mean| + {k:g} sigma {format_value(float(np.max(np.abs(mean) + k * std)), unit)}"]
    if pdata.has_psd(result, ch):
        f, t = pdata.psd_peak(result, ch)
        lo, hi = pdata.psd_band(result, ch)
        parts.append(f"PSD peak at {format_number(f, 3)} Hz (t = {t:.3g} s); 99 % of sigma^2 at max sigma in "
                     f"{format_number(lo, 3)}-{format_number(hi, 3)} Hz")
    lim = code_limit(ch, result.scenario)
    if lim is not None:
        parts.append(f"screening limit {format_value(lim.value, lim.unit)} [check]")
    return esc(" · ".join(parts))


_CAPTIONS = {
    "bounds": "mean and mean +- {k:g} sigma against time",
    "psd_map": "time-dependent one-sided PSD",
    "psd_slices": "PSD at the time of maximum sigma",
    "history": "history of the run",
    "pem_vs_mc": "PEM against Monte Carlo: mean and sigma",
}


def _img(png: bytes, alt: str) -> str:
    return f'<img alt="{esc(alt)}" src="data:image/png;base64,{base64.b64encode(compact_png(png)).decode("ascii")}">'


def left_out_line(left_out: Sequence[str]) -> str:
    """The page's line on the channels whose figures it leaves out (:func:`tb_exudyn.plotting.data.page_channel`)."""
    cars = sorted({c for c in map(pdata.channel_car, left_out) if c is not None})
    who = f"car {cars[0]}" if len(cars) == 1 else f"cars {', '.join(map(str, cars[:-1]))} and {cars[-1]}" if cars \
        else "other channels"
    return (f"Not drawn here: the figures (sigma and mean, PSD map and slices) of {len(left_out)} channels of {who} "
            f"({', '.join(left_out)}; their numbers are in the channel table). "
            "'tb-exudyn plot FOLDER' draws them into the result's figures folder; "
            "'tb-exudyn run ... --figures all' or 'tb-exudyn report FOLDER --figures all' puts them on the page.")


def figures_section(found: Sequence[tuple[Path, Result]], pictures: dict[tuple[str, str, str], bytes],
                    names: dict[str, list[str]], k: float, comparison: list[str], left_out: Sequence[str] = ()) -> str:
    """Per result, per channel group (bridge, car k, car k wheelsets): each channel's numbers
    above its figures; the bridge's group open (else the first), the others folded.
    ``pictures[(result folder name, channel, kind)]`` = PNG bytes; ``left_out``: the channels whose
    figures the page leaves out (one line says which and how to draw them)."""
    out = ['<section id="figures"><h2>Figures</h2>']
    if left_out:
        out.append(f'<p class="left-out">{esc(left_out_line(left_out))}</p>')
    many = len(found) > 1
    for path, result in found:
        if many:
            out.append(f"<h3>{esc(result_name(path, result))}</h3>")
        groups: dict[str, tuple[str, list[str]]] = {}
        for ch in names[path.name]:
            key, heading = channel_group(ch)
            groups.setdefault(key, (heading, []))[1].append(ch)
        shown = "bridge" if "bridge" in groups else next(iter(groups), "")
        for key, (heading, chans) in groups.items():  # the bridge's figures open, the vehicle's a click away
            out.append(f'<details class="figgroup"{" open" if key == shown else ""}><summary>{esc(heading)} '
                       f"({len(chans)} channels)</summary>")
            for ch in chans:
                fig_id = anchor("fig", ch) if path.name == found[0][0].name else anchor(f"fig-{path.name}", ch)
                out.append(f'<section class="channel" id="{esc(fig_id)}"><h4>{esc(channel_label(ch))} '
                           f"<small><code>{esc(ch)}</code></small></h4>")
                out.append(f'<p class="nums">{_numbers(result, ch, k)}</p><div class="figs">')
                for kind in ("bounds", "psd_map", "psd_slices", "history"):
                    png = pictures.get((path.name, ch, kind))
                    if png is not None:
                        cap = _CAPTIONS[kind].format(k=k)
                        out.append(f"<figure>{_img(png, f'{ch}: {cap}')}<figcaption>{esc(cap)}</figcaption></figure>")
                out.append("</div></section>")
            out.append("</details>")
    if comparison:
        out.append("<h3>PEM against Monte Carlo</h3><div class=\"figs\">")
        for ch in comparison:
            png = pictures.get(("", ch, "pem_vs_mc"))
            if png is not None:
                cap = f"{channel_label(ch)}: PEM against Monte Carlo"
                out.append(f'<figure id="{esc(anchor("cmp", ch))}">{_img(png, cap)}<figcaption>{esc(cap)} '
                           f"<code>{esc(ch)}</code></figcaption></figure>")
        out.append("</div>")
    out.append("</section>")
    return "\n".join(out)


def channels_section(found: Sequence[tuple[Path, Result]], k: float, figure_ids: set[str]) -> str:
    """Every channel of every result, grouped (bridge, car k, car k wheelsets) in collapsed
    <details>, with a filter box (made by the inline script)."""
    out = ['<section id="channels"><h2>All channels</h2>',
           f"<p>Per channel over the run: max |mean|, max sigma and max |mean| + {k:g} sigma (random responses), "
           "or max |value| (one run), in engineering units. The table and its groups open on click; "
           'the box filters by words of the label or name.</p><div id="channel-filter"></div>']
    n_all = sum(len(pdata.channel_names(r)) for _, r in found)
    out.append(f'<details id="channels-all"><summary>The table of all {n_all} channels, by group</summary>')
    for path, result in found:
        if len(found) > 1:
            out.append(f"<h3>{esc(result_name(path, result))}</h3>")
        groups: dict[str, tuple[str, list]] = {}
        if isinstance(result, RandomResponse):
            what = f"sigma over {pdata.band_text(result)}" + (f", {result.n_samples} samples" if result.n_samples else "")
            out.append(f"<p class=\"meta\">{esc(result_name(path, result))}: {esc(what)}</p>")
            for c, u, m, s, p in result.summary_rows(k):
                groups.setdefault(channel_group(c)[0], (channel_group(c)[1], []))[1].append(
                    (c, u, (_shown(m, u), _shown(s, u), _shown(p, u))))
            head = ["channel", "name", "unit", "max |mean|", "max sigma", f"max |mean| + {k:g} sigma"]
        else:
            for c in result.names:
                peak = float(np.max(np.abs(result[c])))
                groups.setdefault(channel_group(c)[0], (channel_group(c)[1], []))[1].append(
                    (c, result.unit(c), (_shown(peak, result.unit(c)),)))
            head = ["channel", "name", "unit", "max |value|"]
        for key, (heading, rows) in groups.items():
            cells = []
            for c, u, values in rows:
                label = channel_label(c)
                target = anchor("fig", c)
                name_cell = Raw(link(target, label)) if target in figure_ids and path.name == found[0][0].name else label
                cells.append((name_cell, Raw(f"<code>{esc(c)}</code>"), display_unit(u).unit) + values)
            out.append(f'<details class="group"><summary>{esc(heading)} ({len(rows)} channels)</summary>'
                       + html_table(f"channels-{path.name}-{key}", head, cells, ("", "", "") + ("num",) * len(head))
                       + "</details>")
    out.append("</details></section>")
    return "\n".join(out)


#: the modes table is shown open up to this many modes, folded beyond
MODES_SHOWN = 12


def damping_text(zeta: float) -> str:
    """A damping ratio as shown: 3 digits, ">= 1" for an overdamped (real) root, whose "frequency" is
    |lambda| / 2 pi and not an oscillation."""
    return ">= 1" if zeta >= 1.0 else f"{zeta:.3g}"


def modes_section(modes: Sequence[ModeEntry] | None) -> str:
    """The modal table, or "not computed"."""
    out = ['<section id="modes"><h2>Modes</h2>']
    if modes is None:
        out.append('<p class="placeholder"><b>Modes: not computed.</b> The modal analysis of the linearised '
                   "train-bridge system was not given to this report.</p>")
    elif not modes:
        out.append("<p>No modes in the analysed band.</p>")
    else:
        rows = [(format_number(m.frequency, 4), damping_text(m.damping_ratio), m.label, m.context,
                 Raw(f'<span class="exceeds">{esc(m.warning)}</span>' if m.warning else ""))
                for m in sorted(modes, key=lambda m: m.frequency)]
        table = html_table("modes-table", ["frequency [Hz] (|lambda| / 2 pi)", "damping ratio", "what moves",
                                           "computed for", "warning"],
                           rows, ("num", "num", "", "", ""))
        if len(modes) <= MODES_SHOWN:
            out.append(table)
        else:  # a long table (the reference study: 100 modes over several screens) folded under a line
            f = [m.frequency for m in modes]
            warned = sum(bool(m.warning) for m in modes)
            out.append(f'<details id="modes-all"><summary>The table of all {len(modes)} modes, '
                       f"{format_number(min(f), 4)}-{format_number(max(f), 4)} Hz"
                       + (f' (<span class="exceeds">{warned} with a warning</span>)' if warned else "")
                       + "</summary>" + table + "</details>")
    out.append("</section>")
    return "\n".join(out)


def scenario_section(scenarios: Sequence[Scenario]) -> str:
    out = ['<section id="scenario"><h2>Scenario</h2>']
    if not scenarios:
        out.append("<p>The results do not record their scenario.</p></section>")
        return "\n".join(out)
    sc = scenarios[0]
    out.append(f"<p><b>{esc(sc.name)}</b>: {esc(run_label(sc))}.</p>")
    out.append(f'<p class="meta">The scenario file\'s description (an override such as --speed-kmh or --set does '
               f"not change it): {esc(sc.description)}</p>")
    others = sorted({s.name for s in scenarios if s != sc})
    if others:
        out.append(f'<p class="warn">Some results were computed for other scenarios: {esc(", ".join(others))}'
                   " (only the first is tabulated).</p>")
    for tid, heading, head, rows in scenario_sections(sc):
        out.append(f"<details><summary>{esc(heading)}</summary>" + html_table(tid, head, rows) + "</details>")
    out.append("</section>")
    return "\n".join(out)


#: a provenance entry with at least this many keys (one per channel, e.g. grid_error.channels) is
#: shown as a table of its own instead of one row per leaf
PER_CHANNEL_ROWS = 10


def _scalar(v: Any) -> bool:
    return isinstance(v, (str, int, float, bool)) or v is None


def _columns(records: Sequence[Any]) -> list[str] | None:
    """The keys the records share when each is a dict of scalars with the same keys, else None."""
    if not records or not all(isinstance(r, dict) for r in records):
        return None
    cols = list(records[0])
    if not cols or any(list(r) != cols or not all(_scalar(x) for x in r.values()) for r in records):
        return None
    return cols


def _split(d: Any, prefix: str = "") -> tuple[list[tuple[str, str]], list[tuple[str, list[str], list[list[str]]]]]:
    """A provenance dict as (key, value) rows and tables (key, header, rows): a dict of many same-shaped
    dicts becomes one table (a row per key), a list of same-shaped dicts one table (a row per item), a
    dict of many scalars one row per distinct value with the keys that hold it; everything else one
    row per leaf (:func:`_flatten`).
    The same information as one row per leaf, in a fraction of the bytes (the reference study's
    provenance: 286 kB as leaves)."""
    if not isinstance(d, dict):
        return _flatten(d, prefix), []
    rows: list[tuple[str, str]] = []
    tables: list[tuple[str, list[str], list[list[str]]]] = []
    for key in sorted(d):
        v, path = d[key], f"{prefix}{key}"
        cols = _columns(list(v.values())) if isinstance(v, dict) and len(v) >= PER_CHANNEL_ROWS else None
        if cols is not None:
            tables.append((path, ["key"] + cols, [[k] + [_flatten(e[c])[0][1] for c in cols] for k, e in sorted(v.items())]))
        elif isinstance(v, list) and len(v) > 1 and _columns(v) is not None:  # records (damped_modes): a row each
            cols = list(v[0])
            tables.append((path, cols, [[_flatten(e[c])[0][1] for c in cols] for e in v]))
        elif isinstance(v, dict) and len(v) >= PER_CHANNEL_ROWS and all(_scalar(x) for x in v.values()):
            by: dict[str, list[str]] = {}
            for k in sorted(v):
                by.setdefault(_flatten(v[k])[0][1], []).append(k)
            tables.append((path, ["value", "count", "keys holding it"], [[val, str(len(ks)), ", ".join(ks)] for val, ks in by.items()]))
        elif isinstance(v, dict) and v:
            r, t = _split(v, path + ".")
            rows += r
            tables += t
        else:
            rows += _flatten(v, path)
    return rows, tables


def provenance_section(found: Sequence[tuple[Path, Result]]) -> str:
    out = ['<section id="provenance"><h2>Provenance</h2>']
    for path, result in found:
        rows, tables = _split(result.provenance)
        if result.scenario is not None:
            rows.insert(0, ("scenario seed (analysis.seed)", str(result.scenario.analysis.seed)))
        parts = [html_table(f"provenance-{path.name}", ["key", "value"], rows)]
        for key, head, trows in tables:
            parts.append(f"<details><summary><code>{esc(key)}</code> ({len(trows)} rows)</summary>"
                         + html_table(f"provenance-{path.name}-{key}", head, trows) + "</details>")
        out.append(f"<details><summary>{esc(result_name(path, result))}</summary>" + "".join(parts) + "</details>")
    out.append("</section>")
    return "\n".join(out)
