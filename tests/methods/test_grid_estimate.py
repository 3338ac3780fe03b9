"""The grid-error estimates (tb_exudyn.methods.grid_error): the local estimate against a closed form,
against the full midpoint estimate, and the results' sigma independent of the estimate chosen.

Every reference is computed in this file, independently of the code under test.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from tb_exudyn.errors import SettingError
from tb_exudyn.methods import run_pem
from tb_exudyn.methods.adaptive_grid import grid_problem
from tb_exudyn.methods.grid import (estimate_cells, frequency_grid, local_grids, local_node_factors,
                                    locally_refined_variance, midpoint_grid, refined_variance)

FN, ZETA, F_MAX = 1.0, 0.02, 50.0


def sdof_psd(f):
    """|H|^2 of a single-DOF oscillator (natural frequency FN [Hz], damping ratio ZETA) in f [Hz], up
    to the constant (2 pi)^-4: 1 / ((fn^2 - f^2)^2 + (2 zeta fn f)^2)."""
    return 1.0 / ((FN**2 - f**2) ** 2 + (2 * ZETA * FN * f) ** 2)


# the closed form: int_0^inf df / ((fn^2 - f^2)^2 + (2 zeta fn f)^2) = pi / (4 zeta fn^3) (the
# oscillator's pi / (2 zeta wn^3) over the whole omega axis, halved and taken to Hz); the band ends at
# F_MAX, where the tail int_F^inf f^-4 (1 + O(f^-2)) df = 1 / (3 F^3) is taken off (2.7e-6 of 39.3)
EXACT = math.pi / (4 * ZETA * FN**3) - 1 / (3 * F_MAX**3)


def _trapezoid_sigma(n: int) -> float:
    g = frequency_grid(0.0, F_MAX, n, 1.0)
    return math.sqrt(float(np.sum(sdof_psd(g.f) * g.df)))


def test_local_estimate_matches_the_closed_form_trapezoid_error():
    """Problem: sigma = sqrt(int_0^50 Hz S), S the single-DOF |H|^2 above (1 Hz, damping ratio 0.02), on
    a linear grid of spacing h = 0.05 Hz (1001 nodes): 2.5 nodes per half-power half-width zeta fn, so
    the trapezoid sum is 8.4 % high (its error is the aliasing of the peak, about 2 exp(-2 pi zeta fn /
    h) of the integral). The local estimate refines only the cells wider than the adaptive grid's rules
    ask (run of 1e4 s: the rule there is zeta fn / 1 = 0.02 Hz, graded away from the mode; below 1 Hz
    5 % of f; LOCAL_RATIO 1.5): 23 of 1000, all below 1.5 Hz.

    Reference: the true error sigma_h - sigma_exact from the closed form EXACT. An estimate from the
    grid refined once (h / 2) is the true error less the refined grid's own error, so the expected
    ratio estimate / true is 1 - E(h/2) / E(h) = 0.9222 (both from the closed form); the full midpoint
    estimate gives it to 1e-4. Tolerance 3e-3 on that ratio: the cells the local estimate leaves out
    (the smooth flanks, 977 cells) change it by their midpoint-trapezoid differences, 1.15e-3 here
    (1.0e-4 with LOCAL_RATIO 1, 29 cells); a wrong weight of the local sweeps changes it by O(1).
    """
    n = 1001
    g = frequency_grid(0.0, F_MAX, n, 1.0)
    var = float(np.sum(sdof_psd(g.f) * g.df))
    cells = estimate_cells(g, grid_problem(1e-6, F_MAX, [(FN, ZETA)], duration=1e4))
    assert cells.sum() == 23  # 2 % of the cells: the mode's and, below 1 Hz, where the background
    f_mid = (g.f[1:] + g.f[:-1])[cells] / 2  # rule (5 % of f) is finer than the grid
    assert np.all(f_mid < 1.5)
    mid, nodes = local_grids(g, cells)
    m, t = float(np.sum(sdof_psd(mid.f) * mid.df)), float(np.sum(sdof_psd(nodes.f) * nodes.df))
    estimate = math.sqrt(var) - math.sqrt(float(locally_refined_variance(var, m, t)))
    true, true_half = _trapezoid_sigma(n) - math.sqrt(EXACT), _trapezoid_sigma(2 * n - 1) - math.sqrt(EXACT)
    assert true / math.sqrt(EXACT) == pytest.approx(0.0845, abs=1e-3)  # the problem as stated
    assert abs(estimate / true - (1 - true_half / true)) < 3e-3


def test_local_estimate_with_every_cell_is_the_midpoint_estimate():
    """Problem: the same integrand on 41 nodes over 0-4 Hz with every cell chosen. Reference: the grid
    refined on every cell is the trapezoid rule on nodes and midpoints, (var + var_mid) / 2
    (refined_variance). Tolerance 1e-12 relative: T is then the grid's own sum, summed in another
    order (round-off)."""
    g = frequency_grid(0.0, 4.0, 41, 1.0)
    var = float(np.sum(sdof_psd(g.f) * g.df))
    mid, nodes = local_grids(g, np.ones(40, dtype=bool))
    m, t = float(np.sum(sdof_psd(mid.f) * mid.df)), float(np.sum(sdof_psd(nodes.f) * nodes.df))
    full = midpoint_grid(g)
    assert np.allclose(nodes.f, g.f, rtol=0, atol=0) and np.allclose(nodes.df, g.df, rtol=1e-15)
    assert locally_refined_variance(var, m, t) == pytest.approx(
        refined_variance(var, float(np.sum(sdof_psd(full.f) * full.df))), rel=1e-12)


def test_node_factors_give_the_node_sweeps_sum_from_the_grids_own_columns():
    """Problem: the local estimate's node sum T taken from the grid's own columns (PEM's grid tasks
    weight each node's |y|^2 by local_node_factors) instead of a sweep on the node grid of local_grids.
    References: (1) that node grid's trapezoid sum of the integrand above, on the grid of the
    closed-form test (23 chosen cells): the factors times the grid's own weights give it to 1e-14
    (the same products, another order); (2) the PEM columns: a column's squared amplitude S(f) d_omega
    on the node grid is the grid's column's times the factor (pem_tasks on the quick scenario's grid
    and its node grid; 1e-14: each amplitude is one square root)."""
    n = 1001
    g = frequency_grid(0.0, F_MAX, n, 1.0)
    cells = estimate_cells(g, grid_problem(1e-6, F_MAX, [(FN, ZETA)], duration=1e4))
    _, nodes = local_grids(g, cells)
    factors = local_node_factors(g, cells)
    k = np.array(sorted(factors))
    assert np.array_equal(g.f[k], nodes.f)
    t_sweep = float(np.sum(sdof_psd(nodes.f) * nodes.df))
    t_grid = float(np.sum(sdof_psd(g.f[k]) * g.df[k] * np.array([factors[i] for i in k])))
    assert t_grid == pytest.approx(t_sweep, rel=1e-14)
    import tb_exudyn as tbx
    from tb_exudyn.methods.pem import pem_tasks

    sc = tbx.load_scenario("quick")
    grid = frequency_grid(sc.analysis.freq_min, sc.analysis.freq_max, 40, sc.speed)
    chosen = np.zeros(39, dtype=bool)
    chosen[[3, 4, 17, 30]] = True
    factors = local_node_factors(grid, chosen)
    by = {(p.type_index, p.freq_index): p.amplitude for p in pem_tasks(sc, grid)}
    node_grid = local_grids(grid, chosen)[1]
    index = np.array(sorted(factors))
    for p in pem_tasks(sc, node_grid):  # its frequency index counts the node grid's nodes
        k = int(index[p.freq_index])
        assert p.amplitude**2 == pytest.approx(by[(p.type_index, k)] ** 2 * factors[k], rel=1e-14)


def test_a_grid_that_meets_the_rules_chooses_no_cell():
    """An adaptive-grid rule met everywhere (a linear grid of spacing 0.01 Hz, below the 0.02 Hz the mode
    asks, and below 5 % of f from 0.2 Hz up) leaves no cell to refine: the local estimate says zero."""
    g = frequency_grid(0.2, 4.0, 381, 1.0)
    assert not estimate_cells(g, grid_problem(0.2, 4.0, [(FN, ZETA)], duration=1e4)).any()


@pytest.mark.exudyn
def test_sigma_is_bitwise_the_same_with_either_estimate():
    """Problem: the damped sprung mass over the VBI-2D beam at 300 km/h (tests/methods/test_pem.py),
    PEM on 12 frequencies, batched engine, one process; without a grid-error estimate, with the
    midpoint estimate and with the local one. The estimate's columns only feed the warning: sigma, the
    variance by type and the PSD maps must be bitwise equal (tolerance 0)."""
    from tests.methods.test_pem import sprung_mass_scenario

    sc = sprung_mass_scenario(lead_in=60.0, run_out=10.0, f_min=1.0, f_max=20.0, n_freq=12,
                              channels=("car1.body.*", "bridge.*"))
    runs = {ge: run_pem(sc, workers=1, progress=False, engine="batched", grid_error=ge)
            for ge in (False, "midpoints", "local")}
    base = runs[False]
    for ge in ("midpoints", "local"):
        r = runs[ge]
        assert np.array_equal(r.std, base.std) and np.array_equal(r.var_by_type, base.var_by_type)
        assert np.array_equal(r.psd, base.psd)
    assert runs["local"].provenance["grid_error"]["method"].startswith("refined locally")
    assert runs["midpoints"].provenance["grid_error"]["method"].startswith("refined: the grid's nodes")


def test_an_unknown_estimate_is_one_clear_error():
    """grid_error takes true, false or an estimate's name; anything else is a SettingError naming
    grid_error and what is allowed, raised before any model is built."""
    from tb_exudyn.methods.pem.method import _estimate

    class Together:
        single_columns = False

    with pytest.raises(SettingError) as info:
        _estimate("coarse", Together, "run_pem")
    text = str(info.value)
    assert "grid_error" in text and "'midpoints'" in text and "'local'" in text
    assert _estimate(None, Together, "run_pem") == ("local", True)
    assert _estimate("local", Together, "run_pem") == ("local", True)
