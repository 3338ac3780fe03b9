"""Linear Kalker creep forces of a wheelset (tb_exudyn.system.creep) against independent references.

Every reference here is written in the test itself: Hertz's circle, a quadrature of the
half-space displacement under Hertz's pressure, kinematic creepages of a wheelset following the
rail, Klingel's kinematic wavelength, and Wickens' linear equations of a two-axle bogie written
out by hand.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from tb_exudyn.errors import SettingError
from tb_exudyn.system.creep import (
    CreepCoefficients,
    WheelsetContact,
    contact_modulus,
    creep_rows,
    hertz_creep_coefficients,
    hertz_ellipse,
    kalker_coefficients,
    rolling_roll_terms,
    wheel_rail_curvatures,
)

R0, B0, LAM = 0.46, 0.7465, 0.15  # rolling radius, half contact distance, conicity
W_AXLE = 140e3  # axle load [N]
E_STEEL, NU = 2.1e11, 0.3


def _coefficients() -> CreepCoefficients:
    return hertz_creep_coefficients(W_AXLE / 2, R0, rail_transverse_radius=0.3, E=E_STEEL, nu=NU)[0]


# ================================================================================ Hertz, Kalker
def test_hertz_circle_matches_the_closed_form():
    """Exact problem: equal relative curvatures A = B = 1/(2R) (a sphere of radius R on a plane).
    Reference: Hertz's closed form a = (3 P R / (4 E*))^(1/3), p0 = 3 P / (2 pi a^2) (Johnson 1985,
    sec. 4.2). Tolerance 1e-12 relative: the same formula, evaluated differently (round-off)."""
    P, R = 7e4, 0.3
    Es = contact_modulus(E_STEEL, NU)
    h = hertz_ellipse(P, 0.5 / R, 0.5 / R, Es)
    a = (3 * P * R / (4 * Es)) ** (1 / 3)
    assert h.a == pytest.approx(a, rel=1e-12) and h.b == pytest.approx(a, rel=1e-12)
    assert h.p0 == pytest.approx(3 * P / (2 * math.pi * a * a), rel=1e-12)
    # a nearly circular ellipse joins the circle continuously
    h2 = hertz_ellipse(P, 0.5 / R, 0.5 / R * (1 + 1e-6), Es)
    assert h2.a == pytest.approx(a, rel=1e-6) and h2.b == pytest.approx(a, rel=1e-6)


def _half_space_displacement(px: float, py: float, a: float, b: float, p0: float, Es: float, n: int = 160) -> float:
    """Normal surface displacement [m] (both bodies together, contact modulus E*) at (px, py) inside
    the ellipse under p = p0 sqrt(1 - x^2/a^2 - y^2/b^2): u = 1/(pi E*) int p / r dA (Boussinesq),
    in polar coordinates about the point (r dr dtheta / r = dr dtheta). The inner integral over
    rho in [0, R(theta)] (R: distance to the ellipse edge) with rho = R (1 - s^2), which removes
    the square-root edge singularity, then Gauss-Legendre in s and the trapezoidal rule in theta
    (periodic: spectrally accurate)."""
    theta = np.linspace(0.0, 2 * np.pi, 2 * n, endpoint=False)
    c, s = np.cos(theta), np.sin(theta)
    qa = (c / a) ** 2 + (s / b) ** 2  # |P + rho e|^2 in ellipse metric: qa rho^2 + 2 qb rho + qc
    qb = px * c / a**2 + py * s / b**2
    qc = px**2 / a**2 + py**2 / b**2 - 1.0
    R = (-qb + np.sqrt(qb * qb - qa * qc)) / qa
    sg, wg = np.polynomial.legendre.leggauss(n)
    sg, wg = 0.5 * (sg + 1.0), 0.5 * wg  # on [0, 1]
    rho = R[:, None] * (1.0 - sg[None, :] ** 2)
    pressure = p0 * np.sqrt(np.clip(-(qa[:, None] * rho**2 + 2 * qb[:, None] * rho + qc), 0.0, None))
    inner = np.sum(pressure * (2.0 * sg[None, :] * R[:, None]) * wg[None, :], axis=1)  # d rho = 2 s R ds
    return float(np.mean(inner) * 2 * np.pi / (np.pi * Es))


def test_hertz_ellipse_reproduces_the_surface_curvatures():
    """Exact problem: a wheel (r0 = 0.46 m, conical tread) on a rail of crown radius 0.3 m under
    70 kN: relative curvatures A = 1.087, B = 1.667 1/m. Reference: an independent quadrature of
    the half-space displacement under the ellipse's Hertz pressure (no elliptic integrals). In
    Hertz's solution the displacement inside the contact is delta - A x^2 - B y^2, so A and B are
    recovered from the displacement differences at points on the axes. Tolerance 1e-9 relative:
    the quadrature's accuracy (160 x 320 points; with half as many the recovered A changes by
    less than 1e-14)."""
    P = 7e4
    A, B = wheel_rail_curvatures(R0, 0.3)
    Es = contact_modulus(E_STEEL, NU)
    h = hertz_ellipse(P, A, B, Es)
    assert h.a > h.b  # the major axis lies along the rolling direction (the smaller curvature)
    u0 = _half_space_displacement(0.0, 0.0, h.a, h.b, h.p0, Es)
    for frac in (0.3, 0.7):
        ux = _half_space_displacement(frac * h.a, 0.0, h.a, h.b, h.p0, Es)
        uy = _half_space_displacement(0.0, frac * h.b, h.a, h.b, h.p0, Es)
        assert (u0 - ux) / (frac * h.a) ** 2 == pytest.approx(A, rel=1e-9)
        assert (u0 - uy) / (frac * h.b) ** 2 == pytest.approx(B, rel=1e-9)


def test_kalker_table_interpolation():
    """Exact problem: Kalker's coefficients at tabulated and between tabulated points.
    Reference: Kalker (1990) Table E.3 values (C11(a/b=0.5, nu=0.25) = 3.62, C22(b/a=0.5, nu=0.5) =
    5.56, C23(a/b=1, nu=0) = 1.33) returned exactly; between rows the value lies between its
    neighbours; a/b = 1 is the same from both halves of the table; outside the table: an error."""
    assert kalker_coefficients(0.25, 0.5).C11 == 3.62
    assert kalker_coefficients(0.5, 2.0).C22 == 5.56
    assert kalker_coefficients(0.0, 1.0).C23 == 1.33
    mid = kalker_coefficients(0.3, 0.55)
    lo, hi = kalker_coefficients(0.3, 0.5), kalker_coefficients(0.3, 0.6)
    for name in ("C11", "C22", "C23", "C33"):
        assert min(getattr(lo, name), getattr(hi, name)) < getattr(mid, name) < max(getattr(lo, name), getattr(hi, name))
    below, above = kalker_coefficients(0.28, 1.0 - 1e-12), kalker_coefficients(0.28, 1.0 + 1e-12)
    for name in ("C11", "C22", "C23", "C33"):
        assert getattr(below, name) == pytest.approx(getattr(above, name), rel=1e-9)
    with pytest.raises(SettingError, match="a_over_b"):
        kalker_coefficients(0.3, 12.0)


# ============================================================================ creepage signs
def test_following_the_rail_gives_no_creep_force():
    """Exact problem: the wheelset follows the rail exactly. (1) The rail line is straight with slope
    psi0 (a kink of the alignment): the wheelset runs along it, y = psi0 v t, yaw psi0. (2) The rail
    (the bridge) sways laterally, y_r(t) = Y sin(w t) at every x, and the wheelset moves with it.
    (3) The wheelset surges, x' = U, and its spin follows it rolling, ry' = U / r0. Reference:
    kinematics, rolling without slip: every creepage is zero, so every row force is zero (the
    gravitational terms too: no offset from the rail, no rail roll). Tolerance: round-off (1e-9 of
    the individual terms). Wheelset coordinates (y, rx, rz, x, ry)."""
    contact = WheelsetContact(_coefficients(), R0, B0, LAM, W_AXLE, spin=True)
    v, psi0, t = 60.0, 2e-3, 0.37
    rows = creep_rows(contact, v)
    y = psi0 * v * t
    f1 = rows.forces((y, 0.0, psi0, 0.0, 0.0), (psi0 * v, 0.0, 0.0, 0.0, 0.0), (y, 0.0, psi0), (0.0, 0.0, 0.0))
    Y, om = 3e-3, 9.0
    f2 = rows.forces((Y * np.sin(om * t), 0.0, 0.0, 0.0, 0.0), (Y * om * np.cos(om * t), 0.0, 0.0, 0.0, 0.0),
                     (Y * np.sin(om * t), 0.0, 0.0), (Y * om * np.cos(om * t), 0.0, 0.0))
    U = 0.05
    f3 = rows.forces((0.0, 0.0, 0.0, 1e-3, 2e-3), (0.0, 0.0, 0.0, U, U / R0))
    scale = 2 * contact.coefficients.f22 * psi0
    assert max(np.abs(f1).max(), np.abs(f2).max(), np.abs(f3).max()) <= 1e-9 * scale


def test_creep_force_directions():
    """Exact problem: three elementary states. (1) Yawed (leading end left, rz > 0), no lateral
    motion: the wheel's contact point slips to the right against the rail, so the rail pushes it to
    the left: force_y = +2 f22 rz. (2) Shifted left by e: the left wheel rolls on the larger radius
    and slips backwards, its creep force points forward (+f11 lambda e / r0), the right one's
    backward, and their yaw moment -2 b0 F_x,left turns the wheelset to the right (back to the
    centre); the gravitational stiffness pushes it back: force_y = -W epsilon e / b0. (3) Rail plane
    rolled by theta (left rail up): the normal load points down the slope, force_y = -W theta.
    (4) The axle moves forward at x' = U, the wheels do not spin faster (ry' = 0): both contact
    points slip forward by U, both creep forces point backward, -f11 U / v each; at the contact
    point r0 below the axle they turn the wheelset forward about +y (the way it rolls):
    Q_ry = -r0 (F_left + F_right) = +2 r0 f11 U / v, and they cancel in the yaw. Reference: these
    hand results. Tolerance: round-off (1e-12 relative)."""
    f = _coefficients()
    contact = WheelsetContact(f, R0, B0, LAM, W_AXLE)
    rows = creep_rows(contact, 50.0)
    i = {name: k for k, name in enumerate(rows.rows)}
    psi, e, th = 1e-3, 2e-3, 1e-3
    zero = np.zeros(5)
    f1 = rows.forces((0.0, 0.0, psi, 0.0, 0.0), zero)
    assert f1[i["force_y"]] == pytest.approx(2 * f.f22 * psi, rel=1e-12)
    f2 = rows.forces((e, 0.0, 0.0, 0.0, 0.0), zero)
    assert f2[i["left.force_x"]] == pytest.approx(f.f11 * LAM * e / R0, rel=1e-12)
    assert f2[i["right.force_x"]] == pytest.approx(-f.f11 * LAM * e / R0, rel=1e-12)
    assert f2[i["force_y"]] == pytest.approx(-W_AXLE * LAM / B0 * e, rel=1e-12)
    Qw = rows.A_w.T @ f2  # generalised forces on (y, rx, rz, x, ry)
    assert Qw[2] == pytest.approx(-2 * B0 * f.f11 * LAM * e / R0, rel=1e-12) and Qw[2] < 0
    f3 = rows.forces(zero, zero, (0.0, th, 0.0))
    assert f3[i["force_y"]] == pytest.approx(-W_AXLE * th, rel=1e-12)
    U = 0.05
    f4 = rows.forces(zero, (0.0, 0.0, 0.0, U, 0.0))
    assert f4[i["left.force_x"]] == pytest.approx(-f.f11 * U / 50.0, rel=1e-12)
    assert f4[i["right.force_x"]] == pytest.approx(-f.f11 * U / 50.0, rel=1e-12)
    assert f4[i["force_y"]] == 0.0 and f4[i["moment_z"]] == 0.0
    Q4 = rows.A_w.T @ f4
    assert Q4[3] == pytest.approx(-2 * f.f11 * U / 50.0, rel=1e-12)
    assert Q4[4] == pytest.approx(2 * R0 * f.f11 * U / 50.0, rel=1e-12)
    assert abs(Q4[2]) <= 1e-12 * abs(Q4[3])


# ================================================================================== Klingel
def _eigenvalues(M: np.ndarray, K: np.ndarray, C: np.ndarray) -> np.ndarray:
    """Eigenvalues of M q'' + C q' + K q = 0 (first-order form; K and C need not be symmetric)."""
    n = M.shape[0]
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-np.linalg.solve(M, K), -np.linalg.solve(M, C)]])
    return np.linalg.eigvals(A)


def _least_oscillatory_pair(M: np.ndarray, K: np.ndarray, C: np.ndarray) -> complex:
    """The oscillatory eigenvalue (Im > 0) of M q'' + C q' + K q = 0 with the smallest modulus."""
    ev = _eigenvalues(M, K, C)
    ev = ev[ev.imag > 1e-9]
    return complex(ev[np.argmin(np.abs(ev))])


def test_klingel_wavelength_of_a_free_wheelset():
    """Exact problem: one unsuspended wheelset (mass 1800 kg, yaw inertia 1000 kg m^2; lateral y and
    yaw rz, roll held) on rigid straight track at 50 m/s, conicity 0.15, r0 = 0.46 m, b0 = 0.7465 m,
    the creep coefficients of a 70 kN wheel load scaled by s = 1 ... 1e4 (gravitational stiffness
    kept). Reference: Klingel's kinematic wavelength 2 pi sqrt(r0 b0 / lambda) = 9.5067 m, the
    limit of rolling without slip (y' = v psi, psi' = -v lambda y / (r0 b0)), which the creep model
    must approach as the creep forces grow. Tolerance: 0.5 % (the acceptance) from s = 10 on, and
    the error must fall as a power of s: the fitted rate over s = 10 ... 1e4 is 2 (the inertia
    terms, relative to creep, enter squared) within 0.05."""
    m, inertia, v = 1800.0, 1000.0, 50.0
    L_k = 2 * math.pi * math.sqrt(R0 * B0 / LAM)
    f = _coefficients()
    scales = np.array([1.0, 10.0, 100.0, 1e3, 1e4])
    errors = []
    for s in scales:
        rows = creep_rows(WheelsetContact(f.scaled(s), R0, B0, LAM, W_AXLE), v)
        keep = [0, 2]  # y, rz
        lam = _least_oscillatory_pair(np.diag([m, inertia]), rows.stiffness[np.ix_(keep, keep)],
                                      rows.damping[np.ix_(keep, keep)])
        errors.append(abs(2 * math.pi * v / lam.imag / L_k - 1.0))
    errors = np.array(errors)
    assert np.all(errors[1:] < 5e-3)
    assert np.all(np.diff(errors) < 0)
    rate = -np.polyfit(np.log(scales[1:]), np.log(errors[1:]), 1)[0]
    assert rate == pytest.approx(2.0, abs=0.05)


HALF_GAUGE = 0.75  # lever of the vertical contact rows (the rail centres)


def _rolling_wheelset(m: float, roll_inertia: float, yaw_inertia: float, k: float, rows) -> tuple[np.ndarray, ...]:  # noqa: ANN001
    """A free wheelset with coordinates (y, z, rx, rz) on two vertical contact springs k at +-HALF_GAUGE
    whose argument is the row of :func:`rolling_roll_terms` (z + s b rx + wheel_y y + wheel_rx rx),
    damped as the builder's (2 * 0.5 sqrt(k m / 2)), plus the creep rows' lateral-plane matrices on
    (y, rx, rz)."""
    contact = WheelsetContact(_coefficients(), R0, B0, LAM, W_AXLE)
    K, C = np.zeros((4, 4)), np.zeros((4, 4))
    c = 2 * 0.5 * math.sqrt(k * m / 2)
    for side in (1.0, -1.0):
        t = rolling_roll_terms(contact, side, HALF_GAUGE)
        h = np.array([t.wheel_y, 1.0, side * HALF_GAUGE + t.wheel_rx, 0.0])
        K += k * np.outer(h, h)
        C += c * np.outer(h, h)
    lat = [0, 2, 3]  # y, rx, rz of the creep rows' (y, rx, rz, x, ry)
    K[np.ix_(lat, lat)] += rows.stiffness[:3, :3]
    C[np.ix_(lat, lat)] += rows.damping[:3, :3]
    return np.diag([m, m, roll_inertia, yaw_inertia]), K, C


def test_rolling_roll_terms_hold_the_roll_of_coned_wheels():
    """Exact problem: the two vertical contact springs of one wheelset (k = 2e9 N/m at +-0.75 m, the
    rows of rolling_roll_terms, conicity 0.15, r0 = 0.46 m, b0 = 0.7465 m), the wheelset displaced
    laterally by y = 1 mm; z and rx where the springs' energy is least. Reference: a wheelset whose
    wheels stay on knife-edge rails rolls by (r_left - r_right) / (2 b0) = lambda e / b0 with e =
    y + r0 rx its contact point's lateral displacement (the left wheel rolls on r0 + lambda e, the
    right on r0 - lambda e), so rx = lambda y / (b0 - lambda r0) and z = 0. Tolerance 1e-12
    (round-off: the minimum is exact). And the rows' rail part: a rail moved with the wheelset
    (y_r = y, e = 0) leaves the wheelset level."""
    contact = WheelsetContact(_coefficients(), R0, B0, LAM, W_AXLE)
    y = 1e-3
    A, rhs = np.zeros((2, 2)), np.zeros(2)
    for side in (1.0, -1.0):
        t = rolling_roll_terms(contact, side, HALF_GAUGE)
        h = np.array([1.0, side * HALF_GAUGE + t.wheel_rx])  # on (z, rx)
        A += np.outer(h, h)
        rhs -= h * t.wheel_y * y
        assert t.rail_y == t.wheel_y  # the rail's lateral motion enters e with the opposite sign of y
    z, rx = np.linalg.solve(A, rhs)
    assert z == pytest.approx(0.0, abs=1e-15)
    assert rx == pytest.approx(LAM * y / (B0 - LAM * R0), rel=1e-12)
    assert rx == pytest.approx(LAM * (y + R0 * rx) / B0, rel=1e-12)
    for side in (1.0, -1.0):  # rail and wheelset moved together: the gap terms cancel at rx = 0
        t = rolling_roll_terms(contact, side, HALF_GAUGE)
        assert t.wheel_y * y - t.rail_y * y == 0.0
    with pytest.raises(SettingError, match="side"):
        rolling_roll_terms(contact, 0.5, HALF_GAUGE)


def test_klingel_wavelength_of_a_free_rolling_wheelset():
    """Exact problem: the free wheelset of test_klingel_wavelength_of_a_free_wheelset (1800 kg, yaw
    inertia 1000 kg m^2, 50 m/s, conicity 0.15) now with its roll and bounce on stiff vertical
    contacts (2e9 N/m, the rows of rolling_roll_terms: the wheelset rolls by lambda e / b0; roll
    inertia 1000 kg m^2), creep coefficients scaled by s = 10 ... 1e4. Reference: Klingel's
    wavelength 2 pi sqrt(r0 b0 / lambda) = 9.5067 m: rolling without slip, e' = v psi (the contact
    point's lateral creepage zero, e = y + r0 rx) and psi' = -v lambda e / (r0 b0), so the roll
    does not change the kinematic wavelength ("Klingel unchanged", issue 29). Tolerance: 0.5 % from
    s = 10 on (the acceptance of the level wheelset's test), falling with s (measured 3.2e-4,
    3.2e-6, 3.2e-8, 3.3e-10 against the level wheelset's 3.8e-4, ..., 3.8e-10: the inertia terms
    differ, the limit does not), and within 1e-8 at s = 1e4."""
    m, inertia, v = 1800.0, 1000.0, 50.0
    L_k = 2 * math.pi * math.sqrt(R0 * B0 / LAM)
    errors = []
    for s in (10.0, 100.0, 1e3, 1e4):
        rows = creep_rows(WheelsetContact(_coefficients().scaled(s), R0, B0, LAM, W_AXLE), v)
        lam = _least_oscillatory_pair(*_rolling_wheelset(m, 1000.0, inertia, 2e9, rows))
        errors.append(abs(2 * math.pi * v / lam.imag / L_k - 1.0))
    errors = np.array(errors)
    assert np.all(errors < 5e-3) and np.all(np.diff(errors) < 0)
    assert errors[-1] < 1e-8


# ===================================================================== bogie critical speed
# A two-axle bogie: wheelsets 1 (leading, x = +a) and 2 (x = -a), frame at x = 0 held to a fixed
# car body by the secondary springs. Lateral y and yaw psi of every body (wheelset roll held).
BOGIE = dict(m=1800.0, I=1000.0, mb=2500.0, Ib=2000.0, a=1.25, d=1.0, kx=5e6, ky=5e6, ksx=2.5e5, ksy=2e5, bs=1.0)


def _wickens_bogie(v: float, f11: float, f22: float, kgy: float, p: dict = BOGIE) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Wickens' linear bogie equations written out by hand (coordinates y1, psi1, y2, psi2, yb, psib;
    primary per axle box kx (longitudinal) at +/-d and ky (lateral); secondary per side ksx at +/-bs
    and ksy; the classical linear bogie model of Wickens' theory):

        m y_i'' + 2 f22/v y_i' + (2 ky + K_gy) y_i - 2 f22 psi_i - 2 ky (yb + x_i psib) = 0
        I psi_i'' + 2 f11 b0^2/v psi_i' + 2 f11 b0 lambda / r0 y_i + 2 kx d^2 (psi_i - psib) = 0
        mb yb'' + (4 ky + 2 ksy) yb - 2 ky (y1 + y2) = 0
        Ib psib'' + (4 ky a^2 + 4 kx d^2 + 2 ksx bs^2) psib - 2 ky a (y1 - y2) - 2 kx d^2 (psi1 + psi2) = 0
    """
    M = np.diag([p["m"], p["I"], p["m"], p["I"], p["mb"], p["Ib"]])
    K, C = np.zeros((6, 6)), np.zeros((6, 6))
    kx, ky, d, a = p["kx"], p["ky"], p["d"], p["a"]
    for i, xi in ((0, a), (1, -a)):
        y, s = 2 * i, 2 * i + 1
        K[y, y] += 2 * ky + kgy
        K[y, s] += -2 * f22
        K[y, 4] += -2 * ky
        K[y, 5] += -2 * ky * xi
        C[y, y] += 2 * f22 / v
        K[s, y] += 2 * f11 * B0 * LAM / R0
        K[s, s] += 2 * kx * d * d
        K[s, 5] += -2 * kx * d * d
        C[s, s] += 2 * f11 * B0 * B0 / v
    K[4, 0] = K[4, 2] = -2 * ky
    K[5, 0], K[5, 2] = -2 * ky * a, 2 * ky * a
    K[5, 1] = K[5, 3] = -2 * kx * d * d
    K[4, 4] = 4 * ky + 2 * p["ksy"]
    K[5, 5] = 4 * ky * a * a + 4 * kx * d * d + 2 * p["ksx"] * p["bs"] ** 2
    return M, K, C


def _assembled_bogie(v: float, contact: WheelsetContact, p: dict = BOGIE) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The same bogie assembled from point springs at their positions (each body's point (px, py)
    moves by (-py psi, y + px psi)) and the creep module's wheelset matrices (y and rz columns)."""
    bodies = {"w1": 0, "w2": 2, "frame": 4}  # first coordinate (y, psi) of each body; None: the car body
    n = 6
    K, C = np.zeros((n, n)), np.zeros((n, n))

    def point_map(body: str | None, px: float, py: float) -> np.ndarray:
        T = np.zeros((2, n))  # rows: x and y displacement of the point
        if body is not None:
            j = bodies[body]
            T[0, j + 1] = -py
            T[1, j], T[1, j + 1] = 1.0, px
        return T

    def spring(b1: str, p1: tuple[float, float], b2: str | None, p2: tuple[float, float], kx: float, ky: float) -> None:
        T = point_map(b1, *p1) - point_map(b2, *p2)
        K[:] += T.T @ np.diag([kx, ky]) @ T

    for w, xw in (("w1", p["a"]), ("w2", -p["a"])):
        for side in (1.0, -1.0):
            spring(w, (0.0, side * p["d"]), "frame", (xw, side * p["d"]), p["kx"], p["ky"])
    for side in (1.0, -1.0):
        spring("frame", (0.0, side * p["bs"]), None, (0.0, side * p["bs"]), p["ksx"], p["ksy"])
    rows = creep_rows(contact, v)
    keep = [0, 2]  # the module's (y, rx, rz, x, ry): y and rz (roll held; x and spin not in this model)
    for w in ("w1", "w2"):
        j = bodies[w]
        K[j:j + 2, j:j + 2] += rows.stiffness[np.ix_(keep, keep)]
        C[j:j + 2, j:j + 2] += rows.damping[np.ix_(keep, keep)]
    M = np.diag([p["m"], p["I"], p["m"], p["I"], p["mb"], p["Ib"]])
    return M, K, C


def _critical_speed(system, lo: float, hi: float) -> float:  # noqa: ANN001
    """Bisection on v for the sign change of the largest real part (to 1e-9 relative)."""
    grow = lambda v: _eigenvalues(*system(v)).real.max()  # noqa: E731
    assert grow(lo) < 0 < grow(hi)
    while hi - lo > 1e-9 * hi:
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if grow(mid) < 0 else (lo, mid)
    return 0.5 * (lo + hi)


def test_bogie_critical_speed_against_wickens_equations():
    """Exact problem: the two-axle bogie of BOGIE (primary kx = ky = 5 MN/m per axle box, frame on
    secondary springs to a fixed body), 70 kN wheel loads (Hertz/Kalker creep coefficients, conicity
    0.15, gravitational stiffness W lambda / b0). Reference: the linear critical speed (the largest
    real part of the eigenvalues crossing zero) of Wickens' equations written out by hand above.
    The creep module's matrices assembled with the point-spring suspension must give the same
    critical speed: the two are the same linear model, so within the bisection tolerance (1e-9),
    asserted to 1e-7 (far inside the acceptance of 1 %). Below it (0.98 v_c) every mode is damped,
    above it (1.02 v_c) exactly one mode (a complex pair) is unstable."""
    f = _coefficients()
    contact = WheelsetContact(f, R0, B0, LAM, W_AXLE)
    kgy = contact.gravitational_stiffness
    vc_ref = _critical_speed(lambda v: _wickens_bogie(v, f.f11, f.f22, kgy), 5.0, 500.0)
    vc = _critical_speed(lambda v: _assembled_bogie(v, contact), 5.0, 500.0)
    assert vc == pytest.approx(vc_ref, rel=1e-7)
    assert 20.0 < vc < 300.0  # a meaningful crossing, not a bracket end
    below = _eigenvalues(*_assembled_bogie(0.98 * vc, contact))
    above = _eigenvalues(*_assembled_bogie(1.02 * vc, contact))
    assert below.real.max() < 0
    unstable = above[above.real > 0]
    assert unstable.size == 2 and abs(unstable[0].imag) > 0 and unstable[0] == pytest.approx(np.conj(unstable[1]))


def test_rigid_bogie_kinematic_wavelength():
    """Exact problem: the same bogie with a rigid primary suspension (kx = ky = 1e13 N/m) and large,
    equal creep coefficients (f11 = f22 = 1e10 N, primary 1000 times stiffer), assembled from the
    module. Reference: the
    kinematic wavelength of a rigid two-axle bogie with f11 = f22, 2 pi sqrt((r0 b0 / lambda)
    (1 + a^2 / b0^2)) (Wickens, Fundamentals of Rail Vehicle Dynamics, 2003; derivation: without
    inertia the lateral creep forces of the two wheelsets balance, y' = v psi, and the yaw moment
    of their lateral creep forces about the bogie centre adds f22 a^2 to f11 b0^2 in the yaw
    balance, psi' (f11 b0^2 + f22 a^2) / v = -f11 b0 lambda y / r0). Tolerance 1e-5: what the finite creep and primary stiffness,
    the gravitational and the secondary stiffness leave (measured 3.2e-7; with a primary only 10
    times stiffer than the creep it would be 2.4e-3)."""
    rigid = {**BOGIE, "kx": 1e13, "ky": 1e13}
    contact = WheelsetContact(CreepCoefficients(1e10, 1e10), R0, B0, LAM, W_AXLE)
    v = 40.0
    kin = _least_oscillatory_pair(*_assembled_bogie(v, contact, rigid))
    L = 2 * math.pi * v / kin.imag
    L_ref = 2 * math.pi * math.sqrt(R0 * B0 / LAM * (1 + BOGIE["a"] ** 2 / B0**2))
    assert L == pytest.approx(L_ref, rel=1e-5)
