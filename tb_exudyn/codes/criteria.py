"""The EN 1990 Annex A2 (A2.4.4) deformation and comfort criteria as data, and the record of a verdict.

The criteria live in ``models/criteria/en1990_a2.toml`` (one ``[[criteria]]`` table each: clause, source, load
model, loaded tracks, quantity, where it is read, ``bound`` upper or lower, unit, and the limit); this module
reads and checks that file (:func:`load_criteria`, a ScenarioError naming the file and key for anything
invalid) and holds the limit kinds that the deck limits of :mod:`tb_exudyn.scenario.limits` do not have: a
ratio of the span (``span_ratio``: L/600) and the comfort figure (``comfort_figure``: Figure A2.3 by speed
and span, with its factors). The fixed and speed-band limits are those of :mod:`tb_exudyn.scenario.limits`.
No limit lives in Python code. The deck acceleration's criterion has one source too: models/limits/
en1990_deck.toml (:func:`deck_acceleration_limit`), read by the moving-force rows and the stochastic column.

A :class:`CriterionVerdict` is one line of the check's verdict per criterion: value, limit, utilisation
(value / limit for an upper bound, limit / value for a lower one), the deciding case and location, the
verdict and its caveats.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import ClassVar, Literal

import numpy as np

from ..errors import SettingError
from ..results.checks import default_limits
from ..results.checks_table import format_value
from ..scenario.limits import FixedLimit, SpeedBandLimit
from ..scenario.registry import models_dir
from ..scenario.schema import NONNEGATIVE, POSITIVE, Check, Context, Validated, convert, param, set_source_file
from ..scenario.toml_io import read_toml

#: the criteria file's stem in models/criteria/
CRITERIA_FILE = "en1990_a2"
#: the deck limits' file and, per track form, its criterion (models/limits/en1990_deck.toml)
DECK_LIMIT_SET = "en1990_deck"
DECK_ACCELERATION_CRITERIA: dict[str, str] = {"ballasted": "deck_acc_ballasted", "direct": "deck_acc_direct_fastened"}



def deck_criterion(track: str) -> str:
    """The deck acceleration criterion of a track form as the records name it: 'en1990_deck/deck_acc_ballasted'."""
    return f"{DECK_LIMIT_SET}/{DECK_ACCELERATION_CRITERIA[track]}"


def moving_force_load_model(train: str) -> str:
    """The load model of a moving-force row of ``train``: HSLM-A or HSLM-B (EN 1991-2 6.4.6.1.1, Annex E), or a
    real train's axle loads."""
    for name in ("HSLM-A", "HSLM-B"):
        if train.startswith(name):
            return f"{name} as moving forces (EN 1991-2 6.4.6.1.1)"
    return "real train as moving forces (its axle loads)"


VERDICT_OK, VERDICT_EXCEEDS, VERDICT_NOT_EVALUATED, VERDICT_INFO = "ok", "exceeds", "not evaluated", "comparison"


@dataclass(frozen=True, kw_only=True)
class SpanRatioLimit(Validated):
    """A limit of L / ratio [m], L the span (L/600)."""

    kind: ClassVar[str] = "span_ratio"
    ratio: float = param(doc="n of L/n", check=POSITIVE)

    def value_at(self, *, span: float) -> float:
        return float(span) / self.ratio


@dataclass(frozen=True, kw_only=True)
class ComfortFigureLimit(Validated):
    """Figure A2.3: the smallest L/delta by speed and span for b_v = 1 m/s^2 and three or more simply
    supported spans, as polylines in L per speed (linear in L, then linear in V between the curves; below the
    first curve its values, above the last: not evaluated); the factor on L/delta for one or two spans and
    for continuous beams of three or more; the floor of L/delta; the spans covered; the comfort levels b_v."""

    kind: ClassVar[str] = "comfort_figure"
    speeds_kmh: tuple[float, ...] = param(unit="km/h", doc="the speeds of the curves, increasing", check=POSITIVE)
    spans_m: tuple[tuple[float, ...], ...] = param(unit="m", doc="per curve its span breakpoints, increasing",
                                                    check=NONNEGATIVE)
    ratios: tuple[tuple[float, ...], ...] = param(doc="per curve L/delta at its breakpoints", check=POSITIVE)
    factor_one_or_two_spans: float = param(doc="factor on L/delta: one span, two simply supported or two continuous",
                                           check=POSITIVE)
    factor_continuous_three_or_more: float = param(doc="factor on L/delta: continuous beam of 3 or more spans",
                                                   check=POSITIVE)
    minimum_ratio: float = param(doc="L/delta is never below this", check=POSITIVE)
    max_span_m: float = param(unit="m", doc="the figure holds up to this span", check=POSITIVE)
    comfort_labels: tuple[str, ...] = param(doc="the comfort levels, best first")
    comfort_b_v: tuple[float, ...] = param(unit="m/s^2", doc="their car-body acceleration b_v", check=POSITIVE)

    def _validate(self, ctx: Context) -> None:
        n = len(self.speeds_kmh)
        if not n or len(self.spans_m) != n or len(self.ratios) != n:
            raise ctx.child("ratios").error(len(self.ratios), f"one span list and one ratio list per speed ({n})",
                                            "length mismatch")
        if any(b <= a for a, b in zip(self.speeds_kmh, self.speeds_kmh[1:])):
            raise ctx.child("speeds_kmh").error(list(self.speeds_kmh), "strictly increasing speeds", "not increasing")
        for i, (s, r) in enumerate(zip(self.spans_m, self.ratios)):
            if len(s) < 2 or len(s) != len(r) or any(b <= a for a, b in zip(s, s[1:])):
                raise ctx.child("spans_m").child(i).error(list(s), "two or more increasing spans, one ratio each",
                                                          "bad curve")
            if s[0] > 0.0 or s[-1] < self.max_span_m:
                raise ctx.child("spans_m").child(i).error(list(s), f"a curve from 0 to max_span_m ({self.max_span_m:g} m)",
                                                          "the curve does not cover the figure's spans")
        if len(self.comfort_labels) != len(self.comfort_b_v) or not self.comfort_b_v:
            raise ctx.child("comfort_b_v").error(list(self.comfort_b_v), "one b_v per comfort label", "length mismatch")

    def base_ratio(self, span: float, speed_kmh: float) -> float:
        """L/delta of the figure (b_v = 1, base case) at ``span`` and ``speed_kmh``; NaN beyond the last
        curve's speed or the figure's spans."""
        if not (0.0 < span <= self.max_span_m) or speed_kmh > self.speeds_kmh[-1] or not speed_kmh > 0:
            return math.nan
        at = [float(np.interp(span, s, r)) for s, r in zip(self.spans_m, self.ratios)]
        return float(np.interp(speed_kmh, self.speeds_kmh, at))

    def span_factor(self, n_spans: int, continuous: bool) -> float:
        """The factor on L/delta: continuous beams of 3 or more spans, else (one span, two spans, or a series
        of simply supported spans counted as the base case when there are 3 or more) 1.0 / 0.7."""
        if continuous and n_spans >= 3:
            return self.factor_continuous_three_or_more
        if n_spans <= 2:
            return self.factor_one_or_two_spans
        return 1.0

    def b_v(self, level: str) -> float:
        if level not in self.comfort_labels:
            raise SettingError("comfort_deflection", "comfort_level", level, " | ".join(self.comfort_labels))
        return self.comfort_b_v[self.comfort_labels.index(level)]

    def ratio(self, span: float, speed_kmh: float, n_spans: int, continuous: bool, level: str) -> float:
        """The limit's L/delta: max(minimum, figure x span factor / b_v) (NaN where the figure has no value)."""
        base = self.base_ratio(span, speed_kmh)
        if math.isnan(base):
            return math.nan
        return max(self.minimum_ratio, base * self.span_factor(n_spans, continuous) / self.b_v(level))


A2Limit = FixedLimit | SpeedBandLimit | SpanRatioLimit | ComfortFigureLimit


@dataclass(frozen=True, kw_only=True)
class A2Criterion(Validated):
    """One A2.4.4 criterion: what is limited, under which load, where, the limit and its source."""

    id: str = param(doc="identifier, unique in the file")
    title: str = param(doc="one line: the criterion in words")
    clause: str = param(doc="the code and clause")
    source: str = param(doc="where the value was read or from what it was recalled")
    load_model: str = param(doc="the load model the criterion applies to")
    tracks: str = param(doc="which tracks carry the load")
    quantity: str = param(doc="the quantity compared with the limit")
    read_at: str = param(doc="where the quantity is read")
    bound: Literal["upper", "lower"] = param(doc="upper: value <= limit; lower: value >= limit")
    unit: str = param(doc="unit of the quantity and the limit")
    limit: A2Limit = param(doc="kind = fixed | speed_bands | span_ratio | comfort_figure")
    check: bool = param(False, doc="true when the clause text was not read")
    note: str = param("", doc="remarks; what to check when check is true")

    def _validate(self, ctx: Context) -> None:
        if self.check and not self.note.strip():
            raise ctx.child("note").error(self.note, "a note saying what to check (check = true)", "empty")

    def limit_value(self, *, speed_kmh: float | None = None, span: float | None = None) -> float:
        """The limit at a line speed [km/h] (speed bands) or span [m] (span ratio); fixed: its value."""
        lim = self.limit
        if isinstance(lim, SpanRatioLimit):
            return lim.value_at(span=span)
        if isinstance(lim, ComfortFigureLimit):
            raise SettingError("A2Criterion.limit_value", "id", self.id, "a criterion without the comfort figure "
                               "(comfort_deflection.comfort_limit computes it)")
        return lim.value_at(speed_kmh=speed_kmh)


@dataclass(frozen=True, kw_only=True)
class CriteriaSet(Validated):
    name: str = param(doc="the file's stem")
    description: str = param(doc="one line")
    source: str = param(doc="the codes the file draws on")
    notes: str = param("", doc="remarks, [check]")
    criteria: tuple[A2Criterion, ...] = param(doc="[[criteria]] tables")

    def _validate(self, ctx: Context) -> None:
        seen: set[str] = set()
        for i, c in enumerate(self.criteria):
            if c.id in seen:
                raise ctx.child("criteria").child(i).child("id").error(c.id, "an id not used before", "duplicate id")
            seen.add(c.id)
        if not self.criteria:
            raise ctx.child("criteria").error([], "at least one [[criteria]] table", "empty")

    def criterion(self, criterion_id: str) -> A2Criterion:
        for c in self.criteria:
            if c.id == criterion_id:
                return c
        raise SettingError(f"criteria {self.name!r}", "id", criterion_id, " | ".join(c.id for c in self.criteria))


def criteria_path() -> Path:
    """models/criteria/en1990_a2.toml of the model library (``$TB_EXUDYN_MODELS``), or the package's own
    when that library has no criteria/ folder."""
    own = models_dir() / "criteria" / f"{CRITERIA_FILE}.toml"
    if own.exists():
        return own
    return Path(__file__).resolve().parent.parent.parent / "models" / "criteria" / f"{CRITERIA_FILE}.toml"


def load_criteria(path: str | Path | None = None) -> CriteriaSet:
    """Read and check the criteria file (default :func:`criteria_path`); ScenarioError names file and key."""
    p = Path(path) if path is not None else criteria_path()
    return set_source_file(convert(CriteriaSet, read_toml(p), Context(str(p))), str(p))


def deck_acceleration_limit(track: str) -> float:
    """The peak deck acceleration limit [m/s^2] of a track form, read from its one source: the criterion
    :data:`DECK_ACCELERATION_CRITERIA` of the limit file ``en1990_deck`` (EN 1990 A2.4.4.2.1(4)P: 3.5
    ballasted, 5.0 direct fastening, recommended values)."""
    if track not in DECK_ACCELERATION_CRITERIA:
        raise SettingError("deck_acceleration_limit", "track", track, " or ".join(DECK_ACCELERATION_CRITERIA))
    sets = {ls.name: ls for ls in default_limits()}
    found = sets.get(DECK_LIMIT_SET)
    crit = None if found is None else next((c for c in found.criteria if c.id == DECK_ACCELERATION_CRITERIA[track]), None)
    if crit is None or crit.limit.kind != "fixed":
        raise SettingError("check", "limits", sorted(sets), f"a limit file {DECK_LIMIT_SET!r} with a fixed criterion "
                           f"{DECK_ACCELERATION_CRITERIA[track]!r} (models/limits/en1990_deck.toml)",
                           "the deck acceleration criterion is missing")
    return float(crit.limit_value())


@dataclass(frozen=True)
class CriterionVerdict:
    """The verdict of one criterion: ``value`` against ``limit`` (both in ``unit``), ``utilisation`` (value /
    limit for an upper bound, limit / value for a lower one; NaN when not evaluated), the deciding case and
    location, and why it could not be evaluated or what it leaves out (``caveats``). ``bound`` 'compare': a
    ratio that is no limit (its verdict is 'comparison', never 'exceeds')."""

    criterion: str
    title: str
    clause: str
    load_model: str
    value: float
    limit: float
    unit: str
    bound: str
    case: str
    location: str
    caveats: str = ""
    check: bool = False

    @property
    def utilisation(self) -> float:
        if not (math.isfinite(self.value) and math.isfinite(self.limit)):
            return math.nan
        if self.bound == "lower":
            return self.limit / self.value if self.value > 0 else math.inf
        return self.value / self.limit if self.limit > 0 else math.inf

    @property
    def verdict(self) -> str:
        u = self.utilisation
        if math.isnan(u):
            return VERDICT_NOT_EVALUATED
        if self.bound == "compare":
            return VERDICT_INFO
        return VERDICT_OK if u <= 1.0 else VERDICT_EXCEEDS

    @property
    def short_clause(self) -> str:
        """The clause as the terminal names it: 'EN 1990 Annex A2, A2.4.4.2.3(2) (limits left ...)' -> 'A2.4.4.2.3(2)'
        (the terminal's block is headed EN 1990 A2.4.4; the full clause is in the report)."""
        text = self.clause.replace("EN 1990 Annex A2, ", "").replace(":2003", "")
        return text.split(";")[0].split(" (")[0]

    def shown(self, x: float) -> str:
        """A value or limit in the project's display units (:func:`tb_exudyn.results.checks_table.format_value`:
        mm for deflections and twists, mrad for rotations); a radius (a lower bound in m) in whole metres."""
        if self.unit == "m" and self.bound == "lower" and math.isfinite(x):
            return f"{x:.0f} m"
        return format_value(x, self.unit)

    def line(self) -> str:
        """One line: criterion, verdict, utilisation, value against limit, deciding case, clause. The caveats,
        the full load and the full clause are in the report (tb_exudyn.report.check)."""
        name = self.criterion.split(" (")[0]
        if self.verdict == VERDICT_NOT_EVALUATED:
            return f"{name}: not evaluated ({self.caveats.split('; ')[0]}) [{self.short_clause}]"
        if self.verdict == VERDICT_INFO:
            return (f"{name}: ratio {self.value:.2f}, a comparison: {self.caveats.split('; ')[0]}; {self.case} "
                    f"[{self.short_clause}]"
                    + (" [check]" if self.check else ""))
        sign = ">=" if self.bound == "lower" else "<="
        state = "EXCEEDED" if self.verdict == VERDICT_EXCEEDS else "met"
        return (f"{name}: {state}, utilisation {self.utilisation:.2f} ({self.shown(self.value)} {sign} "
                f"{self.shown(self.limit)}), {self.case}, {self.location} [{self.short_clause}]"
                + (" [check]" if self.check else ""))


__all__ = ["deck_criterion", "moving_force_load_model", "A2Criterion", "ComfortFigureLimit", "CriteriaSet", "CriterionVerdict", "DECK_ACCELERATION_CRITERIA",
           "SpanRatioLimit", "criteria_path", "deck_acceleration_limit", "load_criteria"]
