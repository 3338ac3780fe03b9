"""Bands, band variance and spatial-to-temporal conversion of one-sided track spectra."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .spectra import Spectrum, SpectrumError, check_band_order

_VALIDITY_RTOL = 1e-9  # round-off allowance when a band edge equals a validity edge


def check_band(spectrum: Spectrum, omega_min: float, omega_max: float) -> None:
    """Raise SpectrumError unless 0 <= omega_min < omega_max lies inside ``spectrum.validity``."""
    check_band_order(omega_min, omega_max)
    lo, hi = spectrum.validity
    if omega_min < lo * (1 - _VALIDITY_RTOL) or omega_max > hi * (1 + _VALIDITY_RTOL):
        raise SpectrumError(f"band [{omega_min:g}, {omega_max:g}] rad/m lies outside the validity "
                            f"[{lo:g}, {hi:g}] rad/m of spectrum {spectrum.name!r}")


def _clip_to_validity(spectrum: Spectrum, omega_min: float, omega_max: float) -> tuple[float, float]:
    lo, hi = spectrum.validity
    return max(omega_min, lo), min(omega_max, hi)


def band_variance(spectrum: Spectrum, omega_min: float | None = None, omega_max: float | None = None) -> float:
    """Variance sigma^2 = integral of the one-sided PSD over [omega_min, omega_max] [unit^2].

    Adaptive quadrature (scipy.integrate.quad) in log(omega) on pieces split at the spectrum's
    breakpoints and at every decade, relative tolerance 1e-12 per piece; [0, first edge] is
    integrated in linear omega, and so is [last edge, inf) (by quad's own mapping of infinite limits).
    Defaults to the spectrum's default band.
    """
    lo, hi = spectrum.default_band
    omega_min = lo if omega_min is None else float(omega_min)
    omega_max = hi if omega_max is None else float(omega_max)
    check_band(spectrum, omega_min, omega_max)
    omega_min, omega_max = _clip_to_validity(spectrum, omega_min, omega_max)
    first = omega_min if omega_min > 0 else min([p for p in spectrum.breakpoints() if p > 0] + [1.0, omega_max]) / 10
    last = omega_max if math.isfinite(omega_max) else max(list(spectrum.breakpoints()) + [first]) * 10
    decades = 10.0 ** np.arange(math.ceil(math.log10(first)), math.floor(math.log10(last)) + 1)
    inner = [p for p in (*spectrum.breakpoints(), *decades) if first < p < last]
    edges = np.log(np.unique([first, *inner, last]))

    def in_log(u: float) -> float:
        w = math.exp(u)
        return float(spectrum.psd(w)) * w

    from scipy.integrate import quad  # here: importing scipy.integrate costs 0.5 s per worker process

    kw = dict(epsabs=0.0, epsrel=1e-12, limit=200)
    total = sum(quad(in_log, a, b, **kw)[0] for a, b in zip(edges[:-1], edges[1:]))
    if omega_min == 0:
        total += quad(lambda w: float(spectrum.psd(w)), 0.0, first, **kw)[0]
    if math.isinf(omega_max):
        total += quad(lambda w: float(spectrum.psd(w)), last, math.inf, **kw)[0]
    return total


def closed_form_variance(spectrum: Spectrum, omega_min: float | None = None,
                         omega_max: float | None = None) -> float:
    """Exact band variance where a closed form exists (German, FRA rad/m form, TB/T 3352, tables).

    Rational spectra use partial fractions (arctan terms), power laws and log-log tables integrate
    segment by segment. Raises SpectrumError for spectra without one (Fryba's form).
    Full band of German vertical: pi A_v Oc / (2 Or (Or + Oc)).
    """
    lo, hi = spectrum.default_band
    omega_min = lo if omega_min is None else float(omega_min)
    omega_max = hi if omega_max is None else float(omega_max)
    check_band(spectrum, omega_min, omega_max)
    return spectrum.closed_form_variance(*_clip_to_validity(spectrum, omega_min, omega_max))


def temporal_psd_rad(spectrum: Spectrum, omega_t: ArrayLike, v: float) -> NDArray[np.float64]:
    """One-sided temporal PSD per rad/s at speed v [m/s]: S_t(omega) = S(omega / v) / v."""
    _check_speed(v)
    return spectrum.psd(np.asarray(omega_t, dtype=float) / v) / v


def temporal_psd_hz(spectrum: Spectrum, f: ArrayLike, v: float) -> NDArray[np.float64]:
    """One-sided temporal PSD per Hz at speed v [m/s]: S(f) = 2 pi S_t(2 pi f)."""
    return 2 * math.pi * temporal_psd_rad(spectrum, 2 * math.pi * np.asarray(f, dtype=float), v)


def _check_speed(v: float) -> None:
    if not (math.isfinite(v) and v > 0):
        raise SpectrumError(f"speed must be finite and > 0 m/s, got {v!r}")
