"""A self-contained HTML report of saved results: scenario, summary with code limits, figures, provenance.

One page, no external resources: figures are embedded as base64 PNG, the style is inline, and every
piece of text is escaped. Code limits are those of the project's limit list, all marked [check]
(to be checked against the code text before use); the peak compared with a limit is
max |mean| + 3 sigma (the 3-sigma rule) for a random response and max |value| for a single run.
matplotlib is imported only when figures are drawn (through :mod:`tb_exudyn.plotting`).
"""

from __future__ import annotations

import base64
import datetime as _dt
import html
import io
import math
import re
from dataclasses import dataclass, fields, is_dataclass
from pathlib import Path
from typing import Any, Iterable, Sequence, Union

import numpy as np

from ._version import __version__
from .atomic import write_text_atomic
from .plotting import plot_bounds, plot_folder, plot_pem_vs_mc, plot_psd_map, plot_time_history, select_channels
from .plotting.data import band_text, crossing_times, mc_label
from .results import RandomResponse, TimeHistory, find_results
from .scenario import Car15, Scenario

Result = Union[RandomResponse, TimeHistory]
esc = html.escape


# ============================================================================================ limits
@dataclass(frozen=True)
class CodeLimit:
    """A limit on the magnitude of a channel (same unit as the channel)."""

    criterion: str
    value: float
    unit: str
    source: str
    note: str = ""


DECK_NOTE = ("ballasted track assumed (direct-fastened track: 5.0 m/s^2); the code checks frequencies up to "
             "max(30 Hz, 1.5 f1, f3); girder axis (torsion times track eccentricity not included)")


def static_axle_load(scenario: Scenario, car: int) -> float | None:
    """Static axle load P_st [N] of car number ``car`` (1-based): its weight shared by its four axles
    (15-DOF cars are symmetric); None for other vehicle kinds."""
    v = scenario.train.vehicles[car - 1]
    if not isinstance(v, Car15):
        return None
    return (v.body.mass + 2 * v.bogie.mass + 4 * v.wheelset.mass) * scenario.analysis.gravity / 4


def code_limit(channel: str, scenario: Scenario | None) -> CodeLimit | None:
    """The code limit that applies to a channel, or None."""
    if re.fullmatch(r"bridge\.span\d+\.\w+\.acc_z", channel):
        return CodeLimit("deck vertical acceleration", 3.5, "m/s^2", "EN 1990 Annex A2, A2.4.4.2.1", DECK_NOTE)
    if re.fullmatch(r"car\d+\.body\.acc_z", channel):
        return CodeLimit("car body vertical acceleration", 1.3, "m/s^2", "TB 10621")
    if re.fullmatch(r"car\d+\.body\.acc_y", channel):
        return CodeLimit("car body lateral acceleration", 1.0, "m/s^2", "TB 10621")
    m = re.fullmatch(r"car(\d+)\.axle\d+\.force_y", channel)
    if m and scenario is not None and int(m.group(1)) <= len(scenario.train.vehicles):
        p_st = static_axle_load(scenario, int(m.group(1)))
        if p_st is not None:
            h = 0.85 * (10.0 + p_st / 1e3 / 3.0) * 1e3
            return CodeLimit("lateral wheelset force H", h, "N", "Prud'homme type limit",
                             f"H <= 0.85 (10 + P_st/3) kN, P_st = {p_st / 1e3:.4g} kN static axle load")
    return None


@dataclass(frozen=True)
class SummaryRow:
    channel: str
    unit: str
    max_abs_mean: float  # a single run: max |value|
    max_sigma: float     # nan for a single run
    peak: float          # max |mean| + k sigma, or max |value|
    limit: CodeLimit | None

    @property
    def margin(self) -> float:
        return math.nan if self.limit is None else self.limit.value - self.peak

    @property
    def status(self) -> str:
        return "" if self.limit is None else ("OK" if self.peak <= self.limit.value else "EXCEEDS")


def summary(result: Result, k: float = 3.0) -> list[SummaryRow]:
    """Per channel: max |mean|, max sigma, max |mean| + k sigma and the code limit with its margin."""
    if isinstance(result, RandomResponse):
        return [SummaryRow(c, u, m, s, p, code_limit(c, result.scenario)) for c, u, m, s, p in result.summary_rows(k)]
    out = []
    for c in result.names:
        peak = float(np.max(np.abs(result[c])))
        out.append(SummaryRow(c, result.unit(c), peak, math.nan, peak, code_limit(c, result.scenario)))
    return out


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
    c = crossing_times(sc)
    derived = [
        ("speed", f"{sc.speed:.6g}", "m/s", "train speed"),
        ("train length", f"{sc.train.length:.6g}", "m", "first to last axle"),
        ("bridge length", f"{sc.bridge.length:.6g}", "m", "sum of spans"),
        ("duration", f"{sc.duration:.6g}", "s", "first axle at -lead_in until the last axle is run_out past the bridge"),
    ] + [(label, f"{t:.6g}", "s", "time t of the event (t = 0: first axle at -lead_in)") for _, label, t in c.marks()]
    sections.append(("scenario-derived", "Derived quantities", head, derived))
    sources = [("scenario", sc.name, sc.source, sc.notes), ("bridge", sc.bridge.name, sc.bridge.source, sc.bridge.notes)]
    sources += [("vehicle", v.name, v.source, v.notes) for v in {v.name: v for v in sc.train.vehicles}.values()]
    sections.append(("scenario-sources", "Sources and notes", ["part", "name", "source", "notes"], sources))
    return sections


# ============================================================================================ HTML
STYLE = """
body{font-family:system-ui,sans-serif;max-width:70rem;margin:1rem auto;padding:0 1rem;color:#222}
table{border-collapse:collapse;margin:.5rem 0 1.2rem;font-size:.85rem}
th,td{border:1px solid #ccc;padding:.2rem .5rem;text-align:left;vertical-align:top}
th{background:#f0f0f0} td.num{text-align:right;font-variant-numeric:tabular-nums}
.exceeds{color:#b00;font-weight:bold} .ok{color:#070} .check{color:#a60}
figure{margin:1rem 0} img{max-width:100%} figcaption{font-size:.85rem;color:#555}
"""


def _table(tid: str, header: Sequence[str], rows: Iterable[Sequence[Any]], classes: Sequence[str] = ()) -> str:
    out = [f'<table id="{esc(tid)}"><thead><tr>' + "".join(f"<th>{esc(h)}</th>" for h in header) + "</tr></thead><tbody>"]
    for row in rows:
        cells = []
        for i, cell in enumerate(row):
            cls = classes[i] if i < len(classes) else ""
            cells.append(f'<td class="{cls}">' if cls else "<td>")
            cells.append((cell.html if isinstance(cell, _Raw) else esc(str(cell))) + "</td>")
        out.append("<tr>" + "".join(cells) + "</tr>")
    return "".join(out) + "</tbody></table>"


@dataclass(frozen=True)
class _Raw:
    """Already escaped HTML for a table cell."""

    html: str


def _num(x: float) -> str:
    return "" if x is None or (isinstance(x, float) and math.isnan(x)) else f"{x:.4g}"


def _summary_table(tid: str, result: Result, k: float) -> str:
    rows = []
    for r in summary(result, k):
        lim = r.limit
        limit_cell = _Raw("") if lim is None else _Raw(
            f'{esc(_num(lim.value))} <span class="check">[check]</span><br><small>{esc(lim.criterion)}, '
            f"{esc(lim.source)}{'; ' + esc(lim.note) if lim.note else ''}</small>")
        status = _Raw("") if lim is None else _Raw(f'<span class="{r.status.lower()}">{esc(r.status)}</span>')
        if isinstance(result, RandomResponse):
            rows.append((r.channel, r.unit, _num(r.max_abs_mean), _num(r.max_sigma), _num(r.peak), limit_cell,
                         _num(r.margin), status))
        else:
            rows.append((r.channel, r.unit, _num(r.peak), limit_cell, _num(r.margin), status))
    if isinstance(result, RandomResponse):
        head = ["channel", "unit", "max |mean|", "max sigma", f"max |mean| + {k:g} sigma", "limit", "margin", "status"]
        classes = ("", "", "num", "num", "num", "", "num", "")
    else:
        head = ["channel", "unit", "max |value|", "limit", "margin", "status"]
        classes = ("", "", "num", "", "num", "")
    return _table(tid, head, rows, classes)


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


def _png(fig, dpi: int = 80) -> str:
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=dpi)
    return base64.b64encode(buf.getvalue()).decode("ascii")


def _figure_html(fig, caption: str) -> str:
    return (f'<figure><img alt="{esc(caption)}" src="data:image/png;base64,{_png(fig)}">'
            f"<figcaption>{esc(caption)}</figcaption></figure>")


def _result_name(path: Path, result: Result) -> str:
    kind = result.method if isinstance(result, RandomResponse) else "time history"
    return f"{path.name} ({kind})"


def render_report(found: Sequence[tuple[Path, Result]], k: float = 3.0,
                  channels: str | Sequence[str] | None = None, title: str | None = None) -> str:
    """The HTML text of a report on ``found`` results (see :func:`write_report`)."""


    scenarios = [r.scenario for _, r in found if r.scenario is not None]
    sc = scenarios[0] if scenarios else None
    title = title or f"tb_exudyn report: {sc.name if sc else found[0][0].name}"
    now = _dt.datetime.now(_dt.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    body = [f"<h1>{esc(title)}</h1>",
            f"<p>Generated {esc(now)} by tb_exudyn {esc(__version__)} from "
            + ", ".join(f"<code>{esc(str(p))}</code>" for p, _ in found) + ".</p>",
            f"<p>{esc(sc.description if sc else '')}</p>",
            '<nav><a href="#summary">Summary</a> | <a href="#figures">Figures</a> | '
            '<a href="#scenario">Scenario</a> | <a href="#provenance">Provenance</a></nav>']

    body.append('<section id="summary"><h2>Summary</h2>')
    body.append(
        "<p>Random responses: mean, sigma over the stated band (one-sided PSD per Hz), and the "
        f"{k:g}-sigma estimate max |mean| + {k:g} sigma (a crude bound for Gaussian responses). Single runs: "
        "max |value|. Limits <span class=\"check\">[check]</span>: deck vertical acceleration 3.5 m/s^2 "
        "(EN 1990 Annex A2; ballasted track taken as default, direct-fastened 5.0 m/s^2); car body vertical "
        "1.3 and lateral 1.0 m/s^2 (TB 10621); lateral wheelset force H &lt;= 0.85 (10 + P_st/3) kN. All are "
        "to be checked against the code text before use. Margin = limit - estimate. Not evaluated here: "
        "derailment coefficient Q/P, wheel load reduction dP/P, Sperling index.</p>")
    for path, result in found:
        what = _result_name(path, result)
        if isinstance(result, RandomResponse):
            what += f", sigma over {band_text(result)}"
            if result.n_samples:
                what += f", {result.n_samples} samples"
        body.append(f"<h3>{esc(what)}</h3>" + _summary_table(f"summary-{path.name}", result, k))
    body.append("</section>")

    body.append('<section id="figures"><h2>Figures</h2>')
    for path, result in found:
        body.append(f"<h3>{esc(_result_name(path, result))}</h3>")
        names = select_channels(result, channels)
        if isinstance(result, RandomResponse):
            for ch in names:
                fig = plot_bounds(result, ch, k=k, samples=True if result.samples is not None else None)
                body.append(_figure_html(fig, f"{ch}: mean and mean +- {k:g} sigma ({mc_label(result)})"))
                if result.psd is not None:
                    body.append(_figure_html(plot_psd_map(result, ch), f"{ch}: time-dependent one-sided PSD"))
        else:
            body.append(_figure_html(plot_time_history(result, names), "deterministic histories"))
    pems = [r for _, r in found if isinstance(r, RandomResponse) and r.method == "pem"]
    mcs = [r for _, r in found if isinstance(r, RandomResponse) and r.method.startswith("monte_carlo")]
    if pems and mcs:
        body.append("<h3>PEM against Monte Carlo</h3>")
        for ch in select_channels(pems[0], channels):
            if all(ch in m.channels for m in mcs):
                body.append(_figure_html(plot_pem_vs_mc(pems[0], mcs, ch), f"{ch}: PEM against Monte Carlo"))
    body.append("</section>")

    body.append('<section id="scenario"><h2>Scenario</h2>')
    if sc is None:
        body.append("<p>The results do not record their scenario.</p>")
    else:
        body.append(f"<p><b>{esc(sc.name)}</b>: {esc(sc.description)}</p>")
        others = sorted({s.name for s in scenarios if s != sc})
        if others:
            body.append(f"<p class=\"exceeds\">Some results were computed for other scenarios: {esc(', '.join(others))}"
                        " (only the first is tabulated).</p>")
        for tid, heading, head, rows in scenario_sections(sc):
            body.append(f"<h3>{esc(heading)}</h3>" + _table(tid, head, rows))
    body.append("</section>")

    body.append('<section id="provenance"><h2>Provenance</h2>')
    for path, result in found:
        rows = _flatten(result.provenance)
        if result.scenario is not None:
            rows.insert(0, ("scenario seed (analysis.seed)", str(result.scenario.analysis.seed)))
        body.append(f"<h3>{esc(_result_name(path, result))}</h3>"
                    + _table(f"provenance-{path.name}", ["key", "value"], rows))
    body.append("</section>")
    return ("<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
            f"<title>{esc(title)}</title><style>{STYLE}</style></head><body>\n" + "\n".join(body) + "\n</body></html>\n")


def write_report(folder: str | Path, out_html: str | Path | None = None, *, k: float = 3.0,
                 channels: str | Sequence[str] | None = None) -> Path:
    """Write one self-contained HTML page on the results in ``folder`` (one result folder, or a
    folder of result folders) to ``out_html`` (default ``<folder>/report.html``), atomically.

    ``channels``: names or glob patterns of the channels to draw (default: the key channels); the
    summary lists every channel.
    """
    folder = Path(folder)
    text = render_report(find_results(folder), k=k, channels=channels)
    out = Path(out_html) if out_html is not None else folder / "report.html"
    write_text_atomic(out, text)
    return out


__all__ = ["CodeLimit", "plot_folder", "SummaryRow", "code_limit", "find_results", "render_report", "scenario_sections",
           "static_axle_load", "summary", "write_report"]
