"""Moving sprung mass on a simply supported beam (VBI-2D data) against an independent modal solver."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

pytest.importorskip("exudyn")

from tb_exudyn.builder import ProfileExcitation, build_model, sampled_profile  # noqa: E402
from tb_exudyn.scenario import Analysis, BeamSection, Scenario, SimpleBeam, SprungMass, Track, Train  # noqa: E402
from tb_exudyn.engines.exudyn_runs import run_model  # noqa: E402
from tb_exudyn.structure import simply_supported_modes  # noqa: E402

pytestmark = pytest.mark.exudyn

# VBI-2D analytical verification data (Cantero's public code; docs/references.md, validation case 3)
L, E, I, MU = 25.0, 3.5e10, 1.3901, 18358.0
MV, KV, V, G = 5750.0, 1.595e6, 25.0, 9.81
LEAD, RUN_OUT = 10.1, 4.9  # no kink of the input (entry, exit, ramp corners) falls on an output time
F_MAX = 100.0  # modes kept: vertical j = 1..4 (4.1, 16.4, 36.9, 65.6 Hz)


def ramp(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """VBI-2D ramp: the wheel path rises linearly by 0.01 m between x = L/3 and L/2, then stays."""
    return sampled_profile([L / 3, L / 2], [0.0, 0.01])(x)


def reference(times: np.ndarray, c: float, profile=None) -> dict[str, np.ndarray]:
    """Independent modal solver: the beam's vertical modes phi_j = sqrt(2/(m L)) sin(j pi x / L)
    (closed form, written here), omega_j = (j pi / L)^2 sqrt(EI/m), and one sprung mass whose
    spring-damper's lower end follows the rail w(x(t), t) + r(x(t)):

        f = k (w + r - y) + c (dw/dt + dr/dt - y'),   m y'' = f - m g,   q_j'' + omega_j^2 q_j = -phi_j(x) f,

    with dw/dt = phi q' + v phi'(x) q, x(t) = -LEAD + V t, starting in static equilibrium
    (y = -m g / k + r(x0), beam at rest). scipy DOP853 (rtol 1e-11) with its dense output,
    integrated piecewise between the kinks of the input (bridge entry and exit, ramp corners)."""
    jj = np.arange(1, 5)
    om = (jj * math.pi / L) ** 2 * math.sqrt(E * I / MU)
    amp = math.sqrt(2.0 / (MU * L))
    n = jj.size

    def shapes(x: float) -> tuple[np.ndarray, np.ndarray]:
        if 0.0 <= x <= L:
            return amp * np.sin(jj * math.pi * x / L), amp * jj * math.pi / L * np.cos(jj * math.pi * x / L)
        return np.zeros(n), np.zeros(n)

    def contact(t: float, s: np.ndarray) -> tuple[float, np.ndarray]:
        q, qd, y, yd = s[:n], s[n:2 * n], s[2 * n], s[2 * n + 1]
        x = -LEAD + V * t
        p, dp = shapes(x)
        r, rd = (0.0, 0.0) if profile is None else (float(profile(np.array([x]))[0][0]), V * float(profile(np.array([x]))[1][0]))
        f = KV * (p @ q + r - y) + c * (p @ qd + V * (dp @ q) + rd - yd)
        return f, p

    def rhs(t: float, s: np.ndarray) -> np.ndarray:
        f, p = contact(t, s)
        return np.concatenate([s[n:2 * n], -om**2 * s[:n] - p * f, [s[2 * n + 1], f / MV - G]])

    kinks = [LEAD / V, (LEAD + L) / V] + ([] if profile is None else [(LEAD + L / 3) / V, (LEAD + L / 2) / V])
    edges = sorted({0.0, float(times[-1]), *[k for k in kinks if 0 < k < times[-1]]})
    state = np.zeros(2 * n + 2)
    x0 = -LEAD
    state[2 * n] = -MV * G / KV + (0.0 if profile is None else float(profile(np.array([x0]))[0][0]))
    ts = np.asarray(times, dtype=float)
    ss = np.empty((ts.size, 2 * n + 2))
    for i, (a, b) in enumerate(zip(edges[:-1], edges[1:])):
        sol = solve_ivp(rhs, (a, b), state, method="DOP853", rtol=1e-11, atol=1e-14, dense_output=True)
        last = i == len(edges) - 2
        mask = (ts >= a) & ((ts <= b) if last else (ts < b))
        ss[mask] = sol.sol(ts[mask]).T
        state = sol.y[:, -1]
    acc, force = [], []
    for tt, s in zip(ts, ss):
        # a kink time belongs to the segment that starts there (the model evaluates the new slope)
        f, _ = contact(tt + 1e-12, s)
        acc.append(f / MV - G)
        force.append(f)
    mid = amp * np.sin(jj * math.pi / 2)
    return {"mid": ss[:, :n] @ mid, "y": ss[:, 2 * n], "acc": np.array(acc), "force": np.array(force)}


def model_run(c: float, time_step: float, profile=None):
    section = BeamSection(E=E, G=E / 2.4, area=1.0, I_y=I, I_z=100 * I, J=1.0, mass_per_length=MU, rot_mass_per_length=1.0e3)
    sc = Scenario(
        name="vbi2d", speed_kmh=V * 3.6, bridge=SimpleBeam(name="vbi2d", spans=(L,), girder=section),
        train=Train(vehicles=(SprungMass(name="sm", mass=MV, stiffness=KV, damping=c, length=10.0),)),
        track=Track(lead_in=LEAD, run_out=RUN_OUT),
        analysis=Analysis(time_step=time_step, output_step=0.01, freq_max=60.0, mode_max_frequency=F_MAX, gravity=G,
                          channels=("bridge.span1.mid.disp_z", "car1.*")),
    )
    modes = simply_supported_modes((L,), E * I, 100 * E * I, E / 2.4, MU, 1.0e3, 0.0, F_MAX)
    assert sum(k == "vertical" for k in modes.mode_types) == 4
    exc = None if profile is None else ProfileExcitation(vertical=profile)
    model = build_model(sc, modal_bridge=modes)
    th, _ = run_model(model, exc, gravity=True, initial="static")
    return th


def _rel_err(value: np.ndarray, ref: np.ndarray, offset: float = 0.0) -> float:
    return float(np.abs(value - ref).max() / np.abs(ref - offset).max())


@pytest.mark.parametrize(
    "c, time_step, ramped",
    [(0.0, 5e-4, False), (4.0e5, 1e-4, False), (0.0, 5e-4, True)],
    ids=["undamped", "damped", "undamped-ramp"],
)
def test_sprung_mass_matches_independent_modal_solver(c, time_step, ramped):
    """Exact problem (VBI-2D analytical verification, docs/references.md, validation case 3): a 5750 kg
    mass on a 1595 kN/m spring (damping 0 or 4e5 N s/m, no wheel mass: the spring's lower end
    follows the rail) crosses an undamped simply supported 25 m beam (E = 3.5e10, I = 1.3901,
    m = 18358 kg/m) at 25 m/s, g = 9.81, starting in static equilibrium 10.1 m before the beam; the
    ramp variant lifts the wheel path by 0.01 m between L/3 and L/2 (a deterministic profile).
    Compared: midspan deflection, the mass's displacement (from its static position) and
    acceleration, and the wheel load's dynamic part, 0 ... 1.6 s at 0.01 s.
    Reference: the independent modal solver above (same four vertical modes, scipy DOP853 at
    rtol 1e-11). Tolerance 0.5 % of each history's peak (the acceptance criterion). Measured:
    displacements <= 2e-4; acceleration and wheel load 0.11 % (undamped, dt = 0.5 ms), 0.13 %
    (damped, dt = 0.1 ms), 0.006 % (ramp). With the damper the mass feels the beam's velocity,
    including its 66 Hz mode, whose phase error under generalized-alpha grows over the run (8 % at
    dt = 1 ms, second order in dt), hence the smaller step for that case."""
    profile = ramp if ramped else None
    th = model_run(c, time_step, profile)
    ref = reference(th.time, c, profile)
    y0 = -MV * G / KV
    assert _rel_err(th["bridge.span1.mid.disp_z"], ref["mid"]) <= 5e-3
    assert _rel_err(th["car1.body.disp_z"], ref["y"], offset=y0) <= 5e-3
    assert th["car1.body.disp_z"][0] == pytest.approx(y0, rel=1e-9)
    assert _rel_err(th["car1.body.acc_z"], ref["acc"]) <= 5e-3
    assert _rel_err(th["car1.axle1.force_z"], ref["force"], offset=MV * G) <= 5e-3
    assert th.units["car1.axle1.force_z"] == "N" and th.units["car1.body.acc_z"] == "m/s^2"
