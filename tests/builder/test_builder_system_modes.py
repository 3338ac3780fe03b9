"""Modes of the built Exudyn model (tb_exudyn.builder.system_modes) against independent models
written here: a car15 on rigid track (with and without its wheelsets on the contact springs), the
ICE bogie yaw closed form, a sprung mass's damping ratio, a sprung mass standing on a modal bridge,
and the secondary yaw damper."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import linear_sum_assignment

pytest.importorskip("exudyn")

from tb_exudyn.builder import build_model  # noqa: E402
from tb_exudyn.builder.system_modes import model_dofs, position_time, system_modes  # noqa: E402
from tb_exudyn.scenario import (  # noqa: E402
    Analysis, BeamSection, Scenario, SimpleBeam, SprungMass, Track, Train, YawDamper,
)
from tb_exudyn.structure import simply_supported_modes  # noqa: E402

from eigen_reference import reference_eigenvalues  # noqa: E402  (tests/builder, on pytest's path)

pytestmark = pytest.mark.exudyn

SECTION = BeamSection(E=3.45e10, G=1.4e10, area=8.9, I_y=10.9, I_z=86.0, J=22.6, mass_per_length=3.4e4,
                      rot_mass_per_length=3.8e5)
HALF_GAUGE = 0.75
CONTACT_ZETA = 0.5  # BuildOptions.contact_damping_ratio (default)


def car_scenario(car, k_contact: float = 2e9) -> Scenario:
    return Scenario(
        name="modes", speed_kmh=100.0, train=Train(vehicles=(car,)),
        bridge=SimpleBeam(name="b", spans=(32.0,), girder=SECTION, damping_ratio=0.02),
        track=Track(lead_in=60.0, run_out=5.0, half_gauge=HALF_GAUGE),
        analysis=Analysis(contact_stiffness_z=k_contact, contact_stiffness_y=k_contact, mode_max_frequency=30.0),
    )


def closed_form_bridge(sc: Scenario):
    g = sc.bridge.girder
    return simply_supported_modes(sc.bridge.spans, g.E * g.I_y, g.E * g.I_z, g.G * g.J, g.mass_per_length,
                                  g.rot_mass_per_length, sc.bridge.damping_ratio, 30.0)


# --------------------------------------------------------------------------------------------
# the independent car model


def reference_car(car, k_contact: float | None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """M, K, D of a car15 on rigid track, written independently of the builder.

    Coordinates: body, bogie 1 (leading), bogie 2, each (y, z, rx, ry, rz) about its centre of
    gravity; with ``k_contact`` also wheelsets 1-4, each (y, z, rx). Linear point kinematics of a
    rigid body: a point at p from the CG moves by dx = -rz py + ry pz (x itself is not modelled:
    decoupled), dy = y + rz px - rx pz, dz = z + rx py - ry px. Suspensions per side act in y and z
    between their end points (secondary at the bogie centre, +-b_s, secondary height; primary at
    the axle, +-b_p, wheelset-centre height). Without ``k_contact`` the wheelsets are fixed to the
    track (the 15-DOF model of the reference study); with it each wheel sits on a vertical contact
    spring k at +-half gauge and each wheelset on a lateral one at rail level (the wheel radius r
    below its centre), dampers c = 2 zeta sqrt(k m) with m half the wheelset mass vertically and the
    wheelset mass laterally (the builder's documented contact). A yaw damper acts in x at the CG
    heights, between body and bogie at +-d."""
    gm = car.geometry
    s, a, r = gm.half_bogie_spacing, gm.half_wheelbase, gm.wheel_radius
    z_w = r
    z_t = z_w + gm.bogie_cg_above_axle
    z_s = z_t + gm.secondary_above_bogie_cg
    z_c = z_s + gm.body_cg_above_secondary
    n_rigid = 15
    n = n_rigid + (12 if k_contact else 0)
    K, D = np.zeros((n, n)), np.zeros((n, n))

    def rows(body: int | None, p: tuple[float, float, float]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Row vectors of the point's (dx, dy, dz) in the coordinates; body None = rigid track,
        0-2 = body / bogies, 3-6 = wheelsets 1-4."""
        rx_, ry_, rz_ = np.zeros(n), np.zeros(n), np.zeros(n)
        if body is None:
            return rx_, ry_, rz_
        px, py, pz = p
        if body < 3:
            o = 5 * body
            rx_[o + 4], rx_[o + 3] = -py, pz
            ry_[o + 0], ry_[o + 4], ry_[o + 2] = 1.0, px, -pz
            rz_[o + 1], rz_[o + 2], rz_[o + 3] = 1.0, py, -px
        else:
            if not k_contact:
                return rx_, ry_, rz_
            o = n_rigid + 3 * (body - 3)
            ry_[o + 0], ry_[o + 2] = 1.0, -pz
            rz_[o + 1], rz_[o + 2] = 1.0, py
        return rx_, ry_, rz_

    def element(b0, p0, b1, p1, k=(0.0, 0.0, 0.0), c=(0.0, 0.0, 0.0)) -> None:
        for e0, e1, kk, cc in zip(rows(b0, p0), rows(b1, p1), k, c):
            d = e1 - e0
            K[:, :] += kk * np.outer(d, d)
            D[:, :] += cc * np.outer(d, d)

    sec, pri = car.secondary, car.primary
    for i, xb in enumerate((s, -s)):
        bogie = 1 + i
        for side in (1.0, -1.0):
            bs = side * gm.half_secondary_span
            element(0, (xb, bs, z_s - z_c), bogie, (0.0, bs, z_s - z_t), (0.0, sec.k_y, sec.k_z), (0.0, sec.c_y, sec.c_z))
            if car.yaw_damper is not None:
                d = side * car.yaw_damper.half_span
                element(0, (xb, d, 0.0), bogie, (0.0, d, 0.0), c=(car.yaw_damper.c_x, 0.0, 0.0))
            for j, xa in enumerate((a, -a)):
                ws = 3 + 2 * i + j
                bp = side * gm.half_primary_span
                element(ws, (0.0, bp, 0.0), bogie, (xa, bp, z_w - z_t), (0.0, pri.k_y, pri.k_z), (0.0, pri.c_y, pri.c_z))
    m_ws = car.wheelset.mass
    if k_contact:
        cz = 2 * CONTACT_ZETA * math.sqrt(k_contact * m_ws / 2)
        cy = 2 * CONTACT_ZETA * math.sqrt(k_contact * m_ws)
        for ws in range(3, 7):
            for side in (1.0, -1.0):
                element(None, (0, 0, 0), ws, (0.0, side * HALF_GAUGE, 0.0), (0.0, 0.0, k_contact), (0.0, 0.0, cz))
            element(None, (0, 0, 0), ws, (0.0, 0.0, -r), (0.0, k_contact, 0.0), (0.0, cy, 0.0))
    rb = [car.body, car.bogie, car.bogie]
    m = [v for b in rb for v in (b.mass, b.mass, b.inertia_roll, b.inertia_pitch, b.inertia_yaw)]
    if k_contact:
        m += 4 * [m_ws, m_ws, car.wheelset.inertia_roll]
    return np.diag(m), K, D


def matched(lam_ref: np.ndarray, lam: np.ndarray) -> np.ndarray:
    """lam reordered to pair with lam_ref (least relative distances)."""
    cost = np.abs(lam_ref[:, None] - lam[None, :]) / np.abs(lam_ref)[:, None]
    i, j = linear_sum_assignment(cost)
    out = np.empty_like(lam_ref)
    out[i] = lam[j]
    return out


def freq_zeta(lam: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    return np.abs(lam) / (2 * np.pi), -lam.real / np.abs(lam)


def car_modes(car, k_contact: float, kinds: tuple[str, ...]):
    sc = car_scenario(car, k_contact)
    model = build_model(sc, modal_bridge=closed_form_bridge(sc), warn=False)
    return system_modes(sc, model=model).of_kind(*kinds)


# --------------------------------------------------------------------------------------------
# tests


@pytest.mark.parametrize("yaw_damper", [None, YawDamper(c_x=2.0e4, half_span=1.3)])
def test_car_on_rigid_track_matches_independent_model_with_contact(ice_motor, ice_trailer, yaw_damper):
    """Exact problem: every damped mode of an ICE motor car and trailer (values of docs/references.md, vehicles) on
    rigid track with its wheelsets on the stiff linear contact (k = 2e9 N/m, zeta 0.5 against the
    wheel mass, the builder's default), without and with a yaw damper (a test value, c_x 20 kN s/m
    per damper at 1.3 m). Reference: the independent 27-DOF numpy model above with the same contact
    springs (module docstring of the builder's vehicles and contact). Both describe the same linear
    equations; the differences come from Exudyn's numerical Jacobian in ComputeLinearizedSystem
    (measured: frequencies 1.2e-7 relative, damping ratios 1.3e-8 absolute), so the acceptance's
    tolerance (frequencies 0.1 %, damping ratios 1 % or 1e-5) is tightened to 1e-6."""
    for car in (ice_motor.replace(yaw_damper=yaw_damper), ice_trailer.replace(yaw_damper=yaw_damper)):
        table = car_modes(car, 2e9, ("vehicle", "contact"))
        lam_ref = reference_eigenvalues(*reference_car(car, 2e9))
        assert len(table) == lam_ref.size, (len(table), lam_ref.size)
        lam = matched(lam_ref, table.eigenvalues)
        f_ref, z_ref = freq_zeta(lam_ref)
        f, z = freq_zeta(lam)
        assert np.allclose(f, f_ref, rtol=1e-6, atol=0.0), np.abs(f / f_ref - 1).max()
        assert np.allclose(z, z_ref, rtol=1e-6, atol=1e-9), np.abs(z - z_ref).max()


def test_car_on_rigid_track_tends_to_the_15dof_model(ice_motor, ice_trailer):
    """Exact problem: the damped modes of the car body and bogies of the ICE cars on rigid track.
    Reference: the 15-DOF model (wheelsets fixed to the track) written above. The project's
    wheelsets sit on a stiff contact; with k = 2e10 N/m (ten times the default) the contact changes
    the car modes by O(k_primary / k) (measured: frequencies 3.4e-4, damping ratios 4.8e-4 relative;
    at the default 2e9 N/m ten times more, 3.6e-3). Tolerance: the acceptance's, frequencies
    within 0.1 %, damping ratios within 1 % or 1e-5 absolute (the contact's own damping gives the
    bogie yaw mode 3e-6, the 15-DOF model 0)."""
    for car in (ice_motor, ice_trailer):
        table = car_modes(car, 2e10, ("vehicle",))
        lam_ref = reference_eigenvalues(*reference_car(car, None))
        assert len(table) == lam_ref.size, (len(table), lam_ref.size)
        lam = matched(lam_ref, table.eigenvalues)
        f_ref, z_ref = freq_zeta(lam_ref)
        f, z = freq_zeta(lam)
        assert np.all(np.abs(f / f_ref - 1.0) < 1e-3), np.abs(f / f_ref - 1).max()
        ok = (np.abs(z - z_ref) <= 0.01 * np.abs(z_ref)) | (np.abs(z - z_ref) <= 1e-5)
        assert ok.all(), list(zip(f_ref[~ok], z_ref[~ok], z[~ok]))


def test_ice_motor_bogie_yaw_closed_form(ice_motor):
    """Exact problem: the yaw of an ICE motor car's bogie on its four primary lateral springs
    (k_y = 3e6 N/m per side, half wheelbase a = 1.25 m, I_yaw = 6800 kg m^2), wheelsets on the
    default contact (2e9 N/m). Reference: f = sqrt(4 k_y a^2 / I_yaw) / 2 pi = 8.357 Hz (the
    secondary spring at the bogie centre takes no yaw). Tolerance 1 % (acceptance): the contact in
    series with the primary springs lowers it by about k_y / k_contact (0.2 %). Damping below 1e-3:
    only the contact's damping acts (no primary lateral damper in the data)."""
    table = car_modes(ice_motor, 2e9, ("vehicle",))
    f_ref = math.sqrt(4 * 3.0e6 * 1.25**2 / 6800.0) / (2 * math.pi)
    yaw = [i for i, lab in enumerate(table.label) if lab.endswith("bogie, yaw")]
    assert len(yaw) == 2, table.text()  # leading and trailing bogie
    assert {table.label[i].split(", ")[1] for i in yaw} == {"leading bogie", "trailing bogie"}
    for i in yaw:
        assert abs(table.frequency[i] / f_ref - 1.0) < 0.01, (table.frequency[i], f_ref)
        assert table.damping_ratio[i] < 1e-3


def sprung_mass_scenario(c: float, wheel_mass: float = 0.0, lead_in: float = 20.0) -> Scenario:
    veh = SprungMass(name="sm", mass=5750.0, stiffness=1.595e6, damping=c, wheel_mass=wheel_mass, length=30.0)
    return Scenario(
        name="sm", speed_kmh=90.0, train=Train(vehicles=(veh,)),
        bridge=SimpleBeam(name="b", spans=(25.0,), girder=SECTION.replace(mass_per_length=2303.0, I_y=2.9, E=2.87e9),
                          damping_ratio=0.01),
        track=Track(lead_in=lead_in, run_out=5.0, taper_length=5.0),
        analysis=Analysis(mode_max_frequency=40.0),
    )


@pytest.mark.parametrize("c", [0.0, 1.0e4, 6.0e4])
def test_sprung_mass_damping_ratio(c):
    """Exact problem: the Yang-Yau sprung mass (m 5750 kg, k 1.595e6 N/m) with suspension damping
    c on rigid track (t = 0, wheel mass 0: the spring's lower end follows the rail). Reference:
    zeta = c / (2 sqrt(k m)), f_n = sqrt(k / m) / 2 pi. The model is that single oscillator, so
    they agree to round-off; tolerance 1e-9. c = 6e4 N s/m is zeta 0.31."""
    sc = sprung_mass_scenario(c)
    table = system_modes(sc).of_kind("vehicle")
    assert len(table) == 1
    k, m = 1.595e6, 5750.0
    assert table.damping_ratio[0] == pytest.approx(c / (2 * math.sqrt(k * m)), abs=1e-9)
    assert table.frequency[0] == pytest.approx(math.sqrt(k / m) / (2 * math.pi), rel=1e-9)
    assert table.label[0] == "car 1 (sm), body, bounce"


def test_sprung_mass_standing_on_the_bridge_couples_with_its_modes():
    """Exact problem: the sprung mass (c = 1e4 N s/m, wheel mass 0) standing at 10 m on a 25 m
    simply supported span, coupled to its vertical modes (closed form, modal damping 1 %).
    Reference: the coupled linear system written here in modal coordinates: bridge M = I,
    K = diag w^2, D = diag 2 zeta w; the spring-damper between the mass z and the rail
    w = sum_k phi_k(x) q_k (phi_k = sqrt(2 / (m L)) sin(k pi x / L)). The frozen coupling has no
    convective term, which the reference omits too. Same equations: tolerance 1e-6 relative on
    every eigenvalue (round-off and the Exudyn Jacobian)."""
    sc = sprung_mass_scenario(1.0e4)
    g = sc.bridge.girder
    modes = simply_supported_modes(sc.bridge.spans, g.E * g.I_y, g.E * g.I_z, g.G * g.J, g.mass_per_length,
                                   g.rot_mass_per_length, sc.bridge.damping_ratio, 40.0)
    model = build_model(sc, modal_bridge=modes, warn=False)
    x = 10.0
    table = system_modes(sc, x, model=model)
    assert "1 of 1 axles on the bridge" in table.description
    # reference
    nb = modes.n_modes
    phi = modes.rail_shapes(np.array([x])).z[0]
    k, c, m = 1.595e6, 1.0e4, 5750.0
    n = nb + 1
    M = np.diag(np.r_[np.ones(nb), m])
    e = np.r_[-phi, 1.0]  # spring extension z - w
    K = np.diag(np.r_[modes.omega**2, 0.0]) + k * np.outer(e, e)
    D = np.diag(np.r_[2 * modes.damping_ratios * modes.omega, 0.0]) + c * np.outer(e, e)
    lam_ref = reference_eigenvalues(M, K, D)
    coupled = table.select([kd in ("bridge", "vehicle") for kd in table.kind])
    assert len(coupled) == lam_ref.size == n
    lam = matched(lam_ref, coupled.eigenvalues)
    assert np.allclose(lam, lam_ref, rtol=1e-6), np.abs(lam / lam_ref - 1).max()
    # and the time <-> position convention
    assert position_time(sc, x) == pytest.approx((x + sc.track.lead_in) / sc.speed)
    assert np.allclose(system_modes(sc, time=position_time(sc, x), model=model).eigenvalues, table.eigenvalues)


def test_dofs_name_every_coordinate_and_the_decoupled_ones(ice_motor):
    """The description of the model's coordinates: the bridge's modal coordinates by the modal
    report's types, each car body / bogie / wheelset coordinate, and exactly the builder's weak
    springs' coordinates (x of body, bogies and wheelsets; wheelset spin and yaw: 3 + 4 x 3 = 15
    per car15) as decoupled; every mode living on them is of kind "decoupled"."""
    sc = car_scenario(ice_motor)
    model = build_model(sc, modal_bridge=closed_form_bridge(sc), warn=False)
    dofs = model_dofs(model)
    assert len(dofs) == model.n_ode2
    bridge = [d for d in dofs if d.role == "bridge"]
    assert len(bridge) == model.bridge.n_modes
    assert {d.component for d in bridge} == set(model.bridge.mode_types)
    dec = [d for d in dofs if d.decoupled]
    assert len(dec) == 15
    assert {d.component for d in dec} == {"longitudinal", "spin", "yaw"}
    assert all(d.role == "wheelset" for d in dec if d.component in ("spin", "yaw"))
    table = system_modes(sc, model=model)
    for i in range(len(table)):
        dec_share = sum(s for s, d in zip(table.shares[i], dofs) if d.decoupled)
        assert (table.kind[i] == "decoupled") == (dec_share > 0.5)
        assert dec_share < 1e-12 or dec_share > 1 - 1e-12  # exactly decoupled


def test_yaw_damper_damps_bogie_yaw_as_a_relative_yaw_damper(ice_motor):
    """Exact problem: the ICE motor car with a yaw damper pair per bogie (c_x = 2e4 N s/m per
    damper at d = 1.3 m; a test value) on rigid track. Reference: the bogie yaw as one oscillator
    (inertia I_yaw = 6800 kg m^2, its frequency w from the table) with the pair's relative-yaw
    damper 2 c_x d^2 to the car body, which is 400 times heavier in yaw and nearly still:
    zeta ~= 2 c_x d^2 / (2 I_yaw w). Tolerance 5 %: the estimate neglects the body's yaw and the
    contact's damping (the full check is the independent model above). And the pair adds nothing
    to the vertical plane: the bounce and pitch modes are unchanged to 1e-9."""
    plain = car_modes(ice_motor, 2e9, ("vehicle",))
    damped = car_modes(ice_motor.replace(yaw_damper=YawDamper(c_x=2.0e4, half_span=1.3)), 2e9, ("vehicle",))
    yaw = [i for i, lab in enumerate(damped.label) if lab.endswith("bogie, yaw")]
    assert len(yaw) == 2
    w = 2 * math.pi * damped.frequency[yaw[0]]
    estimate = 2 * 2.0e4 * 1.3**2 / (2 * 6800.0 * w)
    for i in yaw:
        assert damped.damping_ratio[i] == pytest.approx(estimate, rel=0.05)
    vertical = [i for i, lab in enumerate(plain.label) if lab.split(", ")[-1] in ("bounce", "pitch")]
    assert vertical
    for i in vertical:
        j = int(np.argmin(np.abs(damped.eigenvalues - plain.eigenvalues[i])))
        assert abs(damped.eigenvalues[j] / plain.eigenvalues[i] - 1) < 1e-9
