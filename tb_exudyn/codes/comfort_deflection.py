"""Passenger comfort by the deflection criterion of EN 1990 Annex A2, A2.4.4.3.2 (Figure A2.3).

The figure gives, for a series of three or more simply supported spans and a car-body acceleration b_v =
1 m/s^2, the smallest L/delta by span L and speed V; delta is the vertical deflection of the track centre line
under LM71 x Phi with alpha = 1, one track loaded. The value is multiplied by 0.7 for a single span and for two
spans (simply supported or continuous), by 0.9 for a continuous beam of three or more spans, divided by the
comfort level's b_v (1.0 / 1.3 / 2.0 m/s^2: very good / good / acceptable) and never taken below 600. Its data
(the digitised curves, factors, floor, levels) live in models/criteria/en1990_a2.toml (``comfort_deflection``;
[check] where marked there); this module applies them.
"""

from __future__ import annotations

import math
from typing import Sequence

from .criteria import ComfortFigureLimit, load_criteria

CRITERION = "comfort_deflection"


def comfort_figure() -> ComfortFigureLimit:
    """The Figure A2.3 limit of the criteria file."""
    return load_criteria().criterion(CRITERION).limit


def comfort_limit(span: float, speed_kmh: float, n_spans: int, continuous: bool = False,
                  level: str = "very good", figure: ComfortFigureLimit | None = None) -> float:
    """The largest deflection delta [m] Figure A2.3 allows for ``span`` [m] at ``speed_kmh`` on a bridge of
    ``n_spans`` spans (``continuous``: one continuous girder) at comfort ``level``: L / ratio; NaN where the
    figure (as digitised) has no value (speeds above its last curve, spans beyond 120 m)."""
    fig = figure or comfort_figure()
    ratio = fig.ratio(span, speed_kmh, n_spans, continuous, level)
    return float(span) / ratio if math.isfinite(ratio) else math.nan


def comfort_utilisations(deflections: Sequence[float], spans: Sequence[float], speed_kmh: float,
                         continuous: bool = False, level: str = "very good") -> list[float]:
    """Per span delta / limit (NaN where the figure has no value): ``deflections`` are each span's largest
    deflection under LM71 x Phi (alpha = 1, one track)."""
    fig = comfort_figure()
    out = []
    for d, span in zip(deflections, spans):
        lim = comfort_limit(span, speed_kmh, len(spans), continuous, level, fig)
        out.append(float(d) / lim if math.isfinite(lim) else math.nan)
    return out


__all__ = ["comfort_figure", "comfort_limit", "comfort_utilisations"]
