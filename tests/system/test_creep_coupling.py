"""The creep rows of tb_exudyn.system.creep as general linear rows of the wheel-rail coupling."""

from __future__ import annotations

import numpy as np
import pytest

from tb_exudyn.structure.modal import simply_supported_modes
from tb_exudyn.system.contact_rows import ContactRows
from tb_exudyn.system.coupling import VERTICAL, WheelRailCoupling
from tb_exudyn.system.creep import CreepCoefficients, WheelsetContact, creep_rows, rolling_roll_terms
from tb_exudyn.system.excitation import ProfileExcitation, rail_inputs

B = 0.75  # half gauge (rail centres) for the vertical rows
R0, B0, LAM, W = 0.46, 0.7465, 0.15, 1.5e5
NODE = 7  # the wheelset's node number; its coordinates x, y, z, rx, ry, rz
SPEED = 30.0


def _bridge():
    return simply_supported_modes((20.0, 25.0), EI_vertical=2e10, EI_lateral=8e10, GJ=1.5e10,
                                  mass_per_length=1.2e4, rot_mass_per_length=9e4, damping_ratio=0.02,
                                  max_frequency=60.0, track_offset=1.5, track_height=1.2)


def _excitation() -> ProfileExcitation:
    def alignment(x):
        return 2e-3 * np.sin(0.4 * x), 2e-3 * 0.4 * np.cos(0.4 * x)

    def cross_level(x):
        return 1e-3 * np.cos(0.3 * x), -1e-3 * 0.3 * np.sin(0.3 * x)

    return ProfileExcitation(alignment=alignment, cross_level=cross_level)


def _rows() -> object:
    contact = WheelsetContact(CreepCoefficients(1.1e7, 1.0e7, 2.5e4, 70.0), R0, B0, LAM, W,
                              gravitational_yaw_stiffness=-3e4, spin=True)
    return creep_rows(contact, SPEED)


WHEEL_COORDS = (1, 3, 5, 0, 4)  # node coordinates of the module's (y, rx, rz, x, ry)


def _coupling(with_creep: bool, excitation=None) -> WheelRailCoupling:  # noqa: ANN001
    rows = ContactRows()
    for side in (1.0, -1.0):  # the vertical penalty rows of one wheelset, as the builder adds them
        rows.add(name=f"axle1.{side}.force_z", axle=0, direction=VERTICAL, rail_offset=side * B,
                 stiffness=2e9, damping=3e5 * (1.5 + side / 4), wheel_terms={(NODE, 2): 1.0, (NODE, 3): side * B},
                 inputs=(1.0, 0.0, side * B))
    if with_creep:
        cr = _rows()
        for i, name in enumerate(cr.rows):
            terms = [{(NODE, c): float(M[i, j]) for j, c in enumerate(WHEEL_COORDS) if M[i, j] != 0.0}
                     for M in (cr.A_w, cr.K_w, cr.C_w)]
            rows.add_linear(name=f"axle1.{name}", axle=0, wheel_application=terms[0], wheel_stiffness=terms[1],
                            wheel_damping=terms[2], rail_application=cr.A_r[i], rail_stiffness=cr.K_r[i],
                            rail_damping=cr.C_r[i])
    layout = rows.layout({NODE: 0}, 6)
    return WheelRailCoupling(_bridge(), axle_start=[-3.0], speed=SPEED, contacts=layout, half_gauge=B,
                             excitation=excitation)


def _state(n: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    return rng.normal(size=n) * 1e-3, rng.normal(size=n) * 1e-2


@pytest.mark.parametrize("t", [0.05, 0.5])  # the axle on the approach track, then on the first span (x = 12 m)
def test_creep_rows_in_the_coupling_match_the_module(t):
    """Exact problem: one wheelset (vertical penalty rows and the four creep rows of the module, spin
    and a gravitational yaw stiffness switched on) on a two-span modal bridge with an alignment and
    a cross-level profile, at a random state. Reference: the module's rows evaluated in the test on
    the rail motion computed here from the bridge's rail shapes and the profiles:
    rho = (S_y q_b + y_a, S_rx q_b + theta_c, S_dy q_b + y_a'), rho'_mat = (S_y, S_rx, S_dy) q_b';
    generalised forces Q_w = A_w^T f on (y, rx, rz, x, ry), Q_b = -(S_y, S_rx, S_dy)^T A_r^T f, added to
    the penalty rows' (from the coupling without creep rows). The penalty rows' forces must be
    bitwise those of the coupling without creep rows. Tolerance 1e-12 of the largest term: the
    same linear algebra in another order (round-off)."""
    exc = _excitation()
    cp, cp0 = _coupling(True, exc), _coupling(False, exc)
    u, ud = _state(cp.n, 11)
    nb = cp.n_bridge
    f = cp.contact_forces(t, u[:nb], ud[:nb], u[nb:], ud[nb:])
    f0 = cp0.contact_forces(t, u[:nb], ud[:nb], u[nb:], ud[nb:])
    assert np.array_equal(f[: cp0.n_contacts], f0)
    # reference
    x = cp.positions(t)
    rs = cp.bridge.rail_shapes(x)
    val, slo = rail_inputs(exc, x, float(cp.axle_start[0]), B)
    Sy, Srx, Sdy = rs.y[0], rs.rx[0], rs.dy[0]
    rho = np.array([Sy @ u[:nb] + val[1, 0], Srx @ u[:nb] + val[2, 0], Sdy @ u[:nb] + slo[1, 0]])
    rho_dot = np.array([Sy @ ud[:nb], Srx @ ud[:nb], Sdy @ ud[:nb]])
    w, wd = u[nb:][list(WHEEL_COORDS)], ud[nb:][list(WHEEL_COORDS)]
    cr = _rows()
    f_ref = cr.forces(w, wd, rho, rho_dot)
    assert f[cp0.n_contacts:] == pytest.approx(f_ref, rel=1e-12, abs=1e-12 * np.abs(f_ref).max())
    Q_ref = cp0.forces(t, u, ud)
    Q_ref[nb:][list(WHEEL_COORDS)] += cr.A_w.T @ f_ref
    Q_ref[:nb] -= np.vstack((Sy, Srx, Sdy)).T @ (cr.A_r.T @ f_ref)
    Q = cp.forces(t, u, ud)
    assert np.abs(Q - Q_ref).max() <= 1e-12 * np.abs(Q_ref).max()
    if t < 0.1:  # off the bridge: the rails are rigid, the bridge gets no force
        assert not np.any(Q[:nb])


def test_creep_row_jacobians_match_finite_differences():
    """Exact problem: the coupling with creep rows at t = 0.5 s (on the bridge, moving shapes).
    Reference: central differences of ``forces`` (exact for forces linear in u, u' up to round-off
    with steps of 1e-6 on unit-scale coordinates). Tolerance 1e-6 of the largest entry. The creep
    stiffness is not symmetric (the lateral creep force depends on the yaw, the yaw moment on y)."""
    cp = _coupling(True, _excitation())
    t = 0.5
    u, ud = _state(cp.n, 5)
    K, D = cp.jacobians(t)
    h = 1e-6
    Kn, Dn = np.zeros_like(K), np.zeros_like(D)
    for i in range(cp.n):
        e = np.zeros(cp.n)
        e[i] = h
        Kn[:, i] = -(cp.forces(t, u + e, ud) - cp.forces(t, u - e, ud)) / (2 * h)
        Dn[:, i] = -(cp.forces(t, u, ud + e) - cp.forces(t, u, ud - e)) / (2 * h)
    assert np.abs(K - Kn).max() <= 1e-6 * np.abs(K).max()
    assert np.abs(D - Dn).max() <= 1e-6 * np.abs(D).max()
    nb = cp.n_bridge
    y, rz = nb + 1, nb + 5
    assert abs(K[y, rz] - K[rz, y]) > 1e-3 * abs(K[y, rz])  # non-symmetric
    assert np.abs(K[:nb, nb:]).max() > 0 and np.abs(K[nb:, :nb]).max() > 0  # bridge coupled both ways


def test_contact_force_history_has_the_creep_rows():
    """Exact problem: force histories of the coupling with creep rows at three times against
    ``contact_forces`` at each time. Reference: the same function (the history only stacks it);
    exact equality. And the static force (train standing at t, inputs only) of the creep rows is
    the input force W^v . val + W^s . slope: the lateral and yaw rows' static reaction to an
    alignment offset (checked against the module: rows.forces(0, 0, rho_input, 0))."""
    exc = _excitation()
    cp = _coupling(True, exc)
    times = np.array([0.05, 0.3, 0.5])
    rng = np.random.default_rng(2)
    qb, qdb = rng.normal(size=(3, cp.n_bridge)) * 1e-3, rng.normal(size=(3, cp.n_bridge)) * 1e-2
    qw, qdw = rng.normal(size=(3, 6)) * 1e-3, rng.normal(size=(3, 6)) * 1e-2
    H = cp.contact_force_history(times, qb, qdb, qw, qdw)
    assert H.shape == (3, cp.n_contacts + cp.n_linear)
    for i, t in enumerate(times):
        assert np.array_equal(H[i], cp.contact_forces(t, qb[i], qdb[i], qw[i], qdw[i]))
    t = 0.05
    x = cp.positions(t)
    val, slo = rail_inputs(exc, x, float(cp.axle_start[0]), B)
    f_in = _rows().forces(np.zeros(5), np.zeros(5), (val[1, 0], val[2, 0], slo[1, 0]), np.zeros(3))
    st = cp.contact_state(t)
    assert st.f_lin == pytest.approx(f_in, rel=1e-12, abs=1e-12 * np.abs(f_in).max())


def _rolling_coupling(excitation=None) -> WheelRailCoupling:  # noqa: ANN001
    """The vertical penalty rows of one coned wheelset with the rolling-radius terms of
    rolling_roll_terms, as the builder adds them for a creep car (no creep rows)."""
    contact = WheelsetContact(CreepCoefficients(1.1e7, 1.0e7), R0, B0, LAM, W)
    rows = ContactRows()
    for side in (1.0, -1.0):
        t = rolling_roll_terms(contact, side, B)
        rows.add(name=f"axle1.{side}.force_z", axle=0, direction=VERTICAL, rail_offset=side * B,
                 stiffness=2e9, damping=3e5 * (1.5 + side / 4),
                 wheel_terms={(NODE, 2): 1.0, (NODE, 3): side * B + t.wheel_rx, (NODE, 1): t.wheel_y},
                 inputs=(1.0, t.rail_y, side * B), rail_lateral=t.rail_y)
    return WheelRailCoupling(_bridge(), axle_start=[-3.0], speed=SPEED, contacts=rows.layout({NODE: 0}, 6),
                             half_gauge=B, excitation=excitation)


@pytest.mark.parametrize("t", [0.05, 0.5])
def test_vertical_rows_with_the_roll_against_the_gap_written_out(t):
    """Exact problem: the two vertical rows of a coned wheelset (conicity 0.15, rolling-radius
    terms with kappa = lambda b / b0) on the two-span modal bridge with alignment and cross-level
    profiles, at a random state, on the approach (t = 0.05 s) and on the first span (0.5 s).
    Reference: the gap written out here, wheel on side s over its rail,

        delta = z_rail - s kappa y_rail - (z + s b rx - s kappa (y + r0 rx)),
        z_rail = (S_z + s b S_rx) q_b + s b theta_c,   y_rail = S_y q_b + y_a,

    its rate the total derivative at the moving wheel (shapes' material rate plus v times their
    slope, the profiles' slope times v), f = k delta + c delta', generalised forces f times the
    wheel's map on (y, z, rx) and -f times the rail's on q_b. Tolerance 1e-12 of the largest
    term (round-off). And the kinematics: a wheelset moved laterally with the rail (y = y_rail,
    rx = 0, z = z_rail's mean) feels no force from the lateral motion."""
    exc = _excitation()
    cp = _rolling_coupling(exc)
    u, ud = _state(cp.n, 7)
    nb = cp.n_bridge
    x = cp.positions(t)
    rs = cp.bridge.rail_shapes(x)
    val, slo = rail_inputs(exc, x, float(cp.axle_start[0]), B)
    qb, qdb, w, wd = u[:nb], ud[:nb], u[nb:], ud[nb:]

    def written_out(kappa, w, wd, alignment=1.0):  # noqa: ANN001
        f_ref, Q_ref = [], np.zeros(cp.n)
        for side, c in ((1.0, 3e5 * 1.75), (-1.0, 3e5 * 1.25)):
            S = rs.z[0] + side * B * rs.rx[0] - side * kappa * rs.y[0]
            dS = rs.dz[0] + side * B * rs.drx[0] - side * kappa * rs.dy[0]
            r = val[0, 0] + side * B * val[2, 0] - side * kappa * alignment * val[1, 0]
            r_dot = SPEED * (slo[0, 0] + side * B * slo[2, 0] - side * kappa * alignment * slo[1, 0])
            G = np.zeros(6)
            G[1], G[2], G[3] = -side * kappa, 1.0, side * B - side * kappa * R0
            delta = S @ qb + r - G @ w
            delta_dot = S @ qdb + SPEED * dS @ qb + r_dot - G @ wd
            f = 2e9 * delta + c * delta_dot
            f_ref.append(f)
            Q_ref[nb:] += G * f
            Q_ref[:nb] -= S * f
        return np.array(f_ref), Q_ref

    f_ref, Q_ref = written_out(LAM * B / B0, w, wd)
    got = cp.contact_forces(t, qb, qdb, w, wd)
    assert got == pytest.approx(f_ref, rel=1e-12, abs=1e-12 * np.abs(f_ref).max())
    Q = cp.forces(t, u, ud)
    assert np.abs(Q - Q_ref).max() <= 1e-12 * np.abs(Q_ref).max()
    # the wheelset following the rail laterally (its lateral velocity the rail's at the moving
    # wheel: material rate plus v times the slopes): the forces of the rows without the roll
    # (kappa = 0) on a level wheelset, no roll from a relative displacement that is not there
    bridge_y = rs.y[0] @ qb
    w_follow, wd_follow = np.zeros(6), np.zeros(6)
    w_follow[1] = bridge_y + val[1, 0]
    wd_follow[1] = rs.y[0] @ qdb + SPEED * (rs.dy[0] @ qb + slo[1, 0])
    f_follow = cp.contact_forces(t, qb, qdb, w_follow, wd_follow)
    f_level = written_out(0.0, np.zeros(6), np.zeros(6), alignment=0.0)[0]
    assert (bridge_y != 0.0) == (t > 0.1) and val[1, 0] != 0.0
    assert f_follow == pytest.approx(f_level, rel=1e-12, abs=1e-12 * np.abs(f_level).max())
    f_moved = cp.contact_forces(t, qb, qdb, np.zeros(6), np.zeros(6))  # not following: it rolls
    assert np.abs(f_moved - f_level).max() > 1e-3 * np.abs(f_level).max()
