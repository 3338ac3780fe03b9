"""PEM frequency grid: quadrature widths and the spatial/temporal conversion."""

from __future__ import annotations

import math

import numpy as np
import pytest

import tb_exudyn as tbx
from tb_exudyn.scenario import ScenarioError
from tb_exudyn.methods.grid import band_mask, check_grid_against_spectra, frequency_grid, scenario_grid
from tb_exudyn.track import get_spectrum


def test_linear_grid_trapezoid_weights_cover_exactly_the_band():
    """Linear grid 0.3..60 Hz, 200 points (the study's): trapezoid widths are the spacing h inside and
    h/2 at both ends, so they sum to exactly the band length 59.7 Hz and the stated band is
    [0.3, 60] Hz; exact up to rounding (1e-12)."""
    g = frequency_grid(0.3, 60.0, 200, speed=61.1)
    h = (60.0 - 0.3) / 199
    assert np.allclose(g.df[1:-1], h, rtol=1e-12) and np.allclose(g.df[[0, -1]], h / 2, rtol=1e-12)
    assert g.df.sum() == pytest.approx(60.0 - 0.3, rel=1e-12)
    assert g.band == (0.3, 60.0)


def test_spatial_conversion():
    """Omega = 2 pi f / v and dOmega = 2 pi df / v, so S(Omega) dOmega = S_hz(f) df with
    S_hz = 2 pi S(Omega) / v (docs/references.md, track spectra: conventions)."""
    v = 220 / 3.6
    g = frequency_grid(0.3, 60.0, 50, speed=v, spacing="log")
    assert np.allclose(g.omega_spatial, 2 * math.pi * g.f / v, rtol=1e-14)
    s = get_spectrum("german_low.vertical")
    lhs = s.psd(g.omega_spatial) * g.d_omega_spatial
    s_hz = 2 * math.pi * s.psd(2 * math.pi * g.f / v) / v
    assert np.allclose(lhs, s_hz * g.df, rtol=1e-13)


def test_band_mask_follows_wavelengths():
    sc = tbx.load_scenario("li_zhu_2011")
    g = scenario_grid(sc)
    lam = sc.speed / g.f
    m = band_mask(g, sc)
    assert np.array_equal(m, (lam >= 1.0) & (lam <= 210.0))


def test_grid_outside_spectrum_validity_is_refused():
    """FRA spectra are defined for 1.524-304.8 m; asking for 1 m wavelengths must fail before a run."""
    sc = tbx.load_scenario("quick")
    sc = sc.replace(track=sc.track.replace(irregularities=("fra_class4.vertical",)),
                    analysis=sc.analysis.replace(freq_max=60.0, freq_spacing="linear", n_freq=16))
    # 69.4 m/s / 60 Hz = 1.16 m
    g = scenario_grid(sc)
    spectra = {n: get_spectrum(n) for n in sc.track.irregularities}
    with pytest.raises(ScenarioError, match="validity"):
        check_grid_against_spectra(g, sc, spectra)


def test_a_single_frequency_covers_the_band_and_no_negative_frequency():
    """Exact problem: one linear frequency over 0.6-30 Hz. Reference: the midpoint rule on one cell, the
    band itself: the node at 15.3 Hz, width 29.4 Hz, band [0.6, 30] Hz (to round-off, 1e-12). With the
    node at f_min the cell reached -14.1 Hz, a band no result may have (the loader refuses it)."""
    from tb_exudyn.methods.grid import frequency_grid

    g = frequency_grid(0.6, 30.0, 1, 60.0)
    assert g.f.tolist() == [15.3] and g.df.tolist() == [29.4]
    lo, hi = g.band
    assert abs(lo - 0.6) < 1e-12 and abs(hi - 30.0) < 1e-12
