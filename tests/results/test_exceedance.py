"""Exceedance probabilities of PEM results against a closed form and against Monte Carlo (issue 16).

Problems, references and tolerances are stated per test. The Monte Carlo case (10^4 linear samples on
the batched engine, about 30 s) is computed once for the module.
"""

from __future__ import annotations

import math
import time
import warnings

import numpy as np
import pytest
from scipy import stats

import tb_exudyn as tbx
from tb_exudyn.methods import run_monte_carlo, run_pem
from tb_exudyn.methods.grid import scenario_grid
from tb_exudyn.system.statistics import upcrossing_rate
from tb_exudyn.scenario import load_bridge, load_vehicle

from ..system.test_comfort import pole_zero_response

pytestmark = pytest.mark.exudyn

N_MC = 10_000


# ============================================================================================ closed form
def test_stationary_upcrossing_rate_of_a_sprung_mass_matches_rice_closed_form():
    """Problem: a sprung mass (5750 kg on 1.595e6 N/m, damping ratio 0.15, no wheel mass) runs 400 m on
    the rigid approach at 300 km/h over the German low-interference vertical profile; PEM (batched
    engine) on 20 frequencies 1-20 Hz; times 4.0-4.7 s, where the start-up transient has decayed (decay
    time 0.4 s: its cross term with the settled response, which decays as exp(-t / 0.4 s), is below
    1e-4 of the variance; at 2 s it was 1.2 %, 5 % on the 3-sigma rate) and the mass is not yet on the
    bridge (4.8 s).

    Reference: Rice's stationary rate nu+ = sigma_yd / (2 pi sigma_y) exp(-b^2 / (2 sigma_y^2)) with
    sigma_y^2 = sum_k |H_k|^2 S_hz(f_k) df_k and sigma_yd^2 = sum_k w_k^2 |H_k|^2 S_hz(f_k) df_k by
    quadrature in this test (H = (k + i c w) / (k - m w^2 + i c w) the base-excited SDOF's absolute
    transfer; S_hz(f) = 2 pi S(Omega) / v with the German low vertical formula typed here; on the PEM
    grid), for the displacement (y = z, yd = velocity: recorded derivative) and the acceleration
    (y = a = -w^2 z, yd = jerk: pseudo-derivative), at b = 2 and 3 sigma_y above the mean.

    Tolerance 1 % (the issue's): the generalized-alpha step errs by <= 1.3e-3 at 20 Hz on sigma
    (tests/methods/test_pem.py), which the exponent multiplies by (b / sigma)^2 <= 9 where the weight
    of 20 Hz is small; rho is 0 and the mean constant in the stationary state. Measured: 1.2e-4 and
    2.5e-4 (displacement, 2 and 3 sigma), 1.8e-4 and 4.0e-4 (acceleration).
    """
    m, k, zeta = 5750.0, 1.595e6, 0.15
    c = 2 * zeta * math.sqrt(k * m)
    car = load_vehicle("vbi2d_damped").replace(damping=c)
    sc = tbx.Scenario(
        name="rice_stationary", speed_kmh=300.0, train=tbx.scenario.Train(vehicles=(car,)),
        bridge=load_bridge("vbi2d_beam"),
        track=tbx.scenario.Track(irregularities=("german_low.vertical",), wavelength_min=1.0, wavelength_max=120.0,
                                 lead_in=400.0, run_out=0.0, taper_length=20.0),
        analysis=tbx.scenario.Analysis(time_step=1e-3, output_step=1e-2, freq_min=1.0, freq_max=20.0, n_freq=20,
                                       channels=("car1.body.disp_z", "car1.body.acc_z"), mode_max_frequency=80.0),
    )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = run_pem(sc, workers=1, progress=False, engine="batched")
    v = sc.speed
    g = scenario_grid(sc)
    w = 2 * math.pi * g.f
    A_v, Oc, Or = 4.032e-7, 0.8246, 0.0206
    omega = 2 * math.pi * g.f / v
    s_hz = 2 * math.pi * (A_v * Oc**2 / ((omega**2 + Or**2) * (omega**2 + Oc**2))) / v
    H2 = np.abs((k + 1j * c * w) / (k - m * w**2 + 1j * c * w)) ** 2
    window = (r.time >= 4.0) & (r.time <= 4.7)
    for channel, p in (("car1.body.disp_z", 0), ("car1.body.acc_z", 2)):
        sy = math.sqrt(np.sum(w ** (2 * p) * H2 * s_hz * g.df))
        syd = math.sqrt(np.sum(w ** (2 * p + 2) * H2 * s_hz * g.df))
        gr = r.gaussian(channel)
        for nb in (2.0, 3.0):
            b = nb * sy
            closed = syd / (2 * math.pi * sy) * math.exp(-b * b / (2 * sy * sy))
            nu = upcrossing_rate(gr.mean + b, gr.mean, gr.mean_rate, gr.sigma, gr.sigma_rate, gr.rho)[window]
            assert np.max(np.abs(nu / closed - 1)) < 0.01, (channel, nb, nu.min() / closed, nu.max() / closed)
    assert r.provenance["derivatives"]["car1.body.disp_z"].startswith("recorded")
    assert r.provenance["derivatives"]["car1.body.acc_z"].startswith("pseudo")


# ============================================================================================ Monte Carlo
def vertical_ice_scenario() -> tbx.Scenario:
    """The reference study's Monte Carlo check shortened: one ICE motor car over one 32 m span (track
    2.5 m off the girder axis) at 220 km/h, 50 m of approach, 20 m run-out, German low vertical only,
    100 frequencies 0.5-25 Hz, output every 5 ms (8 samples per period at 25 Hz)."""
    sc = tbx.load_scenario("li_zhu_2011_mc_check")
    return sc.replace(
        track=sc.track.replace(irregularities=("german_low.vertical",), lead_in=50.0, run_out=20.0),
        analysis=sc.analysis.replace(n_freq=100, freq_min=0.5, freq_max=25.0, output_step=0.005,
                                     channels=("bridge.span1.mid.acc_z*", "car1.body.acc_z*", "car1.body.sperling_z", "car1.axle1.*")))


@pytest.fixture(scope="module")
def case():
    sc = vertical_ice_scenario()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        t0 = time.perf_counter()
        pem = run_pem(sc, workers=1, progress=False, engine="batched", psd_channels="all")
        t1 = time.perf_counter()
        mc = run_monte_carlo(sc, n_samples=N_MC, seed=16, workers=1, progress=False, engine="batched",
                             discretisation="pem_grid_gaussian")
        t2 = time.perf_counter()
    pem.provenance["test_wall_time_s"], mc.provenance["test_wall_time_s"] = t1 - t0, t2 - t1
    return pem, mc


QUANTITIES = ("bridge.span1.mid.acc_z_en1990", "car1.axle1.left.force_z", "car1.body.acc_z_wb")
#: Poisson's error on these responses (module docstring of test_pem_probability_...): it counts every
#: out-crossing as an independent first passage and so errs high by the mean clump size - 1
POISSON_EXCESS = 0.35


@pytest.mark.parametrize("channel", QUANTITIES)
@pytest.mark.parametrize("target", [0.03, 0.15])
def test_pem_probability_within_monte_carlo_interval(case, channel, target):
    """Problem: ``vertical_ice_scenario``; a deck acceleration in the EN 1990 range (modes up to
    f_cut), a wheel load and the Wb-weighted car-body acceleration; the symmetric level b at which the
    PEM (Poisson) probability of |y| > b somewhere in the passage is 0.03 and 0.15.

    Reference: the fraction of 10^4 linear Monte Carlo samples (batched engine, Gaussian coefficients on
    the PEM grid: the same discrete Gaussian process PEM analyses) whose |y| exceeds b, with its
    Clopper-Pearson 99 % interval; the problem requires it in 0.01-0.3.

    Tolerance: the interval, its upper end widened by Poisson's error. Poisson treats every
    out-crossing as an independent event; crossings that come in clumps (two peaks of one envelope
    maximum) make it err HIGH by the mean clump size: counted in 3000 kept samples of this case
    (E[N] / P(N >= 1) - 1), +1 to +11 % at 0.03 and +6 to +24 % at 0.15 (largest: the car body),
    bounded here by 35 %. It never errs low (so the lower end is not widened); Rice's expected number
    of crossings itself matched the samples' counts to within their standard errors (2-3 %). Monte
    Carlo sees crossings only at the 5 ms outputs: it errs low by < 2 % (2 ms outputs gave the same
    probabilities within their errors). Measured PEM / MC (seed 16): 1.15 and 1.14 (deck, 0.03 and
    0.15), 1.07 and 1.07 (wheel load), 1.10 and 1.08 (car body, Wb); Vanmarcke's is 4-6 % lower than
    Poisson's here. The random-phase samples of ``pem_grid`` (not Gaussian in the tails) gave half
    the car body's probability at 0.03: exceedance needs the Gaussian discretisation.
    """
    pem, mc = case
    level = pem.exceedance_level(channel, target, kind="symmetric").level
    p_pem = pem.exceedance_probability(channel, upper=level, lower=-level).probability
    emp = mc.exceedance_probability(channel, upper=level, lower=-level, confidence=0.99)
    assert abs(p_pem - target) < 1e-9
    assert emp.n_samples == N_MC and 0.01 <= emp.probability <= 0.3, emp
    low, high = emp.interval
    assert low <= p_pem <= high * (1 + POISSON_EXCESS), (channel, target, emp.probability, emp.interval)
    # the Monte Carlo level answers the inverse question within its own interval
    lev_mc = mc.exceedance_level(channel, target, kind="symmetric", confidence=0.99)
    assert lev_mc.interval[0] <= level * (1 + 0.1) and level <= lev_mc.interval[1] * (1 + 0.1)


DERIVED = ("bridge.span1.mid.acc_z_en1990", "car1.body.acc_z_wb", "car1.axle1.unloading", "car1.axle1.left.derailment",
           "car1.axle1.right.derailment")
INPUTS = ("bridge.span1.mid.acc_z", "car1.body.acc_z", "car1.axle1.left.force_z", "car1.axle1.right.force_z",
          "car1.axle1.force_y")


def test_pem_and_monte_carlo_statistics_of_the_derived_channels(case):
    """Problem: as above; the derived channels and their inputs, at the time of each one's largest
    PEM sigma.

    Reference: the Monte Carlo sample sigma of 10^4 samples, with its chi-square interval at 99.9 %
    (Bonferroni over the 10 channels: +-2.3 %). Tolerance: that interval plus 3 % for the weighted
    car-body acceleration, where PEM's per-frequency weighting W(f_k) y_k leaves out the filter's
    start-up and the spread of the modulated response around f_k (Monte Carlo filters each sample in
    time from rest). The ratios' Monte Carlo samples are exact ratios, PEM's first order: here the
    wheel loads vary by 5 % (sigma / mean), so second-order terms are 0.3 % of sigma, inside the
    interval. Measured: see the assertion messages. Also the PEM weighted PSD is |W(f)|^2 times the
    unweighted one at every frequency (W typed here as a product of poles and zeros,
    tests/system/test_comfort.py), to the PSD's float32 transport (1e-5).
    """
    pem, mc = case
    q = stats.chi2.ppf([0.0005, 0.9995], N_MC - 1)
    band = (math.sqrt((N_MC - 1) / q[1]) - 1, math.sqrt((N_MC - 1) / q[0]) - 1)
    for c in DERIVED + INPUTS:
        i = pem.index(c)
        k = int(np.argmax(pem.std[i]))
        ratio = mc.std[i, k] / pem.std[i, k] - 1
        extra = 0.03 if c.endswith("_wb") else 0.0
        assert band[0] - extra <= ratio <= band[1] + extra, (c, ratio, band)
    psd_a, psd_wb = pem["car1.body.acc_z"].psd, pem["car1.body.acc_z_wb"].psd
    H2 = np.abs(pole_zero_response("wb", pem.freq)) ** 2
    ok = psd_a > 1e-6 * psd_a.max()
    assert np.max(np.abs(psd_wb[ok] / (H2[:, None] * psd_a)[ok] - 1)) < 1e-5
    # Sperling: PEM's index of the expected energy against the samples' mean index (documented +0.5 %)
    s = pem.index("car1.body.sperling_z")
    fin = np.isfinite(pem.mean[s])
    assert np.max(np.abs(pem.mean[s][fin] / mc.mean[s][fin] - 1)) < 0.02


def test_checks_of_the_monte_carlo_case(case):
    """The checks table of both results: every criterion with a channel in the results has rows, the
    verdict follows the probability and the target, Monte Carlo verdicts follow the interval, the
    text names every row, and the plain data round-trips through JSON."""
    import json

    pem, mc = case
    for result in (pem, mc):
        table = result.checks(probability=0.05)
        assert table.rows and table.target == 0.05
        for r in table.rows:
            if r.verdict == "NOT EVALUATED" or r.probability is None:
                continue
            if result.method == "pem":
                assert r.verdict == ("OK" if r.probability <= 0.05 else "EXCEEDS"), r
            else:
                lo, hi = r.interval
                assert r.verdict == ("OK" if hi <= 0.05 else "EXCEEDS" if lo > 0.05 else "UNDETERMINED"), r
        text = table.text()
        assert all(r.channel in text for r in table.rows)
        json.dumps(table.to_dict())
        crit = {r.criterion for r in table.rows}
        assert {"en1990_deck/deck_acc_ballasted", "ride_comfort/body_acc_z_tb10621",
                "running_safety/unloading_high_speed", "ride_comfort/sperling_z_gb5599"} <= crit


def test_pseudo_derivative_against_the_recorded_velocity():
    """Problem: ``vertical_ice_scenario`` with the vertical displacements of the deck at midspan, the
    car body, the leading bogie and the first wheelset, whose velocities the engines record.

    Reference: sigma of the time derivative from the recorded velocity channels. The same sweep's
    pseudo-derivative of the displacements (what accelerations, forces and derived channels get)
    differs by the error of differencing a response part at a frequency nu other than the column's
    f_k, (2 pi (nu - f_k) dt)^2 / 6 at most, here 10 % for |nu - f_k| up to the 25 Hz band at dt = 5 ms;
    it errs low (a central difference of a harmonic gives sin(x)/x of its derivative). Tolerance: that
    bound, over the times where sigma_yd exceeds 5 % of its largest value. Measured: 1.6 % (deck, whose
    free vibration at its 5 Hz mode is excited by every f_k), 0.6 % (bogie), 0.09 % (car body), 0.04 %
    (wheelset, which follows the rail: forced response only).
    """
    from tb_exudyn.engines.batched import BatchedEngine
    from tb_exudyn.methods.pem import PsdReducer, column_frequencies, harmonic_columns, pem_tasks
    from tb_exudyn.methods.reduction import finish_pem_task, reduction_plan

    sc = vertical_ice_scenario()
    sc = sc.replace(analysis=sc.analysis.replace(channels=("bridge.span1.mid.disp_z", "car1.body.disp_z",
                                                           "car1.bogie1.disp_z", "car1.axle1.disp_z")))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        eng = BatchedEngine(sc)
    pt = pem_tasks(sc, scenario_grid(sc))
    cols = harmonic_columns(pt, sc)
    got = {}
    for recorded in (True, False):
        plan = reduction_plan(eng.outputs.names, [(c.name, c.unit) for c in eng.model.selected], eng.model.derived,
                              recorded_derivatives=recorded)
        red = PsdReducer(cols, plan, column_frequencies(pt, cols), eng.steps.n_outputs, 1, 1.0 / eng.fs, False)
        got[recorded] = (plan, finish_pem_task(eng.integrate(cols, red), plan, None)["dvar"])
    plan, exact = got[True]
    _, pseudo = got[False]
    errors = {}
    for k, name in enumerate(plan.names):
        s_ex, s_ps = np.sqrt(exact[:, k]), np.sqrt(pseudo[:, k])
        keep = s_ex > 0.05 * s_ex.max()
        errors[name] = float(np.max(np.abs(s_ps[keep] / s_ex[keep] - 1)))
    bound = (2 * math.pi * 25.0 * 0.005) ** 2 / 6
    assert max(errors.values()) < bound, errors


def test_derailment_coefficient_to_first_order_against_monte_carlo_ratios():
    """Problem: ``vertical_ice_scenario`` with the German low vertical, alignment and cross-level
    profiles and secondary yaw dampers (5e4 N s/m at +-1.3 m: the bogie yaw modes are damped, no
    damping-guard warning); the first wheelset's Q/P (-H / P_L, H / P_R) and dP/P.

    Reference: 4000 linear Monte Carlo samples (Gaussian on the PEM grid), each the exact ratio of its
    total forces; at the time of PEM's largest sigma. PEM's ratio is first order about the means. The
    second order: with N ~ 0 (H has mean ~0), D = D(1 + d), r = N / D (1 - d + d^2 ...) gives
    Var r = sigma_N^2 / D^2 [1 + 3 cv^2 (1 + 2 rho^2)] for Gaussian N, D (cv = sigma_D / D, rho their
    correlation), i.e. sigma higher by 1.5 cv^2 (1 + 2 rho^2) <= 4.5 cv^2 = 2.6 % here (cv = 7.6 %).
    Tolerances: (1) sigma within the Monte Carlo 99 % chi-square interval (+-2.9 %) plus 4.5 cv^2;
    (2) sharper, the sampling noise cancelled: the ratio's sigma(MC) / sigma(PEM) over its numerator
    H's sigma(MC) / sigma(PEM) within 4.5 cv^2 of 1 (the ratio is nearly H over the mean load, so
    both carry the same sampling error); (3) the means within 3 standard errors of the Monte Carlo
    mean plus the first order's bias bound sigma_N sigma_D / D^2 + |N| sigma_D^2 / |D|^3. Measured:
    sigma MC / PEM - 1 = +2.0 % and +3.5 % (left, right Q/P), +1.7 % (dP/P); noise-cancelled +1.1 %
    and +1.6 % (the second order, on the high side as derived); means -0.0036 and -0.0052 against
    PEM's -0.0002 and -0.0017 (standard error 0.0013, bias bound 0.006).
    """
    from tb_exudyn.scenario.model import YawDamper

    sc = vertical_ice_scenario()
    car = sc.train.vehicles[0].replace(yaw_damper=YawDamper(c_x=5e4, half_span=1.3))
    sc = sc.replace(train=sc.train.replace(vehicles=(car,)),
                    track=sc.track.replace(irregularities=("german_low.vertical", "german_low.alignment",
                                                           "german_low.cross_level")),
                    analysis=sc.analysis.replace(channels=("car1.axle1.*",)))
    n = 4000
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        pem = run_pem(sc, workers=1, progress=False, engine="batched", psd_channels="all")
        mc = run_monte_carlo(sc, n_samples=n, seed=5, workers=1, progress=False, engine="batched",
                             discretisation="pem_grid_gaussian")
    assert not pem.provenance["damping_warnings"]
    q = stats.chi2.ppf([0.005, 0.995], n - 1)
    band = (math.sqrt((n - 1) / q[1]) - 1, math.sqrt((n - 1) / q[0]) - 1)
    cv = max(np.max(pem.std[pem.index(c)] / pem.mean[pem.index(c)])
             for c in ("car1.axle1.left.force_z", "car1.axle1.right.force_z"))
    second = 4.5 * cv**2
    for ratio, num, den in (("car1.axle1.left.derailment", "car1.axle1.force_y", "car1.axle1.left.force_z"),
                            ("car1.axle1.right.derailment", "car1.axle1.force_y", "car1.axle1.right.force_z"),
                            ("car1.axle1.unloading", None, None)):
        i = pem.index(ratio)
        k = int(np.argmax(pem.std[i]))
        rel = mc.std[i, k] / pem.std[i, k]
        assert band[0] - second <= rel - 1 <= band[1] + second, (ratio, rel - 1, band, second)
        if num is not None:
            j = pem.index(num)
            rel_n = mc.std[j, k] / pem.std[j, k]
            assert abs(rel / rel_n - 1) <= second, (ratio, rel / rel_n - 1, second)
            d = pem.index(den)
            sn, sd, dm, nm = pem.std[j, k], pem.std[d, k], pem.mean[d, k], pem.mean[j, k]
            bias = sn * sd / dm**2 + abs(nm) * sd**2 / abs(dm) ** 3
            assert abs(mc.mean[i, k] - pem.mean[i, k]) <= 3 * mc.std[i, k] / math.sqrt(n) + bias, (ratio, bias)
