"""The kinds of a code limit (the ``limit`` table of a criterion, :mod:`tb_exudyn.scenario.limits`): a fixed
value, speed bands, grades, a share of the static load (a criterion on a result's channels), a ratio of the
span and Figure A2.3's comfort curves (the EN 1991-2 check's structural criteria); each validated on
construction, each with ``kind`` (its TOML ``kind``) and the value at a speed, load or span."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar, Literal, Sequence

import numpy as np

from ..errors import SettingError
from .schema import NONNEGATIVE, POSITIVE, Check, Context, Validated, param


def _finite(ctx: Context, key: str, values: Sequence[float]) -> None:
    """Every limit value a finite number: NaN would leave the criterion NOT EVALUATED and inf would always pass."""
    for i, v in enumerate(values):
        if not math.isfinite(v):
            sub = ctx.child(key) if key == "value" else ctx.child(key).child(i)
            raise sub.error(v, "a finite number", "not a limit (nan is never evaluated, inf always passes)")


@dataclass(frozen=True, kw_only=True)
class FixedLimit(Validated):
    """One value, in the quantity's unit."""

    kind: ClassVar[str] = "fixed"
    value: float = param(doc="the limit, in the quantity's unit")

    def value_at(self, *, speed_kmh: float | None = None, static_axle_load: float | None = None,
                 static_wheel_load: float | None = None) -> float:
        return self.value

    def _validate(self, ctx: Context) -> None:
        _finite(ctx, "value", (self.value,))


@dataclass(frozen=True, kw_only=True)
class SpeedBandLimit(Validated):
    """Values by train speed: values[i] applies up to speed_max_kmh[i] (inclusive), above the previous one."""

    kind: ClassVar[str] = "speed_bands"
    speed_max_kmh: tuple[float, ...] = param(unit="km/h", doc="upper end of each band, increasing, the last inf",
                                             check=Check(low=0.0, allow_inf=True))
    values: tuple[float, ...] = param(doc="the limit in each band, in the quantity's unit")

    def value_at(self, *, speed_kmh: float | None = None, static_axle_load: float | None = None,
                 static_wheel_load: float | None = None) -> float:
        if speed_kmh is None or not speed_kmh > 0:
            raise SettingError("value_at", "speed_kmh", speed_kmh, "the train speed in km/h (> 0): this limit has speed bands")
        for v_max, value in zip(self.speed_max_kmh, self.values):
            if speed_kmh <= v_max:
                return value
        raise AssertionError("the last band is inf")  # pragma: no cover - _validate guarantees it

    def _validate(self, ctx: Context) -> None:
        if len(self.values) != len(self.speed_max_kmh) or not self.values:
            raise ctx.child("values").error(list(self.values), f"one value per band ({len(self.speed_max_kmh)})",
                                            "length mismatch")
        _finite(ctx, "values", self.values)
        if any(b <= a for a, b in zip(self.speed_max_kmh, self.speed_max_kmh[1:])):
            raise ctx.child("speed_max_kmh").error(list(self.speed_max_kmh), "strictly increasing speeds", "not increasing")
        if not math.isinf(self.speed_max_kmh[-1]):
            raise ctx.child("speed_max_kmh").error(list(self.speed_max_kmh), "a last band up to inf (every speed covered)",
                                                   "speeds above the last band have no limit")


@dataclass(frozen=True, kw_only=True)
class GradedLimit(Validated):
    """Graded levels (e.g. comfort 'very good', 'good', 'acceptable'): labels[i] holds up to values[i].
    The pass/fail limit is the last value."""

    kind: ClassVar[str] = "grades"
    labels: tuple[str, ...] = param(doc="grade names, best first")
    values: tuple[float, ...] = param(doc="upper end of each grade, increasing, in the quantity's unit")

    def value_at(self, *, speed_kmh: float | None = None, static_axle_load: float | None = None,
                 static_wheel_load: float | None = None) -> float:
        return self.values[-1]

    def grade(self, value: float) -> str | None:
        """The best grade whose upper end the value does not exceed, or None (beyond the last grade)."""
        for label, upper in zip(self.labels, self.values):
            if value <= upper:
                return label
        return None

    def _validate(self, ctx: Context) -> None:
        if len(self.labels) != len(self.values) or not self.values:
            raise ctx.child("values").error(list(self.values), f"one value per label ({len(self.labels)})", "length mismatch")
        _finite(ctx, "values", self.values)
        for i, label in enumerate(self.labels):
            if not label.strip() or label in self.labels[:i]:
                raise ctx.child("labels").child(i).error(label, "a grade name, not empty and not used before in labels",
                                                         "empty" if not label.strip() else "duplicate label")
        if any(b <= a for a, b in zip(self.values, self.values[1:])):
            raise ctx.child("values").error(list(self.values), "strictly increasing values (best grade first)", "not increasing")


@dataclass(frozen=True, kw_only=True)
class StaticLoadLimit(Validated):
    """limit = factor * (constant + coefficient * reference) [N], reference the static axle or wheel load [N]
    (e.g. Prud'homme 0.85 (10 kN + P/3))."""

    kind: ClassVar[str] = "static_load"
    reference: Literal["static_axle_load", "static_wheel_load"] = param(doc="which static load enters")
    factor: float = param(doc="alpha", check=POSITIVE)
    constant: float = param(unit="N", doc="constant term (10 kN in the Prud'homme form)", check=NONNEGATIVE)
    coefficient: float = param(doc="multiplier of the static load", check=NONNEGATIVE)

    def value_at(self, *, speed_kmh: float | None = None, static_axle_load: float | None = None,
                 static_wheel_load: float | None = None) -> float:
        load = static_axle_load if self.reference == "static_axle_load" else static_wheel_load
        if load is None or not load > 0:
            raise SettingError("value_at", self.reference, load, f"the {self.reference.replace('_', ' ')} in N (> 0)")
        return self.factor * (self.constant + self.coefficient * load)

    def _validate(self, ctx: Context) -> None:
        if not self.constant + self.coefficient > 0:
            raise ctx.child("coefficient").error(self.coefficient, "constant + coefficient > 0", "the limit is 0")


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


Limit = FixedLimit | SpeedBandLimit | GradedLimit | StaticLoadLimit | SpanRatioLimit | ComfortFigureLimit
LIMIT_KINDS: dict[str, type] = {c.kind: c for c in (FixedLimit, SpeedBandLimit, GradedLimit, StaticLoadLimit, SpanRatioLimit,
                                                     ComfortFigureLimit)}
#: the limit kinds of a criterion on a result's channels (a statistic) and of a structural one (a bound)
RESPONSE_LIMITS = ("fixed", "speed_bands", "grades", "static_load")
STRUCTURAL_LIMITS = ("fixed", "speed_bands", "span_ratio", "comfort_figure")


__all__ = ["ComfortFigureLimit", "FixedLimit", "GradedLimit", "LIMIT_KINDS", "Limit", "RESPONSE_LIMITS", "STRUCTURAL_LIMITS", "SpanRatioLimit", "SpeedBandLimit", "StaticLoadLimit"]
