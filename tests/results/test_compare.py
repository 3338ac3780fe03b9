"""The PEM-against-Monte-Carlo comparison helper on synthetic results (no model runs).

Each test builds a PEM and a Monte Carlo RandomResponse by hand with known sigma ratios and mean
offsets, so the expected fractions are exact.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from tb_exudyn.results import RandomResponse
from tb_exudyn.results.compare import ComparisonError, compare, compare_folders

from ..methods.test_pem import sprung_mass_scenario

N = 400
T = np.arange(101) * 0.01


@pytest.fixture(scope="module")
def scenario():
    return sprung_mass_scenario(lead_in=40.0, run_out=5.0, f_min=1.0, f_max=20.0, n_freq=8, channels=("*",))


def _pair(scenario, ratio, mean_shift_se=0.0, taper=True):
    """PEM sigma = 1 + t (two channels); MC sigma = ratio x PEM sigma; MC mean = PEM mean +
    mean_shift_se standard errors."""
    sc = scenario if taper else scenario.replace(track=scenario.track.replace(taper_length=0.0))
    std = np.vstack([1 + T, 2 + T])
    mean = np.vstack([np.sin(T), np.cos(T)])
    kw = dict(time=T, channels=("a.disp_z", "b.acc_z"), units=("m", "m/s^2"), band=(1.0, 20.0), scenario=sc)
    pem = RandomResponse(method="pem", mean=mean, std=std, **kw)
    mc_std = std * ratio
    mc = RandomResponse(method="monte_carlo", mean=mean + mean_shift_se * mc_std / math.sqrt(N), std=mc_std,
                        n_samples=N, **kw)
    return pem, mc


def test_ratio_inside_and_outside_the_sampling_band(scenario):
    """The band is 1 +- 3/sqrt(800) = [0.894, 1.106]: a ratio 1.05 is inside at every time, 1.2
    at none; a ratio crossing the band edge halfway through the run is inside at half the times."""
    pem, mc = _pair(scenario, 1.05)
    c = compare(pem, mc)
    assert c.band == pytest.approx((1 - 3 / math.sqrt(800), 1 + 3 / math.sqrt(800)))
    assert [r.inside for r in c.rows] == [1.0, 1.0] and c.rows[0].ratio_median == pytest.approx(1.05)
    assert [r.inside for r in compare(*_pair(scenario, 1.2)).rows] == [0.0, 0.0]
    ramp = np.where(T < 0.5, 1.0, 1.2)[None, :]
    row = compare(*_pair(scenario, ramp)).row("a.disp_z")
    assert row.inside == pytest.approx(50 / 101) and row.n_times == 101


def test_mean_difference_in_standard_errors(scenario):
    """MC mean offset by 2 standard errors: |z| = 2 everywhere, inside; by 4: outside."""
    r2 = compare(*_pair(scenario, 1.0, 2.0)).row("b.acc_z")
    assert r2.mean_z_max == pytest.approx(2.0) and r2.mean_inside == 1.0
    r4 = compare(*_pair(scenario, 1.0, 4.0)).row("b.acc_z")
    assert r4.mean_z_max == pytest.approx(4.0) and r4.mean_inside == 0.0


def test_compared_times_threshold_and_start(scenario):
    """Without a taper the comparison starts when the first axle reaches the bridge (40 m at
    300 km/h: 0.48 s); times where sigma_PEM is below 5 % of its maximum are skipped."""
    pem, mc = _pair(scenario, 1.0, taper=False)
    c = compare(pem, mc)
    assert c.t_min == pytest.approx(40 / (300 / 3.6)) and c.rows[0].n_times == np.sum(T >= c.t_min - 1e-12)
    pem.std[0, :50] = 1e-3 * pem.std[0, 50:].max()
    assert compare(pem, mc, t_min=0.0).row("a.disp_z").n_times == 51


def test_table_and_folders(scenario, tmp_path):
    """The printed table names every channel with its numbers; saved results compare alike from
    the result folders or from an --out folder holding pem/ and mc/."""
    pem, mc = _pair(scenario, 1.05, 1.0)
    c = compare(pem, mc)
    table = c.table()
    assert "a.disp_z" in table and "b.acc_z" in table and "[0.894, 1.106]" in table and "1.050" in table
    # the first line sums it up: every channel's median ratio (1.05 and 1.0) lies in the band, the worst
    # is the one furthest from 1
    worst = max(c.rows, key=lambda r: abs(r.ratio_median - 1))
    assert table.splitlines()[0] == c.summary()
    assert c.summary().startswith(f"{len(c.rows)} of {len(c.rows)} channels with the median sigma ratio in [0.894, 1.106]")
    assert f"worst {worst.channel}: median {worst.ratio_median:.3f}" in c.summary()
    pem.save(tmp_path / "pem")
    mc.save(tmp_path / "mc")
    assert compare_folders(tmp_path / "pem", tmp_path / "mc") == table
    assert compare_folders(tmp_path, tmp_path) == table


def test_incompatible_results_are_refused(scenario):
    pem, mc = _pair(scenario, 1.0)
    with pytest.raises(ComparisonError, match="PEM and a Monte Carlo"):
        compare(mc, pem)
    short = RandomResponse(method="monte_carlo", time=T[:50], channels=mc.channels, units=mc.units,
                           mean=mc.mean[:, :50], std=mc.std[:, :50], band=mc.band, scenario=scenario, n_samples=N)
    with pytest.raises(ComparisonError, match="output times differ"):
        compare(pem, short)
    with pytest.raises(ComparisonError, match="no channel"):
        compare(pem, mc, "bridge.*")
