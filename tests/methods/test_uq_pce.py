"""The polynomial chaos machinery on functions with known answers (issue 46).

The functions of tb_exudyn.methods.uq.pce take node values, not the runner: the same calls the
uncertainty study makes on its PEM nodes (germs of the keys, nodes, key values, fit, moments, Sobol
indices) are made here on the Ishigami function
f = sin x1 + a sin^2 x2 + b x3^4 sin x1, x_i ~ U(-pi, pi), a = 7, b = 0.1,
whose mean a / 2, variance a^2/8 + b pi^4/5 + b^2 pi^8/18 + 1/2 and partial variances
V1 = (1 + b pi^4/5)^2 / 2, V2 = a^2/8, V3 = 0, V13 = 8 b^2 pi^8 / 225 are known in closed form
(Ishigami & Homma 1990; Sobol' & Levitan 1999), typed in here.

Tolerance 1e-3 (the issue's) on the mean, the relative variance and every Sobol index: an order-10
expansion on the 11^3 tensor Gauss grid is measured within 4e-5 (order 12: 2e-7); the Sobol design
of 1500 points with least squares within 2e-5 at order 10.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from tb_exudyn.errors import ScenarioError, SettingError
from tb_exudyn.methods.uq import pce
from tb_exudyn.scenario.uncertain import lognormal_parameters, parse_key


A, B = 7.0, 0.1
V = A**2 / 8 + B * math.pi**4 / 5 + B**2 * math.pi**8 / 18 + 0.5
V1, V2, V13 = 0.5 * (1 + B * math.pi**4 / 5) ** 2, A**2 / 8, 8 * B**2 * math.pi**8 / 225
FIRST = np.array([V1 / V, V2 / V, 0.0])
TOTAL = np.array([(V1 + V13) / V, V2 / V, V13 / V])


def ishigami(x):
    return np.sin(x[0]) + A * np.sin(x[1]) ** 2 + B * x[2] ** 4 * np.sin(x[0])


def keys():
    """x1..x3 as uncertain keys: uniform, absolute bounds (the parser the scenario files use)."""
    return [parse_key(f"x{i}", {"distribution": "uniform", "bounds": [-math.pi, math.pi]}, 0.0, "test")
            for i in range(3)]


@pytest.mark.parametrize("design, order, n_nodes", [("tensor", 10, None), ("sobol", 10, 1500)])
def test_ishigami_moments_and_sobol_indices(design, order, n_nodes):
    ks = keys()
    germs = [pce.key_germ(k) for k in ks]
    x, w = pce.nodes(germs, order, design, n_nodes)
    values = ishigami(np.stack([pce.key_value(k, x[j]) for j, k in enumerate(ks)]))
    e = pce.fit(germs, order, x, w, values)
    assert abs(e.mean - A / 2) < 1e-3
    assert abs(e.variance / V - 1) < 1e-3
    assert np.max(np.abs(e.sobol_first() - FIRST)) < 1e-3
    assert np.max(np.abs(e.sobol_total() - TOTAL)) < 1e-3
    assert e.loo < 1e-3


def test_vector_outputs_are_expanded_elementwise():
    """Node values of any shape: each element its own expansion (a product of polynomials in
    normal and lognormal keys, whose mean and variance are known: E[a + b X1 + X1 X2] with X1 ~ N(2, 0.5^2)
    and X2 lognormal of mean 3, cov 0.2: mean a + 2 b + 6, variance by independence)."""
    k1 = parse_key("x1", {"distribution": "normal", "std": 0.5}, 2.0, "test")
    k2 = parse_key("x2", {"distribution": "lognormal", "cov": 0.2}, 3.0, "test")
    germs = [pce.key_germ(k1), pce.key_germ(k2)]
    x, w = pce.nodes(germs, 6, "tensor")
    x1, x2 = pce.key_value(k1, x[0]), pce.key_value(k2, x[1])
    a, b = np.array([1.0, -2.0, 0.0]), np.array([0.0, 1.0, 3.0])
    values = a[None, :] + b[None, :] * x1[:, None] + (x1 * x2)[:, None]
    e = pce.fit(germs, 6, x, w, values)
    ex1, vx1, ex2, vx2 = 2.0, 0.25, 3.0, (0.2 * 3.0) ** 2
    mean = a + b * ex1 + ex1 * ex2
    # Var(b X1 + X1 X2) = E[X1^2 (b + X2)^2] - (E[X1](b + E X2))^2
    var = (vx1 + ex1**2) * ((b + ex2) ** 2 + vx2) - (ex1 * (b + ex2)) ** 2
    assert np.allclose(e.mean, mean, rtol=1e-9)
    # a lognormal is no polynomial of its germ: order 6 leaves a relative error of order s^7 / 7!
    assert np.allclose(e.variance, var, rtol=1e-6)
    mu, s = lognormal_parameters(3.0, 0.6)
    assert math.isclose(math.exp(mu + s**2 / 2), 3.0) and math.isclose(math.exp(2 * mu + s**2) * math.expm1(s**2), 0.36)


@pytest.mark.parametrize("order, design, nodes", [(0, "tensor", None), (3, "latin", None), (3, "tensor", 50),
                                                  (2, "sobol", 1), (True, "tensor", None)])
def test_bad_design_is_refused(order, design, nodes):
    with pytest.raises(SettingError, match="run_uq"):
        pce.check_design(order, design, nodes, "run_uq")


@pytest.mark.parametrize("entry, match", [
    ({"distribution": "gamma", "cov": 0.1}, "unknown distribution"),
    ({"distribution": "normal", "cov": -0.1}, "not positive"),
    ({"distribution": "normal", "cov": 0.1, "std": 1.0}, "both given"),
    ({"distribution": "uniform", "bounds": [2.0, 1.0]}, "bad bounds"),
    ({"distribution": "truncated_normal", "cov": 0.1}, "bad parameters"),
    ({"distribution": "normal", "cov": 0.1, "sigma": 3}, "unknown key"),
])
def test_bad_entries_name_the_key(entry, match):
    with pytest.raises(ScenarioError, match=f"uncertain.k.*{match}"):
        parse_key("k", entry, 1.0, "f.toml")


def test_lognormal_of_a_zero_key_is_refused():
    with pytest.raises(ScenarioError, match="lognormal: a positive mean"):
        parse_key("k", {"distribution": "lognormal", "std": 0.1}, 0.0, "f.toml")


def test_uncertain_table_in_a_scenario_file(tmp_path):
    """A scenario file's [uncertain] table: load_study reads and checks it (absolute parameters from
    the scenario's values); load_scenario (run, show) leaves it aside."""
    from tb_exudyn.scenario import load_scenario, save_scenario
    from tb_exudyn.scenario.uncertain import load_study

    path = save_scenario(load_scenario("quick"), tmp_path / "s.toml")
    path.write_text(path.read_text() + '\n[uncertain."bridge.girder.E"]\ndistribution = "lognormal"\ncov = 0.1\n'
                    '[uncertain."track.irregularity_level"]\ndistribution = "truncated_normal"\nstd = 0.3\n'
                    'bounds = [0.5, 2.0]\n')
    sc, keys = load_study(path)
    assert sc == load_scenario(path)
    assert keys[0].key == "bridge.girder.E" and keys[0].mean == sc.bridge.girder.E
    assert math.isclose(keys[0].std, 0.1 * sc.bridge.girder.E)
    assert (keys[1].mean, keys[1].std, keys[1].low, keys[1].high) == (1.0, 0.3, 0.5, 2.0)


@pytest.mark.parametrize("design", ["tensor", "sparse"])
def test_polynomial_is_reproduced_exactly(design):
    """f = 1 + X0 + 2 X1 X2 + X0^2 X2, X_i ~ N(0, 1) independent, is a polynomial of total degree 3: an
    order-3 expansion on either quadrature reproduces it, so its moments are exact to round-off.
    By hand, with X0^2 X2 = (X0^2 - 1) X2 + X2 (orthogonal parts of variances 2 and 1): E f = 1;
    Var f = 1 + 4 + 2 + 1 = 8; first order: X0 alone 1, X1 alone 0, X2 alone 1; total: X0 in X0 and
    (X0^2 - 1) X2 (1 + 2 = 3), X1 in 2 X1 X2 (4), X2 in 2 X1 X2, (X0^2 - 1) X2 and X2 (4 + 2 + 1 = 7)."""
    ks = [parse_key(f"x{i}", {"distribution": "normal", "std": 1.0}, 0.0, "test") for i in range(3)]
    germs = [pce.key_germ(k) for k in ks]
    x, w = pce.nodes(germs, 3, design)
    X = np.stack([pce.key_value(k, x[j]) for j, k in enumerate(ks)])
    e = pce.fit(germs, 3, x, w, 1 + X[0] + 2 * X[1] * X[2] + X[0] ** 2 * X[2])
    assert abs(e.mean - 1) < 1e-12 and abs(e.variance - 8) < 1e-11
    assert np.allclose(e.sobol_first(), [1 / 8, 0, 1 / 8], atol=1e-12)
    assert np.allclose(e.sobol_total(), [3 / 8, 4 / 8, 7 / 8], atol=1e-12)


def test_loo_warning_above_one_per_cent():
    """The surrogate's leave-one-out error: a quadratic fitted at order 1 on 16 Sobol nodes misses its
    curvature (warned), at order 2 it is exact (no warning); a probability far below any target and a
    quantity the keys hardly move are not judged."""
    from tb_exudyn.methods.uq.summary import loo_warnings

    k = parse_key("x", {"distribution": "uniform", "bounds": [0.0, 1.0]}, 0.5, "test")
    germs = [pce.key_germ(k)]
    x, _ = pce.nodes(germs, 1, "sobol", 16)
    y = pce.key_value(k, x[0]) ** 2
    assert pce.fit(germs, 1, x, None, y).loo > 0.01
    assert pce.fit(germs, 2, x, None, y).loo < 1e-20
    assert loo_warnings(["max_sigma:a", "b"], np.array([0.02, 0.001]))[0].count("1 of 2 quantities") == 1
    assert loo_warnings(["probability:c"], np.array([5.0]), np.array([1e-30])) == []
    assert loo_warnings(["max_sigma:a"], np.array([0.005])) == []
    # a quantity the keys hardly move (cov 2e-4, the car body on li_zhu_2011): its LOO of 9 % is noise
    assert loo_warnings(["max_sigma:b"], np.array([0.09]), np.array([0.093]), np.array([1.9e-5])) == []
    assert loo_warnings(["max_sigma:d"], np.array([0.019]), np.array([0.101]), np.array([0.0091]))


def test_quantity_band_is_the_keys_quantiles():
    """The 5, 50 and 95 % points of a quantity over the keys (``quantity_band``: the surrogate at 1024
    Sobol points). The quantities are the keys themselves, a uniform on [2, 4] and a normal N(10, 1),
    whose quantiles are known in closed form: 2 + 2 p, and 10 + z_p (z_0.95 = 1.6449). The expansion of
    a key in its own germ is exact at order 1, so what is left is the Sobol points' quantile error: each
    key's 1024 points fall about one in each of 1024 equal-probability cells, and the percentile
    interpolates between neighbours: an error of about one cell, 1/1024 of the probability, that is
    2.0e-3 in the uniform's value and 9.8e-4 / phi(z_0.95) = 9.5e-3 in the normal's at 5 and 95 %
    (measured: 1.9e-3 and 8.9e-3); tolerance two cells, 4e-3 and 2e-2. A max sigma is clipped at 0 and a probability to [0, 1] (a polynomial may leave
    them between the nodes); a least-squares design gives the same points."""
    from statistics import NormalDist

    from tb_exudyn.methods.uq.summary import quantity_band

    ks = [parse_key("u", {"distribution": "uniform", "bounds": [2.0, 4.0]}, 3.0, "test"),
          parse_key("n", {"distribution": "normal", "std": 1.0}, 10.0, "test")]
    germs = [pce.key_germ(k) for k in ks]
    for design, n in (("tensor", None), ("sobol", 20)):
        x, w = pce.nodes(germs, 2, design, n)
        v = np.stack([pce.key_value(k, x[j]) for j, k in enumerate(ks)])
        values = np.stack([v[0], v[1], v[1] - 10.0, v[1] - 10.0], axis=1)  # node x quantity
        e = pce.fit(germs, 2, x, w, values)
        band = quantity_band(germs, 2, e, ["estimate:u", "estimate:n", "max_sigma:c", "probability:c"])
        z = [NormalDist().inv_cdf(p / 100) for p in (5, 50, 95)]
        assert np.allclose(band[:, 0], [2.1, 3.0, 3.9], atol=4e-3), band[:, 0]
        assert np.allclose(band[:, 1], 10.0 + np.array(z), atol=2e-2), band[:, 1]
        assert band[0, 2] == 0.0 and band[2, 2] == pytest.approx(z[2], abs=2e-2)  # clipped at 0
        assert band[0, 3] == 0.0 and band[2, 3] == 1.0  # clipped to [0, 1]


def test_ballast_density_key_moves_the_ballast_mass():
    """``bridge.code.ballast_density`` as an uncertain key is the ballast's density, and the model's mass
    follows it: on the reference study's frame, whose added mass carries 11677.75 kg/m of ballast at
    1800 kg/m^3, 1900 kg/m^3 adds 11677.75 x (1900 / 1800 - 1) = 648.76 kg/m to the added mass (its
    polar moment by the same ratio), as EN 1991-2's mass case at that density would; a simple beam's
    girder carries it likewise. Reach outside the code data's density range (EN 1991-1-1's 1700-2000
    kg/m^3) and a bridge without ballast are refused naming the key."""
    import tb_exudyn as tbx
    from tb_exudyn.scenario.code_data import with_mass_case
    from tb_exudyn.scenario.uncertain import BALLAST_DENSITY, apply_values, check_uncertain

    sc = tbx.load_scenario("li_zhu_2011")
    am = sc.bridge.added_mass
    node = apply_values(sc, [(BALLAST_DENSITY, 1900.0), ("bridge.damping_ratio", 0.04)])
    dm = 11677.75 * (1900.0 / 1800.0 - 1.0)
    assert node.bridge.added_mass.mass_per_length == pytest.approx(am.mass_per_length + dm, rel=1e-14)
    assert node.bridge.added_mass.rot_mass_per_length == pytest.approx(
        am.rot_mass_per_length * (am.mass_per_length + dm) / am.mass_per_length, rel=1e-14)
    assert node.bridge.code.ballast_density == 1900.0 and node.bridge.damping_ratio == 0.04
    assert node.bridge.girder == sc.bridge.girder
    upper = with_mass_case(sc.bridge, "upper")  # the mass case at 2000 kg/m^3: the same change
    assert apply_values(sc, [(BALLAST_DENSITY, 2000.0)]).bridge.added_mass.mass_per_length == pytest.approx(
        upper.added_mass.mass_per_length, rel=1e-14)
    beam = tbx.load_scenario("quick")  # a simple beam: its girder carries the ballast
    assert apply_values(beam, [(BALLAST_DENSITY, 1900.0)]).bridge.girder.mass_per_length == pytest.approx(
        beam.bridge.girder.mass_per_length + beam.bridge.code.ballast_mass_per_length / 18.0, rel=1e-14)
    keys = check_uncertain(sc, {BALLAST_DENSITY: {"distribution": "uniform", "bounds": [1700.0, 2000.0]}}, "t.toml")
    assert keys[0].nominal == 1800.0
    with pytest.raises(ScenarioError, match="uncertain.bridge.code.ballast_density.*density range"):
        check_uncertain(sc, {BALLAST_DENSITY: {"distribution": "uniform", "bounds": [1600.0, 2000.0]}}, "t.toml")
    with pytest.raises(ScenarioError, match="uncertain.bridge.code.ballast_density.*no ballast"):
        check_uncertain(tbx.load_scenario("yang_yau_sprung_mass"),
                        {BALLAST_DENSITY: {"distribution": "uniform", "bounds": [1700.0, 2000.0]}}, "t.toml")
