"""tb_exudyn.system.modes on small systems whose modes are known in closed form: the damped
eigenvalues, overdamped and rigid modes, labels (also of degenerate modes), and the damping guard."""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.linalg

from tb_exudyn.system.damping_guard import RunTimes, damping_warnings, merged_messages
from tb_exudyn.system.modes import Dof, mode_label, mode_table, nth_frequency


def body(group: str, part: str, component: str, channel: str, **kw) -> Dof:
    return Dof(group, part, component, channel, **kw)


def diag_system(m, k, c):
    return np.diag(m), np.diag(k), np.diag(c)


def test_single_oscillator_closed_form():
    """Exact problem: m q'' + c q' + k q = 0 with m = 2 kg, k = 5000 N/m, c = 4 N s/m. Reference:
    omega_n = sqrt(k / m), zeta = c / (2 sqrt(k m)), omega_d = omega_n sqrt(1 - zeta^2), decay time
    1 / (zeta omega_n) = 2 m / c. One mode (the conjugate pair once). Tolerance 1e-12 relative:
    one 2 x 2 eigenproblem, round-off only."""
    m, k, c = 2.0, 5000.0, 4.0
    t = mode_table(*diag_system([m], [k], [c]), [body("car 1 (x)", "body", "bounce", "car1.body")])
    assert len(t) == 1
    wn = math.sqrt(k / m)
    zeta = c / (2 * math.sqrt(k * m))
    assert t.frequency[0] == pytest.approx(wn / (2 * math.pi), rel=1e-12)
    assert t.damping_ratio[0] == pytest.approx(zeta, rel=1e-12)
    assert t.damped_frequency[0] == pytest.approx(wn * math.sqrt(1 - zeta**2) / (2 * math.pi), rel=1e-12)
    assert t.decay_time[0] == pytest.approx(2 * m / c, rel=1e-12)
    assert t.label[0] == "car 1 (x), body, bounce" and t.kind[0] == "vehicle"
    assert not t.overdamped[0]


def test_overdamped_rigid_and_undamped_modes_never_crash():
    """Exact problem: three uncoupled coordinates: an overdamped oscillator (m 1, k 100, c 50:
    zeta 2.5), a free body with a damper (k 0, c 3: eigenvalues 0 and -3) and an undamped one
    (m 1, k 400, c 0). Reference: the overdamped roots lambda = -c/2 +- sqrt(c^2/4 - k) (real, each
    its own row, f_n = |lambda| / 2 pi, zeta reported 1, flagged overdamped, decay 1 / |lambda|);
    the rigid mode f = 0, zeta nan; the undamped one zeta 0, decay time inf. Tolerance 1e-10."""
    M, K, D = diag_system([1.0, 1.0, 1.0], [100.0, 0.0, 400.0], [50.0, 3.0, 0.0])
    dofs = [body("car 1 (x)", "body", c, "car1.body") for c in ("bounce", "lateral", "roll")]
    t = mode_table(M, K, D, dofs)
    assert len(t) == 5
    roots = sorted(abs(-25.0 + s * math.sqrt(625.0 - 100.0)) for s in (1, -1))
    over = np.flatnonzero(t.overdamped)
    lam_real = sorted(abs(t.eigenvalues[over].real))
    assert np.allclose(lam_real, sorted(roots + [3.0]), rtol=1e-10)
    assert np.all(t.damping_ratio[over] == 1.0)
    assert np.allclose(t.decay_time[over], 1.0 / np.abs(t.eigenvalues[over].real))
    rigid = [i for i, k in enumerate(t.kind) if k == "rigid"]
    assert len(rigid) == 1 and t.frequency[rigid[0]] == 0.0 and math.isnan(t.damping_ratio[rigid[0]])
    und = int(np.argmin(np.abs(t.frequency - 20.0 / (2 * math.pi))))
    assert t.damping_ratio[und] == 0.0 and math.isinf(t.decay_time[und])
    text = t.text()
    assert ">= 1" in text and "nan" in text and "inf" in text


def bogie_pair(k_c: float = 5.0e7):
    """A toy car: body lateral y_b; two bogies (lateral y_i, yaw r_i, inertia J) each on two wheels
    (lateral u_ia, u_ib) through springs k_p between u_ia and y_i + a r_i, u_ib and y_i - a r_i; wheels
    on springs k_c to the ground; bogies to the body by k_s. The bogie yaw modes (r_i with u_ia =
    -u_ib) exert no force on y_i: two equal, uncoupled modes inside one connected system."""
    mb, mt, J, mw = 40000.0, 3000.0, 6000.0, 100.0
    kp, ks, a = 3.0e6, 5.0e5, 1.25
    names = ["y_b", "y_1", "r_1", "u_1a", "u_1b", "y_2", "r_2", "u_2a", "u_2b"]
    n = len(names)
    K = np.zeros((n, n))

    def spring(k, e):
        K[:, :] += k * np.outer(e, e)

    idx = {s: i for i, s in enumerate(names)}
    for b in ("1", "2"):
        e = np.zeros(n); e[idx["y_b"]] = 1; e[idx[f"y_{b}"]] = -1
        spring(ks, e)
        for w, sign in (("a", 1.0), ("b", -1.0)):
            e = np.zeros(n); e[idx[f"u_{b}{w}"]] = 1; e[idx[f"y_{b}"]] = -1; e[idx[f"r_{b}"]] = -sign * a
            spring(kp, e)
            e = np.zeros(n); e[idx[f"u_{b}{w}"]] = 1
            spring(k_c, e)
    M = np.diag([mb, mt, J, mw, mw, mt, J, mw, mw])
    D = 1e-3 * K  # stiffness-proportional damping: the modes stay those of (K, M)
    g = "car 1 (toy)"
    dofs = [body(g, "body", "lateral", "car1.body")]
    for b, part in (("1", "leading bogie"), ("2", "trailing bogie")):
        dofs += [body(g, part, "lateral", f"car1.bogie{b}"), body(g, part, "yaw", f"car1.bogie{b}")]
        dofs += [body(g, f"axle {w}", "lateral", f"car1.axle{w}", role="wheelset") for w in ("1", "2")]
    return M, K, D, dofs


def test_degenerate_bogie_yaw_modes_are_localised():
    """Exact problem: the toy car of :func:`bogie_pair`, whose two bogie yaw modes have the same
    eigenvalue. Reference: the modes are any combination within their 2-D space; the table must give
    the localised pair, one on each bogie (share of the other bogie below 1e-9, round-off), labelled
    "leading bogie, yaw" and "trailing bogie, yaw"; their undamped frequency (stiffness-proportional
    damping: |lambda| = omega_n) is the lower one of the yaw subsystem (r, u_a = -u_b) computed
    here. Tolerance 1e-6: round-off of the 18 x 18 eigenproblem."""
    M, K, D, dofs = bogie_pair()
    t = mode_table(M, K, D, dofs)
    yaw = [i for i, lab in enumerate(t.label) if lab.endswith("bogie, yaw")]
    assert [t.label[i] for i in yaw] in (
        ["car 1 (toy), leading bogie, yaw", "car 1 (toy), trailing bogie, yaw"],
        ["car 1 (toy), trailing bogie, yaw", "car 1 (toy), leading bogie, yaw"],
    )
    lead = [j for j, d in enumerate(dofs) if d.part == "leading bogie"]
    trail = [j for j, d in enumerate(dofs) if d.part == "trailing bogie"]
    for i in yaw:
        s1, s2 = t.shares[i, lead].sum(), t.shares[i, trail].sum()
        assert min(s1, s2) < 1e-9, (s1, s2)
    # the yaw subsystem in antisymmetric coordinates (r, u) with u_a = u, u_b = -u: kinetic energy
    # J r'^2 / 2 + 2 m_w u'^2 / 2, potential 2 k_p (u - a r)^2 / 2 + 2 k_c u^2 / 2
    J, mw, kp, kc, a = 6000.0, 100.0, 3.0e6, 5.0e7, 1.25
    Ks = np.array([[2 * kp * a * a, -2 * kp * a], [-2 * kp * a, 2 * kp + 2 * kc]])
    Ms = np.diag([J, 2 * mw])
    w = math.sqrt(scipy.linalg.eigh(Ks, Ms, eigvals_only=True).min())
    for i in yaw:
        assert t.frequency[i] == pytest.approx(w / (2 * math.pi), rel=1e-6)


def test_identical_independent_cars_do_not_mix():
    """Two identical oscillators in two groups (uncoupled, equal eigenvalues): each mode lives on one
    car (the independent parts are solved one by one), labels 'car 1 ...' and 'car 2 ...'."""
    M, K, D = diag_system([1.0, 1.0], [100.0, 100.0], [0.1, 0.1])
    dofs = [body("car 1 (a)", "body", "bounce", "car1.body"), body("car 2 (a)", "body", "bounce", "car2.body")]
    t = mode_table(M, K, D, dofs)
    assert sorted(t.label) == ["car 1 (a), body, bounce", "car 2 (a), body, bounce"]
    assert np.allclose(np.sort(t.shares.max(axis=1)), 1.0)
    assert t.affected_channels(0) in (("car1.*",), ("car2.*",))


def test_label_names_groups_parts_and_components():
    """The label format: groups with >= 20 % of the energy (' & '), in each the parts, and in each
    part the components with >= 20 % of the part; bridge modal coordinates by their own names."""
    dofs = [
        body("bridge", "vertical 1", "vertical", "bridge", role="bridge"),
        body("bridge", "torsion 1", "torsion", "bridge", role="bridge"),
        body("car 1 (x)", "body", "lateral", "car1.body"),
        body("car 1 (x)", "body", "roll", "car1.body"),
        body("car 1 (x)", "leading bogie", "lateral", "car1.bogie1"),
        body("car 1 (x)", "axle 1", "yaw", "car1.axle1", role="wheelset", decoupled=True),
    ]
    assert mode_label(np.array([0.7, 0.3, 0, 0, 0, 0]), dofs) == "bridge, vertical 1 + torsion 1"
    assert mode_label(np.array([0.0, 0.0, 0.5, 0.3, 0.2, 0.0]), dofs) == "car 1 (x), body, lateral + roll; leading bogie, lateral"
    assert mode_label(np.array([0.6, 0.0, 0.4, 0.0, 0.0, 0.0]), dofs) == "bridge, vertical 1 & car 1 (x), body, lateral"
    assert mode_label(np.array([0.0, 0.0, 0.0, 0.0, 0.0, 1.0]), dofs) == "car 1 (x), axle 1, yaw (decoupled)"


def guard_system():
    """Five uncoupled oscillators (mass 1): 8 Hz zeta 1e-4 (a car mode), 1 Hz zeta 0.2 (car body),
    5 Hz zeta 0 (a decoupled weak-spring coordinate), 100 Hz zeta 1e-4 (outside the band), 200 Hz
    zeta 0.5 (a wheelset on the contact), 3 Hz zeta 0.01 (the bridge: tau = 5.3 s)."""
    f = np.array([8.0, 1.0, 5.0, 100.0, 200.0, 3.0])
    z = np.array([1e-4, 0.2, 0.0, 1e-4, 0.5, 0.01])
    w = 2 * np.pi * f
    dofs = [
        body("car 1 (x)", "leading bogie", "yaw", "car1.bogie1"),
        body("car 2 (x)", "body", "lateral", "car2.body"),
        body("car 1 (x)", "body", "longitudinal", "car1.body", decoupled=True),
        body("car 1 (x)", "trailing bogie", "yaw", "car1.bogie2"),
        body("car 1 (x)", "axle 1", "lateral", "car1.axle1", role="wheelset"),
        body("bridge", "vertical 1", "vertical", "bridge", role="bridge"),
    ]
    return mode_table(np.eye(6), np.diag(w**2), np.diag(2 * z * w), dofs)


def test_damping_guard_warns_only_for_lightly_damped_excited_modes_in_band():
    """Exact problem: :func:`guard_system` with the band 0.3-60 Hz and runs of T = 5 s and 10 s.
    Reference: decay times 1 / (zeta w): 199 s (8 Hz), 0.8 s (1 Hz), inf (decoupled), 16 s (100 Hz,
    outside the band), 1.6 ms (contact), 5.3 s (bridge). So T = 5 s warns for 8 Hz and the bridge
    mode, T = 10 s for 8 Hz only; never for the decoupled, out-of-band or contact modes; with the
    8 Hz mode's coordinate marked not excited, only the bridge mode is left. Tolerance 1e-9 on the
    decay time and damping (a diagonal system: round-off)."""
    t = guard_system()
    band = (0.3, 60.0)
    w5 = damping_warnings(t, band, RunTimes(5.0, 1.0, 4.0))
    assert sorted(round(w.frequency, 6) for w in w5) == [3.0, 8.0]
    w8 = next(w for w in w5 if abs(w.frequency - 8.0) < 1e-9)
    assert w8.decay_time == pytest.approx(1 / (1e-4 * 2 * np.pi * 8.0), rel=1e-9)
    assert w8.damping_ratio == pytest.approx(1e-4, rel=1e-9)
    assert w8.channels == ("car1.*",) and w8.label == "car 1 (x), leading bogie, yaw"
    assert "8 Hz" in w8.message and "grows through the run" in w8.message and "frequency grid" in w8.message
    bridge = next(w for w in w5 if abs(w.frequency - 3.0) < 1e-9)
    assert bridge.channels == ("bridge.*",)
    assert [round(w.frequency, 6) for w in damping_warnings(t, band, RunTimes(10.0, 1.0, 4.0))] == [8.0]
    excited = np.array([False, True, False, True, True, True])
    assert [round(w.frequency, 6) for w in damping_warnings(t, band, RunTimes(5.0, 1.0, 4.0), excited=excited)] == [3.0]
    # fraction 0.1: decay times above 0.5 s warn, the 1 Hz body mode (0.8 s) too
    strict = damping_warnings(t, band, RunTimes(5.0, 1.0, 4.0), fraction=0.1)
    assert sorted(round(w.frequency, 6) for w in strict) == [1.0, 3.0, 8.0]


def test_merged_messages_and_nth_frequency():
    """Equal modes of identical cars become one line; nth_frequency counts within a type."""
    t = guard_system()
    ws = damping_warnings(t, (0.3, 60.0), RunTimes(5.0, 1.0, 4.0))
    assert len(merged_messages(ws + ws)) == 2
    assert merged_messages(ws + ws)[0].startswith("2 lightly damped modes")
    assert nth_frequency([5.0, 3.0, 4.0, 1.0], ["vertical", "lateral", "vertical", "vertical"], "vertical", 3) == 5.0
    assert math.isnan(nth_frequency([5.0], ["vertical"], "torsion"))
    assert t.bridge_frequency("vertical", 1) == pytest.approx(3.0, rel=1e-9)
    assert math.isnan(t.bridge_frequency("lateral", 1))


@pytest.mark.parametrize("zeta", [1e-4, 0.003, 0.02])
def test_envelope_growth_against_the_exact_covariance(zeta):
    """Exact problem: x'' + 2 zeta w x' + w^2 x = white noise, from rest at t = 0 (w = 2 pi 8 Hz,
    the ICE bogie yaw). Reference: the exact state covariance P(t) = int_0^t e^{A s} B B^T e^{A^T s} ds
    by Van Loan's block exponential (independent of the envelope), sigma(t) = sqrt(P_11(t)).
    envelope_growth gives sigma(t1) / sigma(t0) - 1 for t0 = 1.64 s, t1 = 4.75 s (li_zhu_2011's
    bridge entry and exit). Tolerance 1 % of the ratio (measured: 0.3 % at most): the envelope drops
    the terms oscillating at 2 omega_d, of relative size zeta and 1 / (omega t)."""
    from scipy.linalg import expm

    from tb_exudyn.system.damping_guard import envelope_growth

    w = 2 * math.pi * 8.0
    A = np.array([[0.0, 1.0], [-w * w, -2 * zeta * w]])
    Q = np.array([[0.0, 0.0], [0.0, 1.0]])

    def sigma(t):
        C = expm(np.block([[-A, Q], [np.zeros((2, 2)), A.T]]) * t)
        F22 = C[2:, 2:]
        G12 = C[:2, 2:]
        P = F22.T @ G12
        return math.sqrt(P[0, 0])

    t0, t1 = 1.64, 4.75
    exact = sigma(t1) / sigma(t0)
    tau = 1.0 / (zeta * w)
    assert 1.0 + envelope_growth(tau, t0, t1) == pytest.approx(exact, rel=0.01)
    assert envelope_growth(math.inf, t0, t1) == pytest.approx(math.sqrt(t1 / t0) - 1, rel=1e-12)


def test_a_round_off_input_entry_does_not_reach_an_independent_part():
    """Exact problem: two uncoupled oscillators (m 1, k 100 and m 2, k 900, light damping) and one
    input column pushing the first with 1e6 N and the second with 1e-12 N (what the left and right
    wheels' opposite creep inputs leave on a wheelset's spin: 1e-18 of the column). Reference: the
    second oscillator is its own independent part, which the column reaches only by round-off:
    its reach must be zero (entries below COUPLING_ZERO = 1e-14 of the column's largest are dropped,
    as in the matrices), the first's is 1 (the cosine of a column with the mode itself). A column
    with 1e-6 N on the second (1e-12 of the largest, above the threshold) reaches it. Exact."""
    M, K, D = diag_system([1.0, 2.0], [100.0, 900.0], [0.1, 0.2])
    dofs = [body("car 1 (x)", "body", "bounce", "car1.body"), body("car 1 (x)", "bogie1", "bounce", "car1.bogie1")]
    for f2, reached in ((1e-12, False), (1e-6, True)):
        t = mode_table(M, K, D, dofs, "two", {"vertical": np.array([[1e6], [f2]])})
        second = np.flatnonzero(np.abs(t.frequency - math.sqrt(450.0) / (2 * math.pi)) < 1e-6)
        assert second.size == 1 and bool(t.reached()[second[0]]) is reached
        first = 1 - second[0]
        assert t.reach[first, 0] == pytest.approx(1.0, rel=1e-9)
