"""The adaptive PEM frequency grid (tb_exudyn.methods.adaptive_grid) and the a posteriori grid error
(tb_exudyn.methods.grid_error).

The model problem of the quadrature checks is one mode, y'' + 2 zeta w0 y' + w0^2 y = exp(i w t),
w0 = 2 pi 8.34 Hz (the ICE motor bogie's yaw, docs/findings.md section 4), driven from rest, times
a smooth input spectrum S(f) = (1 + (f / 2 Hz)^2)^(-3/2) that falls like f^-3 as the track spectra
do, over the study's band 0.3-60 Hz. Its response in closed form (below) is the PEM pseudo-response
of a single mode; the exact integrals come from scipy.integrate.quad on sub-intervals that break at
the peak (and at every 1/T for the transient, whose integrand oscillates with period 1/T in f).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad

from tb_exudyn.methods.adaptive_grid import (
    GridResolution, adaptive_nodes, grid_problem, points_needed, required_spacing, scenario_grid_problem,
)
from tb_exudyn.methods.grid import adaptive_grid, midpoint_grid, refined_grid, refined_variance, scenario_adaptive_grid
from tb_exudyn.methods.grid_error import grid_error_from_sigma
from tb_exudyn.scenario import ScenarioError, load_scenario
from tb_exudyn.track import quadrature_weights

F_MIN, F_MAX, F_M = 0.3, 60.0, 8.34


def spectrum(f):
    return (1 + (np.asarray(f) / 2.0) ** 2) ** -1.5


def h2_stationary(f, zeta):
    """|H(f)|^2 of the mode (unit mass), H = 1 / (w0^2 - w^2 + 2 i zeta w0 w)."""
    w, w0 = 2 * np.pi * np.asarray(f), 2 * np.pi * F_M
    return 1 / ((w0**2 - w**2) ** 2 + (2 * zeta * w0 * w) ** 2)


def response_from_rest(f, t, zeta):
    """y(f, t), shape (nf, nt): H e^{iwt} + c1 e^{l1 t} + c2 e^{l2 t} with l1,2 = -zeta w0 +- i wd and
    c1, c2 from y(0) = y'(0) = 0: c1 = -H (iw - l2) / (l1 - l2), c2 = H (iw - l1) / (l1 - l2)."""
    w, t = 2 * np.pi * np.asarray(f, dtype=float)[:, None], np.asarray(t, dtype=float)[None, :]
    w0 = 2 * np.pi * F_M
    l1 = -zeta * w0 + 1j * w0 * math.sqrt(1 - zeta**2)
    l2 = l1.conjugate()
    H = 1 / (w0**2 - w**2 + 2j * zeta * w0 * w)
    return H * np.exp(1j * w * t) - H * (1j * w - l2) / (l1 - l2) * np.exp(l1 * t) + H * (1j * w - l1) / (l1 - l2) * np.exp(l2 * t)


def exact_integral(g, breaks):
    """quad over sub-intervals between the break points and at every 1 Hz, each to 1e-10 relative or
    1e-12 of the whole (a far, tiny piece needs no relative accuracy of its own)."""
    edges = np.unique(np.clip(np.concatenate(([F_MIN, F_MAX], breaks, np.arange(1.0, F_MAX))), F_MIN, F_MAX))
    pieces = [quad(g, a, b, limit=200, epsabs=0, epsrel=1e-4)[0] for a, b in zip(edges[:-1], edges[1:])]
    tol = 1e-12 * sum(pieces)
    return sum(quad(g, a, b, limit=200, epsabs=tol, epsrel=1e-10)[0] for a, b in zip(edges[:-1], edges[1:]))


def test_closed_form_response_satisfies_its_ode():
    """The closed form above: y(0) = 0, and y(dt) = dt^2 / 2 (y'(0) = 0 and y''(0) = 1, the force at
    t = 0; the next term, of order w dt, is 2e-3 relative at dt = 1e-5 s and 30 Hz); the ODE residual
    by central differences at t = 0.7 s (truncation (w dt)^2 / 12 ~ 1e-6 of w0^2 y, round-off
    eps |y| / dt^2 ~ 1e-6: tolerance 1e-4 against the forcing of modulus 1)."""
    f, zeta, dt = np.array([0.5, 8.0, F_M, 30.0]), 0.01, 1e-5
    t = np.array([0.0, dt, 0.7 - dt, 0.7, 0.7 + dt])
    y = response_from_rest(f, t, zeta)
    w0, w = 2 * np.pi * F_M, 2 * np.pi * f
    assert np.allclose(y[:, 0], 0, atol=1e-15) and np.allclose(y[:, 1] / (dt**2 / 2), 1, rtol=3e-3)
    ydd = (y[:, 2] - 2 * y[:, 3] + y[:, 4]) / dt**2
    yd = (y[:, 4] - y[:, 2]) / (2 * dt)
    residual = ydd + 2 * zeta * w0 * yd + w0**2 * y[:, 3] - np.exp(1j * w * 0.7)
    assert np.allclose(residual, 0, atol=1e-4)


def test_weights_sum_to_the_band_and_nodes_span_it():
    """Trapezoid weights on the non-uniform nodes: the band is exactly [f_min, f_max] (the nodes
    include both ends) and the weights telescope to f_max - f_min (rounding only, 1e-12)."""
    g = adaptive_grid(grid_problem(F_MIN, F_MAX, [(F_M, 1e-4), (3.33, 0.05), (12.42, 2.5e-4)], 5.57), 61.1, 300)
    assert g.f.size == 300 and g.f[0] == F_MIN and g.f[-1] == F_MAX and np.all(np.diff(g.f) > 0)
    assert g.band == (F_MIN, F_MAX) and g.rule == "trapezoid"
    assert g.df.sum() == pytest.approx(F_MAX - F_MIN, rel=1e-12)
    assert np.allclose(g.df, quadrature_weights(g.f, "trapezoid"), rtol=1e-15)


def test_nodes_cluster_at_the_modes_as_specified():
    """With the least number of points, every cell is no wider than the required spacing anywhere in
    it (1 % slack: the point count is integrated on an auxiliary grid at 1/8 of the spacing); at the
    lightly damped mode the spacing is about 1 / (run_factor T) (not much finer either: within a
    factor 1.3), at the 2 % mode about zeta f / halfwidth_points, and away from the modes the
    background's min(0.05 f, 1 / (spread + 1 / background_max)) holds (spread 1.5 s: 0.5 Hz)."""
    res, T = GridResolution(), 5.57
    modes = [(F_M, 1e-4), (24.0, 0.02)]
    problem = grid_problem(F_MIN, F_MAX, modes, T, spread=1.5)
    n = points_needed(problem, res)
    f = adaptive_nodes(problem, n, res)
    h = np.diff(f)
    inside = f[:-1, None] + h[:, None] * np.linspace(0, 1, 21)[None, :]
    allowed = required_spacing(problem, inside.ravel(), res).reshape(inside.shape).max(axis=1)
    assert np.all(h <= 1.01 * allowed)
    at_light = h[np.searchsorted(f, F_M) - 1]
    assert 1 / (1.3 * res.run_factor * T) <= at_light <= 1.01 / (res.run_factor * T)
    near = np.abs(f - F_M) <= 1 / T  # the run's spectral width: about 2 run_factor + 1 nodes in it
    assert near.sum() >= 2 * res.run_factor
    at_damped = h[np.searchsorted(f, 24.0) - 1]
    assert 0.77 * 0.02 * 24.0 <= at_damped <= 1.01 * 0.02 * 24.0 / res.halfwidth_points
    assert h[0] <= 1.01 * 0.05 * f[1]
    assert 0.9 * 0.5 <= h[np.searchsorted(f, 45.0)] <= 1.01 * 0.5



@pytest.mark.parametrize("grade, background_max", [(10.0, 2.0), (3.0, 0.5), (30.0, 2.0)])
def test_required_spacing_equals_its_formula_over_every_mode(grade, background_max):
    """required_spacing evaluates each mode only near it (within 1.01 grade h_bg, where it can lower
    h): the values must be those of the formula h(f) = min(background_relative f, h_bg, min over all
    modes sqrt(h_m^2 + ((f - f_m) / grade)^2)) evaluated here over every mode and every f, exactly
    (the same floating-point operations where a mode counts; elsewhere the formula's term exceeds
    h_bg). 60 random modes (zeta 1e-4 .. 0.3, two outside the band), f unsorted, 2-D and scalar."""
    rng = np.random.default_rng(7)
    res = GridResolution(grade=grade, background_max=background_max)
    modes = [(float(f), float(z)) for f, z in zip(rng.uniform(0.1, 70.0, 60), 10 ** rng.uniform(-4, -0.5, 60))]
    problem = grid_problem(F_MIN, F_MAX, modes, 5.57, spread=1.5)
    hm = np.maximum(problem.modes[:, 1] * problem.modes[:, 0] / res.halfwidth_points, 1 / (res.run_factor * 5.57))
    h_bg = 1 / (1.5 + 1 / background_max)
    for f in (rng.uniform(F_MIN, F_MAX, 4000), rng.uniform(F_MIN, F_MAX, (40, 25)), np.float64(8.0)):
        f = np.asarray(f)
        terms = np.hypot(hm[:, None], (f.reshape(1, -1) - problem.modes[:, :1]) / grade)  # every mode at every f
        expected = np.minimum(np.minimum(res.background_relative * f.reshape(-1), h_bg), terms.min(axis=0))
        got = required_spacing(problem, f, res)
        assert got.shape == f.shape
        assert np.array_equal(got.reshape(-1), expected)

def test_n_max_is_respected_and_too_few_points_name_the_key():
    """n_max nodes exactly (extra points refine the whole grid); fewer than needed: ValueError from the
    plain function, ScenarioError naming analysis.n_freq and the count needed from the scenario's."""
    modes = [(F_M, 1e-4), (12.42, 2.5e-4), (3.33, 0.05)]
    need = points_needed(grid_problem(F_MIN, F_MAX, modes, 5.57))
    assert adaptive_grid(grid_problem(F_MIN, F_MAX, modes, 5.57), 61.1, need).f.size == need
    assert adaptive_grid(grid_problem(F_MIN, F_MAX, modes, 5.57), 61.1, 2 * need).f.size == 2 * need
    with pytest.raises(ValueError, match=f"at least {need} frequencies"):
        adaptive_grid(grid_problem(F_MIN, F_MAX, modes, 5.57), 61.1, need - 1)
    sc = load_scenario("li_zhu_2011")
    sc = sc.replace(analysis=sc.analysis.replace(freq_spacing="adaptive", n_freq=100))
    need_sc = points_needed(scenario_grid_problem(sc, modes))
    with pytest.raises(ScenarioError) as err:
        scenario_adaptive_grid(sc, modes)
    message = str(err.value)
    assert "'analysis.n_freq' = 100" in message and f"at least {need_sc}" in message and "8.34 Hz" in message
    assert len(message.splitlines()) == 1
    grid = scenario_adaptive_grid(sc.replace(analysis=sc.analysis.replace(n_freq=need_sc)), modes)
    assert grid.f.size == need_sc and grid.speed == pytest.approx(sc.speed)


def test_adaptive_needs_at_least_two_frequencies():
    sc = load_scenario("quick")
    with pytest.raises(ScenarioError, match="n_freq"):
        sc.replace(analysis=sc.analysis.replace(freq_spacing="adaptive", n_freq=1))


def _fitted_rate(ns, errors):
    return float(np.polyfit(np.log(ns), np.log(errors), 1)[0])


@pytest.mark.parametrize("zeta", [1e-3, 0.05])
def test_quadrature_of_a_stationary_resonance_converges_at_second_order(zeta):
    """integral |H|^2 S df on the adaptive grid for a long run (T = 1e4 s: the damping criterion
    governs, spacing zeta f at the peak). With the least number of points the error is below 0.3 %
    (aliasing estimate 2 exp(-2 pi) = 0.4 % with one point per half-width, graded tails); refining
    by 1.5-8 x converges at the trapezoid rule's second order: fitted rate <= -1.8."""
    T = 1e4
    exact = exact_integral(lambda f: float(h2_stationary(f, zeta) * spectrum(f)),
                           F_M + zeta * F_M * np.array([-30.0, -3.0, 0.0, 3.0, 30.0]))
    need = points_needed(grid_problem(F_MIN, F_MAX, [(F_M, zeta)], T))
    ns = [int(k * need) for k in (1, 1.5, 2, 3, 4, 6, 8)]
    errors = []
    for n in ns:
        f = adaptive_nodes(grid_problem(F_MIN, F_MAX, [(F_M, zeta)], T), n)
        errors.append(abs(float(np.sum(h2_stationary(f, zeta) * spectrum(f) * quadrature_weights(f, "trapezoid"))) / exact - 1))
    assert errors[0] < 3e-3
    assert _fitted_rate(ns, errors) <= -1.8


@pytest.mark.parametrize("zeta", [1e-3, 0.05])
def test_quadrature_of_a_transient_resonance_resolves_the_run(zeta):
    """integral |y(f, T)|^2 S df of the mode started from rest, T = 5 s: for zeta = 1e-3 the mode's
    decay time 1 / (zeta w0) = 19 s exceeds the run and the integrand is a Fejer-like kernel of width
    1/T = 0.2 Hz. The adaptive grid with the least number of points is within 1 % (the design
    target); a linear grid of as many points is off by more than 3 % for the light mode (its spacing
    0.45 Hz > 1/T); refining the adaptive grid converges at a fitted rate <= -1.8."""
    T = 5.0

    def g(f: float) -> float:
        return float(np.abs(response_from_rest(np.array([f]), [T], zeta)[0, 0]) ** 2 * spectrum(f))

    exact = exact_integral(g, F_M + np.arange(-40, 41) / T)
    need = points_needed(grid_problem(F_MIN, F_MAX, [(F_M, zeta)], T))

    def quadrature(f):
        return float(np.sum(np.abs(response_from_rest(f, [T], zeta)[:, 0]) ** 2 * spectrum(f) * quadrature_weights(f, "trapezoid")))

    ns = [int(k * need) for k in (1, 1.5, 2, 3, 4, 6, 8)]
    errors = [abs(quadrature(adaptive_nodes(grid_problem(F_MIN, F_MAX, [(F_M, zeta)], T), n)) / exact - 1) for n in ns]
    assert errors[0] < 1e-2
    assert _fitted_rate(ns, errors) <= -1.8
    if zeta < 1 / (2 * np.pi * F_M * T):
        assert abs(quadrature(np.linspace(F_MIN, F_MAX, need)) / exact - 1) > 0.03


def test_midpoint_refinement_is_the_trapezoid_rule_on_the_union():
    """(trapezoid(grid) + midpoint(cells)) / 2 equals the trapezoid rule on nodes and midpoints together,
    exactly (cell by cell: h/4 (g_a + 2 g_m + g_b)); checked on an arbitrary smooth integrand to 1e-13."""
    g = adaptive_grid(grid_problem(F_MIN, F_MAX, [(F_M, 1e-3)], 5.0), 61.1, 250)
    m, u = midpoint_grid(g), refined_grid(g)
    assert m.df.sum() == pytest.approx(F_MAX - F_MIN, rel=1e-12) and u.f.size == 2 * g.f.size - 1

    def integrand(f):
        return np.stack([np.sin(f) ** 2 * spectrum(f), h2_stationary(f, 0.01)])

    combined = refined_variance(integrand(g.f) @ g.df, integrand(m.f) @ m.df)
    assert np.allclose(combined, integrand(u.f) @ u.df, rtol=1e-13, atol=0)


def test_grid_error_estimate_on_a_known_case():
    """sigma(t) of the mode (zeta = 1e-3) from rest over 0 < t <= 5 s on the study's 200-point linear
    grid (spacing 0.3 Hz: the run outgrows 1/df = 3.3 s), its estimated error from the midpoint
    refinement, and its true error against a 4000-point linear grid (spacing 0.015 Hz, 1/df = 67 s:
    accurate to 1e-4, checked against quad at t = T). The estimate of the relative error of max sigma is
    within a factor of 2 of the true one (the acceptance criterion), the time of the largest deviation
    is the true one to one output step, and a converged grid reports below 1 %."""
    zeta, T = 1e-3, 5.0
    t = np.linspace(0.01, T, 500)

    def sigma(grid_f, grid_df):
        return np.sqrt(np.sum(np.abs(response_from_rest(grid_f, t, zeta)) ** 2 * (spectrum(grid_f) * grid_df)[:, None], axis=0))

    coarse_f = np.linspace(F_MIN, F_MAX, 200)
    coarse_w = quadrature_weights(coarse_f, "trapezoid")
    mid_f, mid_w = (coarse_f[1:] + coarse_f[:-1]) / 2, np.diff(coarse_f)
    var_c = sigma(coarse_f, coarse_w) ** 2
    refined = np.sqrt(refined_variance(var_c, sigma(mid_f, mid_w) ** 2))
    fine_f = np.linspace(F_MIN, F_MAX, 4000)
    truth = sigma(fine_f, quadrature_weights(fine_f, "trapezoid"))
    exact_T = exact_integral(lambda f: float(np.abs(response_from_rest(np.array([f]), [T], zeta)[0, 0]) ** 2 * spectrum(f)),
                             F_M + np.arange(-40, 41) / T)
    assert truth[-1] == pytest.approx(math.sqrt(exact_T), rel=1e-4)

    names = ["mode.disp"]
    estimate = grid_error_from_sigma(t, names, np.sqrt(var_c)[None], refined[None])
    true = grid_error_from_sigma(t, names, np.sqrt(var_c)[None], truth[None])
    assert abs(true.rel_error_max_sigma[0]) > 0.05  # the case is a real test: a large error
    assert 0.5 <= estimate.rel_error_max_sigma[0] / true.rel_error_max_sigma[0] <= 2.0
    assert abs(estimate.time_of_deviation[0] - true.time_of_deviation[0]) <= t[1] - t[0] + 1e-12
    assert estimate.exceeding(0.01) == names

    g = adaptive_grid(grid_problem(F_MIN, F_MAX, [(F_M, zeta)], T), 61.1, points_needed(grid_problem(F_MIN, F_MAX, [(F_M, zeta)], T)))
    m = midpoint_grid(g)
    s_a = sigma(g.f, g.df)
    converged = grid_error_from_sigma(t, names, s_a[None], np.sqrt(refined_variance(s_a**2, sigma(m.f, m.df) ** 2))[None])
    assert converged.exceeding(0.01) == []
    assert abs(grid_error_from_sigma(t, names, s_a[None], truth[None]).rel_error_max_sigma[0]) < 0.01


def test_refined_response_interleaves_and_averages():
    """refined_response on two synthetic PEM results (quick's channels and times, random variances of a
    seeded generator): variances (a + b) / 2 per type, sigma their sum's root, frequencies and PSD
    interleaved, weights the trapezoid rule on the union (identities: rtol 1e-14); grid_error of the
    pair says it used the midpoints."""
    from tb_exudyn.methods.grid_error import grid_error, refined_response
    from tb_exudyn.results.random_response import RandomResponse

    rng = np.random.default_rng(14)
    sc = load_scenario("quick")
    f = np.array([1.0, 2.0, 4.0, 5.0])
    fm = (f[1:] + f[:-1]) / 2
    time, channels = np.linspace(0, 1, 5), ("a.x", "b.y")

    def response(freq, df):
        var = rng.uniform(1, 2, (3, 2, time.size))
        return RandomResponse(method="pem", time=time, channels=channels, units=("m", "m"), mean=np.zeros((2, 5)),
                              std=np.sqrt(var.sum(0)), band=(1.0, 5.0), scenario=sc, freq=freq, df=df,
                              psd=rng.uniform(0, 1, (2, freq.size, 5)), var_by_type=var, types=("p", "q", "r"))

    coarse, mid = response(f, quadrature_weights(f, "trapezoid")), response(fm, np.diff(f))
    r = refined_response(coarse, mid)
    assert np.allclose(r.var_by_type, (coarse.var_by_type + mid.var_by_type) / 2, rtol=1e-14)
    assert np.allclose(r.std, np.sqrt(r.var_by_type.sum(0)), rtol=1e-14)
    assert np.array_equal(r.freq, [1.0, 1.5, 2.0, 3.0, 4.0, 4.5, 5.0])
    assert np.allclose(r.df, quadrature_weights(r.freq, "trapezoid"), rtol=1e-14)
    assert np.array_equal(r.psd[:, ::2], coarse.psd) and np.array_equal(r.psd[:, 1::2], mid.psd)
    assert grid_error(coarse, r).method.startswith("refined")
    with pytest.raises(ValueError, match="midpoints"):
        refined_response(coarse, coarse)


def test_grid_error_fields_and_json_form():
    """Two channels over 3 times: one overstated by 2 % at its maximum (t = 2 s), one exact, one zero
    throughout; the relative errors, the time of the largest deviation and the JSON form follow by hand."""
    import json

    t = np.array([0.0, 1.0, 2.0])
    refined = np.array([[1.0, 2.0, 3.0], [1.0, 1.0, 1.0], [0.0, 0.0, 0.0]])
    sigma = refined * np.array([[1.0], [1.0], [1.0]]) + np.array([[0.0, 0.0, 0.06], [0, 0, 0], [0, 0, 0]])
    e = grid_error_from_sigma(t, ["a", "b", "c"], sigma, refined)
    assert e.rel_error_max_sigma == pytest.approx([0.02, 0.0, 0.0], abs=1e-15)
    assert e.rel_deviation == pytest.approx([0.02, 0.0, 0.0], abs=1e-15) and e.time_of_deviation[0] == 2.0
    assert e.exceeding(0.01) == ["a"] and e.exceeding(0.03) == []
    d = json.loads(json.dumps(e.as_dict()))
    assert d["channels"]["a"]["rel_error_max_sigma"] == pytest.approx(0.02) and d["method"] == e.method
