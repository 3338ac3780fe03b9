"""EN 1991-2 tables and formulas as functions, against values worked out by hand from the formulas as
the standard prints them (the arithmetic is in each test). Tolerances: the printed rounding of the
standard's own figures (3.03 / 7.09 Hz to 0.005 Hz) or 1e-4 relative for our hand arithmetic to 4-5
figures."""

from __future__ import annotations

import math

import numpy as np
import pytest

from tb_exudyn.codes import en1991 as code
from tb_exudyn.errors import SettingError


@pytest.mark.parametrize("construction, span, percent", [
    ("prestressed_concrete", 32.0, 1.0),           # L >= 20 m
    ("prestressed_concrete", 10.0, 1.7),           # 1.0 + 0.07 * (20 - 10)
    ("steel_composite", 10.0, 1.75),               # 0.5 + 0.125 * 10
    ("steel_composite", 25.0, 0.5),
    ("reinforced_concrete", 15.0, 1.85),           # 1.5 + 0.07 * 5
    ("filler_beam", 20.0, 1.5),
])
def test_table_6_6(construction, span, percent):
    assert code.damping_ratio_table_6_6(construction, span) == pytest.approx(percent / 100, rel=1e-12)


@pytest.mark.parametrize("span, percent", [
    (10.0, 0.123 / 0.374),        # (0.187 - 0.064) / (1 - 0.441 - 0.44 + 0.255)
    (20.0, 0.118 / 0.398),        # (0.374 - 0.256) / (1 - 0.882 - 1.76 + 2.04)
    (5.0, 0.0775 / 0.701375),     # (0.0935 - 0.016) / (1 - 0.2205 - 0.11 + 0.031875)
    (30.0, 0.0),                  # not below 30 m
    (40.0, 0.0),
])
def test_eq_6_13(span, percent):
    assert code.additional_damping_eq_6_13(span) == pytest.approx(percent / 100, rel=1e-12, abs=1e-15)


def test_figure_6_10_at_32_m_is_3_03_to_7_09_hz():
    lower, upper = code.frequency_limits_fig_6_10(32.0)
    assert lower == pytest.approx(3.03, abs=0.005) and upper == pytest.approx(7.09, abs=0.005)
    # L = 10 m: lower 80 / L = 8; upper 94.76 * 10^-0.748 = 16.93
    lower, upper = code.frequency_limits_fig_6_10(10.0)
    assert lower == pytest.approx(8.0, rel=1e-12) and upper == pytest.approx(94.76 * 10**-0.748, rel=1e-12)
    with pytest.raises(SettingError, match="Figure 6.10"):
        code.frequency_limits_fig_6_10(120.0)


def test_figure_6_9_branches():
    assert code.dynamic_analysis_required(250.0, 32.0, 5.12)[0] is True       # above 200 km/h
    assert code.dynamic_analysis_required(160.0, 32.0, 5.12)[0] is False      # 3.03 <= 5.12 <= 7.09
    assert code.dynamic_analysis_required(160.0, 32.0, 8.0)[0] is True        # above the upper limit
    assert code.dynamic_analysis_required(160.0, 120.0, 1.0)[0] is True       # outside 4-100 m


def test_phi_irregularity_annex_c():
    # n0 = 5.12 Hz, L = 32 m: 56 e^-10.24 + 50 (5.12 * 32 / 80 - 1) e^-2.56 = 0.00201 + 52.4 * 0.077305 = 4.0528
    assert code.phi_irregularity_annex_c(5.12, 32.0) == pytest.approx(0.040528, rel=1e-4)
    # n0 = 10 Hz, L = 10 m: 56 e^-1 + 50 (100 / 80 - 1) e^-0.25 = 20.6014 + 9.7350 = 30.3364
    assert code.phi_irregularity_annex_c(10.0, 10.0) == pytest.approx(0.303364, rel=1e-4)
    # alpha = v / 22 below 22 m/s
    assert code.phi_irregularity_annex_c(10.0, 10.0, 11.0) == pytest.approx(0.151682, rel=1e-4)
    # never negative: n0 L / 80 < 1 with L = 40 m, n0 = 1 Hz: 56 e^-16 + 50 (0.5 - 1) e^-4 < 0 -> 0
    assert code.phi_irregularity_annex_c(1.0, 40.0) == 0.0
    assert code.irregularity_enhancement(0.3, 0.04) == pytest.approx(1.32)
    assert code.irregularity_enhancement(0.3, 0.04, "standard") == pytest.approx(1.34)


def test_dynamic_factors():
    # L = 32 m: 1.44 / (5.65685 - 0.2) + 0.82 = 1.08390; 2.16 / 5.45685 + 0.73 = 1.12584
    assert code.dynamic_factor_phi2(32.0) == pytest.approx(1.08390, rel=1e-4)
    assert code.dynamic_factor_phi3(32.0) == pytest.approx(1.12584, rel=1e-4)
    assert code.dynamic_factor_phi2(1.0) == 1.67 and code.dynamic_factor_phi3(200.0) == 1.0


def test_speed_series():
    """Line speed 250 km/h: 144 ... 300 km/h, steps of at most 5 km/h, resonant speeds inside refined
    at 1 km/h within +- 5 km/h; outside resonances ignored."""
    v = code.speed_series(250.0, resonant_kmh=[166.0, 400.0])
    assert v[0] == 144.0 and v[-1] == 300.0
    assert np.all(np.diff(v) > 0) and np.diff(v).max() <= 5.0 + 1e-9
    assert set(np.arange(161.0, 172.0)) <= set(v)
    assert code.speed_series(100.0)[-1] == 120.0 and code.speed_series(100.0).size == 1  # 1.2 V < 144 km/h
    for bad in (0.0, -10.0, 601.0, math.nan):
        with pytest.raises(SettingError, match="line_speed_kmh"):
            code.speed_series(bad)
    np.testing.assert_allclose(code.resonant_speeds_kmh(5.0, 18.0), [324.0, 162.0, 108.0, 81.0])


def test_cutoff_and_limits():
    assert code.cutoff_frequency(5.12, 46.08) == 46.08
    assert code.cutoff_frequency(25.0, None) == 37.5
    assert code.cutoff_frequency(5.0, 20.0) == 30.0
    assert code.deck_acceleration_limit("ballasted") == 3.5 and code.deck_acceleration_limit("direct") == 5.0
