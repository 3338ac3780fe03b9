"""The moving-force response against an independent modal solution, and the resonance of HSLM-A.

Problem 1: one simply supported span L = 32 m, EI = 3.45e10 * 10.947 N m^2, m = 33 900 kg/m (the girder of
models/bridges/single_span_32m), its first three vertical bending modes (f_j = (j pi / L)^2 sqrt(EI / m)
/ 2 pi: 5.12, 20.48, 46.08 Hz, the EN 1990 cut-off being f3), 1 % damping (Table 6.6, prestressed
concrete, L >= 20 m), HSLM-A1. Reference: the modal equations q_j'' + 2 zeta w_j q_j' + w_j^2 q_j =
- sum_k sqrt(2 / (m L)) sin(j pi x_k / L) P_k written out here and integrated by scipy's DOP853 (rtol
1e-10) from the first axle's arrival until two periods of mode 1 after the last axle left; the peak
|acceleration| at mid-span over a 0.1 ms grid of its dense output. Acceptance (issue 25): within 1 %.
The function integrates each mode exactly for a load linear between samples 0.04 m apart; what is left
is the sampled peak (20 samples per period of mode 3) and the load's linearisation: measured 0.21 % at
165.9 km/h (v_2 = n0 D / 2) and 0.13 % at 300 km/h.

Problem 2: resonance. A 20 m span tuned to n0 = 3.3 Hz under HSLM-A4 (D = 21 m): the first resonant
speed v_1 = n0 D = 249.48 km/h. Over speeds 200 ... 300 km/h in 5 km/h steps the largest mid-span
acceleration must lie within one step of v_1 (EN 1991-2 6.4.6.2: resonance at v_i = n0 D / i).
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from tb_exudyn.codes.moving_force import deck_stations, moving_force_response
from tb_exudyn.codes.trains import hslm_a
from tb_exudyn.structure import simply_supported_modes

L, EI, M, ZETA = 32.0, 3.45e10 * 10.947, 33900.0, 0.01


def _bridge(length: float, ei: float, m: float, f_max: float):
    # lateral and torsion stiffness large enough to keep those modes out of the way (only vertical used)
    return simply_supported_modes([length], ei, 1e3 * ei, 1e3 * ei, m, m, ZETA, f_max)


def _reference_peak_acc(train, speed_kmh: float, n_modes: int = 3) -> float:
    v = speed_kmh / 3.6
    j = np.arange(1, n_modes + 1)
    w = (j * np.pi / L) ** 2 * np.sqrt(EI / M)
    amp = np.sqrt(2.0 / (M * L))
    a, p = train.positions, train.loads

    def load(t: float) -> np.ndarray:
        x = v * t - a
        on = (x >= 0) & (x <= L)
        return -(amp * np.sin(np.outer(j, x[on]) * np.pi / L)) @ p[on]

    def rhs(t, y):
        q, qd = y[:n_modes], y[n_modes:]
        return np.concatenate([qd, load(t) - 2 * ZETA * w * qd - w**2 * q])

    t_end = (L + train.length) / v + 2.0 / (w[0] / (2 * np.pi))
    sol = solve_ivp(rhs, (0.0, t_end), np.zeros(2 * n_modes), method="DOP853", rtol=1e-10, atol=1e-12,
                    dense_output=True, max_step=2.5e-3)
    assert sol.success
    t = np.arange(0.0, t_end, 1e-4)  # the peak of a 46 Hz harmonic sampled at 0.1 ms: within 1e-4
    y = sol.sol(t)
    f = np.zeros((n_modes, t.size))
    for k in range(0, t.size, 5000):  # the same load as load(t), on blocks of the grid
        x = v * t[k:k + 5000, None] - a[None, :]
        on = (x >= 0) & (x <= L)
        f[:, k:k + 5000] = -np.einsum("jtk,k->jt", amp * np.sin(j[:, None, None] * np.pi * x[None] / L) * on, p)
    acc = f - 2 * ZETA * w[:, None] * y[n_modes:] - (w**2)[:, None] * y[:n_modes]
    mid = amp * np.sin(j * np.pi / 2)
    return float(np.abs(mid @ acc).max())


@pytest.mark.parametrize("speed_kmh", [165.9, 300.0])
def test_hslm_a1_mid_span_acceleration_against_solve_ivp(speed_kmh):
    bridge = _bridge(L, EI, M, 47.0)
    assert [f"{f:.2f}" for f, t in zip(bridge.frequencies, bridge.mode_types) if t == "vertical"] == \
        ["5.12", "20.48", "46.08"]
    train = hslm_a(1)
    r = moving_force_response(bridge, train, [speed_kmh], [L], damping_ratio=ZETA)
    mid = r.mid_stations[0]
    assert r.station_x[mid] == 16.0
    ref = _reference_peak_acc(train, speed_kmh)
    assert r.max_acc[mid, 0] == pytest.approx(ref, rel=0.01)


def test_static_deflection_and_phi_dyn_at_a_crawl():
    """One 170 kN axle at 5 km/h. The static mid-span deflection of the modes used is the modal series
    sum_j phi_j(L/2)^2 P / w_j^2 = P L^3 / (48 EI) (96 / pi^4) sum_(j = 1, 3) 1 / j^4 (mode 2 has a node at
    mid-span): exact up to the position sampling, (dx / L)^2 ~ 1e-9, so 1e-6 relative. At a crawl the
    dynamic peak equals it: phi'_dyn below 1e-3 (measured 1e-4)."""
    bridge = _bridge(L, EI, M, 47.0)
    a1 = hslm_a(1)
    one = type(a1)("one axle", a1.positions[:1], a1.loads[:1], 18.0)
    r = moving_force_response(bridge, one, [5.0], [L], damping_ratio=ZETA)
    mid = r.mid_stations[0]
    series = one.loads[0] * L**3 / (48 * EI) * 96 / np.pi**4 * (1 + 1 / 81)
    assert r.static_disp[mid] == pytest.approx(series, rel=1e-6)
    assert abs(r.phi_dyn[0, 0]) < 1e-3


def test_resonance_of_hslm_a4_within_one_speed_step_of_n0_d():
    span, n0 = 20.0, 3.3
    ei = (2 * np.pi * n0 / (np.pi / span) ** 2) ** 2 * M  # f1 = (pi / L)^2 sqrt(EI / m) / 2 pi = n0
    bridge = _bridge(span, ei, M, 3 * n0 * 9)
    train = hslm_a(4)
    speeds = np.arange(200.0, 300.1, 5.0)
    r = moving_force_response(bridge, train, speeds, [span], damping_ratio=ZETA)
    peak_speed = speeds[np.argmax(r.max_acc[r.mid_stations[0]])]
    v1 = 3.6 * n0 * train.regular_length
    assert abs(peak_speed - v1) <= 5.0, (peak_speed, v1)


def test_stations_at_most_l_over_8_apart():
    x, names, span, mids = deck_stations([32.0, 24.0])
    np.testing.assert_allclose(x[:7], 4.0 * np.arange(1, 8))
    np.testing.assert_allclose(x[7:], 32.0 + 3.0 * np.arange(1, 8))
    assert list(mids) == [3, 10] and names[3] == "span1.x4/8" and list(span) == [0] * 7 + [1] * 7


GJ, IP, E_TRACK = 1.4375e10 * 22.65, 383040.5, 2.5  # single_span_32m's torsion and its track's offset


def _reference_track_and_axis_peaks(train, speed_kmh: float) -> tuple[float, float]:
    """Problem 3 written out: the first three vertical modes (shape at the track line sqrt(2 / (m L))
    sin(j pi x / L)) and the first three torsion modes (theta_j = sqrt(2 / (I_p L)) sin(j pi x / L),
    w_j = (j pi / L) sqrt(G J / I_p); at the track line, e = 2.5 m off the axis, dz = e theta), all
    loaded by the axles on the track line; DOP853 as above. Returns the peak |acceleration| at mid-span
    on the track line (w + e theta) and on the girder axis (w)."""
    v = speed_kmh / 3.6
    j = np.arange(1, 4)
    w = np.concatenate([(j * np.pi / L) ** 2 * np.sqrt(EI / M), j * np.pi / L * np.sqrt(GJ / IP)])
    amp = np.concatenate([np.full(3, np.sqrt(2.0 / (M * L))), np.full(3, E_TRACK * np.sqrt(2.0 / (IP * L)))])
    jj = np.concatenate([j, j])
    a, p = train.positions, train.loads

    def shapes(x: np.ndarray) -> np.ndarray:  # (6, n_x) at the track line, zero off the span
        on = (x >= 0) & (x <= L)
        return amp[:, None] * np.sin(np.outer(jj, x) * np.pi / L) * on

    def rhs(t, y):
        q, qd = y[:6], y[6:]
        return np.concatenate([qd, -shapes(v * t - a) @ p - 2 * ZETA * w * qd - w**2 * q])

    t_end = (L + train.length) / v + 2.0 / (w[0] / (2 * np.pi))
    sol = solve_ivp(rhs, (0.0, t_end), np.zeros(12), method="DOP853", rtol=1e-10, atol=1e-12,
                    dense_output=True, max_step=2.5e-3)
    assert sol.success
    t = np.arange(0.0, t_end, 1e-4)
    y = sol.sol(t)
    f = np.concatenate([-shapes(v * tk - a) @ p[:, None] for tk in t], axis=1)
    acc = f - 2 * ZETA * w[:, None] * y[6:] - (w**2)[:, None] * y[:6]
    mid = shapes(np.array([L / 2]))[:, 0]
    return float(np.abs(mid @ acc).max()), float(np.abs(mid[:3] @ acc[:3]).max())


def test_deck_acceleration_along_an_eccentric_track_includes_the_torsion():
    """Problem 3: the span of problem 1 with its torsion (G J = 1.4375e10 x 22.65 N m^2, I_p = 383 040.5
    kg m, models/bridges/single_span_32m) and the track 2.5 m off the girder axis, HSLM-A1 at 300 km/h.
    Reference: the six-mode solution written out here (_reference_track_and_axis_peaks). The function's
    peak on the track line (closed-form modes up to 47 Hz: three vertical, three torsion) and on the
    axis (the vertical modes alone: torsion does not move the axis) agree within 1 % (the acceptance's
    tolerance; the sampling and load linearisation of problem 1; measured 0.13 % and 0.12 %); the
    track line's peak is the larger, and the torsion's share of it, track minus axis (1.4 % of the
    peak here), agrees within 10 % of itself (measured 1.2 %), so the torsion term is there and right."""
    train = hslm_a(1)
    bridge = simply_supported_modes([L], EI, 1e3 * EI, GJ, M, IP, ZETA, 47.0, track_offset=E_TRACK)
    assert sorted(bridge.mode_types) == ["torsion"] * 3 + ["vertical"] * 3
    track_ref, axis_ref = _reference_track_and_axis_peaks(train, 300.0)
    peak = {}
    for name, modes in (("track", None), ("axis", [i for i, t in enumerate(bridge.mode_types) if t == "vertical"])):
        resp = moving_force_response(bridge, train, np.array([300.0]), [L], damping_ratio=ZETA, modes=modes)
        peak[name] = float(resp.max_acc[resp.mid_stations[0], 0])
    assert abs(peak["track"] / track_ref - 1) < 0.01 and abs(peak["axis"] / axis_ref - 1) < 0.01, (peak, track_ref)
    assert track_ref > axis_ref and peak["track"] > peak["axis"]
    assert abs((peak["track"] - peak["axis"]) / (track_ref - axis_ref) - 1) < 0.1, (peak, track_ref, axis_ref)


def test_twist_of_an_eccentric_track_at_a_crawl():
    """The twist output (EN 1990 A2.4.4.2.2) on closed-form modes: a 32 m span, torsion modes
    omega_j = (j pi / L) sqrt(GJ / I_p), shape sqrt(2 / (I_p L)) sin(j pi x / L), track 2.5 m off the axis.
    Reference written here: the quasi-static twist 1.435 |theta(x) - theta(x + 3)| with theta(x) = sum_j
    phi_j(x) sum_k phi_j(a_k) e P_k / omega_j^2 over the same torsion modes, the peak over the train's
    positions every 0.01 m (its sampling error ~1e-6); the function's static_twist to 1e-4, and its dynamic
    peak at 5 m/s (far below any resonance: a dynamic increment of order (v / (2 f L))^2) within 1 %."""
    gj, ip, e = 1.4375e10 * 22.65, 383040.5, 2.5
    bridge = simply_supported_modes([L], EI, 1e3 * EI, gj, M, ip, ZETA, 60.0, track_offset=e)
    tors = [i for i, t in enumerate(bridge.mode_types) if t == "torsion"]
    assert len(tors) >= 2
    train = hslm_a(1)
    train = type(train)(name="short", positions=train.positions[:6], loads=train.loads[:6], regular_length=3.0)
    r = moving_force_response(bridge, train, [18.0], [L], damping_ratio=ZETA, modes=tors)
    j = np.arange(1, len(tors) + 1)
    w = j * np.pi / L * np.sqrt(gj / ip)
    amp = np.sqrt(2.0 / (ip * L))

    def theta(x, front):  # rotation at x with the first axle at ``front``
        a = front - train.positions
        on = (a >= 0) & (a <= L)
        q = (amp * np.sin(np.outer(j, a[on]) * np.pi / L) @ (e * train.loads[on])) / w**2
        xx = np.asarray(x, dtype=float)
        shape = np.where((xx >= 0) & (xx <= L), amp * np.sin(np.pi * np.outer(xx, j) / L), 0.0)
        return shape @ q

    fronts = np.arange(0.0, L + train.positions[-1] + 0.01, 0.01)
    ref = np.array([max(abs(1.435 * (theta([x], f)[0] - theta([x + 3.0], f)[0])) for f in fronts) for x in r.twist_x])
    np.testing.assert_allclose(r.static_twist, ref, rtol=1e-4, atol=1e-6 * ref.max())
    np.testing.assert_allclose(r.max_twist[:, 0], ref, rtol=0.01, atol=1e-3 * ref.max())
