"""Pseudo-excitation inputs for several wheels and quadrature weights (tb_exudyn.track)."""

import math

import numpy as np
import pytest

from tb_exudyn.track import (band_variance, get_spectrum, pseudo_excitation, pseudo_excitation_hz,
                             quadrature_weights, temporal_psd_hz)

SPEC = get_spectrum("german_high.vertical")
V = 250 / 3.6
OFFSETS = np.array([0.0, 2.5, 17.5, 20.0])  # one car: two bogies of two axles
OMEGA = np.linspace(0.06, 6.2, 300)
D_OMEGA = OMEGA[1] - OMEGA[0]
TIMES = np.array([0.0, 0.37, 1.9])


def test_power_sums_to_discretised_variance():
    """sum_k |r~_jk(t)|^2 = sum_k G(O_k) dO for every wheel j and time t.

    Reference: the discretised band variance computed here from the spectrum on the same grid.
    Tolerance 1e-12 relative (|exp(i phi)| = 1 up to rounding).
    """
    r, _ = pseudo_excitation(SPEC, OMEGA, D_OMEGA, V, TIMES, OFFSETS)
    assert r.shape == (OMEGA.size, OFFSETS.size, TIMES.size)
    ref = np.sum(SPEC.psd(OMEGA)) * D_OMEGA
    np.testing.assert_allclose(np.sum(np.abs(r) ** 2, axis=0), ref, rtol=1e-12)


def test_wheel_phases_and_time_derivative():
    """r~_j / r~_0 = exp(-i O a_j); r_dot = i O v r~ checked against a central difference in t.

    Reference: the defining formula; central difference with h = 1e-6 s (truncation ~ (O v h)^2/6
    ~ 3e-8 relative at O v = 430 rad/s). Tolerances 1e-12 (phase, rounding of O a_j up to ~120 rad)
    and 1e-6 relative to the largest |r_dot| (difference round-off ~1e-16/1e-6 * |r|).
    """
    r, r_dot = pseudo_excitation(SPEC, OMEGA, D_OMEGA, V, TIMES, OFFSETS)
    np.testing.assert_allclose(r / r[:, :1, :], np.exp(-1j * OMEGA[:, None, None] * OFFSETS[None, :, None])
                               * np.ones_like(r), rtol=0, atol=1e-12)
    h = 1e-6
    fd = (pseudo_excitation(SPEC, OMEGA, D_OMEGA, V, TIMES + h, OFFSETS)[0]
          - pseudo_excitation(SPEC, OMEGA, D_OMEGA, V, TIMES - h, OFFSETS)[0]) / (2 * h)
    np.testing.assert_allclose(r_dot, fd, rtol=0, atol=1e-6 * np.abs(r_dot).max())


def test_hz_grid_version():
    """Hz grid: same as the spatial call with O = 2 pi f / v, dO = 2 pi df / v; power = S_hz(f) df.

    Problem: mid-point linear grid f_k = 0.5 + (k - 1/2) 0.1 Hz, k = 1..100, at 250 km/h. References:
    the spatial call (same formula; O is rounded in another order, and an ulp of O times phases
    up to ~100 rad gives ~1e-14: tolerance 1e-12), temporal_psd_hz times df (1e-12), and the band variance
    over 0.5-10.5 Hz, i.e. wavelengths 6.6-139 m (mid-point rule error ~1e-3 for 100 cells; 5e-3).
    """
    df = 0.1
    f = 0.5 + (np.arange(1, 101) - 0.5) * df
    r, r_dot = pseudo_excitation_hz(SPEC, f, V, 0.3, OFFSETS)
    np.testing.assert_allclose(quadrature_weights(f), df, rtol=1e-12)
    r2, _ = pseudo_excitation(SPEC, 2 * math.pi * f / V, 2 * math.pi * df / V, V, 0.3, OFFSETS)
    np.testing.assert_allclose(r, r2, rtol=1e-12, atol=0)
    np.testing.assert_allclose(np.abs(r[:, 0, 0]) ** 2, temporal_psd_hz(SPEC, f, V) * df, rtol=1e-12)
    np.testing.assert_allclose(r_dot, 2j * math.pi * f[:, None, None] * r, rtol=1e-12)
    ref = band_variance(SPEC, 2 * math.pi * 0.5 / V, 2 * math.pi * 10.5 / V)
    assert np.sum(np.abs(r[:, 0, 0]) ** 2) == pytest.approx(ref, rel=5e-3)


def test_quadrature_weights_rules():
    """Mid-point and trapezoid weights on a non-uniform grid.

    Reference: hand-computed weights for the grid (0, 1, 3, 4): trapezoid (0.5, 1.5, 1.5, 0.5)
    (integrates linear functions exactly between the end nodes); mid-point cells with edges
    (-0.5, 0.5, 2, 3.5, 4.5) give (1, 1.5, 1.5, 1). Exact binary fractions: tolerance 1e-15.
    """
    grid = [0.0, 1.0, 3.0, 4.0]
    np.testing.assert_allclose(quadrature_weights(grid, "trapezoid"), [0.5, 1.5, 1.5, 0.5], atol=1e-15)
    np.testing.assert_allclose(quadrature_weights(grid, "midpoint"), [1.0, 1.5, 1.5, 1.0], atol=1e-15)
