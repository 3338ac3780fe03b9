"""Off the bridge the ground is a track (issue 47): the wheel-rail force of a vehicle coming off the approach
onto the bridge shows the change of the track's support stiffness.

The problem: the Yang & Yau sprung mass (m = 5750 kg on k_s = 1.595e6 N/m, undamped, no wheel mass: its
spring's lower end follows the rail) at 180 km/h over the ballasted UIC60 track: off the bridge the
sleepers stand on ballast and subgrade (pad, ballast, subgrade in series), on a 10 m deck made rigid (the
VBI-2D girder, E and G times 100) on the ballast alone. Without the track the force stays the weight until
the wheel reaches the bridge.

Expected sign and size (closed form): the rail under a static point load P on a rail (EI) on a continuous
foundation k sinks P beta / (2 k), beta = (k / 4 EI)^(1/4); the weight by halves on the two rails, 0.356 mm
on the subgrade and 0.235 mm on the deck. Entering the bridge the rail under the wheel rises by Delta w =
0.121 mm within about 2 / beta = 1.6 m (0.03 s at 50 m/s), too fast for the body (2.65 Hz) to follow: the
force rises by up to k_s Delta w = +193 N, the body then swings about its new level, and leaving the bridge
the same happens downwards.

The reference, written here: that rail on the continuous foundation (pad and ballast in series per spacing a
on the deck, pad, ballast and subgrade off it, switching midway between the last sleeper off the deck and
the first on it: at x = 0 and x = 10.2 m), solved by finite differences (h = 2.5 cm) for the load at each place
of the wheel (quasi-static: the track's own dynamics under a load moving at 50 m/s, far below its
critical speed, change the deflection by well under 1 %), and the body's m u'' = k_s (e - u) (e the rail's
rise under the wheel since t = 0) by an ODE solver: F = m g + k_s (e - u).
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
import scipy.sparse as sp
from scipy.integrate import solve_ivp
from scipy.sparse.linalg import splu

from tb_exudyn import load_scenario, run_deterministic
from tb_exudyn.scenario.track_structure import load_track_structure
from tb_exudyn.system.track_bridge import MARGIN_BAYS

G = 9.81
MASS, K_S = 5750.0, 1.595e6


def _scenario():  # noqa: ANN202
    sc = load_scenario("yang_yau_sprung_mass")
    g = sc.bridge.girder
    bridge = sc.bridge.replace(track_height=1.0, spans=(10.0,), girder=g.replace(E=100 * g.E, G=100 * g.G))
    return sc.replace(speed_kmh=180.0, bridge=bridge,
                      track=sc.track.replace(structure="ballasted_uic60", lead_in=6.0, taper_length=3.0, run_out=0.0),
                      analysis=sc.analysis.replace(mode_max_frequency=1000.0, channels=("car1.*",)))


def winkler_path(xs: np.ndarray, length: float, deck: tuple[float, float]) -> np.ndarray:
    """The rail's deflection under a unit load at each x of ``xs``, by finite differences on [-40, L + 40] m:
    EI w'''' + k(x) w = delta(x - x_load), k = k_deck on ``deck`` = (x_in, x_out), k_ground elsewhere (per
    metre), w = 0 at the
    far ends (the deflection decays as exp(-beta x): 1e-20 there)."""
    ts = load_track_structure("ballasted_uic60")
    ei, a = ts.rail.E * ts.rail.I, ts.spacing
    k_deck = 1.0 / (1.0 / ts.pad.stiffness + 1.0 / ts.ballast.stiffness) / a
    k_ground = 1.0 / (1.0 / ts.pad.stiffness + 1.0 / ts.ballast.stiffness + 1.0 / ts.subgrade.stiffness) / a
    h = 0.025
    x = np.arange(-40.0, length + 40.0 + h / 2, h)
    n = x.size
    k = np.where((x >= deck[0]) & (x <= deck[1]), k_deck, k_ground)
    stencil = ei / h**4 * np.array([1.0, -4.0, 6.0, -4.0, 1.0])
    A = sp.diags([np.full(n - abs(d), stencil[d + 2]) for d in range(-2, 3)], range(-2, 3), format="lil")
    A.setdiag(A.diagonal() + k)
    lu = splu(A.tocsc())
    # the load shared linearly by the two nodes around it, its deflection read the same way
    i = np.clip(((xs - x[0]) / h).astype(int), 0, n - 2)
    f = (xs - x[i]) / h
    rhs = np.zeros((n, xs.size))
    rhs[i, np.arange(xs.size)] = (1 - f) / h
    rhs[i + 1, np.arange(xs.size)] = f / h
    w = lu.solve(rhs)
    return (1 - f) * w[i, np.arange(xs.size)] + f * w[i + 1, np.arange(xs.size)]


def test_the_wheel_force_shows_the_transition_from_the_subgrade_to_the_bridge():
    """The run's contact force against the reference (module docstring), over the whole run (on, over and
    off the bridge): within 10 % of k_s Delta w (19 N on a 56.4 kN wheel load). Tolerance: the discrete
    sleepers make the rail 1.1 % stiffer above a sleeper than the smeared foundation and as soft mid-bay
    (tests/builder/test_track_scenario.py; on Delta w about 3 % of its size), and ripple the deflection by
    about +-3 um as the wheel passes them (+-4 N); the modes above 2 kHz left out are in those figures; the
    quasi-static reference leaves out the track's own response to the moving load at the transition (up to
    11 N 2 m into the span). The run's first 3 m are left out: the track starts from rest under a load that
    moves at once (15 N, gone after 2 m)."""
    sc = _scenario()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        det = run_deterministic(sc)
    t = np.asarray(det.time)
    force = np.asarray(det["car1.axle1.force_z"])
    v, length = sc.speed, sc.bridge.length
    x0 = -sc.track.lead_in
    xs = np.linspace(x0, x0 + v * t[-1], 4001)
    # the smeared foundation switches midway between the last sleeper off the deck and the first on it (the
    # sleepers of the run's track: every 0.6 m from MARGIN_BAYS bays before the wheel's start, 0 <= x_s <= L on it)
    a = load_track_structure("ballasted_uic60").spacing
    sleepers = x0 - MARGIN_BAYS * a + (np.arange(200) + 0.5) * a
    on_deck = sleepers[(sleepers >= 0.0) & (sleepers <= length)]
    deck = (on_deck[0] - a / 2, on_deck[-1] + a / 2)  # (0.0, 10.2) m
    sink = 0.5 * MASS * G * winkler_path(xs, length, deck)  # the weight by halves on the two rails: the rail sinks by it

    def rise(tt: float) -> float:  # the rail's rise under the wheel since t = 0
        return float(sink[0] - np.interp(x0 + v * tt, xs, sink))

    def rhs(tt: float, y: np.ndarray) -> list[float]:
        return [y[1], K_S / MASS * (rise(tt) - y[0])]

    sol = solve_ivp(rhs, (0.0, t[-1]), [0.0, 0.0], t_eval=t, rtol=1e-10, atol=1e-14, max_step=1e-3)
    e = np.array([rise(tt) for tt in t])
    ref = MASS * G + K_S * (e - sol.y[0])
    dw = float(sink[0] - np.interp(5.0, xs, sink))  # the rail's rise on the deck: +0.121 mm
    assert dw == pytest.approx(0.121e-3, rel=0.02)
    assert force[0] == pytest.approx(MASS * G, rel=1e-6)  # the static start on the approach's track
    settled = x0 + v * t > -3.0  # the run's first 3 m: the track's start from rest under a moving load (15 N)
    err = np.max(np.abs(force - ref)[settled])
    assert err < 0.1 * K_S * dw, (err, K_S * dw)  # measured 14.1 N of 192 N (7.4 %)
    on = (x0 + v * t > 0.0) & (x0 + v * t < 1.0)  # entering the bridge: the force rises by about k_s Delta w
    assert np.max(force[on]) - MASS * G > 0.8 * K_S * dw  # measured +184 N
