"""Moving constant force over a simply supported span against Fryba's closed form."""

from __future__ import annotations

import math

import numpy as np
import pytest

pytest.importorskip("exudyn")

from tb_exudyn.builder import build_model  # noqa: E402
from tb_exudyn.scenario import Analysis, BeamSection, MovingForce, Scenario, SimpleBeam, Track, Train  # noqa: E402
from tb_exudyn.engines.exudyn_runs import run_model  # noqa: E402
from tb_exudyn.structure import simply_supported_modes  # noqa: E402

pytestmark = pytest.mark.exudyn

L, MU, F1, P = 20.0, 1.0e4, 5.0, 1.0e5  # span [m], mass [kg/m], first frequency [Hz], force [N]
EI = MU * (2 * math.pi * F1 / (math.pi / L) ** 2) ** 2
LEAD = 2.0
N_VERTICAL = 4  # vertical modes below 100 Hz: 5, 20, 45, 80 Hz


def fryba_midspan(t: np.ndarray, c: float, n_modes: int) -> np.ndarray:
    """Midspan deflection (positive DOWN) of an undamped simply supported beam under a constant
    force P entering at t = 0 with speed c (Fryba, Vibration of Solids and Structures under Moving
    Loads, ch. 1; docs/references.md, validation case 2), modes j = 1..n_modes; after the force leaves at
    T = L / c every mode vibrates freely from its state at T."""
    w1 = (math.pi / L) ** 2 * math.sqrt(EI / MU)
    om = math.pi * c / L
    alpha = om / w1
    w0 = 2 * P * L**3 / (math.pi**4 * EI)
    T = L / c
    out = np.zeros_like(t)
    for j in range(1, n_modes + 1):
        wj = j * j * w1

        def amp(tt: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
            if abs(j - alpha) < 1e-12:  # resonance j = alpha: the limit of the closed form
                a = w0 / (2 * j**2) * (np.sin(wj * tt) - wj * tt * np.cos(wj * tt)) / j**2
                ad = w0 / (2 * j**4) * wj**2 * tt * np.sin(wj * tt)
                return a, ad
            f = w0 / (j**2 * (j**2 - alpha**2))
            return (f * (np.sin(j * om * tt) - alpha / j * np.sin(wj * tt)),
                    f * (j * om * np.cos(j * om * tt) - alpha / j * wj * np.cos(wj * tt)))

        during = (t >= 0) & (t <= T)
        a = np.zeros_like(t)
        a[during] = amp(t[during])[0]
        aT, adT = amp(np.array([T]))
        after = t > T
        tau = t[after] - T
        a[after] = aT * np.cos(wj * tau) + adT / wj * np.sin(wj * tau)
        out += a * math.sin(j * math.pi / 2)
    return out


def _run(c: float, time_step: float, run_out: float):
    section = BeamSection(E=3.0e10, G=1.2e10, area=1.0, I_y=EI / 3.0e10, I_z=100 * EI / 3.0e10, J=1.0,
                          mass_per_length=MU, rot_mass_per_length=1.0e3)
    bridge = SimpleBeam(name="fryba", spans=(L,), girder=section)
    sc = Scenario(
        name="fryba", speed_kmh=c * 3.6, bridge=bridge,
        train=Train(vehicles=(MovingForce(name="P", force=P, length=10.0),)),
        track=Track(lead_in=LEAD, run_out=run_out),
        analysis=Analysis(time_step=time_step, output_step=10 * time_step, freq_max=0.1 / time_step,
                          mode_max_frequency=100.0, channels=("bridge.span1.mid.disp_z",)),
    )
    modes = simply_supported_modes((L,), EI, 100 * EI, 1.2e10, MU, 1.0e3, 0.0, 100.0)
    assert sum(k == "vertical" for k in modes.mode_types) == N_VERTICAL
    model = build_model(sc, modal_bridge=modes)
    th, _ = run_model(model, None, gravity=True, initial="static")
    return th, -fryba_midspan(th.time - LEAD / sc.speed, sc.speed, N_VERTICAL)


@pytest.mark.parametrize("alpha", [1.0, 0.2])
def test_moving_force_midspan_history_matches_fryba(alpha):
    """Exact problem: constant force P = 100 kN crossing an undamped simply supported 20 m span
    (m = 1e4 kg/m, f1 = 5 Hz) at speed parameter alpha = c / (2 f1 L) = 1 (c = 200 m/s) and 0.2
    (40 m/s), starting 2 m before the span; the midspan deflection during and after the crossing.
    Reference: Fryba's modal closed form (docs/references.md, validation case 2), evaluated here with the
    same four vertical modes the model keeps (<= 100 Hz), the free vibration after exit from each
    mode's exit state. Tolerance 1 % of the peak (the acceptance criterion); the measured error
    is 1e-5 of the peak at dt = 1e-4 s (7e-4 at dt = 1 ms: generalized-alpha's period error on
    the 80 Hz mode). Sub-checks: at alpha = 1 the midspan deflection when the force leaves is
    (pi/2) w0 exactly (all higher modes vanish there); at alpha = 0.2 (1/alpha odd) the free
    vibration after exit vanishes."""
    c = alpha * 2 * F1 * L
    th, ref = _run(c, time_step=1e-4, run_out=10.0 if alpha == 1.0 else 20.0)
    w = th["bridge.span1.mid.disp_z"]
    peak = np.abs(ref).max()
    assert np.abs(w - ref).max() <= 0.01 * peak
    w0 = 2 * P * L**3 / (math.pi**4 * EI)
    t_exit = (LEAD + L) / c
    i_exit = int(np.argmin(np.abs(th.time - t_exit)))
    assert abs(th.time[i_exit] - t_exit) < 1e-9
    if alpha == 1.0:
        assert w[i_exit] == pytest.approx(-math.pi / 2 * w0, rel=0.01)
    else:
        assert np.abs(w[th.time > t_exit + 1e-9]).max() <= 0.01 * peak
