"""Ride-comfort weightings and indices: EN 12299 filters Wb, Wc, Wd and the Sperling ride index Wz.

Plain numpy/scipy. Sources: docs/references.md (ride comfort; the weightings read in public code:
comfpy filters.py; a BS 6841 band-limit script).

EN 12299 weightings (analog, s = j 2 pi f, w_i = 2 pi f_i), W = H_h H_l H_t H_s:

    H_h = s^2 / (s^2 + w1 s / Q1 + w1^2)                        high-pass (band limit), Q1 = 1/sqrt(2)
    H_l = w2^2 / (s^2 + w2 s / Q1 + w2^2)                       low-pass (band limit)
    H_t = (1 + s / w3) / (1 + s / (Q4 w4) + s^2 / w4^2)          acceleration-velocity transition
    H_s = K (1 + s / (Q5 w5) + s^2 / w5^2) / (1 + s / (Q6 w6) + s^2 / w6^2)   upward step (Wb only)

    Wb (vertical):   f1 0.4, f2 100, f3 16, f4 16, Q4 0.63, f5 2.5, Q5 0.8, f6 4, Q6 0.8, K 0.4
    Wd (horizontal): f1 0.4, f2 100, f3 2,  f4 2,  Q4 0.63 (no H_s)
    Wc:              f1 0.4, f2 100, f3 8,  f4 8,  Q4 0.63 (no H_s)

Time-domain application (:func:`apply_weighting`): each of the (up to) four second-order sections is
turned into a digital biquad by the bilinear transform prewarped at the section's own characteristic
frequency (f1, f2, f4, sqrt(f5 f6)) when it lies below 0.45 fs (else without prewarping: it is then
outside the sampled band), and the cascade runs from rest at ``oversample`` times the signal's rate:
the signal is interpolated up and the result decimated back by polyphase FIR filters
(scipy.signal.resample_poly, Kaiser window beta = 8). Bilinear alone at fs = 100 Hz is within 0.15 %
of |H| up to 16 Hz but 13 % low at 25 Hz (frequency warping); oversampled to >= 2000 Hz (the default)
the measured steady-state error is <= 0.25 % of |H(f)| in amplitude and <= 0.35 degree in phase up to
0.7 times the Nyquist frequency (35 Hz at fs = 100 Hz), and about -2 % at 0.8 times (the transition
band of the interpolation filters), for Wb, Wc and Wd at fs = 100 and 200 Hz
(tests/system/test_comfort.py). The interpolation filters are
symmetric (zero phase), so the cascade is causal up to their half-length (about 10 samples of the
original rate). A signal that does not start at 0 gives a start-up transient of a few seconds (the
0.4 Hz high-pass).

Sperling ride index (:func:`sperling_weighting`, docs/references.md, ride comfort): with the frequency weighting
B(f) = 0.588 sqrt((1.911 f^2 + (0.25 f^2)^2) / ((1 - 0.277 f^2)^2 + (1.563 f - 0.0368 f^3)^2)) for
vertical motion and 1.25 B(f) for lateral motion, and the one-sided acceleration PSD G_a [(m/s^2)^2/Hz],
the form used here is the integral form (Forstberg's)

    Wz = [2 integral (100 B(f))^2 G_a(f) df]^0.15 = 4.42 a_B,rms^0.3

(100: m/s^2 to cm/s^2; a_B,rms = the B-weighted r.m.s. in m/s^2; (2 * 1e4)^0.15 = 4.42). The factor 2
makes a harmonic of amplitude A [m/s^2] at f give Wz = (B(f) * 100 A)^0.3, Sperling's single-frequency
formula W = (B a)^0.3 with a the amplitude in cm/s^2 (= 0.896 (a^3 F(f)/f)^0.1, GB 5599's
7.08 (A_g^3 F(f)/f)^0.1, to within the accuracy of B as a fit of F: 1 % for 1-10 Hz vertical).
For broadband input the band form [sum_i (B(f_i) a_i)^3]^0.1 over amplitudes a_i depends on the
frequency resolution and is not used. The index of a record depends on its length: GB/T 5599-2019
evaluates windows of 5 s (:func:`sperling_windows`); a PEM result gives the index of the expected PSD
averaged over each window (:func:`sperling_windows_from_psd`), which for a random signal is the
expected Wz^(1/0.15) of a window, not the expected Wz: x^0.15 is concave, so the mean of per-window
Wz of Monte Carlo samples is lower, by about 0.064 CV^2 for a per-window relative spread CV of the
weighted power (CV = 0.27, 0.5 % for 5 s windows of the car-body-like PSD of the tests).

Units: frequencies in Hz, accelerations in m/s^2, times in s; Wz is dimensionless.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import SettingError

WeightingName = Literal["wb", "wc", "wd"]
Direction = Literal["vertical", "lateral"]
DIRECTIONS: tuple[str, ...] = ("vertical", "lateral")

Q1 = 1.0 / math.sqrt(2.0)


@dataclass(frozen=True)
class WeightingParameters:
    """Pole/zero data of an EN 12299 weighting (docs/references.md, ride comfort): frequencies [Hz], quality factors, gain.
    ``f5`` = 0 means no H_s section (Wc, Wd)."""

    name: str
    f1: float
    f2: float
    f3: float
    f4: float
    q4: float
    f5: float = 0.0
    q5: float = 1.0
    f6: float = 0.0
    q6: float = 1.0
    k: float = 1.0


WEIGHTINGS: dict[str, WeightingParameters] = {
    "wb": WeightingParameters("wb", 0.4, 100.0, 16.0, 16.0, 0.63, 2.5, 0.8, 4.0, 0.8, 0.4),
    "wc": WeightingParameters("wc", 0.4, 100.0, 8.0, 8.0, 0.63),
    "wd": WeightingParameters("wd", 0.4, 100.0, 2.0, 2.0, 0.63),
}


def _parameters(name: str, where: str) -> WeightingParameters:
    if name not in WEIGHTINGS:
        raise SettingError(where, "name", name, " | ".join(repr(n) for n in WEIGHTINGS))
    return WEIGHTINGS[name]


def weighting_sections(name: WeightingName) -> list[tuple[NDArray[np.float64], NDArray[np.float64], float]]:
    """The analog sections (numerator, denominator, characteristic frequency [Hz]) of a weighting, as
    polynomials in s (highest power first): H_h, H_l, H_t and (Wb) H_s."""
    p = _parameters(name, "weighting_sections")
    w1, w2, w3, w4 = (2 * math.pi * f for f in (p.f1, p.f2, p.f3, p.f4))
    out = [
        (np.array([1.0, 0.0, 0.0]), np.array([1.0, w1 / Q1, w1 * w1]), p.f1),
        (np.array([0.0, 0.0, w2 * w2]), np.array([1.0, w2 / Q1, w2 * w2]), p.f2),
        (np.array([0.0, 1.0 / w3, 1.0]), np.array([1.0 / w4 ** 2, 1.0 / (p.q4 * w4), 1.0]), p.f4),
    ]
    if p.f5 > 0:
        w5, w6 = 2 * math.pi * p.f5, 2 * math.pi * p.f6
        out.append((p.k * np.array([1.0 / w5 ** 2, 1.0 / (p.q5 * w5), 1.0]),
                    np.array([1.0 / w6 ** 2, 1.0 / (p.q6 * w6), 1.0]), math.sqrt(p.f5 * p.f6)))
    return out


def weighting_response(name: WeightingName, freq: ArrayLike) -> NDArray[np.complex128]:
    """The complex frequency response H(f) = H_h H_l H_t H_s of weighting ``name`` at ``freq`` [Hz]."""
    s = 2j * np.pi * np.asarray(freq, dtype=float)
    h = np.ones_like(s)
    for num, den, _ in weighting_sections(name):
        h = h * np.polyval(num, s) / np.polyval(den, s)
    return h


def weighting_sos(name: WeightingName, fs: float) -> NDArray[np.float64]:
    """Second-order sections (scipy 'sos' layout) of the digital weighting at sampling rate fs [Hz]:
    the bilinear transform of each analog section, prewarped at its characteristic frequency when that
    is below 0.45 fs."""
    from scipy import signal

    if not (isinstance(fs, (int, float)) and fs > 0 and math.isfinite(fs)):
        raise SettingError("weighting_sos", "fs", fs, "a sampling rate > 0 in Hz")
    sos = []
    for num, den, fc in weighting_sections(name):
        if fc < 0.45 * fs:
            wp = 2 * math.pi * fc
            rate = wp / (2.0 * math.tan(wp / (2.0 * fs)))  # bilinear's 2/T replaced by wp / tan(wp T/2)
        else:
            rate = float(fs)
        b, a = signal.bilinear(num, den, rate)
        b = np.concatenate([np.zeros(3 - len(b)), b])
        sos.append(np.concatenate([b / a[0], a / a[0]]))
    return np.array(sos)


def default_oversample(fs: float) -> int:
    """The smallest integer factor that brings fs to at least 2000 Hz (1 when fs >= 2000 Hz)."""
    return max(1, math.ceil(2000.0 / fs - 1e-12))


def apply_weighting(signal_: ArrayLike, fs: float, name: WeightingName, *, oversample: int | None = None,
                    axis: int = -1) -> NDArray:
    """The weighted signal: EN 12299 weighting ``name`` applied from rest along ``axis``.

    signal_ : samples at rate fs [Hz] (real, or complex pseudo-responses: the filter is linear and real,
        so real and imaginary parts are filtered independently); same shape out.
    oversample : rate multiplier for the digital filter (default :func:`default_oversample`); see the
        module text for the accuracy.
    """
    from scipy import signal

    x = np.asarray(signal_)
    m = default_oversample(fs) if oversample is None else int(oversample)
    if m < 1:
        raise SettingError("apply_weighting", "oversample", oversample, "an integer >= 1")
    sos = weighting_sos(name, fs * m)
    if m == 1:
        return signal.sosfilt(sos, x, axis=axis)
    window = ("kaiser", 8.0)
    up = signal.resample_poly(x, m, 1, axis=axis, window=window)
    y = signal.sosfilt(sos, up, axis=axis)
    out = signal.resample_poly(y, 1, m, axis=axis, window=window)
    return np.take(out, np.arange(x.shape[axis]), axis=axis)


# ============================================================================================ Sperling
def sperling_weighting(freq: ArrayLike, direction: Direction = "vertical") -> NDArray[np.float64]:
    """Sperling's frequency weighting B(f) (vertical), 1.25 B(f) (lateral); freq in Hz."""
    if direction not in DIRECTIONS:
        raise SettingError("sperling_weighting", "direction", direction, " | ".join(map(repr, DIRECTIONS)))
    f = np.asarray(freq, dtype=float)
    f2 = f * f
    b = 0.588 * np.sqrt((1.911 * f2 + (0.25 * f2) ** 2) / ((1 - 0.277 * f2) ** 2 + (1.563 * f - 0.0368 * f * f2) ** 2))
    return 1.25 * b if direction == "lateral" else b


def _band_mask(freq: NDArray[np.float64], band: tuple[float, float] | None, where: str) -> NDArray[np.bool_]:
    if band is None:
        return np.ones(freq.shape, dtype=bool)
    try:
        lo, hi = (float(b) for b in band)
    except (TypeError, ValueError):
        raise SettingError(where, "band", band, "(f_low, f_high) in Hz") from None
    if not 0 <= lo < hi:
        raise SettingError(where, "band", band, "(f_low, f_high) in Hz with 0 <= f_low < f_high")
    return (freq >= lo) & (freq <= hi)


#: Wz = energy^SPERLING_EXPONENT (module text)
SPERLING_EXPONENT = 0.15


def sperling_power_weights(freq: ArrayLike, direction: Direction = "vertical") -> NDArray[np.float64]:
    """2 (100 B(f))^2 per frequency: the Sperling energy of a response is the sum of these weights times
    the response's variance at each frequency (G(f_k) df_k, or |y_k|^2 of a PEM pseudo-response)."""
    return 2.0 * (100.0 * sperling_weighting(freq, direction)) ** 2


def sperling_index(energy: ArrayLike) -> NDArray[np.float64]:
    """Wz = energy^0.15 from the Sperling energy 2 sum (100 B)^2 G df (negative round-off clipped to 0)."""
    return np.power(np.maximum(np.asarray(energy, dtype=float), 0.0), SPERLING_EXPONENT)


def sperling_energy(freq: ArrayLike, psd: ArrayLike, df: ArrayLike, direction: Direction = "vertical", *,
                    band: tuple[float, float] | None = None, axis: int = 0) -> NDArray[np.float64]:
    """The Sperling energy 2 sum_k (100 B(f_k))^2 G_a(f_k) df_k of a one-sided acceleration PSD (arguments
    as :func:`sperling_from_psd`)."""
    f = np.asarray(freq, dtype=float)
    g = np.moveaxis(np.asarray(psd, dtype=float), axis, 0)
    if g.shape[0] != f.size:
        raise SettingError("sperling_from_psd", "psd", f"array of shape {np.shape(psd)}",
                           f"{f.size} frequencies along axis {axis}")
    w = np.broadcast_to(np.asarray(df, dtype=float), f.shape) * _band_mask(f, band, "sperling_from_psd")
    return np.tensordot(sperling_power_weights(f, direction) * w, g, axes=(0, 0))


def sperling_from_psd(freq: ArrayLike, psd: ArrayLike, df: ArrayLike, direction: Direction = "vertical", *,
                      band: tuple[float, float] | None = None, axis: int = 0) -> NDArray[np.float64]:
    """Wz = [2 sum_k (100 B(f_k))^2 G_a(f_k) df_k]^0.15 of a one-sided acceleration PSD.

    freq : (n_f,) [Hz]; psd : G_a [(m/s^2)^2/Hz] with the frequency along ``axis`` (e.g. a PEM
    psd (n_f, n_t): one index per time); df : quadrature widths [Hz], scalar or (n_f,);
    band : (f_low, f_high) [Hz] to restrict the sum to, or None (all given frequencies).
    """
    return sperling_index(sperling_energy(freq, psd, df, direction, band=band, axis=axis))


@dataclass(frozen=True)
class WindowedIndex:
    """An index evaluated over consecutive windows of a record.

    quantity : e.g. 'sperling_vertical', 'rms'
    start : (n_w,) window start times [s]; window : window length [s] actually used (whole samples)
    values : (n_w,) the index per window (or (n_w, ...) for several signals)
    """

    quantity: str
    start: NDArray[np.float64]
    window: float
    values: NDArray[np.float64]

    @property
    def max(self) -> float:
        """The largest window value (the statistic the limits compare)."""
        return float(np.max(self.values))


def window_slices(n: int, fs: float, window: float, where: str = "window_slices") -> tuple[list[slice], float]:
    """Consecutive, non-overlapping windows of round(window fs) samples from the first sample; a last,
    shorter remainder is dropped (it would change the frequency resolution). Returns (slices, length [s])."""
    if not (window > 0 and math.isfinite(window)):
        raise SettingError(where, "window", window, "a window length > 0 in s")
    m = int(round(window * fs))
    if m < 2 or m > n:
        raise SettingError(where, "window", window,
                           f"a length between 2 samples and the record ({n / fs:g} s at {fs:g} Hz)")
    return [slice(i, i + m) for i in range(0, n - m + 1, m)], m / fs


def sperling_window_energy(acc: ArrayLike, fs: float, direction: Direction = "vertical", *, window: float = 5.0,
                           band: tuple[float, float] | None = None) -> tuple[list[slice], float, NDArray[np.float64]]:
    """(windows, window length [s], Sperling energy per window (..., n_w)) of acceleration histories
    (..., n_t) [m/s^2] at fs [Hz] (time along the last axis): each window's one-sided periodogram
    (rectangular window, G_k = 2 |X_k|^2 / (N fs), the Nyquist bin not doubled, the mean bin excluded)
    enters :func:`sperling_energy` with df = fs / N."""
    a = np.asarray(acc, dtype=float)
    if a.ndim < 1:
        raise SettingError("sperling_windows", "acc", f"array of shape {a.shape}", "time histories (..., n_t)")
    slices, length = window_slices(a.shape[-1], fs, window, "sperling_windows")
    m = slices[0].stop - slices[0].start
    freq = np.fft.rfftfreq(m, 1.0 / fs)
    scale = np.full(freq.size, 2.0 / (m * fs))
    scale[0] = 0.0
    if m % 2 == 0:
        scale[-1] = 1.0 / (m * fs)
    blocks = np.stack([a[..., s] for s in slices], axis=-2)
    psd = np.abs(np.fft.rfft(blocks, axis=-1)) ** 2 * scale
    return slices, length, sperling_energy(freq, psd, fs / m, direction, band=band, axis=-1)


def sperling_windows(acc: ArrayLike, fs: float, direction: Direction = "vertical", *, window: float = 5.0,
                     band: tuple[float, float] | None = None, start_time: float = 0.0) -> WindowedIndex:
    """Sperling Wz of an acceleration time history [m/s^2] sampled at fs [Hz], per window of ``window`` s
    (default 5 s, GB/T 5599-2019 [check]; docs/references.md, ride comfort); several histories (..., n_t) give
    values (..., n_w).

    Each window's one-sided periodogram (rectangular window, G_k = 2 |X_k|^2 / (N fs), the Nyquist bin
    not doubled, the mean bin excluded) enters :func:`sperling_from_psd` with df = fs / N.
    """
    slices, length, energy = sperling_window_energy(acc, fs, direction, window=window, band=band)
    start = start_time + np.array([s.start for s in slices]) / fs
    return WindowedIndex(f"sperling_{direction}", start, length, sperling_index(energy))


def sperling_windows_from_psd(time: ArrayLike, freq: ArrayLike, df: ArrayLike, psd: ArrayLike,
                              direction: Direction = "vertical", *, window: float = 5.0,
                              band: tuple[float, float] | None = None) -> WindowedIndex:
    """Sperling Wz per window of a time-dependent PSD (PEM): psd (n_f, n_t) [(m/s^2)^2/Hz] at the
    uniformly spaced ``time`` [s], averaged over each window's time samples (the windows of
    :func:`window_slices`), then :func:`sperling_from_psd`."""
    t = np.asarray(time, dtype=float)
    g = np.asarray(psd, dtype=float)
    if t.ndim != 1 or t.size < 2 or g.ndim != 2 or g.shape[1] != t.size:
        raise SettingError("sperling_windows_from_psd", "psd", f"array of shape {g.shape}",
                           f"(n_f, n_t = {t.size}) matching time")
    dt = float(np.mean(np.diff(t)))
    slices, length = window_slices(t.size, 1.0 / dt, window, "sperling_windows_from_psd")
    mean_psd = np.stack([g[:, s].mean(axis=1) for s in slices], axis=1)
    values = sperling_from_psd(freq, mean_psd, df, direction, band=band, axis=0)
    return WindowedIndex(f"sperling_{direction}", t[[s.start for s in slices]], length, values)


def windowed_rms(signal_: ArrayLike, fs: float, *, window: float = 5.0, start_time: float = 0.0) -> WindowedIndex:
    """The r.m.s. of a (weighted) signal over consecutive windows of ``window`` s (EN 12299 uses 5 s
    r.m.s. values of the weighted accelerations [recalled])."""
    x = np.asarray(signal_, dtype=float)
    slices, length = window_slices(x.size, fs, window, "windowed_rms")
    values = np.array([math.sqrt(float(np.mean(x[s] ** 2))) for s in slices])
    return WindowedIndex("rms", start_time + np.array([s.start for s in slices]) / fs, length, values)


__all__ = [
    "DIRECTIONS", "SPERLING_EXPONENT", "WEIGHTINGS", "WeightingParameters", "WindowedIndex", "apply_weighting",
    "default_oversample", "sperling_energy", "sperling_from_psd", "sperling_index", "sperling_power_weights",
    "sperling_weighting", "sperling_window_energy", "sperling_windows", "sperling_windows_from_psd", "weighting_response",
    "weighting_sections", "weighting_sos", "window_slices", "windowed_rms",
]
