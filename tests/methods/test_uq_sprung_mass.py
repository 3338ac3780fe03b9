"""Polynomial chaos over PEM runs against a closed form: a sprung mass on rigid track (issue 46).

Problem: the damped VBI-2D sprung mass (5750 kg; 1.595e6 N/m, 4.0e5 N s/m nominal; no wheel mass) runs
250 m of rigid approach at 300 km/h over the German low-interference vertical profile (PEM on 200
linear frequencies, 1-20 Hz), then crosses a girder made 1000 times stiffer than the VBI-2D beam, so
that the track stays rigid for the whole run and sigma(t) stays stationary after the taper. Uncertain:
the suspension stiffness k lognormal (mean the nominal, cov 10 %) and the damping c uniform (nominal
+-20 %).

Reference (independent of the code under test): for a base-excited SDOF the absolute acceleration's
transfer is w^2 H, H = (k + i c w) / (k - m w^2 + i c w), so the stationary sigma of the body
acceleration is sigma(k, c)^2 = int_{1 Hz}^{20 Hz} w^4 |H|^2 S_hz(f) df with S_hz(f) = 2 pi S(Omega) / v,
Omega = 2 pi f / v and S the German vertical spectrum A_v Oc^2 / ((Omega^2 + Or^2)(Omega^2 + Oc^2))
(the formula typed in here), integrated with scipy's quad. Its mean, standard deviation and first-order
Sobol indices over (k, c) come from a 12 x 12 tensor Gauss quadrature written here (Gauss-Hermite in
the standard normal of log k, Gauss-Legendre in c), far finer than the study's order-3 expansion.

Tolerances (the issue's): mean and std of the stationary sigma within 0.5 % (the PEM itself is within
2.4e-4 of the closed form on this model, tests/methods/test_pem.py; the 200-point grid's midpoint rule
against quad adds about 1e-4; sigma(k, c) is smooth, so an order-3 expansion on 4 x 4 Gauss nodes
errs far less); Sobol first-order indices within 0.02.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import tb_exudyn as tbx
from tb_exudyn.scenario import load_bridge, load_vehicle
from tb_exudyn.scenario.uncertain import check_uncertain

pytestmark = pytest.mark.exudyn

V = 300 / 3.6
M, K0, C0 = 5750.0, 1.595e6, 4.0e5
F_MIN, F_MAX = 1.0, 20.0
KEYS = {"train.vehicles.0.stiffness": {"distribution": "lognormal", "cov": 0.10},
        "train.vehicles.0.damping": {"distribution": "uniform", "relative_bounds": [-0.2, 0.2]}}


def scenario():
    car = load_vehicle("vbi2d_damped")
    beam = load_bridge("vbi2d_beam")
    stiff = beam.replace(girder=beam.girder.replace(E=beam.girder.E * 1000.0))
    return tbx.Scenario(
        name="uq_sprung_mass", speed_kmh=300.0, train=tbx.scenario.Train(vehicles=(car,)), bridge=stiff,
        track=tbx.scenario.Track(irregularities=("german_low.vertical",), wavelength_min=1.0, wavelength_max=120.0,
                                 lead_in=250.0, run_out=0.0, taper_length=20.0),
        analysis=tbx.scenario.Analysis(time_step=1e-3, output_step=1e-2, freq_min=F_MIN, freq_max=F_MAX, n_freq=200,
                                       channels=("car1.body.acc_z",), mode_max_frequency=80.0, spectral_radius=0.9))


def closed_form_sigma(k, c):
    """sigma of the body acceleration of a base-excited SDOF (module docstring), by quad."""
    from scipy.integrate import quad

    a_v, oc, o_r = 4.032e-7, 0.8246, 0.0206

    def integrand(f):
        w = 2 * math.pi * f
        om = w / V
        s_hz = 2 * math.pi * a_v * oc**2 / ((om**2 + o_r**2) * (om**2 + oc**2)) / V
        h2 = abs((k + 1j * c * w) / (k - M * w**2 + 1j * c * w)) ** 2
        return w**4 * h2 * s_hz

    return math.sqrt(quad(integrand, F_MIN, F_MAX, epsabs=0, epsrel=1e-10, limit=200)[0])


def reference_statistics(n=12):
    """Mean, std and first-order Sobol indices (k, c) of sigma(k, c) by tensor Gauss quadrature."""
    xh, wh = np.polynomial.hermite_e.hermegauss(n)
    wh = wh / wh.sum()
    s2 = math.log1p(0.10**2)
    ks = np.exp(math.log(K0) - s2 / 2 + math.sqrt(s2) * xh)  # lognormal of mean K0, cov 10 %
    xl, wl = np.polynomial.legendre.leggauss(n)
    wl = wl / wl.sum()
    cs = C0 * (1 + 0.2 * xl)
    f = np.array([[closed_form_sigma(k, c) for c in cs] for k in ks])
    mean = wh @ f @ wl
    var = wh @ (f - mean) ** 2 @ wl
    v_k = wh @ (f @ wl - mean) ** 2
    v_c = wl @ (wh @ f - mean) ** 2
    return mean, math.sqrt(var), np.array([v_k / var, v_c / var])


def test_pce_over_pem_matches_quadrature_of_closed_form():
    sc = scenario()
    keys = check_uncertain(sc, KEYS, "test")
    # from 2.5 s the start-up transient (slowest pole about 3.3 rad/s) has decayed below 1e-3
    r = tbx.run_uq(sc, keys, order=3, workers=1, progress=False, channels=["car1.body.acc_z"], window=(2.5, 10.0))
    mean, std, first = reference_statistics()
    i = r.index("car1.body.acc_z")
    window = r.time >= 2.5
    assert r.data["node_weights"].size == 16  # 4 x 4 Gauss nodes
    assert np.max(np.abs(r.mean_sigma[i, window] / mean - 1)) < 5e-3
    assert np.max(np.abs(r.std_sigma[i, window] / std - 1)) < 5e-3
    q = r.quantity("max_sigma:car1.body.acc_z")  # over the window: the stationary sigma
    assert abs(q["mean"] / mean - 1) < 5e-3 and abs(q["std"] / std - 1) < 5e-3
    got = np.array([q["sobol_first"][k] for k in KEYS])
    assert np.max(np.abs(got - first)) < 0.02
    assert q["loo"] < 0.01


def test_irregularity_level_scales_the_variance():
    """track.irregularity_level multiplies every spectrum's PSD: PEM is linear in the PSD, so sigma(t)
    at level 2.5 is sqrt(2.5) times that at level 1, to round-off (1e-12); the mean is unchanged."""
    sc = scenario()
    sc = sc.replace(track=sc.track.replace(lead_in=60.0), analysis=sc.analysis.replace(n_freq=8))
    one = tbx.run_pem(sc, workers=1, progress=False, grid_error=False)
    two = tbx.run_pem(sc.replace(track=sc.track.replace(irregularity_level=2.5)), workers=1, progress=False,
                       grid_error=False)
    assert np.allclose(two.std, math.sqrt(2.5) * one.std, rtol=1e-12, atol=0)
    assert np.array_equal(two.mean, one.mean)
