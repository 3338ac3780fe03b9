"""The creep_car vehicle kind as built (tb_exudyn.builder.vehicles.add_creep_car): its modes against
an independent model written here, its wheelsets' longitudinal/spin mode against a closed form, its
channels, and the acceptance of issue 19 on rigid track (every mode in the analysed band damped above
1 % on the reference study's train)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import linear_sum_assignment

pytest.importorskip("exudyn")

import tb_exudyn as tbx  # noqa: E402
from tb_exudyn.builder import build_model  # noqa: E402
from tb_exudyn.builder.system_modes import analysed_band, damping_guard, system_modes  # noqa: E402
from tb_exudyn.builder.vehicles import WEAK_SPRING_DAMPING_RATIO, WEAK_SPRING_FREQUENCY  # noqa: E402
from tb_exudyn.scenario import Train, load_vehicle  # noqa: E402
from tb_exudyn.system.coupling import VERTICAL  # noqa: E402
from tb_exudyn.system.creep import hertz_creep_coefficients  # noqa: E402

from eigen_reference import reference_eigenvalues  # noqa: E402  (tests/builder, on pytest's path)
from test_builder_system_modes import CONTACT_ZETA, HALF_GAUGE, car_scenario, closed_form_bridge  # noqa: E402

pytestmark = pytest.mark.exudyn

SPEED_KMH = 220.0


def creep_scenario(car, speed_kmh: float = SPEED_KMH):  # noqa: ANN001
    return car_scenario(car).replace(speed_kmh=speed_kmh)


# --------------------------------------------------------------------------------------------
# the independent model


def reference_creep_car(car, v: float, g: float, k_contact: float, roll: bool = True) -> tuple[np.ndarray, np.ndarray, np.ndarray]:  # noqa: ANN001
    """M, K, D of a creep car on rigid track at speed v, written independently of the builder.

    Coordinates: body, bogie 1, bogie 2, wheelsets 1-4, each (x, y, z, rx, ry, rz) about its centre
    of gravity. A point at p from the CG moves by dx = x - rz py + ry pz, dy = y + rz px - rx pz,
    dz = z + rx py - ry px (small rotations). Springs and dampers per side act between the end
    points in x, y and z: secondary at (x_bogie, +-b_s, secondary height), primary at (x_axle,
    +-b_p, wheelset-centre height), yaw dampers in x at the CG heights at +-d. Weak springs (the
    builder's documented 0.1 Hz, critically damped) hold the body's and bogies' x and each
    wheelset's spin (inertia ``wheelset.inertia_spin``). Each wheel on a vertical contact spring at
    +-half gauge b with c = 2 zeta sqrt(k m / 2), on the height of the wheel's lowest point over its
    rail (``roll``: coned wheels): the left wheel rolls on r0 + lambda e (the right on
    r0 - lambda e), so with the wheelset rolled by rx its lowest point over the left rail is at
    z + b rx - lambda e b / b0 (the axle rises by lambda e at the contact point, b0 from the centre;
    at the rail centre b that is lambda e b / b0), the right one's at z - b rx + lambda e b / b0;
    the spring acts on that height (virtual work: its force also pushes the wheelset laterally by
    -/+ lambda (b / b0) N, the lateral components of the normal forces). Without ``roll``: z +- b rx
    (the wheelset held level). Creep forces  (Wickens' linear wheelset, rail fixed): with e = y + r0 rx
    the contact point's lateral offset, lateral creepage (y' + r0 rx') / v - rz, longitudinal
    creepage of the left wheel -(lambda e / r0 + b0 rz' / v) (the right one opposite),
    F_y = -2 f22 xi_y - (W eps / b0) e acting at rail level (Q_y = F_y, Q_rx = r0 F_y),
    F_x,left = -f11 xi_x,left = -F_x,right, yaw moment -2 b0 F_x,left; and the common longitudinal
    creepage (x' - r0 ry') / v of both wheels (the contact point r0 below the axle of a wheel
    spinning at v / r0 + ry'), its force -2 f11 (x' - r0 ry') / v on x and, at the contact point,
    r0 times its negative on the spin ry. Creep coefficients
    f11, f22 of Hertz and Kalker at the static wheel load W / 2 (tb_exudyn.system.creep, tested
    in tests/system/test_creep.py)."""
    gm = car.geometry
    s, a, r0 = gm.half_bogie_spacing, gm.half_wheelbase, gm.wheel_radius
    z_w = r0
    z_t = z_w + gm.bogie_cg_above_axle
    z_s = z_t + gm.secondary_above_bogie_cg
    z_c = z_s + gm.body_cg_above_secondary
    n = 42
    K, D = np.zeros((n, n)), np.zeros((n, n))

    def rows(body: int | None, p) -> tuple[np.ndarray, np.ndarray, np.ndarray]:  # noqa: ANN001
        ex, ey, ez = np.zeros(n), np.zeros(n), np.zeros(n)
        if body is None:
            return ex, ey, ez
        o = 6 * body
        px, py, pz = p
        ex[o], ex[o + 5], ex[o + 4] = 1.0, -py, pz
        ey[o + 1], ey[o + 5], ey[o + 3] = 1.0, px, -pz
        ez[o + 2], ez[o + 3], ez[o + 4] = 1.0, py, -px
        return ex, ey, ez

    def element(b0, p0, b1, p1, k=(0.0, 0.0, 0.0), c=(0.0, 0.0, 0.0)) -> None:  # noqa: ANN001
        for e0, e1, kk, cc in zip(rows(b0, p0), rows(b1, p1), k, c):
            d = e1 - e0
            K[:, :] += kk * np.outer(d, d)
            D[:, :] += cc * np.outer(d, d)

    sec, pri = car.secondary, car.primary
    for i, xb in enumerate((s, -s)):
        bogie = 1 + i
        for side in (1.0, -1.0):
            bs = side * gm.half_secondary_span
            element(0, (xb, bs, z_s - z_c), bogie, (0.0, bs, z_s - z_t), (sec.k_x, sec.k_y, sec.k_z),
                    (sec.c_x, sec.c_y, sec.c_z))
            if car.yaw_damper is not None:
                d = side * car.yaw_damper.half_span
                element(0, (xb, d, 0.0), bogie, (0.0, d, 0.0), c=(car.yaw_damper.c_x, 0.0, 0.0))
            for j, xa in enumerate((a, -a)):
                ws = 3 + 2 * i + j
                bp = side * gm.half_primary_span
                element(ws, (0.0, bp, 0.0), bogie, (xa, bp, z_w - z_t), (pri.k_x, pri.k_y, pri.k_z),
                        (pri.c_x, pri.c_y, pri.c_z))
    ws_ = car.wheelset
    masses = [car.body, car.bogie, car.bogie]
    m = [v_ for b in masses for v_ in (b.mass, b.mass, b.mass, b.inertia_roll, b.inertia_pitch, b.inertia_yaw)]
    m += 4 * [ws_.mass, ws_.mass, ws_.mass, ws_.inertia_roll, ws_.inertia_spin, ws_.inertia_yaw]
    om, zeta_w = 2 * math.pi * WEAK_SPRING_FREQUENCY, WEAK_SPRING_DAMPING_RATIO
    for i in [0, 6, 12] + [6 * w + 4 for w in range(3, 7)]:  # body and bogie x, wheelset spin
        K[i, i] += m[i] * om**2
        D[i, i] += 2 * zeta_w * m[i] * om
    W = g * (car.body.mass / 4 + car.bogie.mass / 2 + ws_.mass)
    cc = car.contact
    f = hertz_creep_coefficients(W / 2, r0, cc.creep.rail_transverse_radius, cc.creep.wheel_transverse_radius,
                                 E=cc.creep.youngs_modulus, nu=cc.creep.poisson_ratio)[0].scaled(cc.creep.factor)
    b0, lam = cc.half_contact_distance, cc.conicity
    k_gy = W * cc.contact_angle_parameter / b0
    cz = 2 * CONTACT_ZETA * math.sqrt(k_contact * ws_.mass / 2)
    for w in range(3, 7):
        o = 6 * w
        y, rx, rz = o + 1, o + 3, o + 5
        for side in (1.0, -1.0):
            height = np.zeros(n)  # the wheel's lowest point over its rail
            height[o + 2], height[rx] = 1.0, side * HALF_GAUGE
            if roll:
                rise = lam * HALF_GAUGE / b0  # of the wheel's point at the rail centre per unit of e
                height[y] -= side * rise
                height[rx] -= side * rise * r0
            K[:, :] += k_contact * np.outer(height, height)
            D[:, :] += cz * np.outer(height, height)
        e = np.zeros(n)
        e[y], e[rx] = 1.0, r0  # the contact point's lateral offset
        # F_y = -2 f22 ((e')/v - rz) - k_gy e, on y and r0 rx;  M_z = -2 b0 f11 (lam e / r0 + b0 rz'/v)
        Fy_q = -k_gy * e
        Fy_q[rz] += 2 * f.f22
        Fy_v = -2 * f.f22 / v * e
        Mz_q = -2 * b0 * f.f11 * lam / r0 * e
        Mz_v = np.zeros(n)
        Mz_v[rz] = -2 * f.f11 * b0 * b0 / v
        for row, lever in ((y, 1.0), (rx, r0)):
            K[row] -= lever * Fy_q
            D[row] -= lever * Fy_v
        K[rz] -= Mz_q
        D[rz] -= Mz_v
        slip = np.zeros(n)  # the common longitudinal slip velocity x' - r0 ry' at the contacts
        slip[o], slip[o + 4] = 1.0, -r0
        D += 2 * f.f11 / v * np.outer(slip, slip)
    return np.diag(m), K, D


def rigid_contact_projection(car) -> np.ndarray:  # noqa: ANN001
    """T (42 x 34): the coordinates of :func:`reference_creep_car` as functions of the ones left when
    every wheel stays on its rail (rigid vertical contact, coned wheels): each wheelset's z = 0 and
    its roll rx = lambda e / b0 with e = y + r0 rx, i.e. rx = lambda y / (b0 - lambda r0) (the
    rolling-radius difference 2 lambda e over the contact distance 2 b0). The constraint forces
    (the normal forces at the inclined contacts, their lateral components included) are what the
    projection M_r = T^T M T, K_r = T^T K T, D_r = T^T D T removes by virtual work."""
    b0, lam, r0 = car.contact.half_contact_distance, car.contact.conicity, car.geometry.wheel_radius
    keep = [i for i in range(42) if not (i >= 18 and i % 6 in (2, 3))]
    T = np.zeros((42, len(keep)))
    for j, i in enumerate(keep):
        T[i, j] = 1.0
        if i >= 18 and i % 6 == 1:  # a wheelset's y also rolls it
            T[i + 2, j] = lam / (b0 - lam * r0)
    return T


def _hunting_growth(lam: np.ndarray) -> float:
    """Largest real part [1/s] of the oscillating eigenvalues above 0.2 Hz (the weak springs' real
    roots and the surge, 0.1 Hz, left out: they are stable at every speed)."""
    lam = lam[np.abs(lam.imag) > 2 * math.pi * 0.2]
    return float(lam.real.max())


def _critical_speed(growth, lo: float, hi: float, tol: float) -> float:  # noqa: ANN001
    """Bisection [km/h] on the sign change of ``growth(speed_kmh)`` between lo (stable) and hi."""
    assert growth(lo) < 0.0 < growth(hi)
    while hi - lo > tol:
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if growth(mid) < 0.0 else (lo, mid)
    return 0.5 * (lo + hi)


#: linear critical speeds [km/h] of the ICE creep cars with rolling wheelsets (yaw dampers on,
#: conicity 0.15) from the independent check reported in issue 29
ISSUE_29_CRITICAL_KMH = {"ice_motor_creep": 322.0, "ice_trailer_creep": 339.0}


@pytest.mark.parametrize("name", ["ice_motor_creep", "ice_trailer_creep"])
def test_rolling_wheelset_critical_speed_against_a_rigid_contact_model(name):
    """Exact problem: the shipped ICE creep car (yaw dampers on, conicity 0.15) alone on rigid
    track; its linear critical speed, the lowest speed at which an oscillating mode above 0.2 Hz
    has a positive real part (bisection between 200 and 500 km/h). Built: the builder's model
    (stiff vertical penalty contacts, 2e9 N/m, with the rolling-radius terms), bisection to
    0.1 km/h. Reference: the independent model above without its contact springs, the wheels held
    on the rails by the constraint of :func:`rigid_contact_projection` (rx = lambda e / b0, z = 0;
    the constraint forces by virtual work), bisection to 0.01 km/h. Tolerance 2 % (the acceptance
    of issue 29: the reference differs in the contact's compliance and its damping, which the
    builder needs, and the independent check of issue 29 gave 322 / 339 km/h, rounded); measured
    0.03 % (motor 321.77 against 321.85 km/h) and below 0.01 % (trailer 338.76 against 338.76 km/h).
    The reference itself lies within 2 % of issue 29's numbers (measured 0.05 and 0.07 %), and the
    same reference with the wheelsets held level (rx = 0, the model before this change: 287.16 /
    293.71 km/h) does not (11 and 13 % lower): the roll is what moves the critical speed."""
    car = load_vehicle(name)
    g = creep_scenario(car).analysis.gravity
    T = rigid_contact_projection(car)

    def reference(kmh: float, level: bool = False) -> float:
        M, K, D = reference_creep_car(car, kmh / 3.6, g, 0.0)
        P = T.copy()
        if level:
            P[[6 * w + 3 for w in range(3, 7)]] = 0.0  # the wheelsets' rx = 0
        return _hunting_growth(reference_eigenvalues(P.T @ M @ P, P.T @ K @ P, P.T @ D @ P))

    def built(kmh: float) -> float:
        sc = creep_scenario(car, kmh)
        table = system_modes(sc, model=build_model(sc, modal_bridge=closed_form_bridge(sc), warn=False))
        return _hunting_growth(table.select([k != "bridge" for k in table.kind]).eigenvalues)

    v_ref = _critical_speed(reference, 200.0, 500.0, 0.01)
    v_built = _critical_speed(built, 200.0, 500.0, 0.1)
    assert v_built == pytest.approx(v_ref, rel=0.02)
    issue = ISSUE_29_CRITICAL_KMH[name]
    assert v_ref == pytest.approx(issue, rel=0.02)
    v_level = _critical_speed(lambda kmh: reference(kmh, level=True), 200.0, 500.0, 0.01)
    assert v_level < 0.95 * issue


# --------------------------------------------------------------------------------------------
# tests


@pytest.mark.parametrize("name", ["ice_motor_creep", "ice_trailer_creep"])
def test_creep_car_modes_match_an_independent_model(name):
    """Exact problem: the shipped ICE creep cars (with their yaw dampers) on rigid track at
    220 km/h, every coordinate (body and bogies x y z rx ry rz, wheelsets x y z rx ry rz), contact
    stiffness 2e9 N/m. Reference: the independent 42-coordinate numpy model above (numpy's
    eigenvalues of the companion matrix). The frequencies must agree to 1e-9 relative and the
    damping ratios to 1e-9 absolute: both describe the same linear equations; what differs is
    Exudyn's numerical Jacobian in ComputeLinearizedSystem (measured, frequencies: 2.3e-10 motor
    car, 3.0e-10 trailer, both at the wheelsets' slow spin roots, at most 1.3e-10 elsewhere;
    damping ratios 1.9e-11 and 5.6e-12; with the wheelsets held level, before the rolling-radius
    terms, 3.4e-11; car15's Cartesian x-free springs leave 1e-7, its test allows 1e-6). Every
    eigenvalue is compared, the wheelsets' slow spin roots too (about -7e-4 1/s: the weak spring
    against the creep damping on the spin). The reference without the rolling-radius terms
    (``roll=False``) misses the built model by 27 % (motor) and 30 % (trailer) in some root."""
    car = load_vehicle(name)
    sc = creep_scenario(car)
    model = build_model(sc, modal_bridge=closed_form_bridge(sc), warn=False)
    table = system_modes(sc, model=model)
    car_modes = table.select([k != "bridge" for k in table.kind])
    ref = reference_eigenvalues(*reference_creep_car(car, sc.speed, sc.analysis.gravity, 2e9))
    got = car_modes.eigenvalues
    assert got.size == ref.size, (got.size, ref.size)
    cost = np.abs(ref[:, None] - got[None, :]) / np.abs(ref)[:, None]
    i, j = linear_sum_assignment(cost)
    lam = np.empty_like(ref)
    lam[i] = got[j]
    assert np.allclose(np.abs(lam), np.abs(ref), rtol=1e-9, atol=0.0), np.abs(np.abs(lam) / np.abs(ref) - 1).max()
    z, z_ref = -lam.real / np.abs(lam), -ref.real / np.abs(ref)
    assert np.abs(z - z_ref).max() < 1e-9
    # the creep makes the stiffness non-symmetric: the lateral creep force 2 f22 rz on y (2.8e7 N/rad)
    # has no counterpart on the yaw
    M, K, D = model.linearized_system(0.0)
    assert np.abs(K - K.T).max() > 1e7


def test_creep_car_rows_and_channels():
    """Exact problem: one ICE motor creep car. Reference: the builder's documented layout: per
    wheelset two vertical penalty rows and no lateral one, four creep rows (force_y,
    left/right.force_x, moment_z) as general rows; channels y, z, rx, rz of each wheelset and the
    creep forces with their units (moment in N m). Exact."""
    sc = creep_scenario(load_vehicle("ice_motor_creep"))
    model = build_model(sc, modal_bridge=closed_form_bridge(sc), warn=False)
    contacts = model.coupling.contacts
    assert contacts.n_contacts == 8 and np.all(contacts.direction == VERTICAL)
    assert contacts.n_linear == 16
    units = {c.name: c.unit for c in model.channels}
    for j in range(1, 5):
        ax = f"car1.axle{j}"
        for q, u in (("disp", "m"), ("vel", "m/s"), ("acc", "m/s^2")):
            assert units[f"{ax}.{q}_y"] == u and units[f"{ax}.{q}_z"] == u
        assert units[f"{ax}.disp_rz"] == "rad" and units[f"{ax}.acc_rz"] == "rad/s^2"
        assert units[f"{ax}.force_y"] == units[f"{ax}.left.force_x"] == units[f"{ax}.right.force_x"] == "N"
        assert units[f"{ax}.left.force_z"] == "N" and units[f"{ax}.moment_z"] == "N m"
        assert f"{ax}.disp_ry" not in units  # spin: a degree of freedom, no channel (docs/channels.md)


def _spin_reference(car, v: float, g: float) -> np.ndarray:  # noqa: ANN001
    """Eigenvalues of one wheelset's longitudinal/spin motion against a fixed frame, written here:
    coordinates x and the spin ry,

        m x'' + 2 k_x x + c (x' - r0 ry') = 0
        I ry'' + k_w ry + c_w ry' - r0 c (x' - r0 ry') = 0

    with c = 2 f11 / v (both wheels' common longitudinal creep; f11 of Hertz and Kalker at W / 2),
    2 k_x the primary's two longitudinal springs, I the spin inertia and the builder's documented
    weak spring on the spin, k_w = I (2 pi 0.1 Hz)^2, c_w = 2 I (2 pi 0.1 Hz) (critical)."""
    ws, r0 = car.wheelset, car.geometry.wheel_radius
    cr = car.contact.creep
    f = hertz_creep_coefficients(car.static_axle_load(g) / 2, r0, cr.rail_transverse_radius, cr.wheel_transverse_radius,
                                 E=cr.youngs_modulus, nu=cr.poisson_ratio)[0].scaled(cr.factor)
    c, om = 2 * f.f11 / v, 2 * math.pi * WEAK_SPRING_FREQUENCY
    I = ws.inertia_spin  # noqa: E741
    M = np.diag([ws.mass, I])
    K = np.diag([2 * car.primary.k_x, I * om**2])
    D = c * np.outer((1.0, -r0), (1.0, -r0)) + np.diag([0.0, 2 * WEAK_SPRING_DAMPING_RATIO * I * om])
    return reference_eigenvalues(M, K, D)


@pytest.mark.parametrize("name", ["ice_motor_creep", "ice_trailer_creep"])
def test_wheelset_longitudinal_spin_mode_against_its_closed_form(name):
    """Exact problem: the shipped ICE creep car alone on rigid track at 220 km/h. The two wheelsets
    of a bogie moving against each other along x (with their spins): their primary forces on the
    bogie cancel, and so do their pitch moments (equal heights), and the antisymmetric yaw parts of
    the creep forces cancel on x, so the bogie stays and each wheelset moves exactly as the
    two-coordinate model of :func:`_spin_reference` on a fixed frame. Reference: its eigenvalues
    (numpy, the companion matrix): one oscillating pair (37.76 Hz, 4.36 % motor car; 37.83 Hz,
    4.57 % trailer) and two real roots (the spin's fast creep relaxation at about -c r0^2 / I and
    the slow one of its weak spring). The car's table must have exactly two modes (one per bogie)
    at the pair and two at the fast real root, to 1e-8 relative (the builder's numerical Jacobian:
    1e-11 in the full comparison above), labelled "longitudinal + spin". Without the common creep
    the pair would be the undamped sqrt(2 k_x / m_w) / 2 pi = 42.36 Hz. (The in-phase motion of a
    bogie's wheelsets moves the bogie along x against them: 63-70 Hz, 17-22 % measured, above the
    band; the acceptance test below covers every mode in the band.)"""
    car = load_vehicle(name)
    sc = creep_scenario(car)
    model = build_model(sc, modal_bridge=closed_form_bridge(sc), warn=False)
    table = system_modes(sc, model=model)
    lam = table.eigenvalues
    ref = _spin_reference(car, sc.speed, sc.analysis.gravity)
    pair = ref[ref.imag > 0]
    assert pair.size == 1
    pair = pair[0]
    fast = ref[ref.imag == 0].real.min()
    assert np.sum(np.abs(lam - pair) < 1e-8 * abs(pair)) == 2
    assert np.sum(np.abs(lam - fast) < 1e-8 * abs(fast)) == 2
    zeta_ref = -pair.real / abs(pair)
    assert 0.01 < zeta_ref < 0.1 and abs(abs(pair) / (2 * math.pi) - 37.8) < 0.1
    assert all("longitudinal + spin" in table.label[i] for i in np.flatnonzero(np.abs(lam - pair) < 1e-8 * abs(pair)))


def test_reference_study_creep_train_on_rigid_track_is_damped():
    """Acceptance (issue 19): the four cars of li_zhu_2011_creep (ice_motor_creep and
    ice_trailer_creep) on rigid track (t = 0, every axle on the approach), 220 km/h. Every vehicle
    or wheelset mode in the analysed band (0.3-60 Hz), reached by an input or not, must have a
    damping ratio above 1 %; the damping guard must give no warning. Measured: the least damped are
    the wheelsets' longitudinal/spin modes (37.76 Hz, 4.36 %, motor cars; 37.83 Hz, 4.57 %,
    trailers: test above), then the motor car's leading bogie lateral mode (2.92 Hz, 10.4 %; 2.85 Hz, 7.2 % with the
    wheelsets held level, before their roll was modelled); the
    reference study's car15 train has 9.8e-5 (docs/findings.md section 4). The longitudinal/spin
    modes are the two wheelsets of a bogie moving against each other: no input reaches them (reach,
    Hautus' test, below REACH_ZERO = 1e-10: measured 6e-17 to 1.4e-16), so the least damped reached
    mode is the 10.4 % one (the trailers' least damped reached: their body's lateral/roll/yaw
    mode, 2.59 Hz, 11.6 %). Tolerances of the measured minima: 0.1 % absolute (the first is the
    closed form's 4.36 % to 1e-8) and 0.2 % (the second)."""
    sc = tbx.load_scenario("li_zhu_2011_creep")
    model = build_model(sc, warn=False)
    table = system_modes(sc, model=model)
    band = analysed_band(sc)
    veh = table.of_kind("vehicle", "contact").in_band(*band)
    for name in ("ice_motor_creep", "ice_trailer_creep"):
        of_car = np.array([f"({name})" in lab for lab in veh.label])
        assert of_car.sum() > 50
        assert veh.damping_ratio[of_car].min() > 0.01, veh.select(of_car).text()
    assert veh.damping_ratio.min() > 0.01 and np.all(np.isfinite(veh.damping_ratio))
    assert veh.damping_ratio.min() == pytest.approx(0.0436, abs=0.001)
    reached = veh.reached(("vertical", "alignment", "cross_level"))
    spin = np.array(["longitudinal + spin" in lab for lab in veh.label])
    assert spin.sum() == 8 and not reached[spin].any() and veh.reach[spin].max() < 1e-10
    assert veh.damping_ratio[reached].min() == pytest.approx(0.104, abs=0.002)
    assert len(table.of_kind("decoupled")) == 0  # the spin is no longer a decoupled weak-spring coordinate
    assert damping_guard(sc, model=model, table=table) == []
