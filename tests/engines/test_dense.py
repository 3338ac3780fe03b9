"""The dense engine (tb_exudyn.engines.dense): the engine registry's small reference.

It integrates the same linear model with the same generalized-alpha step as the batched engine, on
full matrices with the coupling's own Jacobians and contact law and the column sources' reference
inputs (``contact_inputs``), none of the batched engine's structure. So the two must agree to
round-off: the batched engine's components, Woodbury solve, folded off-bridge operators and per-step
input forms are each an exact rearrangement. Adding this engine took one module and one registry
line (tb_exudyn/engines/__init__.py: ENGINES).
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from tb_exudyn.engines.alpha import GeneralizedAlpha
from tb_exudyn.engines.batched.kernels import advance

from ..methods.test_pem import sprung_mass_scenario

pytestmark = pytest.mark.exudyn


def _relative(a: np.ndarray, b: np.ndarray) -> float:
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)  # float32 PSD: 1e-300 would underflow
    axes = tuple(range(1, b.ndim))
    return float(np.max(np.abs(a - b).max(axis=axes) / np.maximum(np.abs(b).max(axis=axes), 1e-300)))


def test_dense_engine_equals_the_batched_engine_on_the_sprung_mass_over_the_span():
    """Problem: the damped VBI-2D sprung mass crosses the 25 m beam at 300 km/h after 30 m of
    approach, German low vertical, 6 frequencies 2-20 Hz, every channel; PEM (and its grid error's
    midpoint sweep) on both engines.

    Reference: the batched engine (verified against the Exudyn engine to 1e-6 in test_batched.py).
    Tolerance 1e-10 of each channel's max sigma and PSD: the same model and step, only the algebra
    differs (measured about 1e-13; the PSD travels in float32, so it is compared to 1e-6). Both take
    the mean from Exudyn's run (the batched engine's own linear mean: tests/engines/test_batched.py)."""
    from tb_exudyn.engines.batched import BatchedOptions
    from tb_exudyn.methods import run_pem

    sc = sprung_mass_scenario(lead_in=30.0, run_out=5.0, f_min=2.0, f_max=20.0, n_freq=6, channels=("*",))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        dense = run_pem(sc, workers=1, progress=False, engine="dense", psd_channels="all")
        batched = run_pem(sc, workers=1, progress=False, engine="batched", psd_channels="all",
                          options=BatchedOptions(mean="exudyn"))
    assert dense.provenance["engine"] == "dense" and dense.channels == batched.channels
    assert _relative(dense.std, batched.std) < 1e-10
    assert _relative(dense.psd, batched.psd) < 1e-6
    assert np.array_equal(dense.mean, batched.mean)


def test_dense_engine_equals_the_batched_engine_on_the_car15_with_creep_free_contacts():
    """Problem: one ICE motor car over one 32 m span at 250 km/h (scenario 'quick' on 2 linear
    frequencies, every channel), the track 2.5 m off the girder axis: vertical, lateral and roll
    coupled through the bridge; linear Monte Carlo of 4 samples too.

    Reference: the batched engine. Tolerance 1e-9 of each channel's max sigma (round-off of two
    different factorisations of a stiff system: contact 2e9 N/m against body springs 4e5 N/m). The
    mean from Exudyn's run on both (the ratio channels' sigma depends on it)."""
    import tb_exudyn as tbx
    from tb_exudyn.engines.batched import BatchedOptions
    from tb_exudyn.methods import run_monte_carlo, run_pem

    sc = tbx.load_scenario("quick")
    sc = sc.replace(analysis=sc.analysis.replace(channels=("*",), n_freq=2, freq_spacing="linear"))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        kw = dict(workers=1, progress=False, grid_error=False)
        dense = run_pem(sc, engine="dense", **kw)
        batched = run_pem(sc, engine="batched", options=BatchedOptions(mean="exudyn"), **kw)
        assert _relative(dense.std, batched.std) < 1e-9
        kw = dict(n_samples=4, seed=3, workers=1, progress=False, keep_samples=True)
        d = run_monte_carlo(sc, engine="dense", **kw)
        b = run_monte_carlo(sc, engine="batched", options=BatchedOptions(mean="exudyn"), **kw)
    assert d.method == b.method == "monte_carlo_linear"
    assert _relative(d.samples.transpose(1, 0, 2), b.samples.transpose(1, 0, 2)) < 1e-9


# ------------------------------------------------------------------------------ no Exudyn needed
def _oscillator_error(n_steps: int, rho: float) -> float:
    """Largest error over [0, T] of the engines' generalized-alpha (the coefficients of
    GeneralizedAlpha and the batched engine's fused update kernel ``advance``) on
    x'' + 2 zeta w x' + w^2 x = sin(W t) from rest, against the closed-form solution."""
    w, zeta, W, T = 2 * math.pi * 3.0, 0.05, 2 * math.pi * 1.7, 2.0
    h = T / n_steps
    ga = GeneralizedAlpha(rho, h)
    m, c, k = 1.0, 2 * zeta * w, w * w
    A0 = ga.beta_p * m + ga.gamma_p * c + k
    # from rest with f(0) = 0: qdd0 = 0, so the first predictor is zero
    qp, vp, ap, dl = (np.zeros(1) for _ in range(4))
    coef = ga.update_coefficients()
    errors = []
    wd = w * math.sqrt(1 - zeta * zeta)
    # closed form: particular + homogeneous for x(0) = x'(0) = 0
    Z = complex(k - W * W, c * W)
    amp = 1.0 / Z  # x_p = Im(amp exp(i W t))
    xp0, vp0 = amp.imag, (1j * W * amp).imag

    def exact(t: float) -> float:
        a1 = -xp0
        b1 = (-vp0 + zeta * w * a1) / wd
        return (amp * np.exp(1j * W * t)).imag + math.exp(-zeta * w * t) * (a1 * math.cos(wd * t) + b1 * math.sin(wd * t))

    for n in range(1, n_steps + 1):
        t = n * h
        R = math.sin(W * t) - (k * qp + c * vp)  # A0 Delta = f(t) - K q~ - D v~
        dl[:] = R / A0
        errors.append(abs(qp[0] + dl[0] - exact(t)))
        advance(coef, h, qp, vp, ap, dl)
    return max(errors)


@pytest.mark.parametrize("rho", [1.0, 0.9, 0.6])
def test_generalized_alpha_converges_at_second_order(rho):
    """Problem: a damped oscillator (3 Hz, 5 % damping) driven by sin(2 pi 1.7 t) from rest over 2 s,
    integrated with the step the batched and dense engines implement, for 100 ... 1600 steps.

    Reference: the closed-form solution. The generalized-alpha method is second-order accurate for
    every spectral radius (Chung & Hulbert 1993): the fitted slope of log(error) over log(h) must be
    2 within 0.15 (measured 1.99-2.01); and at 1600 steps the error stays below the phase error a
    second-order method accumulates over the run, (w h)^2 / 12 x w T, times the forced amplitude
    (measured 0.2 of that bound)."""
    steps = np.array([100, 200, 400, 800, 1600])
    err = np.array([_oscillator_error(n, rho) for n in steps])
    slope = np.polyfit(np.log(2.0 / steps), np.log(err), 1)[0]
    assert abs(slope - 2.0) < 0.15, (rho, slope, err)
    w, W, h, T = 2 * math.pi * 3.0, 2 * math.pi * 1.7, 2.0 / 1600, 2.0
    amplitude = abs(1 / complex(w * w - W * W, 2 * 0.05 * w * W))
    assert err[-1] < (w * h) ** 2 / 12 * w * T * amplitude, (err[-1], amplitude)
