"""The plain-numpy wheel-rail coupling, excitation and channel selection (no Exudyn needed)."""

from __future__ import annotations

import numpy as np
import pytest

from tb_exudyn.system.channels import catalogue, select
from tb_exudyn.system.coupling import LATERAL, VERTICAL, ContactLayout, WheelRailCoupling
from tb_exudyn.system.excitation import HarmonicExcitation, ProfileExcitation, rail_inputs, sampled_profile
from tb_exudyn.structure.modal import simply_supported_modes

B = 0.75  # half gauge
R = 0.46  # wheel radius


def _bridge():
    return simply_supported_modes((20.0, 25.0), EI_vertical=2e10, EI_lateral=8e10, GJ=1.5e10,
                                  mass_per_length=1.2e4, rot_mass_per_length=9e4, damping_ratio=0.02,
                                  max_frequency=60.0, track_offset=1.5, track_height=1.2)


def _two_wheelsets(k=2e9, c=3e5):
    """Two wheelset nodes of 6 coordinates (x, y, z, rx, ry, rz), three contacts each."""
    rows, G, W = [], [], []
    for j in range(2):
        for side in (1.0, -1.0):
            g = np.zeros(12)
            g[6 * j + 2], g[6 * j + 3] = 1.0, side * B
            rows.append((j, VERTICAL, side * B))
            G.append(g)
            W.append((1.0, 0.0, side * B))
        g = np.zeros(12)
        g[6 * j + 1], g[6 * j + 3] = 1.0, R
        rows.append((j, LATERAL, 0.0))
        G.append(g)
        W.append((0.0, 1.0, 0.0))
    n = len(rows)
    return ContactLayout(
        axle=np.array([r[0] for r in rows]), direction=np.array([r[1] for r in rows]),
        rail_offset=np.array([r[2] for r in rows]), stiffness=np.full(n, k),
        damping=np.linspace(1.0, 2.0, n) * c, wheel_map=np.array(G), input_map=np.array(W),
    )


def _coupling(excitation=None, speed=30.0, c=3e5):
    bridge = _bridge()
    return WheelRailCoupling(bridge, axle_start=[-2.0, -4.5], speed=speed, contacts=_two_wheelsets(c=c),
                             load_axle=[1], load_force=[1e5], half_gauge=B, excitation=excitation)


def test_jacobians_match_finite_differences_of_the_forces():
    """Exact problem: the coupling's analytic stiffness and damping Jacobians K = -dQ/du and
    D = -dQ/du' at a time when both wheelsets are on the first span (moving shapes, convective
    term, damping) against central differences of ``forces``. Reference: numerical differentiation
    of the same force function. Tolerance 1e-6 of the largest entry: the forces are linear in u, so
    central differences are exact up to round-off (step 1e-6 of unit-scale coordinates)."""
    cp = _coupling(HarmonicExcitation("vertical", 0.7, 1e-3))
    t = 0.4  # axles at x = 10 and 7.5 m
    rng = np.random.default_rng(3)
    u, ud = rng.normal(size=cp.n) * 1e-3, rng.normal(size=cp.n) * 1e-2
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
    assert np.abs(K[: cp.n_bridge, : cp.n_bridge]).max() > 0  # the bridge block is really coupled


def test_force_signs_and_bridge_reaction():
    """Exact problem: wheelset 1 on the bridge pushed 1 mm into the rail (z lowered by 1e-3 m, bridge
    at rest, no input). Reference: hand calculation: each wheel carries k * 1e-3 in compression
    (force_z > 0), the wheelset is pushed up (Q_w on z = +2 k 1e-3), and the bridge modal force
    is -(shape at the wheel)^T f (the rail pushed down), plus the moving point load on axle 2.
    Tolerance: round-off only (1e-9 relative)."""
    cp = _coupling(speed=30.0, c=0.0)
    t = 0.4
    q_w = np.zeros(12)
    q_w[2] = -1e-3
    f = cp.contact_forces(t, np.zeros(cp.n_bridge), np.zeros(cp.n_bridge), q_w, np.zeros(12))
    k = cp.contacts.stiffness[0]
    assert f[:2] == pytest.approx([k * 1e-3, k * 1e-3], rel=1e-12)
    assert np.all(f[2:] == 0.0)
    Qb, Qw = cp.generalized_forces(t, np.zeros(cp.n_bridge), np.zeros(cp.n_bridge), q_w, np.zeros(12))
    assert Qw[2] == pytest.approx(2 * k * 1e-3, rel=1e-12)
    rs = cp.bridge.rail_shapes(cp.positions(t))
    left, right = rs.z[0] + B * rs.rx[0], rs.z[0] - B * rs.rx[0]
    expected = -(left + right) * k * 1e-3 - rs.z[1] * 1e5
    assert np.allclose(Qb, expected, rtol=1e-9, atol=1e-9 * np.abs(expected).max())


def test_off_the_bridge_the_rail_is_rigid():
    """Exact problem: both axles on the approach (x < 0): the bridge's modal coordinates must not
    enter the gap (shape rows zero) and no force reaches the bridge. Reference: the definition
    (rigid approach track). Tolerance: exact zeros."""
    cp = _coupling()
    st = cp.contact_state(0.0)
    assert not st.on_bridge and np.all(st.S == 0.0)
    Qb, _ = cp.generalized_forces(0.0, np.ones(cp.n_bridge), np.ones(cp.n_bridge), np.zeros(12), np.zeros(12))
    assert np.all(Qb == 0.0)


def test_harmonic_input_lags_with_axle_spacing():
    """Exact problem: a harmonic vertical pseudo-excitation A cos(Omega (v t - a_j)) (real part) and
    A sin(...) (imaginary part) at wheels trailing the first by a_j = 0 and 2.5 m, and its rate
    A Omega v (-sin, cos). Reference: the closed form written here. Tolerance 1e-12 (round-off)."""
    A, Om, v, t = 2e-3, 0.9, 30.0, 0.37
    for part, f, df in (("real", np.cos, lambda p: -np.sin(p)), ("imag", np.sin, np.cos)):
        cp = _coupling(HarmonicExcitation("vertical", Om, A, part=part), speed=v)
        st = cp.contact_state(t)
        a = np.array([0.0, 2.5])
        phase = Om * (v * t - a)
        assert np.allclose(st.r[[0, 1, 3, 4]], np.repeat(A * f(phase), 2), atol=1e-15)
        assert np.allclose(st.r_dot[[0, 3]], A * Om * v * df(phase), atol=1e-15)
        assert np.all(st.r[[2, 5]] == 0.0)  # no lateral input from a vertical profile


def test_cross_level_as_angle_or_height():
    """Exact problem: cross-level input theta_c given as an angle, or as the height difference
    h = 2 b theta_c: the rails must sit at z_L,R = +- b theta_c either way. Reference: the
    definition z_L,R = z_v +- b theta_c. Tolerance 1e-15 (round-off)."""
    x = np.array([1.0, 2.0])
    theta = lambda x: (1e-3 * x, 1e-3 + 0 * x)  # noqa: E731
    height = lambda x: (2 * B * 1e-3 * x, 2 * B * 1e-3 + 0 * x)  # noqa: E731
    v1, s1 = rail_inputs(ProfileExcitation(cross_level=theta), x, 0.0, B)
    v2, s2 = rail_inputs(ProfileExcitation(cross_level=height, cross_level_unit="height"), x, 0.0, B)
    assert np.allclose(v1, v2, atol=1e-15) and np.allclose(s1, s2, atol=1e-15)
    assert np.allclose(v1[2], 1e-3 * x)


def test_sampled_profile_interpolates_with_slopes():
    """Exact problem: a profile from samples (0, 0), (1, 2), (3, 2): linear interpolation with
    slopes 2 and 0, constant (slope 0) outside. Reference: hand values. Tolerance: exact."""
    p = sampled_profile([0.0, 1.0, 3.0], [0.0, 2.0, 2.0])
    val, slo = p(np.array([-1.0, 0.5, 2.0, 4.0]))
    assert np.allclose(val, [0.0, 1.0, 2.0, 2.0]) and np.allclose(slo, [0.0, 2.0, 0.0, 0.0])


def test_channel_glob_selection_and_unknown_pattern():
    """Channel selection by glob patterns keeps catalogue order; a pattern matching nothing is a
    clear error naming the pattern."""
    chans = catalogue(("span1.mid",), [("car1.body", 3, (("y", 1), ("z", 2), ("rx", 3)))],
                      ("car1.axle1.left.force_z",), ())
    names = [c.name for c in select(chans, ["car1.body.acc_*", "*.force_z"])]
    assert names == ["car1.body.acc_y", "car1.body.acc_z", "car1.body.acc_rx", "car1.axle1.left.force_z"]
    units = {c.name: c.unit for c in chans}
    assert units["bridge.span1.mid.acc_z"] == "m/s^2" and units["car1.body.vel_rx"] == "rad/s"
    with pytest.raises(ValueError, match="car9"):
        select(chans, ["car9.*"])
