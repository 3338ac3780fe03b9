"""A self-contained HTML report of saved results, read top-down by an engineer.

Sections, in order: the verdicts (:class:`CheckEntry` rows, from the checks of a result) and the
warnings (each result's provenance ``warnings``); for a scenario that reproduces a study, the
study's stated findings beside ours (data: ``models/studies/*.toml``, :func:`load_study`); the
figures, each next to the numbers it explains, grouped by bridge / car / wheelsets; the full
channel table, grouped the same way, collapsible and filterable; the modes (:class:`ModeEntry`
rows); the scenario; the provenance.

Inputs that other layers compute arrive as documented data objects; a section whose input is
absent says "not computed":

- ``checks``: a sequence of :class:`CheckEntry` (or objects with the same attribute names, e.g. the
  rows of ``result.checks()``), one per criterion and location;
- ``modes``: a sequence of :class:`ModeEntry` (or objects with the same attribute names), the
  damped modes of the linearised system.

One page, no external resources: figures are embedded as base64 PNG, the style and the few lines
of script (the channel filter; the page reads the same without it) are inline, and every piece of
text is escaped. Values are shown in engineering units (:func:`tb_exudyn.plotting.data.display_unit`).
Until the checks exist, the verdict section shows a screening of max |mean| + 3 sigma against the
limits of :func:`code_limit` (all [check]), clearly labelled as not being a verdict.
matplotlib is imported only when figures are drawn (through :mod:`tb_exudyn.plotting`).
"""

from __future__ import annotations

import base64
import datetime as _dt
import html
import math
import re
from dataclasses import MISSING, dataclass, fields, is_dataclass
from pathlib import Path
from typing import Any, Iterable, Literal, Sequence, Union

import numpy as np

from ._version import __version__
from .atomic import write_text_atomic
from .plotting import data as pdata
from .plotting.data import channel_group, channel_label, crossing_times, display_unit, format_number
from .results import RandomResponse, TimeHistory, find_results
from .scenario import Car15, Scenario
from .scenario.errors import ScenarioError
from .scenario.schema import Context, Validated, from_dict, param

Result = Union[RandomResponse, TimeHistory]
esc = html.escape


# ============================================================================================ inputs
@dataclass(frozen=True)
class CheckEntry:
    """One row of the verdicts table: a criterion checked at one location.

    The checks of a result (issue 16, ``result.checks()``) provide these attributes; any object
    with them is accepted (:func:`as_check_entries`). ``estimate`` and ``limit`` are in ``unit``
    (SI; shown in its display unit). ``verdict`` is a word ("OK", "EXCEEDS", "NOT APPLICABLE", ...);
    ``probability`` the probability that the limit is exceeded at least once per passage (NaN: not
    computed); ``caveats`` the warnings that apply to this row (a lightly damped mode, a grid error,
    a quantity the linear model cannot represent); ``channel`` the channel it comes from (links the
    row to its figures)."""

    criterion: str
    location: str
    estimate: float
    limit: float
    unit: str
    verdict: str
    probability: float = math.nan
    clause: str = ""
    caveats: tuple[str, ...] = ()
    channel: str = ""


@dataclass(frozen=True)
class ModeEntry:
    """One damped mode of the linearised system: ``frequency`` [Hz], ``damping_ratio`` [1], a
    ``label`` saying what moves ("car 2, leading bogie, yaw"), the ``context`` it was computed in
    ("vehicles on rigid track", "coupled, train at t = 3.3 s") and a ``warning`` ("" or e.g.
    "lightly damped: decay time longer than the run"). Any object with these attributes is accepted."""

    frequency: float
    damping_ratio: float
    label: str
    context: str = ""
    warning: str = ""


def _entries(rows: Iterable[Any] | None, cls: type) -> list | None:
    if rows is None:
        return None
    out = []
    required = [f.name for f in fields(cls) if f.default is MISSING and f.default_factory is MISSING]
    for i, row in enumerate(rows):
        if isinstance(row, cls):
            out.append(row)
            continue
        missing = [n for n in required if not hasattr(row, n)]
        if missing:
            raise TypeError(f"{cls.__name__} row {i}: {type(row).__name__} has no attribute {missing[0]!r} "
                            f"(needs {', '.join(required)})")
        values = {f.name: getattr(row, f.name) for f in fields(cls) if hasattr(row, f.name)}
        if "caveats" in values:
            values["caveats"] = tuple(values["caveats"] or ())
        out.append(cls(**values))
    return out


def as_check_entries(rows: Iterable[Any] | None) -> list[CheckEntry] | None:
    """The verdict rows as :class:`CheckEntry` (None stays None: "not computed")."""
    return _entries(rows, CheckEntry)


def as_mode_entries(rows: Iterable[Any] | None) -> list[ModeEntry] | None:
    """The modes as :class:`ModeEntry` (None stays None: "not computed")."""
    return _entries(rows, ModeEntry)


# ============================================================================================ screening limits
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
    """The screening limit that applies to a channel, or None (interim: the verdicts of the checks
    replace this screening; their limits are data in models/limits)."""
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
    """Per channel: max |mean|, max sigma, max |mean| + k sigma and the screening limit with its margin."""
    if isinstance(result, RandomResponse):
        return [SummaryRow(c, u, m, s, p, code_limit(c, result.scenario)) for c, u, m, s, p in result.summary_rows(k)]
    out = []
    for c in result.names:
        peak = float(np.max(np.abs(result[c])))
        out.append(SummaryRow(c, result.unit(c), peak, math.nan, peak, code_limit(c, result.scenario)))
    return out


@dataclass(frozen=True)
class ScreeningRow:
    """Per screening criterion: the location with the smallest margin, and how many exceed."""

    criterion: str
    worst: SummaryRow
    n_locations: int
    n_exceeding: int


def screening(result: Result, k: float = 3.0) -> list[ScreeningRow]:
    """The interim screening: per criterion of :func:`code_limit`, the worst location."""
    by: dict[str, list[SummaryRow]] = {}
    for r in summary(result, k):
        if r.limit is not None:
            by.setdefault(r.limit.criterion, []).append(r)
    return [ScreeningRow(c, min(rows, key=lambda r: r.margin / r.limit.value), len(rows),
                         sum(r.status == "EXCEEDS" for r in rows)) for c, rows in by.items()]


# ============================================================================================ study findings
Measure = Literal["psd_peak_frequency", "psd_band_99", "sigma_to_mean_ratio", "band_across_zero_share"]
MEASURES: dict[str, tuple[str, str]] = {  # measure -> (unit, description)
    "psd_peak_frequency": ("Hz", "frequency of the PSD map's peak"),
    "psd_band_99": ("Hz", "band holding 99 % of sigma^2 at max sigma"),
    "sigma_to_mean_ratio": ("", "3 max sigma / max |mean|"),
    "band_across_zero_share": ("", "share of the crossing with the 3-sigma band across zero"),
}


@dataclass(frozen=True, kw_only=True)
class StudyQuantity(Validated):
    """A quantity a finding is read by: what the study says and how we judge agreement."""

    channel: str = param(doc="the channel (tb_exudyn naming)")
    measure: Measure = param(doc="how the quantity is computed from a result (see MEASURES)")
    study: float = param(math.nan, doc="the value the study states, in the measure's unit (nan: none)")
    study_range: tuple[float, ...] = param((), doc="the range the study states [low, high]")
    study_text: str = param("", doc="the study's words, for a qualitative statement")
    tolerance: float = param(math.nan, doc="agreement if |ours - study| <= tolerance (nan: no such rule)")
    agree_below: float = param(math.nan, doc="agreement if ours < agree_below")
    agree_above: float = param(math.nan, doc="agreement if ours > agree_above")
    basis: str = param("", doc="where the agreement rule comes from ([check]: our reading)")

    def _validate(self, ctx: Context) -> None:
        if self.study_range and len(self.study_range) != 2:
            raise ctx.child("study_range").error(list(self.study_range), "[low, high]", "not two numbers")
        rules = [n for n in ("tolerance", "agree_below", "agree_above") if not math.isnan(getattr(self, n))]
        if len(rules) > 1:
            raise ctx.child(rules[1]).error(getattr(self, rules[1]), f"at most one rule (already {rules[0]})",
                                            "two agreement rules")
        if "tolerance" in rules and math.isnan(self.study):
            raise ctx.child("study").error("<missing>", "a number (tolerance needs the study's value)", "missing key")


@dataclass(frozen=True, kw_only=True)
class StudyFinding(Validated):
    """One finding the study states, with the quantities it is read by."""

    id: str = param(doc="short name (conclusion or figure)")
    claim: str = param(doc="the study's statement")
    where: str = param("", doc="section or figure of the study")
    quantities: tuple[StudyQuantity, ...] = param((), doc="the quantities compared")


@dataclass(frozen=True, kw_only=True)
class Study(Validated):
    """A published study a scenario reproduces, with its stated findings (models/studies/NAME.toml)."""

    name: str = param(doc="identifier")
    title: str = param(doc="author and title")
    source: str = param("", doc="citation")
    scenarios: tuple[str, ...] = param((), doc="the scenarios that reproduce it")
    findings: tuple[StudyFinding, ...] = param((), doc="the stated findings")


def studies_dir() -> Path:
    """models/studies (beside vehicles/, bridges/, scenarios/)."""
    from .scenario.registry import models_dir

    return models_dir() / "studies"


def load_study(path: str | Path) -> Study:
    """Read a study file; a bad file gets a one-line ScenarioError naming the file and the key."""
    from .scenario.toml_io import read_toml

    path = Path(path)
    return from_dict(Study, read_toml(path), Context(str(path)))


def studies_for(scenario: Scenario | None) -> list[Study]:
    """The studies whose ``scenarios`` list the scenario's name."""
    if scenario is None:
        return []
    folder = studies_dir()
    files = sorted(folder.glob("*.toml")) if folder.is_dir() else []
    return [s for s in map(load_study, files) if scenario.name in s.scenarios]


@dataclass(frozen=True)
class FindingRow:
    """A study quantity beside ours: ``ours`` (a value, or (low, high) for a band), the agreement
    ("matched", "not matched", "" without a rule, or why it could not be computed)."""

    finding: StudyFinding
    quantity: StudyQuantity
    ours: float | tuple[float, float] | None
    agreement: str


def measure(resp: RandomResponse, q: StudyQuantity) -> float | tuple[float, float]:
    """Our value of a study quantity (:data:`MEASURES`)."""
    if q.measure == "psd_peak_frequency":
        return pdata.psd_peak(resp, q.channel)[0]
    if q.measure == "psd_band_99":
        return pdata.psd_band(resp, q.channel, 0.99)
    if q.measure == "sigma_to_mean_ratio":
        return pdata.sigma_to_mean_ratio(resp, q.channel, 3.0)
    return pdata.band_across_zero_share(resp, q.channel, 3.0)


def compare_findings(study: Study, resp: RandomResponse) -> list[FindingRow]:
    """Every quantity of the study's findings beside ours."""
    rows = []
    for f in study.findings:
        for q in f.quantities:
            if q.channel not in resp.channels:
                rows.append(FindingRow(f, q, None, "channel not in this result"))
                continue
            try:
                ours = measure(resp, q)
            except ValueError as exc:  # no PSD map of this channel
                rows.append(FindingRow(f, q, None, str(exc).split(" (")[0]))
                continue
            agreement = ""
            if isinstance(ours, float):
                if not math.isnan(q.tolerance):
                    # to within rounding: a peak exactly `tolerance` away (a whole number of grid cells) matches
                    agreement = "matched" if abs(ours - q.study) <= q.tolerance * (1 + 1e-9) else "not matched"
                elif not math.isnan(q.agree_below):
                    agreement = "matched" if ours < q.agree_below else "not matched"
                elif not math.isnan(q.agree_above):
                    agreement = "matched" if ours > q.agree_above else "not matched"
            rows.append(FindingRow(f, q, ours, agreement))
    return rows


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
body{font-family:system-ui,sans-serif;max-width:76rem;margin:.6rem auto;padding:0 1rem;color:#222;line-height:1.35}
h1{font-size:1.45rem;margin:.2rem 0} h2{font-size:1.2rem;margin:1.2rem 0 .4rem;border-bottom:1px solid #ddd}
h3{font-size:1.05rem;margin:.9rem 0 .3rem} h4{font-size:.95rem;margin:.8rem 0 .2rem}
p.meta{margin:.1rem 0;color:#555;font-size:.85rem} nav{font-size:.85rem;margin:.2rem 0 .4rem}
table{border-collapse:collapse;margin:.3rem 0 .8rem;font-size:.82rem}
th,td{border:1px solid #ccc;padding:.15rem .45rem;text-align:left;vertical-align:top}
th{background:#f0f0f0} td.num{text-align:right;font-variant-numeric:tabular-nums;white-space:nowrap}
.exceeds,.not-matched{color:#b00;font-weight:bold} .ok,.matched{color:#070;font-weight:bold} .check{color:#a60}
.placeholder{background:#fff8e0;border:1px solid #e6c200;padding:.3rem .6rem;margin:.3rem 0;font-size:.88rem}
.warn{background:#fdeaea;border-left:4px solid #b00;padding:.2rem .6rem;margin:.2rem 0;font-size:.88rem}
.figs{display:grid;grid-template-columns:repeat(auto-fill,minmax(34rem,1fr));gap:.4rem}
figure{margin:0} img{max-width:100%;height:auto} figcaption{font-size:.78rem;color:#555}
p.nums{font-size:.85rem;margin:.1rem 0 .3rem} code{font-size:.85em} small{color:#555}
details{margin:.2rem 0} summary{cursor:pointer;font-weight:600}
"""

#: the channel filter: an input box, made by the script (without it the page reads the same)
FILTER_SCRIPT = """
(function(){var box=document.getElementById('channel-filter');if(!box)return;
var input=document.createElement('input');input.type='search';input.size=40;
input.placeholder='filter channels: words, e.g. car2 lateral';box.appendChild(input);
input.addEventListener('input',function(){var words=input.value.toLowerCase().split(/\\s+/).filter(Boolean);
document.querySelectorAll('#channels details.group').forEach(function(d){var n=0;
d.querySelectorAll('tbody tr').forEach(function(tr){var t=tr.textContent.toLowerCase();
var ok=words.every(function(w){return t.indexOf(w)>=0;});tr.hidden=!ok;if(ok)n++;});
d.hidden=n===0;d.open=words.length>0&&n>0;});});})();
"""


@dataclass(frozen=True)
class _Raw:
    """Already escaped HTML for a table cell."""

    html: str


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


def _shown(value: float, si_unit: str) -> str:
    """A value in its display unit (number only)."""
    return format_number(value * display_unit(si_unit).factor)


def _with_unit(value: float, si_unit: str) -> str:
    du = display_unit(si_unit)
    text = format_number(value * du.factor)
    return f"{text} {du.unit}".strip() if text else ""


def _verdict_class(word: str) -> str:
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


def _result_name(path: Path, result: Result) -> str:
    kind = result.method if isinstance(result, RandomResponse) else "time history"
    return f"{path.name} ({kind})"


def _anchor(prefix: str, name: str) -> str:
    return f"{prefix}-{name}"


def _link(target: str, text: str) -> str:
    return f'<a href="#{esc(target)}">{esc(text)}</a>'


# ============================================================================================ sections
def verdicts_section(checks: Sequence[CheckEntry] | None, first: Result | None, k: float,
                     figure_ids: set[str], max_rows: int = 12) -> str:
    """The verdicts: the checks table (exceeding rows first; beyond ``max_rows`` the rest folded),
    or "not computed" with the interim screening."""
    out = ['<section id="verdicts"><h2>Verdicts</h2>']
    if checks is None:
        out.append('<p class="placeholder"><b>Verdicts: not computed.</b> The code checks (exceedance '
                   "probabilities of the limits in models/limits) were not given to this report. Below: a "
                   f"screening of max |mean| + {k:g} sigma against the interim limits, all "
                   '<span class="check">[check]</span>, which is not a verdict (a Gaussian response exceeds '
                   f"its {k:g}-sigma level in a sizeable share of passages).</p>")
        if first is not None:
            rows = []
            for s in screening(first, k):
                w = s.worst
                ch = w.channel
                where = _link(_anchor("fig", ch), channel_label(ch)) if _anchor("fig", ch) in figure_ids else esc(channel_label(ch))
                rows.append((s.criterion, _Raw(f"{where}<br><small><code>{esc(ch)}</code></small>"),
                             _with_unit(w.peak, w.unit), _Raw(f'{esc(_with_unit(w.limit.value, w.unit))} '
                                                              f'<span class="check">[check]</span>'),
                             _Raw(f'<span class="{_verdict_class(w.status)}">{esc(w.status)}</span>'),
                             f"{s.n_exceeding} of {s.n_locations}", _Raw(f"<small>{esc(w.limit.source)}"
                                                                         f"{'; ' + esc(w.limit.note) if w.limit.note else ''}</small>")))
            head = ["criterion", "worst location", f"max |mean| + {k:g} sigma", "limit", "screening",
                    "locations exceeding", "source"]
            out.append(_table("verdicts-table", head, rows, ("", "", "num", "num", "", "num", "")) if rows
                       else '<p id="verdicts-table">No channel of this result has a screening limit.</p>')
        out.append("</section>")
        return "\n".join(out)
    order = sorted(range(len(checks)), key=lambda i: (checks[i].verdict.upper() == "OK", i))
    rows = []
    for i in order:
        c = checks[i]
        where = esc(c.location)
        if c.channel and _anchor("fig", c.channel) in figure_ids:
            where = _link(_anchor("fig", c.channel), c.location)
        caveats = "".join(f"<li>{esc(x)}</li>" for x in c.caveats)
        rows.append((c.criterion, _Raw(where), _with_unit(c.estimate, c.unit), _with_unit(c.limit, c.unit),
                     "" if math.isnan(c.probability) else f"{c.probability:.3g}",
                     _Raw(f'<span class="{_verdict_class(c.verdict)}">{esc(c.verdict)}</span>'),
                     _Raw(f"<ul>{caveats}</ul>" if caveats else ""), _Raw(f"<small>{esc(c.clause)}</small>")))
    head = ["criterion", "location", "estimate", "limit", "P(exceed) per passage", "verdict", "caveats", "clause"]
    classes = ("", "", "num", "num", "num", "", "", "")
    out.append(_table("verdicts-table", head, rows[:max_rows], classes))
    if len(rows) > max_rows:
        out.append(f"<details><summary>{len(rows) - max_rows} more checks</summary>"
                   + _table("verdicts-more", head, rows[max_rows:], classes) + "</details>")
    out.append("</section>")
    return "\n".join(out)


def warnings_section(found: Sequence[tuple[Path, Result]], extra: Sequence[str] = ()) -> str:
    """Every result's provenance ``warnings`` (and the report's own), or "none recorded"."""
    items = [(None, w) for w in extra]
    for path, result in found:
        items += [(_result_name(path, result), str(w)) for w in (result.provenance.get("warnings") or [])]
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
            where = _link(_anchor("fig", ch), channel_label(ch)) if _anchor("fig", ch) in figure_ids else esc(channel_label(ch))
            agreement = r.agreement
            cls = _verdict_class(agreement) if agreement in ("matched", "not matched") else ""
            rule = _rule_text(r.quantity)
            claim = (_Raw("") if r.finding is previous else  # the claim once, on its first quantity
                     _Raw(f"<b>{esc(r.finding.id)}</b>: {esc(r.finding.claim)}<br><small>{esc(r.finding.where)}</small>"))
            previous = r.finding
            rows.append((claim,
                         _Raw(f"{where}<br><small><code>{esc(ch)}</code></small>"),
                         MEASURES[r.quantity.measure][1], _study_text(r.quantity), _ours_text(r),
                         _Raw((f'<span class="{cls}">{esc(agreement)}</span>' if cls else esc(agreement))
                              + (f"<br><small>{esc(rule)}: {esc(r.quantity.basis)}</small>" if rule else
                                 f"<small>{esc(r.quantity.basis)}</small>"))))
        head = ["finding (the study)", "channel", "measure", "the study", "ours", "agreement"]
        out.append(_table(f"findings-{study.name}", head, rows, ("", "", "", "num", "num", "")))
    out.append("</section>")
    return "\n".join(out)


def _numbers(result: Result, ch: str, k: float) -> str:
    """The numbers a channel's figures explain, in one line."""
    if isinstance(result, TimeHistory):
        value, t = result.peak(ch)
        return f"max |value| {esc(_with_unit(abs(value), result.unit(ch)))} at t = {t:.3g} s"
    row = result.index(ch)
    unit = result.unit(ch)
    mean, std = result.mean[row], result.std[row]
    j = int(np.argmax(std))
    parts = [f"max |mean| {_with_unit(float(np.max(np.abs(mean))), unit)}",
             f"max sigma {_with_unit(float(std[j]), unit)} at t = {result.time[j]:.3g} s",
             f"max |mean| + {k:g} sigma {_with_unit(float(np.max(np.abs(mean) + k * std)), unit)}"]
    if pdata.has_psd(result, ch):
        f, t = pdata.psd_peak(result, ch)
        lo, hi = pdata.psd_band(result, ch)
        parts.append(f"PSD peak at {format_number(f, 3)} Hz (t = {t:.3g} s); 99 % of sigma^2 at max sigma in "
                     f"{format_number(lo, 3)}-{format_number(hi, 3)} Hz")
    lim = code_limit(ch, result.scenario)
    if lim is not None:
        parts.append(f"screening limit {_with_unit(lim.value, lim.unit)} [check]")
    return esc(" · ".join(parts))


_CAPTIONS = {
    "bounds": "mean and mean +- {k:g} sigma against time",
    "psd_map": "time-dependent one-sided PSD",
    "psd_slices": "PSD at the time of maximum sigma",
    "history": "history of the run",
    "pem_vs_mc": "PEM against Monte Carlo: mean and sigma",
}


def _img(png: bytes, alt: str) -> str:
    return f'<img alt="{esc(alt)}" src="data:image/png;base64,{base64.b64encode(png).decode("ascii")}">'


def figures_section(found: Sequence[tuple[Path, Result]], pictures: dict[tuple[str, str, str], bytes],
                    names: dict[str, list[str]], k: float, comparison: list[str]) -> str:
    """Per result, per channel group (bridge, car k, car k wheelsets): each channel's numbers
    above its figures. ``pictures[(result folder name, channel, kind)]`` = PNG bytes."""
    out = ['<section id="figures"><h2>Figures</h2>']
    many = len(found) > 1
    for path, result in found:
        if many:
            out.append(f"<h3>{esc(_result_name(path, result))}</h3>")
        groups: dict[str, tuple[str, list[str]]] = {}
        for ch in names[path.name]:
            key, heading = channel_group(ch)
            groups.setdefault(key, (heading, []))[1].append(ch)
        for key, (heading, chans) in groups.items():
            out.append(f'<details class="figgroup" open><summary>{esc(heading)} ({len(chans)} channels)</summary>')
            for ch in chans:
                anchor = _anchor("fig", ch) if path.name == found[0][0].name else _anchor(f"fig-{path.name}", ch)
                out.append(f'<section class="channel" id="{esc(anchor)}"><h4>{esc(channel_label(ch))} '
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
                out.append(f'<figure id="{esc(_anchor("cmp", ch))}">{_img(png, cap)}<figcaption>{esc(cap)} '
                           f"<code>{esc(ch)}</code></figcaption></figure>")
        out.append("</div>")
    out.append("</section>")
    return "\n".join(out)


def channels_section(found: Sequence[tuple[Path, Result]], k: float, figure_ids: set[str]) -> str:
    """Every channel of every result, grouped (bridge, car k, car k wheelsets) in collapsed
    <details>, with a filter box (made by the inline script)."""
    out = ['<section id="channels"><h2>All channels</h2>',
           f"<p>Per channel over the run: max |mean|, max sigma and max |mean| + {k:g} sigma (random responses), "
           "or max |value| (one run), in engineering units. Groups open on click; "
           'the box filters by words of the label or name.</p><div id="channel-filter"></div>']
    for path, result in found:
        if len(found) > 1:
            out.append(f"<h3>{esc(_result_name(path, result))}</h3>")
        groups: dict[str, tuple[str, list]] = {}
        if isinstance(result, RandomResponse):
            what = f"sigma over {pdata.band_text(result)}" + (f", {result.n_samples} samples" if result.n_samples else "")
            out.append(f"<p class=\"meta\">{esc(_result_name(path, result))}: {esc(what)}</p>")
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
                target = _anchor("fig", c)
                name_cell = _Raw(_link(target, label)) if target in figure_ids and path.name == found[0][0].name else label
                cells.append((name_cell, _Raw(f"<code>{esc(c)}</code>"), display_unit(u).unit) + values)
            out.append(f'<details class="group"><summary>{esc(heading)} ({len(rows)} channels)</summary>'
                       + _table(f"channels-{path.name}-{key}", head, cells, ("", "", "") + ("num",) * len(head))
                       + "</details>")
    out.append("</section>")
    return "\n".join(out)


def modes_section(modes: Sequence[ModeEntry] | None) -> str:
    """The modal table, or "not computed"."""
    out = ['<section id="modes"><h2>Modes</h2>']
    if modes is None:
        out.append('<p class="placeholder"><b>Modes: not computed.</b> The modal analysis of the linearised '
                   "train-bridge system was not given to this report.</p>")
    elif not modes:
        out.append("<p>No modes in the analysed band.</p>")
    else:
        rows = [(format_number(m.frequency, 4), f"{m.damping_ratio:.3g}", m.label, m.context,
                 _Raw(f'<span class="exceeds">{esc(m.warning)}</span>' if m.warning else ""))
                for m in sorted(modes, key=lambda m: m.frequency)]
        out.append(_table("modes-table", ["frequency [Hz]", "damping ratio", "what moves", "computed for", "warning"],
                          rows, ("num", "num", "", "", "")))
    out.append("</section>")
    return "\n".join(out)


def scenario_section(scenarios: Sequence[Scenario]) -> str:
    out = ['<section id="scenario"><h2>Scenario</h2>']
    if not scenarios:
        out.append("<p>The results do not record their scenario.</p></section>")
        return "\n".join(out)
    sc = scenarios[0]
    out.append(f"<p><b>{esc(sc.name)}</b>: {esc(sc.description)}</p>")
    others = sorted({s.name for s in scenarios if s != sc})
    if others:
        out.append(f'<p class="warn">Some results were computed for other scenarios: {esc(", ".join(others))}'
                   " (only the first is tabulated).</p>")
    for tid, heading, head, rows in scenario_sections(sc):
        out.append(f"<details><summary>{esc(heading)}</summary>" + _table(tid, head, rows) + "</details>")
    out.append("</section>")
    return "\n".join(out)


def provenance_section(found: Sequence[tuple[Path, Result]]) -> str:
    out = ['<section id="provenance"><h2>Provenance</h2>']
    for path, result in found:
        rows = _flatten(result.provenance)
        if result.scenario is not None:
            rows.insert(0, ("scenario seed (analysis.seed)", str(result.scenario.analysis.seed)))
        out.append(f"<details><summary>{esc(_result_name(path, result))}</summary>"
                   + _table(f"provenance-{path.name}", ["key", "value"], rows) + "</details>")
    out.append("</section>")
    return "\n".join(out)


# ============================================================================================ page
def ordered(found: Sequence[tuple[Path, Result]]) -> list[tuple[Path, Result]]:
    """The results in reading order: PEM first, then Monte Carlo, then single runs (stable)."""
    def rank(item):
        r = item[1]
        return 0 if isinstance(r, RandomResponse) and r.method == "pem" else 1 if isinstance(r, RandomResponse) else 2
    return sorted(found, key=rank)


def _first_random(found: Sequence[tuple[Path, Result]]) -> Result | None:
    for _, r in found:
        if isinstance(r, RandomResponse) and r.method == "pem":
            return r
    return found[0][1] if found else None


def render_report(found: Sequence[tuple[Path, Result]], k: float = 3.0,
                  channels: str | Sequence[str] | None = None, title: str | None = None, *,
                  checks: Iterable[Any] | None = None, modes: Iterable[Any] | None = None,
                  pictures: dict[tuple[str, str, str], bytes] | None = None,
                  names: dict[str, list[str]] | None = None, comparison: Sequence[str] = (),
                  warnings: Sequence[str] = ()) -> str:
    """The HTML text of a report on ``found`` results (see :func:`write_report`).

    ``pictures``: PNG bytes by (result folder name, channel, kind) ("" as folder for pem_vs_mc);
    ``names``: the channels with figures per result folder name (default: ``channels`` selected);
    ``comparison``: channels with a PEM against Monte Carlo figure; ``warnings``: the report's own.
    """
    found = ordered(found)
    check_rows = as_check_entries(checks)
    mode_rows = as_mode_entries(modes)
    pictures = pictures or {}
    if names is None:
        names = {p.name: pdata.select_channels(r, channels) for p, r in found}
    figure_ids = {_anchor("fig", ch) for ch in names.get(found[0][0].name, [])} if found else set()
    scenarios = [r.scenario for _, r in found if r.scenario is not None]
    sc = scenarios[0] if scenarios else None
    first = _first_random(found)
    title = title or f"tb_exudyn report: {sc.name if sc else found[0][0].name}"
    now = _dt.datetime.now(_dt.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    what = []
    for path, r in found:
        w = _result_name(path, r)
        if isinstance(r, RandomResponse):
            w += f", sigma over {pdata.band_text(r)}" + (f", {r.n_samples} samples" if r.n_samples else
                                                         f", {len(r.freq)} frequencies")
        what.append(w)
    pem = next((r for _, r in found if isinstance(r, RandomResponse) and r.method == "pem" and r.psd is not None), None)
    studies = studies_for(sc)
    nav = [("verdicts", "Verdicts"), ("warnings", "Warnings")] + ([("findings", "Study findings")] if studies else []) + [
        ("figures", "Figures"), ("channels", "All channels"), ("modes", "Modes"), ("scenario", "Scenario"),
        ("provenance", "Provenance")]
    body = [f"<h1>{esc(title)}</h1>",
            f'<p class="meta">{esc(sc.description if sc else "")}</p>',
            f'<p class="meta">{esc("; ".join(what))}. Generated {esc(now)} by tb_exudyn {esc(__version__)}.</p>',
            "<nav>" + " | ".join(_link(a, t) for a, t in nav) + "</nav>",
            verdicts_section(check_rows, first, k, figure_ids),
            warnings_section(found, warnings),
            findings_section(studies, pem, figure_ids),
            figures_section(found, pictures, names, k, list(comparison)),
            channels_section(found, k, figure_ids),
            modes_section(mode_rows),
            scenario_section(scenarios),
            provenance_section(found)]
    return ("<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
            f"<meta name=\"viewport\" content=\"width=device-width\"><title>{esc(title)}</title>"
            f"<style>{STYLE}</style></head><body>\n" + "\n".join(b for b in body if b)
            + f"\n<script>{FILTER_SCRIPT}</script>\n</body></html>\n")


def _fresh(png: Path, newest_input: float) -> bool:
    try:
        return png.stat().st_mtime >= newest_input
    except OSError:
        return False


def report_pictures(folder: Path, found: Sequence[tuple[Path, Result]], channels, *, workers: int | None = None,
                    progress: bool = False) -> tuple[dict[tuple[str, str, str], bytes], dict[str, list[str]], list[str]]:
    """The report's figures as PNG bytes: the files ``plot_folder`` wrote when they are newer than
    the results, the others drawn now (in parallel, into the same files). Returns (pictures,
    channels with figures per result folder name, channels with a PEM against Monte Carlo figure)."""
    from .plotting.files import draw_jobs, figure_jobs

    jobs = figure_jobs(folder, found, channels, ("png",))
    newest = max((p / n).stat().st_mtime for p, _ in found for n in ("arrays.npz", "meta.json") if (p / n).exists())
    missing = [j for j in jobs if not _fresh(j.paths[0], newest)]
    draw_jobs(missing, workers=workers, progress=progress)
    pictures: dict[tuple[str, str, str], bytes] = {}
    names: dict[str, list[str]] = {p.name: [] for p, _ in found}
    comparison: list[str] = []
    for job in jobs:
        if job.kind == "pem_vs_mc":
            pictures[("", job.channel, job.kind)] = job.paths[0].read_bytes()
            comparison.append(job.channel)
            continue
        result_dir = job.paths[0].parent.parent.name
        pictures[(result_dir, job.channel, job.kind)] = job.paths[0].read_bytes()
        if job.channel not in names[result_dir]:
            names[result_dir].append(job.channel)
    return pictures, names, comparison


def write_report(folder: str | Path, out_html: str | Path | None = None, *, k: float = 3.0,
                 channels: str | Sequence[str] | None = None, checks: Iterable[Any] | None = None,
                 modes: Iterable[Any] | None = None, workers: int | None = None, progress: bool = False,
                 found: Sequence[tuple[Path, Result]] | None = None) -> Path:
    """Write one self-contained HTML page on the results in ``folder`` (one result folder, or a
    folder of result folders) to ``out_html`` (default ``<folder>/report.html``), atomically.

    ``channels``: names or glob patterns of the channels to draw (default: the channels that
    matter, :func:`tb_exudyn.plotting.data.default_channels`); the channel table lists every
    channel. Figures that ``plot_folder`` already wrote (newer than the results) are embedded as
    they are; missing ones are drawn (``workers`` processes, a progress bar with ``progress``) into
    ``<result>/figures``. ``checks``, ``modes``: the verdict rows and the modes (see
    :class:`CheckEntry`, :class:`ModeEntry`; None: "not computed"). ``found``: the results already
    loaded (``find_results(folder)``).
    """
    folder = Path(folder)
    found = find_results(folder) if found is None else found
    pictures, names, comparison = report_pictures(folder, found, channels, workers=workers, progress=progress)
    text = render_report(found, k=k, channels=channels, checks=checks, modes=modes, pictures=pictures,
                         names=names, comparison=comparison)
    out = Path(out_html) if out_html is not None else folder / "report.html"
    write_text_atomic(out, text)
    return out


__all__ = ["CheckEntry", "CodeLimit", "FindingRow", "ModeEntry", "Study", "StudyFinding", "StudyQuantity",
           "SummaryRow", "as_check_entries", "as_mode_entries", "code_limit", "compare_findings", "find_results",
           "load_study", "render_report", "report_pictures", "scenario_sections", "screening", "static_axle_load",
           "studies_for", "summary", "write_report"]
