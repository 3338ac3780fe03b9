"""The report's inputs as data: the verdict rows (:class:`CheckEntry`, :class:`Verdicts`), the modes
(:class:`ModeEntry`), the per-channel summary, the screening against the former hard-coded limits,
and the study's findings beside ours (:func:`compare_findings`)."""

from __future__ import annotations

import math
import re
from dataclasses import MISSING, dataclass, fields
from typing import Any, Iterable, Union

import numpy as np

from ..plotting import data as pdata
from ..system.labels import channel_label
from ..results import RandomResponse, TimeHistory
from ..results.checks_table import Caveat
from ..results.kinds import ResultKind
from ..scenario import Car15, Scenario
from ..scenario.studies import Study, StudyFinding, StudyQuantity

Result = Union[RandomResponse, TimeHistory]


@dataclass(frozen=True)
class CheckEntry:
    """One row of the verdicts: a criterion checked at one location.

    The rows of a checks table (:func:`tb_exudyn.results.checks.checks`) arrive through
    :func:`check_entries`; any object with these attributes is accepted (:func:`as_check_entries`).
    ``estimate`` and ``limit`` are in ``unit`` (SI; shown in its display unit). ``verdict`` is a word
    ("OK", "EXCEEDS", "UNDETERMINED", "NOT EVALUATED", ...); ``probability`` the probability that the
    limit is exceeded at least once per passage (None or NaN: not computed) and ``interval`` its
    confidence interval (Monte Carlo); ``caveats`` what qualifies the row (:class:`Caveat`, or plain
    text: a caveat that does not change the verdict); ``channel`` the channel it comes from (links the
    row to its figures); ``conditional``: a caveat could turn the verdict; ``grade`` the grade of a
    graded limit; ``decisive``: this location decides its criterion (its worst), the row of the
    report's first table (the others are in the per-location table); ``limit_set`` the name of the
    limit file it comes from ("en1990_deck"; "": unknown), which places the row on the first screen
    (the bridge's sets first, :func:`part_of`)."""

    criterion: str
    location: str
    estimate: float
    limit: float
    unit: str
    verdict: str
    probability: float | None = None
    clause: str = ""
    caveats: tuple[Caveat, ...] = ()
    channel: str = ""
    interval: tuple[float, float] | None = None
    grade: str = ""
    conditional: bool = False
    decisive: bool = True
    limit_set: str = ""

    def __post_init__(self) -> None:
        if self.probability is not None and math.isnan(self.probability):
            object.__setattr__(self, "probability", None)
        object.__setattr__(self, "caveats", tuple(c if isinstance(c, Caveat) else Caveat("", str(c), False)
                                                  for c in (self.caveats or ())))


@dataclass(frozen=True)
class Verdicts:
    """The report's verdict section: ``rows`` (every criterion and location, :class:`CheckEntry`),
    ``heading`` (what was checked: method, speed, passage, target probability; "" if unknown), the
    table's ``notes`` (remarks on the whole table), the ``target`` probability per passage (None if
    unknown), what the result is (``kind``, :class:`~tb_exudyn.results.kinds.ResultKind`; None if unknown), the
    train speed and the bridge's name (the scope the bridge's verdict holds for; None / "" if unknown)."""

    rows: tuple[CheckEntry, ...]
    heading: str = ""
    notes: tuple[str, ...] = ()
    target: float | None = None
    kind: ResultKind | None = None
    speed_kmh: float | None = None
    bridge: str = ""

    @property
    def decisive(self) -> list[CheckEntry]:
        """One row per criterion: the location that decides it."""
        return [r for r in self.rows if r.decisive]

    @property
    def deterministic(self) -> bool:
        """One deterministic run (no probability); False when the kind is not known."""
        return self.kind is not None and not self.kind.random


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
        out.append(cls(**{f.name: getattr(row, f.name) for f in fields(cls) if hasattr(row, f.name)}))
    return out


def as_check_entries(rows: Iterable[Any] | None) -> list[CheckEntry] | None:
    """The verdict rows as :class:`CheckEntry` (None stays None: "not computed")."""
    return _entries(rows, CheckEntry)


def check_entries(table: Any) -> list[CheckEntry]:
    """The report's rows of a checks table (:func:`tb_exudyn.results.checks.checks`): every criterion
    and location, the deciding location of each criterion (``table.worst()``) marked ``decisive``,
    conditional as the table shows it (``verdict_text``), the caveats as they are."""
    worst = {id(r) for r in table.worst()}
    return [CheckEntry(
        criterion=r.title or r.criterion, location=channel_label(r.channel), estimate=float(r.estimate),
        limit=float(r.limit), unit=r.unit, verdict=r.verdict, probability=r.probability, clause=r.clause,
        caveats=tuple(r.caveats), channel=r.channel, interval=r.interval, grade=r.grade,
        conditional=r.verdict_text != r.verdict, decisive=id(r) in worst, limit_set=r.criterion.split("/")[0],
    ) for r in table.rows]


#: the limit sets of the bridge (the first screen's first part); any set whose channels are the
#: bridge's belongs to it too
BRIDGE_SETS = ("en1990_deck",)


def part_of(row: CheckEntry) -> str:
    """"bridge" or "vehicle": the part of the first screen a row belongs to (a bridge limit set, or a
    bridge channel, bridge.*: the bridge's)."""
    return "bridge" if row.limit_set in BRIDGE_SETS or row.channel.startswith("bridge.") else "vehicle"


#: the PEM first-passage methods in words
FIRST_PASSAGE_WORDS = {"poisson": "Poisson up-crossings at Rice's rate", "vanmarcke": "Vanmarcke's first passage"}


def verdicts_of(checks: Any, scenario: Scenario | None = None) -> Verdicts | None:
    """The verdict section's data: from a checks table (an object with ``rows`` and ``worst()``, e.g.
    :class:`tb_exudyn.results.checks_table.ChecksTable`) or from a sequence of rows (each a
    :class:`CheckEntry` or an object with its attributes); None stays None ("not computed").
    ``scenario``: the run's, for the heading's bridge crossing times and the bridge's name."""
    if checks is None:
        return None
    crossed, bridge = "", ""
    if scenario is not None:
        c = pdata.crossing_times(scenario)
        crossed, bridge = f" (the train on the bridge {c.first_on:.3g}-{c.last_off:.3g} s)", scenario.bridge.name
    if hasattr(checks, "rows") and hasattr(checks, "worst"):
        heading = (f"{checks.method}, {checks.speed_kmh:g} km/h, passage: the run {checks.window[0]:.3g}-"
                   f"{checks.window[1]:.4g} s{crossed}, target P <= {checks.target:.3g} per passage"
                   + (f" ({FIRST_PASSAGE_WORDS.get(checks.first_passage, checks.first_passage)})"
                      if checks.kind.gaussian else ""))
        return Verdicts(tuple(check_entries(checks)), heading, tuple(checks.notes), float(checks.target), checks.kind,
                        float(checks.speed_kmh), bridge)
    return Verdicts(tuple(as_check_entries(checks)))


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
