"""Sampled profiles: variance, PSD, reproducibility, independence, interpolation (tb_exudyn.track)."""

import math

import numpy as np
import pytest
from scipy.fft import next_fast_len
from scipy.stats import chi2

from tb_exudyn.track import (GridProfile, HarmonicProfile, band_variance, fft_bins, fft_profile, get_spectrum,
                             harmonic_profile, rail_profiles, sample_rng, welch_psd)

SPEC = get_spectrum("german_low.vertical")
BAND = SPEC.default_band  # wavelengths 1-120 m
TRUE_VAR = band_variance(SPEC, *BAND)


N_HARM = 512


def _harmonic_target():
    """Exact ensemble variance of the harmonic sample: the mid-point sum sum_k G(O_k) dO."""
    d_omega = (BAND[1] - BAND[0]) / N_HARM
    return float(np.sum(SPEC.psd(BAND[0] + (np.arange(N_HARM) + 0.5) * d_omega)) * d_omega)


def _harmonic_ms(seed, n_samples):
    """Per-sample mean of r^2 at 200 points spread over 300 m (less than a period) for harmonic samples."""
    x = np.linspace(0.0, 300.0, 200)
    return np.array([np.mean(harmonic_profile(SPEC, sample_rng(seed, i), N_HARM, BAND).value(x) ** 2)
                     for i in range(n_samples)])


def _fft_target(length, dx):
    """Exact ensemble variance of the FFT sample: sum_k G(centre_k) w_k over its bins."""
    n_fft = next_fast_len(int(round(length / dx)) + 1)
    _, w, node = fft_bins(*BAND, n_fft, dx)
    return float(np.sum(SPEC.psd(node) * w))


def _fft_ms(seed, n_samples):
    """Per-sample mean of r^2 at 200 points over the first 300 m of 400 m FFT samples (dx = 0.25 m)."""
    return np.array([np.mean(fft_profile(SPEC, sample_rng(seed, i), 400.0, 0.25, BAND).values[:1200:6] ** 2)
                     for i in range(n_samples)])


def test_discretisation_error_of_the_generators():
    """Discretised variances of both generators vs the band variance (German low vertical, 1-120 m).

    Reference: band_variance (quadrature, 1e-10). Harmonic, 512 mid-point frequencies: the mid-point
    rule underestimates the steep low-frequency end by about 0.39 % (first cell error ~ (dO/O_min)^2/4);
    tolerance 0.5 %. FFT on 2 km (dO = 2 pi / 2005 m, 16x finer): about 2.5e-4 below; tolerance 1e-3. The FFT bin
    weights must also tile the band exactly (sum = band width, 1e-12).
    """
    assert _harmonic_target() == pytest.approx(TRUE_VAR, rel=5e-3)
    assert _fft_target(2000.0, 0.25) == pytest.approx(TRUE_VAR, rel=1e-3)
    _, w, _ = fft_bins(*BAND, next_fast_len(8001), 0.25)
    assert w.sum() == pytest.approx(BAND[1] - BAND[0], rel=1e-12)


def test_ensemble_variance_harmonic_and_fft():
    """Ensemble variance of harmonic (400 samples) and FFT (400 samples) profiles.

    Problem: German low vertical, 1-120 m. Statistic per sample: mean of r^2 at 200 points over
    300 m, shorter than the period, so it is random (over a full period it would be the deterministic
    sum a_k^2/2); unbiased for the ensemble variance since E[r(x)^2] = sum G w at every x. Samples
    are independent, so the standard error is std/sqrt(n) from the samples (about 1 %). Reference:
    the exact expectation, the discretised variance sum G w (harmonic: mid-point sum, 0.39 % below
    the band variance; FFT on 400 m: its bin sum). Tolerance: 3 standard errors. The two generators
    must also agree with each other, each scaled by its own discretised variance, within 3 combined
    standard errors (same statistics).
    """
    h, f = _harmonic_ms(1, 400), _fft_ms(2, 400)
    th, tf = _harmonic_target(), _fft_target(400.0, 0.25)
    se_h, se_f = h.std(ddof=1) / math.sqrt(h.size), f.std(ddof=1) / math.sqrt(f.size)
    assert abs(h.mean() - th) < 3 * se_h
    assert abs(f.mean() - tf) < 3 * se_f
    assert abs(h.mean() / th - f.mean() / tf) < 3 * math.hypot(se_h / th, se_f / tf)
    assert se_h < 0.03 * th and se_f < 0.03 * tf  # the test has resolving power


def _log_ratio_tolerance(n_values, nperseg, n_bins):
    """4-sigma bound on the band-mean of log(Welch / target) for a Gaussian process.

    Welch with a Hann window and 50 % overlap has nu = 2K / (1 + 2 * 0.167^2) degrees of freedom
    (Welch 1967), so log of one bin has sd ~ sqrt(2 / nu) and bias ~ -1/nu; adjacent Hann bins are
    correlated, so only n_bins / 2 count as independent.
    """
    k = (n_values - nperseg) // (nperseg // 2) + 1
    nu = 2 * k / (1 + 2 * 0.167**2)
    return 4 * math.sqrt(2 / nu) / math.sqrt(n_bins / 2) + 1 / nu, nu


def test_welch_psd_of_long_fft_sample_matches_target():
    """Welch PSD of one 50 km FFT sample (dx = 0.25 m) against German low vertical over 1-120 m.

    Reference: the spectrum's formula (checked elsewhere against typed values). Bins within 3 bins of
    a band edge are dropped (the Hann main lobe mixes in the empty outside of the band).
    Checks: (1) mean of log(Welch/target) over the band and over 4 log-spaced sub-bands within a
    4-sigma Gaussian bound (see _log_ratio_tolerance; ~2 % on the band); (2) per bin, at most 2 % of
    bins outside the central 99 % chi-square band of nu degrees of freedom. Both are conservative for
    the random-phase process (its amplitudes are not random, so it scatters less than a Gaussian one),
    yet a factor-2 or 2-pi unit error fails both at once.
    """
    dx, nperseg = 0.25, 4096
    values = fft_profile(SPEC, sample_rng(3, 0), 50_000.0, dx, BAND, interpolation="linear").values
    omega, est = welch_psd(values, dx, nperseg=nperseg)
    d = omega[1] - omega[0]
    inside = (omega > BAND[0] + 3 * d) & (omega < BAND[1] - 3 * d)
    ratio = est[inside] / SPEC.psd(omega[inside])
    tol, nu = _log_ratio_tolerance(values.size, nperseg, inside.sum())
    assert abs(np.mean(np.log(ratio))) < tol
    edges = np.geomspace(*BAND, 5)
    for a, b in zip(edges[:-1], edges[1:]):
        sub = (omega[inside] >= a) & (omega[inside] < b)
        assert abs(np.mean(np.log(ratio[sub]))) < _log_ratio_tolerance(values.size, nperseg, sub.sum())[0]
    lo, hi = chi2.ppf([0.005, 0.995], nu) / nu
    assert np.mean((ratio < lo) | (ratio > hi)) < 0.02


def test_harmonic_and_fft_psd_agree():
    """Band-mean of log(Welch_harmonic / Welch_fft) over 1-120 m: the two generators give the same PSD.

    Problem: 12 samples of 1 km at dx = 0.25 m from each generator (harmonic with 1024 frequencies,
    period 1.03 km), Welch nperseg 1024 averaged over the samples. Reference: the other generator.
    Tolerance: 4-sigma bound of the difference of two independent band means (sqrt 2 times the
    single-estimate bound of _log_ratio_tolerance with 12x the segments), about 3 %.
    """
    dx, nperseg, n = 0.25, 1024, 12
    x = np.arange(4001) * dx
    harm = [harmonic_profile(SPEC, sample_rng(4, i), 1024, BAND).value(x) for i in range(n)]
    fft = [fft_profile(SPEC, sample_rng(5, i), 1000.0, dx, BAND).values for i in range(n)]
    omega = welch_psd(harm[0], dx, nperseg=nperseg)[0]
    s_h = np.mean([welch_psd(v, dx, nperseg=nperseg)[1] for v in harm], axis=0)
    s_f = np.mean([welch_psd(v, dx, nperseg=nperseg)[1] for v in fft], axis=0)
    d = omega[1] - omega[0]
    inside = (omega > BAND[0] + 3 * d) & (omega < BAND[1] - 3 * d)
    tol, _ = _log_ratio_tolerance(n * x.size, nperseg, inside.sum())
    assert abs(np.mean(np.log(s_h[inside] / s_f[inside]))) < math.sqrt(2) * tol


def test_fft_profile_equals_the_harmonic_sum_it_represents():
    """White-box: the FFT sample equals sum_k sqrt(2 G w_k) cos((k + 1/2) dO x + phi_k) at the grid points.

    Problem: 300 m at dx = 0.5 m, German low vertical 2-100 m. Reference: HarmonicProfile (an exact
    direct sum) with the same bins, weights and phases (phases redrawn from the same seed, in the
    FFT generator's documented order). Tolerance 1e-12 of the standard deviation (FFT round-off).
    """
    band = (2 * math.pi / 100, 2 * math.pi / 2)
    dx, n_points = 0.5, 601
    n_fft = next_fast_len(n_points)
    k, w, node = fft_bins(*band, n_fft, dx)
    omega = (k + 0.5) * 2 * math.pi / (n_fft * dx)
    phase = np.random.default_rng(9).uniform(0, 2 * math.pi, k.size)
    ref = HarmonicProfile(unit="m", kind="vertical", omega=omega,
                          amplitude=np.sqrt(2 * SPEC.psd(node) * w), phase=phase)
    grid = fft_profile(SPEC, np.random.default_rng(9), 300.0, dx, band)
    x = np.arange(n_points) * dx
    np.testing.assert_allclose(grid.values, ref.value(x), rtol=0, atol=1e-12 * math.sqrt(TRUE_VAR))


def test_same_seed_same_profile_and_rng_matches_spawn():
    """Same (seed, index) gives bit-identical profiles; sample_rng equals SeedSequence(seed).spawn.

    Reference: numpy's own SeedSequence.spawn (the documented way to make independent streams), so
    a sample does not depend on which worker draws it. Exact equality (deterministic arithmetic).
    """
    a = fft_profile(SPEC, sample_rng(42, 7), 500.0, 0.5)
    b = fft_profile(SPEC, sample_rng(42, 7), 500.0, 0.5)
    assert np.array_equal(a.values, b.values)
    h1, h2 = (harmonic_profile(SPEC, sample_rng(42, 7), 64, jitter=0.5) for _ in range(2))
    assert np.array_equal(h1.value(np.linspace(0, 100, 50)), h2.value(np.linspace(0, 100, 50)))
    spawned = np.random.default_rng(np.random.SeedSequence(42).spawn(8)[7])
    assert np.array_equal(sample_rng(42, 7).random(5), spawned.random(5))


def test_different_indices_are_independent():
    """Correlation across samples of r(x = 150 m) between sample 2m and 2m+1 (m < 800) is near 0.

    Problem: German low vertical, FFT samples of 300 m at 0.5 m. Under independence the sample
    correlation of 800 pairs has sd 1/sqrt(800) = 0.035; bound 4/sqrt(800) = 0.14. A shared or
    index-ignoring stream gives correlation 1. The same index with another seed must differ too.
    """
    n = 800
    vals = np.array([fft_profile(SPEC, sample_rng(7, i), 300.0, 0.5).values[300] for i in range(2 * n)])
    rho = np.corrcoef(vals[0::2], vals[1::2])[0, 1]
    assert abs(rho) < 4 / math.sqrt(n)
    assert not np.array_equal(fft_profile(SPEC, sample_rng(8, 0), 300.0, 0.5).values,
                              fft_profile(SPEC, sample_rng(7, 0), 300.0, 0.5).values)


def test_profile_derivatives():
    """Derivatives in x: harmonic exact sum vs central differences; grid interpolation of sin(0.3 x).

    References: central difference (h = 1e-4 m, truncation ~h^2 O^2/6 ~ 1e-8 relative for O <= 6.3
    rad/m, tolerance 1e-6 of the derivative's scale); analytic sin/cos for the grid profile at
    dx = 0.1 m: cubic spline error ~ (O dx)^4 / 384 -> tolerance 1e-5 (value) and 1e-4 (slope) of the
    amplitude; linear interpolation error <= (O dx)^2 / 8 = 1.1e-4, and its derivative is exactly
    the chord slope.
    """
    p = harmonic_profile(SPEC, np.random.default_rng(1), 256)
    x = np.linspace(3.0, 97.0, 41)
    fd = (p.value(x + 1e-4) - p.value(x - 1e-4)) / 2e-4
    scale = np.sqrt(np.sum((p.amplitude * p.omega) ** 2))
    np.testing.assert_allclose(p.derivative(x), fd, rtol=0, atol=1e-6 * scale)
    grid_x = np.arange(0, 101) * 0.1
    xs = np.linspace(0.05, 9.95, 77)
    cubic = GridProfile(unit="m", kind="vertical", dx=0.1, values=np.sin(0.3 * grid_x))
    np.testing.assert_allclose(cubic.value(xs), np.sin(0.3 * xs), atol=1e-5)
    np.testing.assert_allclose(cubic.derivative(xs[5:-5]), 0.3 * np.cos(0.3 * xs[5:-5]), atol=1e-4)
    linear = GridProfile(unit="m", kind="vertical", dx=0.1, values=np.sin(0.3 * grid_x), interpolation="linear")
    np.testing.assert_allclose(linear.value(xs), np.sin(0.3 * xs), atol=1.2e-4)
    i = np.floor(xs / 0.1).astype(int)
    np.testing.assert_allclose(linear.derivative(xs), (np.sin(0.3 * grid_x[i + 1]) - np.sin(0.3 * grid_x[i])) / 0.1,
                               rtol=1e-12)
    assert cubic.value(np.zeros((2, 3))).shape == (2, 3)
    with pytest.raises(ValueError, match="outside the profile"):
        cubic.value(10.5)


def test_rail_profiles_from_vertical_and_cross_level():
    """z_L,R = z_v +- b theta_c (left = +y): mean of the rails is z_v, difference is 2 b theta_c.

    Problem: harmonic samples of German low vertical and cross-level angle; also a cross-level height
    h gives z_L - z_R = h. Reference: the definitions. Tolerance 1e-15 m (rounding).
    """
    zv = harmonic_profile(SPEC, np.random.default_rng(1), 64)
    th = harmonic_profile(get_spectrum("german_low.cross_level"), np.random.default_rng(2), 64)
    left, right = rail_profiles(zv, th)
    x = np.linspace(0, 50, 11)
    np.testing.assert_allclose(left.value(x) - right.value(x), 2 * 0.75 * th.value(x), atol=1e-15)
    np.testing.assert_allclose(0.5 * (left.value(x) + right.value(x)), zv.value(x), atol=1e-15)
    np.testing.assert_allclose(left.derivative(x), zv.derivative(x) + 0.75 * th.derivative(x), atol=1e-15)
    hh = harmonic_profile(get_spectrum("german_low.cross_level_height"), np.random.default_rng(2), 64)
    left, right = rail_profiles(zv, hh)
    np.testing.assert_allclose(left.value(x) - right.value(x), hh.value(x), atol=1e-15)


def test_welch_psd_units_on_white_noise():
    """welch_psd of white noise (variance s^2, spacing dx) is flat at s^2 dx / pi per rad/m on (0, pi/dx).

    Reference: one-sided density in rad/m that integrates to s^2 over [0, pi/dx]; checks the
    cycles/m -> rad/m conversion independently of any spectrum. 2^18 points, nperseg 2048: band mean
    over ~1000 interior bins has sd ~0.4 %; tolerance 2 %.
    """
    dx, s = 0.2, 3e-3
    values = np.random.default_rng(0).normal(0, s, 2**18)
    omega, est = welch_psd(values, dx, nperseg=2048)
    assert omega[-1] == pytest.approx(math.pi / dx, rel=1e-12)
    assert np.mean(est[1:-1]) == pytest.approx(s**2 * dx / math.pi, rel=0.02)
