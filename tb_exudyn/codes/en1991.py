"""EN 1991-2:2003 (railway bridges, dynamic analysis) and EN 1990 Annex A2 as functions.

Each function names its clause. Values marked [check] in the docstrings are the standard's well-known
content as the project recalled it, not read from the text here: verify them against EN 1991-2 (and the
national annex) before relying on them (docs/en1991.md lists them clause by clause).

Units: spans L in m, frequencies in Hz, speeds in km/h unless the name says m/s, damping ratios as
fractions (Table 6.6 gives percent; the functions return percent / 100).
"""

from __future__ import annotations

import math
from typing import Iterable, Sequence

import numpy as np

from ..errors import SettingError
from .criteria import DECK_ACCELERATION_CRITERIA
from .criteria import deck_acceleration_limit as _deck_limit

#: construction types of Table 6.6
CONSTRUCTION_TYPES = ("steel_composite", "prestressed_concrete", "reinforced_concrete", "filler_beam")
#: Table 6.6: (zeta [%] for L >= 20 m, slope [% per m] below 20 m)
_TABLE_6_6 = {
    "steel_composite": (0.5, 0.125),
    "prestressed_concrete": (1.0, 0.07),
    "reinforced_concrete": (1.5, 0.07),
    "filler_beam": (1.5, 0.07),
}
#: EN 1990 A2.4.4.2.1(4): the track forms of the deck acceleration limit and their criterion in the limits'
#: one source, models/limits/en1990_deck.toml (the value: :func:`deck_acceleration_limit`)
DECK_ACCELERATION_LIMITS = DECK_ACCELERATION_CRITERIA
#: 6.4.6.2: the speed series starts at 40 m/s [km/h]
SPEED_SERIES_START_KMH = 40.0 * 3.6
#: 6.4.6.2: the maximum design speed is 1.2 x the maximum line speed
DESIGN_SPEED_FACTOR = 1.2
#: the step of the speed series is at most this [km/h] (the project's rule, see speed_series)
MAX_SPEED_STEP_KMH = 5.0
#: EN 1990 A2.4.4.2.1: modes up to at least this frequency count for the deck acceleration [Hz]
MIN_CUTOFF_HZ = 30.0
#: the largest line speed a check accepts [km/h]
MAX_LINE_SPEED_KMH = 600.0


def _number(where: str, key: str, value, allowed: str, low: float = 0.0, high: float = math.inf,
            low_open: bool = True) -> float:
    ok = isinstance(value, (int, float, np.floating, np.integer)) and not isinstance(value, bool)
    if ok:
        v = float(value)
        ok = math.isfinite(v) and (v > low if low_open else v >= low) and v <= high
    if not ok:
        raise SettingError(where, key, value, allowed)
    return float(value)


# ------------------------------------------------------------------------------ damping (6.4.6.3.1)
def damping_ratio_table_6_6(construction: str, span: float) -> float:
    """Lower limit of the damping ratio (fraction of critical) by construction type and span L [m],
    EN 1991-2:2003 6.4.6.3.1 Table 6.6 [check]:

    steel and composite 0.5 % + 0.125 (20 - L) % for L < 20 m, 0.5 % from 20 m; prestressed concrete
    1.0 % + 0.07 (20 - L) %, 1.0 %; filler beam and reinforced concrete 1.5 % + 0.07 (20 - L) %, 1.5 %.
    """
    if construction not in _TABLE_6_6:
        raise SettingError("damping_ratio_table_6_6", "construction", construction, ", ".join(CONSTRUCTION_TYPES))
    span = _number("damping_ratio_table_6_6", "span", span, "a span L > 0 m")
    base, slope = _TABLE_6_6[construction]
    return 0.01 * (base + slope * max(0.0, 20.0 - span))


def additional_damping_eq_6_13(span: float) -> float:
    """Additional damping ratio (fraction) for vehicle-bridge interaction with a moving-force model,
    EN 1991-2:2003 6.4.6.3.1(3) eq. (6.13) [check], spans L < 30 m (0 from 30 m):

    Delta zeta = (0.0187 L - 0.00064 L^2) / (1 - 0.0441 L - 0.0044 L^2 + 0.000255 L^3) [%].
    Not for models with the vehicles' own dynamics (interaction models).
    """
    span = _number("additional_damping_eq_6_13", "span", span, "a span L > 0 m")
    if span >= 30.0:
        return 0.0
    num = 0.0187 * span - 0.00064 * span**2
    den = 1.0 - 0.0441 * span - 0.0044 * span**2 + 0.000255 * span**3
    return max(0.0, 0.01 * num / den)


# ------------------------------------------------------------ is a dynamic analysis required (6.4.4)
def frequency_limits_fig_6_10(span: float) -> tuple[float, float]:
    """(lower, upper) limit of the first natural frequency n0 [Hz] of EN 1991-2:2003 6.4.4 Figure 6.10
    [check] for 4 m <= L <= 100 m: upper 94.76 L^-0.748; lower 80 / L up to 20 m, 23.58 L^-0.592 above
    (L = 32 m: 3.03 and 7.09 Hz)."""
    span = _number("frequency_limits_fig_6_10", "span", span, "4 <= L <= 100 m (EN 1991-2 Figure 6.10)",
                   low=4.0, high=100.0, low_open=False)
    upper = 94.76 * span**-0.748
    lower = 80.0 / span if span <= 20.0 else 23.58 * span**-0.592
    return lower, upper


def dynamic_analysis_required(line_speed_kmh: float, span: float, n0: float) -> tuple[bool, str]:
    """Whether EN 1991-2:2003 6.4.4 Figure 6.9 asks for a dynamic analysis [check], as (required, why).

    Only the branch the flow chart gives for simply supported spans is followed: not required when the
    maximum line speed is at most 200 km/h and n0 lies within Figure 6.10's limits; required otherwise
    (above 200 km/h the chart's route through Annex F for simple structures, and the torsion condition
    n_T > 1.2 n0, are not followed here: [check]).
    """
    line_speed_kmh = _number("dynamic_analysis_required", "line_speed_kmh", line_speed_kmh, "a speed > 0 km/h")
    if not 4.0 <= span <= 100.0:
        return True, f"span {span:g} m outside Figure 6.10's 4-100 m"
    lower, upper = frequency_limits_fig_6_10(span)
    inside = lower <= n0 <= upper
    band = f"n0 = {n0:.3g} Hz {'within' if inside else 'outside'} Figure 6.10's {lower:.3g}-{upper:.3g} Hz"
    if line_speed_kmh > 200.0:
        return True, f"line speed {line_speed_kmh:g} km/h > 200 km/h ({band})"
    if not inside:
        return True, band
    return False, f"line speed {line_speed_kmh:g} km/h <= 200 km/h and {band}"


# ------------------------------------------------------------------------- dynamic factors (6.4.5)
def dynamic_factor_phi2(determinant_length: float) -> float:
    """Phi_2 = 1.44 / (sqrt(L_Phi) - 0.2) + 0.82 within [1.00, 1.67], carefully maintained track,
    EN 1991-2:2003 6.4.5.2 eq. (6.4) [check]."""
    lp = _number("dynamic_factor_phi2", "determinant_length", determinant_length, "L_Phi > 0.04 m", low=0.04)
    return min(1.67, max(1.0, 1.44 / (math.sqrt(lp) - 0.2) + 0.82))


def dynamic_factor_phi3(determinant_length: float) -> float:
    """Phi_3 = 2.16 / (sqrt(L_Phi) - 0.2) + 0.73 within [1.00, 2.00], standard maintenance,
    EN 1991-2:2003 6.4.5.2 eq. (6.5) [check]."""
    lp = _number("dynamic_factor_phi3", "determinant_length", determinant_length, "L_Phi > 0.04 m", low=0.04)
    return min(2.0, max(1.0, 2.16 / (math.sqrt(lp) - 0.2) + 0.73))


#: Annex C: the factor on phi'' in the enhancement 1 + phi'_dyn + k phi'' by maintenance standard
IRREGULARITY_FACTOR = {"careful": 0.5, "standard": 1.0}


def phi_irregularity_annex_c(n0: float, determinant_length: float, speed_ms: float | None = None) -> float:
    """phi'' of EN 1991-2:2003 Annex C [check], the track irregularity part of the dynamic factor:

    phi'' = (alpha / 100) [56 exp(-(L_Phi / 10)^2) + 50 (n0 L_Phi / 80 - 1) exp(-(L_Phi / 20)^2)] >= 0,
    alpha = v / 22 for v <= 22 m/s and 1 above (``speed_ms`` None: alpha = 1).
    """
    n0 = _number("phi_irregularity_annex_c", "n0", n0, "a frequency > 0 Hz")
    lp = _number("phi_irregularity_annex_c", "determinant_length", determinant_length, "L_Phi > 0 m")
    alpha = 1.0
    if speed_ms is not None:
        v = _number("phi_irregularity_annex_c", "speed_ms", speed_ms, "a speed >= 0 m/s", low_open=False)
        alpha = min(1.0, v / 22.0)
    value = alpha / 100.0 * (56.0 * math.exp(-((lp / 10.0) ** 2))
                             + 50.0 * (n0 * lp / 80.0 - 1.0) * math.exp(-((lp / 20.0) ** 2)))
    return max(0.0, value)


def irregularity_enhancement(phi_dyn: float | np.ndarray, phi2: float, maintenance: str = "careful"):
    """1 + phi'_dyn + k phi'' (k = 1/2 carefully maintained, 1 standard maintenance), EN 1991-2:2003
    6.4.6.5(3) and Annex C [check]: the factor on the load effects of a dynamic analysis."""
    if maintenance not in IRREGULARITY_FACTOR:
        raise SettingError("irregularity_enhancement", "maintenance", maintenance, " or ".join(IRREGULARITY_FACTOR))
    return 1.0 + np.asarray(phi_dyn) + IRREGULARITY_FACTOR[maintenance] * phi2


# --------------------------------------------------------------------------------- speeds (6.4.6.2)
def resonant_speeds_kmh(n0: float, regular_length: float, orders: Iterable[int] = (1, 2, 3, 4)) -> np.ndarray:
    """v_i = n0 D / i [km/h], EN 1991-2:2003 6.4.6.2 and eq. (6.9) (lambda_i = D / i) [check]."""
    return np.array([3.6 * n0 * regular_length / i for i in orders])


def speed_series(line_speed_kmh: float, resonant_kmh: Sequence[float] = (), step_kmh: float = MAX_SPEED_STEP_KMH,
                 fine_step_kmh: float = 1.0, fine_half_width_kmh: float = 5.0) -> np.ndarray:
    """The speeds of the check [km/h], EN 1991-2:2003 6.4.6.2 [check]: from 40 m/s (144 km/h) up to the
    maximum design speed 1.2 x the line speed in steps of ``step_kmh`` (at most 5 km/h), both ends
    included, refined near each resonant speed inside that range: every ``fine_step_kmh`` within
    ``fine_half_width_kmh`` of it, and the resonant speed itself. If 1.2 x the line speed is below
    144 km/h the series is that one speed. Sorted, without duplicates (rounded to 1e-6 km/h).
    """
    v = _number("speed_series", "line_speed_kmh", line_speed_kmh, f"a speed in (0, {MAX_LINE_SPEED_KMH:g}] km/h",
                high=MAX_LINE_SPEED_KMH)
    step = _number("speed_series", "step_kmh", step_kmh, f"0 < step <= {MAX_SPEED_STEP_KMH:g} km/h",
                   high=MAX_SPEED_STEP_KMH)
    fine = _number("speed_series", "fine_step_kmh", fine_step_kmh, "a step > 0 km/h")
    top = DESIGN_SPEED_FACTOR * v
    start = min(SPEED_SERIES_START_KMH, top)
    n = max(1, int(math.ceil((top - start) / step - 1e-9)))
    speeds = [start + (top - start) * i / n for i in range(n + 1)]  # equal steps <= step, both ends
    k = int(round(fine_half_width_kmh / fine))
    for vr in resonant_kmh:
        if start <= vr <= top:
            speeds.extend(vr + j * fine for j in range(-k, k + 1) if start <= vr + j * fine <= top)
    return np.unique(np.round(np.array(speeds), 6))


# ------------------------------------------------------------------------ modes (EN 1990 A2.4.4.2.1)
def cutoff_frequency(f1: float, f3: float | None) -> float:
    """The highest frequency whose modes count for the deck acceleration [Hz]: max(30 Hz, 1.5 f1, f3),
    EN 1990 Annex A2, A2.4.4.2.1(4)P note (f1, f3: first and third natural frequency of the member;
    ``f3`` None when the model has no third mode below its own limit)."""
    f1 = _number("cutoff_frequency", "f1", f1, "a frequency > 0 Hz")
    out = max(MIN_CUTOFF_HZ, 1.5 * f1)
    if f3 is not None:
        out = max(out, _number("cutoff_frequency", "f3", f3, "a frequency > 0 Hz"))
    return out


def deck_acceleration_limit(track: str) -> float:
    """Peak vertical deck acceleration limit [m/s^2], EN 1990 A2.4.4.2.1(4)P: 3.5 on ballasted track,
    5.0 on direct-fastened track (recommended values), read from the one source of the deck limits,
    models/limits/en1990_deck.toml, which the stochastic column reads too."""
    return _deck_limit(track)


__all__ = [
    "CONSTRUCTION_TYPES", "DECK_ACCELERATION_LIMITS", "DESIGN_SPEED_FACTOR", "IRREGULARITY_FACTOR",
    "MAX_LINE_SPEED_KMH", "MAX_SPEED_STEP_KMH", "MIN_CUTOFF_HZ", "SPEED_SERIES_START_KMH",
    "additional_damping_eq_6_13", "cutoff_frequency", "damping_ratio_table_6_6", "deck_acceleration_limit",
    "dynamic_analysis_required", "dynamic_factor_phi2", "dynamic_factor_phi3", "frequency_limits_fig_6_10",
    "irregularity_enhancement", "phi_irregularity_annex_c", "resonant_speeds_kmh", "speed_series",
]
