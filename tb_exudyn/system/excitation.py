"""Excitation of a built model as data: no irregularity, a sampled profile, or one harmonic.

Pure numpy, no Exudyn. The built model reads an excitation through :func:`rail_inputs`, which
returns, for wheel positions x along the track, the three irregularity inputs (vertical profile
z_v [m], alignment y_a [m], cross-level angle theta_c [rad]) and their slopes d/dx. The rails
then sit at

    z_left  = z_v + b theta_c,   z_right = z_v - b theta_c,   y_rail = y_a,

with b the half gauge. A cross-level given as a height difference h = z_left - z_right [m] is
converted to the angle theta_c = h / (2 b) (:func:`~.conventions.cross_level_scale`).

A *profile* is any callable ``x -> (value, slope)`` (vectorised over x [m]); a sample drawn by
``tb_exudyn.track`` only needs wrapping in such a callable (e.g. :func:`sampled_profile`).
A *harmonic* pseudo-excitation of spatial circular frequency Omega [rad/m] gives wheel j, which
trails the train's first axle by a_j, the input

    real part:  A cos(Omega (v t - a_j)),    imaginary part:  A sin(Omega (v t - a_j)),

i.e. the profile A cos(Omega (x - x_ref)) (resp. sin) with x_ref the first axle's position at
t = 0 (x_j(t) = x_ref - a_j + v t). Its time derivative is v times the slope.

Every input is multiplied by a taper w(x) along the track: 0 up to x_ref, rising as
(1 - cos(pi s / L_t)) / 2 over s = x - x_ref in [0, L_t] (Track.taper_length), 1 beyond. So at t = 0
every wheel (all at x <= x_ref) sees zero input and zero slope: a run starts in equilibrium (at rest
without gravity, static with it) instead of with a jolt of the stiff contact. The taper lies on the
approach track, before the bridge; PEM and Monte Carlo see the same tapered process.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Literal, Optional, Union

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .conventions import cross_level_scale, harmonic_phase

#: Irregularity kinds in the order of the rows returned by :func:`rail_inputs`.
KINDS: tuple[str, ...] = ("vertical", "alignment", "cross_level")

Profile = Callable[[NDArray[np.float64]], tuple[NDArray[np.float64], NDArray[np.float64]]]
CrossLevelUnit = Literal["angle", "height"]


@dataclass(frozen=True)
class NoExcitation:
    """Perfectly smooth track: no irregularity input."""


@dataclass(frozen=True)
class ProfileExcitation:
    """A deterministic irregularity sample: one profile callable per kind (None: zero).

    Attributes
    ----------
    vertical, alignment, cross_level : callable ``x -> (value, slope)`` or None
        Vertical profile [m], alignment [m] and cross-level ([rad] or [m], see
        ``cross_level_unit``) along the track, x [m] with x = 0 at the bridge start.
    cross_level_unit : "angle" (theta_c in rad) or "height" (z_left - z_right in m).
    """

    vertical: Optional[Profile] = None
    alignment: Optional[Profile] = None
    cross_level: Optional[Profile] = None
    cross_level_unit: CrossLevelUnit = "angle"

    def __post_init__(self) -> None:
        _check_unit(self.cross_level_unit)


@dataclass(frozen=True)
class HarmonicExcitation:
    """One harmonic pseudo-excitation (the real or imaginary part of A exp(i Omega (v t - a_j))).

    Attributes
    ----------
    kind : "vertical", "alignment" or "cross_level"
    spatial_frequency : Omega [rad/m] (> 0)
    amplitude : A [m], or [rad] / [m] for cross-level by ``cross_level_unit``
    part : "real" (cosine input) or "imag" (sine input)
    cross_level_unit : "angle" or "height" (only used for kind = "cross_level")
    """

    kind: Literal["vertical", "alignment", "cross_level"]
    spatial_frequency: float
    amplitude: float
    part: Literal["real", "imag"] = "real"
    cross_level_unit: CrossLevelUnit = "angle"

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise ValueError(f"harmonic excitation kind must be one of {KINDS}, got {self.kind!r}")
        if not (np.isfinite(self.spatial_frequency) and self.spatial_frequency > 0):
            raise ValueError(f"spatial_frequency must be a finite number > 0 rad/m, got {self.spatial_frequency!r}")
        if not np.isfinite(self.amplitude):
            raise ValueError(f"amplitude must be finite, got {self.amplitude!r}")
        if self.part not in ("real", "imag"):
            raise ValueError(f"part must be 'real' or 'imag', got {self.part!r}")
        _check_unit(self.cross_level_unit)


Excitation = Union[NoExcitation, ProfileExcitation, HarmonicExcitation]


def _check_unit(unit: str) -> None:
    if unit not in ("angle", "height"):
        raise ValueError(f"cross_level_unit must be 'angle' (rad) or 'height' (m), got {unit!r}")


def as_excitation(excitation: Excitation | None) -> Excitation:
    """``None`` -> :class:`NoExcitation`; an excitation is returned unchanged; anything else raises."""
    if excitation is None:
        return NoExcitation()
    if isinstance(excitation, (NoExcitation, ProfileExcitation, HarmonicExcitation)):
        return excitation
    raise TypeError(
        "excitation must be None, NoExcitation, ProfileExcitation or HarmonicExcitation, "
        f"got {type(excitation).__name__}"
    )


def is_zero(excitation: Excitation) -> bool:
    """True when the excitation gives no input anywhere."""
    if isinstance(excitation, NoExcitation):
        return True
    if isinstance(excitation, ProfileExcitation):
        return excitation.vertical is None and excitation.alignment is None and excitation.cross_level is None
    return excitation.amplitude == 0.0


def taper(x: NDArray[np.float64], x_ref: float, length: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The cosine taper w(x) and its slope (see the module docstring); ``length`` 0: a step at x_ref."""
    s = x - x_ref
    if length <= 0.0:
        return (s >= 0.0).astype(float), np.zeros_like(x)
    u = np.clip(s / length, 0.0, 1.0)
    w = 0.5 * (1.0 - np.cos(np.pi * u))
    dw = np.where((s > 0.0) & (s < length), 0.5 * np.pi / length * np.sin(np.pi * u), 0.0)
    return w, dw


def rail_inputs(
    excitation: Excitation, x: ArrayLike, x_ref: float, half_gauge: float, taper_length: float = 0.0
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Irregularity inputs and their slopes at track positions x.

    Parameters
    ----------
    excitation : the excitation
    x : (n,) positions along the track [m]
    x_ref : phase reference of a harmonic excitation: the first axle's position at t = 0 [m]
    half_gauge : b [m], for a cross-level given as a height difference
    taper_length : L_t [m] of the taper that starts at x_ref (0: a step at x_ref)

    Returns
    -------
    values, slopes : (3, n) arrays, rows (vertical [m], alignment [m], cross-level angle [rad])
        and their derivatives along x.
    """
    xs = np.atleast_1d(np.asarray(x, dtype=float))
    values = np.zeros((3, xs.size))
    slopes = np.zeros((3, xs.size))
    if isinstance(excitation, HarmonicExcitation):
        row = KINDS.index(excitation.kind)
        phase = harmonic_phase(excitation.spatial_frequency, xs, x_ref)
        amp, om = excitation.amplitude, excitation.spatial_frequency
        if excitation.part == "real":
            values[row], slopes[row] = amp * np.cos(phase), -amp * om * np.sin(phase)
        else:
            values[row], slopes[row] = amp * np.sin(phase), amp * om * np.cos(phase)
        if excitation.kind == "cross_level":
            scale = cross_level_scale(excitation.cross_level_unit, half_gauge)
            values[2] *= scale
            slopes[2] *= scale
    elif isinstance(excitation, ProfileExcitation):
        for row, profile in enumerate((excitation.vertical, excitation.alignment, excitation.cross_level)):
            if profile is None:
                continue
            val, slo = profile(xs)
            values[row] = np.broadcast_to(np.asarray(val, dtype=float), xs.shape)
            slopes[row] = np.broadcast_to(np.asarray(slo, dtype=float), xs.shape)
        scale = cross_level_scale(excitation.cross_level_unit, half_gauge)
        values[2] *= scale
        slopes[2] *= scale
    else:
        return values, slopes
    w, dw = taper(xs, x_ref, taper_length)
    return values * w, slopes * w + values * dw


def sampled_profile(x_samples: ArrayLike, values: ArrayLike) -> Profile:
    """A profile callable from samples: linear interpolation, constant outside the samples.

    The slope is the slope of the interpolating polygon (zero outside the samples).
    """
    xs = np.asarray(x_samples, dtype=float)
    vs = np.asarray(values, dtype=float)
    if xs.ndim != 1 or xs.size < 2 or xs.shape != vs.shape or np.any(np.diff(xs) <= 0):
        raise ValueError("x_samples must be 1-D strictly increasing with >= 2 points and values the same shape")
    seg_slope = np.diff(vs) / np.diff(xs)

    def profile(x: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        x = np.asarray(x, dtype=float)
        i = np.clip(np.searchsorted(xs, x, side="right") - 1, 0, xs.size - 2)
        inside = (x >= xs[0]) & (x <= xs[-1])
        return np.interp(x, xs, vs), np.where(inside, seg_slope[i], 0.0)

    return profile
