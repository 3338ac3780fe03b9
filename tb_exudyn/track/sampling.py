"""Sampled irregularity profiles (spectral representation, Shinozuka & Deodatis 1991).

For a one-sided PSD G(omega) a sample is r(x) = sum_k sqrt(2 G(omega_k) w_k) cos(omega_k x + phi_k),
phi_k ~ U[0, 2 pi) independent, so that E[r(x)^2] = sum_k G(omega_k) w_k at every x.
Randomness only comes from a ``numpy.random.Generator`` passed in; ``sample_rng(seed, index)`` gives
the generator of Monte Carlo sample ``index``, the same whichever worker runs it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .bands import check_band
from .spectra import HALF_RAIL_DISTANCE, Spectrum, SpectrumError

_CHUNK = 2_000_000  # max elements of one (points x frequencies) block in HarmonicProfile


def sample_rng(seed: int, index: int) -> np.random.Generator:
    """Independent generator for sample ``index`` of a run seeded with ``seed``.

    Identical to ``np.random.default_rng(np.random.SeedSequence(seed).spawn(index + 1)[index])``
    but O(1) in ``index``: the child seed sequence has spawn_key ``(index,)``.
    """
    if int(seed) != seed or seed < 0 or int(index) != index or index < 0:
        raise ValueError(f"seed and index must be integers >= 0, got seed={seed!r}, index={index!r}")
    return np.random.default_rng(np.random.SeedSequence(int(seed), spawn_key=(int(index),)))


def _frozen(values: ArrayLike) -> NDArray[np.float64]:
    """Read-only float copy (profiles are immutable)."""
    out = np.array(values, dtype=float)
    out.flags.writeable = False
    return out


@dataclass(frozen=True, eq=False)
class TrackProfile:
    """An irregularity profile r(x) along the track, x [m] in the direction of travel.

    ``value(x)`` and ``derivative(x)`` (dr/dx) accept any array shape and return that shape.
    ``unit`` is the unit of r ("m" or "rad"); ``kind`` the irregularity kind.
    """

    unit: str
    kind: str

    def value(self, x: ArrayLike) -> NDArray[np.float64]:
        raise NotImplementedError

    def derivative(self, x: ArrayLike) -> NDArray[np.float64]:
        raise NotImplementedError


@dataclass(frozen=True, eq=False)
class HarmonicProfile(TrackProfile):
    """Exact sum r(x) = sum_k amplitude_k cos(omega_k x + phase_k); valid for every x.

    Periodic with period 2 pi / d_omega for a mid-point grid without jitter.
    """

    omega: NDArray[np.float64] = field(default_factory=lambda: np.zeros(0))
    amplitude: NDArray[np.float64] = field(default_factory=lambda: np.zeros(0))
    phase: NDArray[np.float64] = field(default_factory=lambda: np.zeros(0))

    def __post_init__(self) -> None:
        for name in ("omega", "amplitude", "phase"):
            object.__setattr__(self, name, _frozen(getattr(self, name)))
        if not self.omega.shape == self.amplitude.shape == self.phase.shape or self.omega.ndim != 1:
            raise ValueError("omega, amplitude and phase must be 1-D arrays of the same length")

    def _sum(self, x: ArrayLike, derivative: bool) -> NDArray[np.float64]:
        x = np.asarray(x, dtype=float)
        flat = x.ravel()
        out = np.empty_like(flat)
        step = max(1, _CHUNK // max(1, self.omega.size))
        coef = -self.amplitude * self.omega if derivative else self.amplitude
        trig = np.sin if derivative else np.cos
        for i in range(0, flat.size, step):
            out[i:i + step] = trig(np.outer(flat[i:i + step], self.omega) + self.phase) @ coef
        return out.reshape(x.shape)

    def value(self, x: ArrayLike) -> NDArray[np.float64]:
        return self._sum(x, derivative=False)

    def derivative(self, x: ArrayLike) -> NDArray[np.float64]:
        return self._sum(x, derivative=True)


@dataclass(frozen=True, eq=False)
class GridProfile(TrackProfile):
    """Profile sampled on x_start + dx * i, i = 0..n-1, interpolated "linear" or "cubic" (spline).

    Evaluation outside [x_start, x_end] raises ValueError (no extrapolation).
    """

    x_start: float = 0.0
    dx: float = 1.0
    values: NDArray[np.float64] = field(default_factory=lambda: np.zeros(2))
    interpolation: str = "cubic"
    _spline: Any = field(init=False, repr=False, default=None)  # a scipy CubicSpline, built on first use

    def __post_init__(self) -> None:
        object.__setattr__(self, "values", _frozen(self.values))
        if self.values.ndim != 1 or self.values.size < 2 or not self.dx > 0:
            raise ValueError("a grid profile needs dx > 0 and at least two values in a 1-D array")
        if self.interpolation not in ("linear", "cubic"):
            raise ValueError(f"interpolation must be 'linear' or 'cubic', got {self.interpolation!r}")
        if self.interpolation == "cubic":
            x = self.x_start + self.dx * np.arange(self.values.size)
            from scipy.interpolate import CubicSpline  # on first use: keeps 0.2 s out of every import

            object.__setattr__(self, "_spline", CubicSpline(x, self.values))

    @property
    def x_end(self) -> float:
        return self.x_start + self.dx * (self.values.size - 1)

    def _check(self, x: ArrayLike) -> NDArray[np.float64]:
        x = np.asarray(x, dtype=float)
        tol = 1e-9 * self.dx
        if x.size and (x.min() < self.x_start - tol or x.max() > self.x_end + tol):
            raise ValueError(f"x in [{x.min():g}, {x.max():g}] m outside the profile [{self.x_start:g}, "
                             f"{self.x_end:g}] m")
        return x

    def _segment(self, x: NDArray[np.float64]) -> NDArray[np.intp]:
        return np.clip(((x - self.x_start) // self.dx).astype(np.intp), 0, self.values.size - 2)

    def value(self, x: ArrayLike) -> NDArray[np.float64]:
        x = self._check(x)
        if self._spline is not None:
            return self._spline(x)
        i = self._segment(x)
        t = (x - self.x_start) / self.dx - i
        return (1 - t) * self.values[i] + t * self.values[i + 1]

    def derivative(self, x: ArrayLike) -> NDArray[np.float64]:
        x = self._check(x)
        if self._spline is not None:
            return self._spline(x, 1)
        i = self._segment(x)
        return (self.values[i + 1] - self.values[i]) / self.dx


@dataclass(frozen=True, eq=False)
class CombinedProfile(TrackProfile):
    """Linear combination sum_i c_i r_i(x) of profiles (e.g. a rail from vertical and cross-level)."""

    terms: tuple[tuple[float, TrackProfile], ...] = ()

    def value(self, x: ArrayLike) -> NDArray[np.float64]:
        return sum(c * p.value(x) for c, p in self.terms)  # type: ignore[return-value]

    def derivative(self, x: ArrayLike) -> NDArray[np.float64]:
        return sum(c * p.derivative(x) for c, p in self.terms)  # type: ignore[return-value]


def rail_profiles(vertical: TrackProfile, cross_level: TrackProfile,
                  half_distance: float = HALF_RAIL_DISTANCE) -> tuple[CombinedProfile, CombinedProfile]:
    """Left and right rail vertical profiles z_L,R = z_v +- b theta_c.

    Left is the +y side (y to the left of the direction of travel, z up), so a positive cross-level
    angle theta_c (a positive rotation about +x) raises the left rail. A cross-level given as a height
    difference h [m] (unit "m") enters as z_L,R = z_v +- h/2.
    """
    if vertical.unit != "m" or cross_level.unit not in ("rad", "m"):
        raise SpectrumError(f"rail_profiles needs a vertical profile in m and a cross-level in rad or m, "
                            f"got {vertical.unit!r} and {cross_level.unit!r}")
    arm = half_distance if cross_level.unit == "rad" else 0.5
    left = CombinedProfile(unit="m", kind="vertical", terms=((1.0, vertical), (arm, cross_level)))
    right = CombinedProfile(unit="m", kind="vertical", terms=((1.0, vertical), (-arm, cross_level)))
    return left, right


def _band(spectrum: Spectrum, band: tuple[float, float] | None) -> tuple[float, float]:
    lo, hi = spectrum.default_band if band is None else band
    check_band(spectrum, lo, hi)
    if math.isinf(hi):
        raise SpectrumError(f"sampling needs a finite band, got upper limit {hi!r} rad/m")
    return float(lo), float(hi)


def harmonic_profile(spectrum: Spectrum, rng: np.random.Generator, n_frequencies: int,
                     band: tuple[float, float] | None = None, jitter: float = 0.0) -> HarmonicProfile:
    """Spectral-representation sample with mid-point frequencies.

    omega_k = omega_min + (k - 1/2) d_omega, k = 1..n, d_omega = (omega_max - omega_min)/n,
    amplitude sqrt(2 G(omega_k) d_omega), phase ~ U[0, 2 pi). With ``jitter`` in [0, 1] each
    frequency moves by d_omega * U(-jitter/2, jitter/2) (amplitudes stay at the nominal frequency,
    so the variance is unchanged); this breaks the period 2 pi / d_omega. Without jitter, choose
    n so that the period exceeds the track length.

    Parameters
    ----------
    spectrum : one-sided spatial PSD.
    rng : seeded generator (e.g. ``sample_rng(seed, index)``); draws phases first, then jitter.
    n_frequencies : number of harmonics n >= 1.
    band : (omega_min, omega_max) [rad/m]; default ``spectrum.default_band``.
    jitter : fraction of d_omega, 0 <= jitter <= 1.
    """
    lo, hi = _band(spectrum, band)
    if int(n_frequencies) != n_frequencies or n_frequencies < 1:
        raise ValueError(f"n_frequencies must be an integer >= 1, got {n_frequencies!r}")
    if not 0.0 <= jitter <= 1.0:
        raise ValueError(f"jitter must be in [0, 1], got {jitter!r}")
    d_omega = (hi - lo) / n_frequencies
    omega = lo + (np.arange(n_frequencies) + 0.5) * d_omega
    amplitude = np.sqrt(2 * spectrum.psd(omega) * d_omega)
    phase = rng.uniform(0.0, 2 * math.pi, n_frequencies)
    if jitter:
        omega = omega + d_omega * jitter * rng.uniform(-0.5, 0.5, n_frequencies)
    return HarmonicProfile(unit=spectrum.unit, kind=spectrum.kind, omega=omega, amplitude=amplitude, phase=phase)


def fft_bins(omega_min: float, omega_max: float, n_fft: int, dx: float
             ) -> tuple[NDArray[np.intp], NDArray[np.float64], NDArray[np.float64]]:
    """FFT bins used for a band: indices k, quadrature weights w_k and PSD nodes [rad/m].

    Bin k is the cell [k, k + 1] d_omega (d_omega = 2 pi / (n_fft dx)); its harmonic has frequency
    (k + 1/2) d_omega. Its weight is the length of the cell's overlap with [omega_min, omega_max]
    (so sum w_k = band width) and its node the centre of that overlap (the bin centre except in the
    two partial edge bins), where the PSD is evaluated.
    """
    d_omega = 2 * math.pi / (n_fft * dx)
    k = np.arange(int(omega_min // d_omega), int(math.ceil(omega_max / d_omega)))
    left, right = np.maximum(k * d_omega, omega_min), np.minimum((k + 1) * d_omega, omega_max)
    keep = right > left
    return k[keep], (right - left)[keep], (0.5 * (left + right))[keep]


def fft_profile(spectrum: Spectrum, rng: np.random.Generator, length: float, dx: float,
                band: tuple[float, float] | None = None, x_start: float = 0.0,
                interpolation: str = "cubic") -> GridProfile:
    """Spectral-representation sample on a grid by one FFT (for long tracks).

    The same process as ``harmonic_profile`` with frequencies on the FFT grid shifted by half a bin,
    omega_k = (k + 1/2) d_omega, d_omega = 2 pi / (N dx), N = next fast length >= number of points,
    and amplitudes sqrt(2 G(node_k) w_k), w_k and node_k the length and centre of the overlap of bin k
    with the band (see ``fft_bins``), so the ensemble variance is sum G w ~ band variance. Computed as
    r_m = Re(exp(i pi m / N) N ifft(c)_m), c_k = amplitude_k exp(i phi_k).

    Parameters
    ----------
    spectrum : one-sided spatial PSD.
    rng : seeded generator; draws one phase per bin in the band, in increasing frequency.
    length, dx : track length and grid spacing [m]; points x_start + i dx cover [x_start, x_start + length].
    band : (omega_min, omega_max) [rad/m], omega_max <= pi / dx (Nyquist); default the spectrum's.
    interpolation : "cubic" (spline, continuous slope) or "linear" between grid points.
    """
    lo, hi = _band(spectrum, band)
    if not (math.isfinite(dx) and dx > 0 and math.isfinite(length) and length > 0):
        raise ValueError(f"length and dx must be finite and > 0 m, got length={length!r}, dx={dx!r}")
    if hi > math.pi / dx * (1 + 1e-12):
        raise SpectrumError(f"band upper limit {hi:g} rad/m exceeds the Nyquist limit pi/dx = {math.pi / dx:g} "
                            f"rad/m of dx = {dx:g} m")
    n_points = int(math.ceil(length / dx - 1e-9)) + 1
    from scipy.fft import ifft, next_fast_len  # on first use: keeps 0.4 s out of every import

    n_fft = next_fast_len(n_points)
    k, w, node = fft_bins(lo, hi, n_fft, dx)
    coef = np.zeros(n_fft, dtype=complex)
    coef[k] = np.sqrt(2 * spectrum.psd(node) * w) * np.exp(1j * rng.uniform(0.0, 2 * math.pi, k.size))
    m = np.arange(n_points)
    values = (np.exp(1j * math.pi * m / n_fft) * (n_fft * ifft(coef)[:n_points])).real
    return GridProfile(unit=spectrum.unit, kind=spectrum.kind, x_start=float(x_start), dx=float(dx),
                       values=values, interpolation=interpolation)
