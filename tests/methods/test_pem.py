"""PEM sweep on the Exudyn model: checks against closed forms and an independent solver.

Every reference is computed in this file, independently of the code under test.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import tb_exudyn as tbx
from tb_exudyn.scenario import load_bridge, load_vehicle
from tb_exudyn.methods.grid import scenario_grid
from tb_exudyn.methods import run_pem
from tb_exudyn.track import get_spectrum

pytestmark = pytest.mark.exudyn

V = 300 / 3.6


def sprung_mass_scenario(*, lead_in, run_out, f_min, f_max, n_freq, channels, spectral_radius=0.9):
    """The damped VBI-2D sprung mass (5750 kg, 1.595e6 N/m, 4.0e5 N s/m, no wheel mass) at 300 km/h
    over the VBI-2D 25 m beam, German low-interference vertical profile."""
    car = load_vehicle("vbi2d_damped")
    bridge = load_bridge("vbi2d_beam")
    return tbx.Scenario(
        name="pem_test", speed_kmh=300.0, train=tbx.scenario.Train(vehicles=(car,)), bridge=bridge,
        track=tbx.scenario.Track(irregularities=("german_low.vertical",), wavelength_min=1.0,
                                 wavelength_max=120.0, lead_in=lead_in, run_out=run_out,
                                 taper_length=min(20.0, lead_in / 2)),
        analysis=tbx.scenario.Analysis(time_step=1e-3, output_step=1e-2, freq_min=f_min, freq_max=f_max,
                                       n_freq=n_freq, channels=channels, mode_max_frequency=80.0,
                                       spectral_radius=spectral_radius),
    )


def test_stationary_sprung_mass_on_rigid_track_matches_quadrature():
    """Problem: the damped sprung mass runs 250 m on the rigid approach at 300 km/h over the German
    low-interference vertical profile; PEM on 20 frequencies from 1 to 20 Hz.

    Reference: for a base-excited SDOF the absolute-displacement transfer is
    H = (k + i c w) / (k - m w^2 + i c w) (docs/references.md, validation case 4), so on the same discrete grid
    sigma_z^2 = sum_k |H(w_k)|^2 S_hz(f_k) df_k and sigma_a^2 = sum_k w_k^4 |H|^2 S_hz df_k, with
    S_hz(f) = 2 pi S(Omega) / v, Omega = 2 pi f / v (the spectrum formula of docs/references.md, track spectra, is
    typed in here). Compared over t = 2.0-2.9 s: the start-up transient (slowest pole 4.2 rad/s) has
    decayed to < 1e-3 and the mass has not reached the bridge (t = 3.0 s).

    Tolerance 1e-3 (the issue asks 0.5 %): generalized-alpha (spectral radius 0.9) at 1 ms has
    amplitude and period errors of order (w h)^2 / 12 <= 1.3e-3 at 20 Hz, weighted down by the
    spectrum; measured 2.4e-4 (displacement) and 1.9e-4 (acceleration). The model is otherwise exact.
    """
    sc = sprung_mass_scenario(lead_in=250.0, run_out=0.0, f_min=1.0, f_max=20.0, n_freq=20,
                              channels=("car1.body.*",))
    r = run_pem(sc, workers=1, progress=False, engine="exudyn", psd_channels="all")
    m, k, c = 5750.0, 1.595e6, 4.0e5
    g = scenario_grid(sc)
    w = 2 * math.pi * g.f
    A_v, Oc, Or = 4.032e-7, 0.8246, 0.0206
    omega = 2 * math.pi * g.f / V
    s_spatial = A_v * Oc**2 / ((omega**2 + Or**2) * (omega**2 + Oc**2))
    s_hz = 2 * math.pi * s_spatial / V
    H2 = np.abs((k + 1j * c * w) / (k - m * w**2 + 1j * c * w)) ** 2
    sigma_z = math.sqrt(np.sum(H2 * s_hz * g.df))
    sigma_a = math.sqrt(np.sum(w**4 * H2 * s_hz * g.df))
    window = (r.time >= 2.0) & (r.time <= 2.9)
    z = r.std[r.index("car1.body.disp_z"), window]
    a = r.std[r.index("car1.body.acc_z"), window]
    assert np.max(np.abs(z / sigma_z - 1)) < 1e-3
    assert np.max(np.abs(a / sigma_a - 1)) < 1e-3
    # the PSD map integrates to sigma^2 over the stated band
    i = r.index("car1.body.disp_z")
    assert np.allclose(np.sum(r.psd[i] * r.df[:, None], axis=0), r.std[i] ** 2, rtol=1e-12)


def reference_pem_sprung_mass_on_beam(sc, n_modes_max=40):
    """Independent batched modal PEM: closed-form sine modes of the simply supported beam and the sprung
    mass (no wheel mass), Newmark average acceleration, all frequencies as complex columns at once.

    Unknowns x = (q_1..q_n, z). Spring force F = k (z - r) + c (z' - r'), with the rail under the wheel
    r = phi(x_w) q + u, r' = phi q' + v phi'(x_w) q + u', u = w(x_w) a_k exp(i Omega_k v t) the
    pseudo-input with the approach taper w = (1 - cos(pi s / L_t)) / 2, s = x_w + lead_in in [0, L_t]
    (written here from its definition in the Track settings).
    Vehicle: m z'' = -F. Beam: q'' + 2 zeta w q' + w^2 q = phi F (force on the beam, z up).
    """
    veh, beam = sc.train.vehicles[0], sc.bridge
    L, EI, mu = beam.spans[0], beam.girder.E * beam.girder.I_y, beam.girder.mass_per_length
    m, k, c, v = veh.mass, veh.stiffness, veh.damping, sc.speed
    j = np.arange(1, n_modes_max + 1)
    wj = (j * np.pi / L) ** 2 * np.sqrt(EI / mu)
    j, wj = j[wj / (2 * np.pi) <= sc.analysis.mode_max_frequency], wj[wj / (2 * np.pi) <= sc.analysis.mode_max_frequency]
    n = j.size
    amp = np.sqrt(2 / (mu * L))
    g = scenario_grid(sc)
    spec = get_spectrum("german_low.vertical")
    ak = np.sqrt(spec.psd(g.omega_spatial) * g.d_omega_spatial)
    Om = g.omega_spatial
    h = sc.analysis.time_step
    n_steps = int(round(sc.duration / h))
    every = int(round(sc.analysis.output_step / h))
    M = np.diag(np.r_[np.ones(n), m])

    def matrices(t):
        x = -sc.track.lead_in + v * t
        inside = 0.0 <= x <= L
        phi = amp * np.sin(j * np.pi * x / L) if inside else np.zeros(n)
        dphi = amp * (j * np.pi / L) * np.cos(j * np.pi * x / L) if inside else np.zeros(n)
        C = np.zeros((n + 1, n + 1))
        K = np.zeros((n + 1, n + 1))
        C[:n, :n] = np.diag(2 * beam.damping_ratio * wj) + c * np.outer(phi, phi)
        K[:n, :n] = np.diag(wj**2) + k * np.outer(phi, phi) + c * v * np.outer(phi, dphi)
        C[:n, n] = -c * phi
        K[:n, n] = -k * phi
        C[n, n], K[n, n] = c, k
        C[n, :n] = -c * phi
        K[n, :n] = -k * phi - c * v * dphi
        s_t, L_t = v * t, sc.track.taper_length
        w = 1.0 if s_t >= L_t else 0.5 * (1 - np.cos(np.pi * s_t / L_t))
        dw = 0.0 if s_t >= L_t else 0.5 * np.pi / L_t * np.sin(np.pi * s_t / L_t)
        e = ak * np.exp(1j * Om * v * t)
        u = w * e
        ud = dw * v * e + 1j * Om * v * u
        f = np.zeros((n + 1, Om.size), dtype=complex)
        f[n] = k * u + c * ud
        f[:n] = -np.outer(phi, k * u + c * ud)
        return C, K, f, phi

    x = np.zeros((n + 1, Om.size), dtype=complex)
    vel = np.zeros_like(x)
    C, K, f, phi = matrices(0.0)
    acc = np.linalg.solve(M, f - C @ vel - K @ x)
    out_t, out_mid, out_acc = [0.0], [np.zeros(Om.size, dtype=complex)], [acc[n].copy()]
    mid = amp * np.sin(j * np.pi / 2)
    for step in range(1, n_steps + 1):
        t = step * h
        C, K, f, phi = matrices(t)
        xp = x + h * vel + h * h / 4 * acc
        vp = vel + h / 2 * acc
        acc = np.linalg.solve(M + h / 2 * C + h * h / 4 * K, f - C @ vp - K @ xp)
        x = xp + h * h / 4 * acc
        vel = vp + h / 2 * acc
        if step % every == 0:
            out_t.append(t)
            out_mid.append(mid @ x[:n])
            out_acc.append(acc[n].copy())
    sig_mid = np.sqrt(np.sum(np.abs(np.array(out_mid)) ** 2, axis=1))
    sig_acc = np.sqrt(np.sum(np.abs(np.array(out_acc)) ** 2, axis=1))
    return np.array(out_t), sig_mid, sig_acc


def test_nonstationary_sprung_mass_over_span_matches_independent_modal_pem():
    """Problem: the damped sprung mass crosses the 25 m VBI-2D beam at 300 km/h after 60 m of rigid
    approach, German low-interference vertical profile, 12 frequencies 1-20 Hz, modes to 80 Hz.

    Reference: the independent batched modal PEM above (closed-form sine modes, Newmark average
    acceleration, complex columns). The Exudyn model runs with spectral radius 1 so that both use
    the same (trapezoidal) scheme; remaining differences: FE modes (20 elements) against sine modes
    (frequencies 1e-5 relative) and Exudyn's Newton tolerance.

    Tolerance 1e-4 relative (the issue asks 0.5 %) at every output time where sigma exceeds 5 % of
    its maximum (the start-up from rest makes sigma small in the first steps): same scheme, so what is
    left is Exudyn's Newton tolerance (1e-8 relative) and FE against sine modes; measured 8e-6
    (midspan displacement) and 2e-6 (vehicle acceleration).
    """
    sc = sprung_mass_scenario(lead_in=60.0, run_out=10.0, f_min=1.0, f_max=20.0, n_freq=12,
                              channels=("bridge.span1.mid.disp_z", "car1.body.acc_z"), spectral_radius=1.0)
    r = run_pem(sc, workers=1, progress=False, engine="exudyn", psd_channels="all")
    t, sig_mid, sig_acc = reference_pem_sprung_mass_on_beam(sc)
    assert t.size == r.time.size and np.allclose(t, r.time, atol=1e-9)
    for name, ref in (("bridge.span1.mid.disp_z", sig_mid), ("car1.body.acc_z", sig_acc)):
        got = r.std[r.index(name)]
        sel = ref > 0.05 * ref.max()
        err = np.max(np.abs(got[sel] / ref[sel] - 1))
        assert err < 1e-4, (name, err)


def _loads(weights, mean_cost, workers):
    """Loads of ``workers`` that take the tasks in order (the mean, of cost ``mean_cost``, first; then
    the slices, of total cost 1 in proportion to ``weights``), each the next task as soon as it is free."""
    costs = [mean_cost] + [w / sum(weights) for w in weights]
    loads = [0.0] * workers
    for c in costs:
        loads[loads.index(min(loads))] += c
    return loads


def test_default_slices_level_the_workers_loads():
    """Problem: the mean task first, then the column slices, on as many workers as cores, each taking
    the next task when free (the process pool's order). Reference: that schedule simulated here, with
    the columns' total cost 1 and the mean's cost its hint over the number of columns. With the hint
    (the batched engine's linear mean) every worker's load is equal (to round-off of the weights,
    1e-12) wherever the mean costs less than 0.9 of a slice (600 and 6000 columns; with 60 columns on
    3 cores it costs more and its worker's last slice is kept at a tenth); without one (an Exudyn mean, assumed half a slice) the rule of a full slice per core and
    a half one, as before."""
    from tb_exudyn.engines import engine_class
    from tb_exudyn.engines.batched import BatchedOptions
    from tb_exudyn.methods.pem import default_slices, slice_weights

    cls = engine_class("batched")
    for cores in (2, 3, 4, 8):
        for n_columns in (600, 6000):
            weights = slice_weights(cls, None, cores, n_columns)
            loads = _loads(weights, cls.mean_cost_columns(None) / n_columns, cores)
            assert len(weights) == cores and max(loads) - min(loads) <= 1e-12, (cores, n_columns, loads)
    assert slice_weights(cls, None, 1, 600) == [1.0]
    assert default_slices(2) == [1.0, 1.0, 0.5]
    assert slice_weights(cls, BatchedOptions(mean="exudyn"), 2, 600) == [1.0, 1.0, 0.5]
