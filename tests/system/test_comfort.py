"""Ride-comfort weightings and the Sperling index (tb_exudyn.system.comfort) against independent forms.

References written here: the EN 12299 weightings as products over their poles and zeros (roots of
the quadratics of docs/references.md, code limits, computed in the test), steady-state sinusoid
amplitudes fitted by least squares, Sperling's single-frequency formula (B a)^0.3 and the GB 5599 form
7.08 (A^3 F(f)/f)^0.1, and a stationary Gaussian signal synthesised from a known PSD.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import integrate

from tb_exudyn.errors import SettingError
from tb_exudyn.system.comfort import (
    apply_weighting,
    sperling_from_psd,
    sperling_weighting,
    sperling_windows,
    sperling_windows_from_psd,
    weighting_response,
    windowed_rms,
)

# EN 12299 weighting parameters (docs/references.md, code limits), typed again here (not read from the module)
PARAMS = {
    "wb": dict(f1=0.4, f2=100.0, f3=16.0, f4=16.0, q4=0.63, f5=2.5, q5=0.8, f6=4.0, q6=0.8, k=0.4),
    "wd": dict(f1=0.4, f2=100.0, f3=2.0, f4=2.0, q4=0.63),
    "wc": dict(f1=0.4, f2=100.0, f3=8.0, f4=8.0, q4=0.63),
}


def _roots(w: float, q: float) -> np.ndarray:
    """Roots of s^2 + (w/q) s + w^2 by the quadratic formula (complex)."""
    disc = np.sqrt(complex((w / q) ** 2 - 4 * w * w))
    return np.array([(-w / q + disc) / 2, (-w / q - disc) / 2])


def pole_zero_response(name: str, f: np.ndarray) -> np.ndarray:
    """gain * prod(s - z) / prod(s - p) with the poles and zeros of H_h, H_l, H_t (and H_s)."""
    p = PARAMS[name]
    w = {k: 2 * math.pi * v for k, v in p.items() if k.startswith("f")}
    q1 = 1 / math.sqrt(2)
    zeros = [0.0, 0.0, -w["f3"]]
    poles = list(_roots(w["f1"], q1)) + list(_roots(w["f2"], q1)) + list(_roots(w["f4"], p["q4"]))
    gain = w["f2"] ** 2 * w["f4"] ** 2 / w["f3"]
    if "f5" in p:
        zeros += list(_roots(w["f5"], p["q5"]))
        poles += list(_roots(w["f6"], p["q6"]))
        gain *= p["k"] * w["f6"] ** 2 / w["f5"] ** 2
    s = 2j * math.pi * f
    return gain * np.prod([s - z for z in zeros], axis=0) / np.prod([s - pl for pl in poles], axis=0)


@pytest.mark.parametrize("name", ["wb", "wc", "wd"])
def test_weighting_response_against_poles_and_zeros(name):
    """H(f) equals the pole/zero product at 0.1-80 Hz to 1e-12 (rounding of two evaluation orders)."""
    f = np.array([0.1, 0.4, 1.0, 2.0, 2.5, 4.0, 8.0, 16.0, 40.0, 80.0])
    np.testing.assert_allclose(weighting_response(name, f), pole_zero_response(name, f), rtol=1e-12)


def test_weighting_shapes():
    """Plausibility of the pole/zero data: Wd is flat (|H| ~ 1) around 1 Hz and falls as 1/f above
    2 Hz; Wb has its plateau of about 1 near 5-16 Hz (K f6^2/f5^2 = 1.024) and is 0.4 at 1 Hz."""
    assert abs(weighting_response("wd", 1.0)) == pytest.approx(1.0, abs=0.07)
    assert abs(weighting_response("wd", 20.0)) * 20 / 2 == pytest.approx(1.0, abs=0.12)
    assert abs(weighting_response("wb", 10.0)) == pytest.approx(1.024, abs=0.1)
    assert abs(weighting_response("wb", 1.0)) == pytest.approx(0.4, abs=0.05)


def _steady_amplitude(y: np.ndarray, t: np.ndarray, f: float, after: float) -> complex:
    """Complex amplitude c of y ~ Im(c e^{i 2 pi f t}) fitted by least squares on t > after."""
    sel = t > after
    a = np.column_stack([np.sin(2 * np.pi * f * t[sel]), np.cos(2 * np.pi * f * t[sel])])
    cs, cc = np.linalg.lstsq(a, y[sel], rcond=None)[0]
    return complex(cs, cc)  # sin coefficient = Re, cos coefficient = Im of H for input sin


@pytest.mark.parametrize("name", ["wb", "wc", "wd"])
@pytest.mark.parametrize("fs", [100.0, 200.0])
def test_digital_weighting_against_response_for_sinusoids(name, fs):
    """A sinusoid through the digital weighting (default oversampling to >= 2000 Hz): the steady-state
    amplitude is within 0.3 % of |H(f)| and the phase within 0.4 degree up to 0.7 times the Nyquist
    frequency (measured <= 0.25 %, 0.31 degree), within 2.5 % at 0.8 times (the interpolation filters'
    transition band; measured -1.9 %). Least-squares fit on the last 20 s of 40 s (start-up decayed)."""
    t = np.arange(0.0, 40.0, 1.0 / fs)
    nyq = fs / 2
    for f in (0.5, 1.0, 2.0, 4.0, 8.0, 16.0, 0.5 * nyq, 0.7 * nyq, 0.8 * nyq):
        y = apply_weighting(np.sin(2 * np.pi * f * t), fs, name)
        c = _steady_amplitude(y, t, f, after=20.0)
        h = complex(weighting_response(name, f))
        tol = 0.003 if f <= 0.7 * nyq + 1e-9 else 0.025
        assert abs(abs(c) / abs(h) - 1) < tol, (f, abs(c) / abs(h) - 1)
        if f <= 0.7 * nyq + 1e-9:
            assert abs(math.degrees(np.angle(c / h))) < 0.4, (f, math.degrees(np.angle(c / h)))


def test_plain_bilinear_is_not_enough_at_100_hz():
    """Without oversampling (bilinear at fs = 100 Hz, sections prewarped) Wb is within 0.2 % up to
    16 Hz but more than 5 % low at 25 Hz (frequency warping): the reason for the default oversampling."""
    fs = 100.0
    t = np.arange(0.0, 40.0, 1.0 / fs)
    for f, ok in ((2.0, True), (8.0, True), (16.0, True), (25.0, False)):
        c = _steady_amplitude(apply_weighting(np.sin(2 * np.pi * f * t), fs, "wb", oversample=1), t, f, 20.0)
        err = abs(c) / abs(complex(weighting_response("wb", f))) - 1
        assert (abs(err) < 0.002) if ok else (err < -0.05), (f, err)


def test_complex_pseudo_responses_are_filtered_part_by_part():
    """Linearity with a real filter: weighting a complex signal = weighting its real and imaginary parts (1e-12)."""
    rng = np.random.default_rng(0)
    z = rng.standard_normal((3, 2000)) + 1j * rng.standard_normal((3, 2000))
    out = apply_weighting(z, 200.0, "wd", axis=1)
    ref = apply_weighting(z.real, 200.0, "wd", axis=1) + 1j * apply_weighting(z.imag, 200.0, "wd", axis=1)
    np.testing.assert_allclose(out, ref, rtol=1e-12, atol=1e-12)


# ============================================================================================ Sperling
@pytest.mark.parametrize("direction", ["vertical", "lateral"])
def test_sperling_of_a_harmonic_is_the_single_frequency_formula(direction):
    """a = A sin(2 pi f t), A = 0.8 m/s^2, f = 3 Hz (15 cycles per 5 s window, exactly on a bin):
    every window's Wz = (B(f) * 100 A)^0.3 to 1e-10 (the periodogram holds the whole power in one bin);
    the PSD form of the same line (G = A^2/2 at f, df = 1) too."""
    fs, amp, f = 200.0, 0.8, 3.0
    t = np.arange(0.0, 30.0, 1.0 / fs)
    res = sperling_windows(amp * np.sin(2 * np.pi * f * t), fs, direction, window=5.0)
    closed = (float(sperling_weighting(f, direction)) * 100 * amp) ** 0.3
    assert res.values.shape == (6,) and res.window == 5.0
    np.testing.assert_allclose(res.start, np.arange(6) * 5.0)
    np.testing.assert_allclose(res.values, closed, rtol=1e-10)
    assert float(sperling_from_psd([f], [amp ** 2 / 2], 1.0, direction)) == pytest.approx(closed, rel=1e-12)


def test_sperling_of_an_off_bin_harmonic_within_leakage():
    """f = 3.1 Hz (15.5 cycles per window): leakage spreads the power over neighbouring bins whose B
    differs, and the window mean (excluded bin) carries a little: within 1 % of the closed form."""
    fs, amp, f = 200.0, 0.8, 3.1
    t = np.arange(0.0, 30.0, 1.0 / fs)
    res = sperling_windows(amp * np.sin(2 * np.pi * f * t), fs, "vertical")
    closed = (float(sperling_weighting(f)) * 100 * amp) ** 0.3
    np.testing.assert_allclose(res.values, closed, rtol=0.01)


def test_sperling_b_weighting_against_gb5599_form():
    """Wz of a harmonic from B(f) against GB 5599's 7.08 (A_g^3 F(f)/f)^0.1 (docs/references.md, code limits):
    B is a fit of F; they agree within 1.2 % vertical and 2.5 % lateral at 1-10 Hz away from F's corners
    (5.9 Hz vertical: 2.5 %, 5.4 Hz lateral: 2.8 %), the fit accuracy measured when writing this test."""
    amp = 1.0
    for direction, freqs, tol in (("vertical", (1, 2, 3, 4, 5, 7, 10), 0.012),
                                  ("lateral", (1, 2, 3, 4, 5, 7, 10), 0.025)):
        for f in freqs:
            if direction == "vertical":
                F = 0.325 * f * f if f < 5.9 else (400 / f ** 2 if f < 20 else 1.0)
            else:
                F = 0.8 * f * f if f < 5.4 else (650 / f ** 2 if f < 26 else 1.0)
            gb = 7.08 * ((amp / 9.81) ** 3 * F / f) ** 0.1
            ours = (float(sperling_weighting(f, direction)) * 100 * amp) ** 0.3
            assert ours / gb == pytest.approx(1.0, abs=tol), (direction, f, ours / gb)


def _target_psd(f: np.ndarray) -> np.ndarray:
    """A car-body-like one-sided acceleration PSD [(m/s^2)^2/Hz]: a 1.2 Hz body mode and a broad tail, cut at 30 Hz."""
    return np.where(f < 30.0, 2e-3 / ((1 - (f / 1.2) ** 2) ** 2 + (2 * 0.2 * f / 1.2) ** 2) + 2e-4, 0.0)


def test_sperling_psd_form_against_time_history_form():
    """A stationary Gaussian signal with the PSD above (FFT synthesis with Gaussian coefficients, 1311 s
    at 100 Hz, 262 windows of 5 s): the mean over windows of Wz^(1/0.15) (each window's weighted power)
    equals 2 int (100 B)^2 G df (quad) within 3 standard errors plus 0.5 % (the periodogram's expected
    value is G smoothed by the Fejer kernel of a 5 s window: its bias for this G, computed from the
    kernel, is +0.38 %). The mean of Wz itself is
    the PSD form's within 3 standard errors plus the concavity bias 0.064 CV^2 (CV: relative spread of
    the window powers)."""
    rng = np.random.default_rng(12299)
    fs, n = 100.0, 2 ** 17
    f = np.fft.rfftfreq(n, 1 / fs)
    var = _target_psd(f) * (fs / n)
    var[0] = 0.0
    coef = rng.standard_normal(f.size) * np.sqrt(var) - 1j * rng.standard_normal(f.size) * np.sqrt(var)
    x = np.fft.irfft(coef * n / 2, n=n)
    res = sperling_windows(x, fs, "vertical", window=5.0)
    energies = res.values ** (1 / 0.15)
    ff = np.linspace(0.0, 30.0, 30001)
    exact = 2 * integrate.trapezoid((100 * sperling_weighting(ff)) ** 2 * _target_psd(ff), ff)
    se = energies.std() / math.sqrt(energies.size)
    assert abs(energies.mean() - exact) < 3 * se + 0.005 * exact, (energies.mean(), exact, se)
    psd_form = float(sperling_from_psd(ff, _target_psd(ff), ff[1] - ff[0]))
    assert psd_form == pytest.approx(exact ** 0.15, rel=1e-3)
    cv = energies.std() / energies.mean()
    se_wz = res.values.std() / math.sqrt(res.values.size)
    assert abs(res.values.mean() - psd_form) < 3 * se_wz + 0.064 * cv ** 2 * psd_form


def test_sperling_windows_from_a_time_dependent_psd():
    """PEM form: the PSD averaged over each 5 s window. A PSD that is G in the first window and 4 G in
    the second gives Wz ratio 4^0.15 between the two; a constant PSD gives sperling_from_psd in every window."""
    f = np.linspace(0.5, 20.0, 40)
    g = _target_psd(f)
    t = np.arange(0.0, 10.0, 0.01)
    psd = np.outer(g, np.where(t < 5.0, 1.0, 4.0))
    res = sperling_windows_from_psd(t, f, f[1] - f[0], psd, "lateral", window=5.0)
    one = float(sperling_from_psd(f, g, f[1] - f[0], "lateral"))
    np.testing.assert_allclose(res.values, [one, one * 4 ** 0.15], rtol=1e-12)
    np.testing.assert_allclose(res.start, [0.0, 5.0])


def test_sperling_band_restricts_the_sum():
    """A band that excludes the only line gives 0; one that includes it changes nothing."""
    assert float(sperling_from_psd([3.0], [0.5], 1.0, band=(0.5, 2.0))) == 0.0
    assert float(sperling_from_psd([3.0], [0.5], 1.0, band=(0.5, 40.0))) == float(sperling_from_psd([3.0], [0.5], 1.0))


def test_windowed_rms_of_a_sinusoid():
    """A sin with whole cycles per window: r.m.s. = A / sqrt(2) in every window (1e-12); the 2 s
    remainder of a 12 s record is dropped."""
    fs = 100.0
    t = np.arange(0.0, 12.0, 1 / fs)
    res = windowed_rms(0.3 * np.sin(2 * np.pi * 2.0 * t), fs, window=5.0)
    np.testing.assert_allclose(res.values, 0.3 / math.sqrt(2), rtol=1e-12)
    assert res.values.size == 2 and res.max == pytest.approx(0.3 / math.sqrt(2), rel=1e-12)


@pytest.mark.parametrize("call,key", [
    (lambda: sperling_weighting(1.0, "longitudinal"), "direction"),
    (lambda: sperling_windows(np.zeros(100), 100.0, window=5.0), "window"),
    (lambda: sperling_from_psd([1.0], [1.0], 1.0, band=(5.0, 1.0)), "band"),
    (lambda: weighting_response("wk", 1.0), "name"),
    (lambda: apply_weighting(np.zeros(10), 100.0, "wb", oversample=0), "oversample"),
])
def test_bad_arguments_are_setting_errors(call, key):
    with pytest.raises(SettingError) as info:
        call()
    assert info.value.key == key and "\n" not in str(info.value)
