"""car15 on rigid track: eigenfrequencies against an independent linear 15-DOF model."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg as la

pytest.importorskip("exudyn")

from tb_exudyn.builder import build_model  # noqa: E402
from tb_exudyn.scenario import Analysis, BeamSection, Scenario, SimpleBeam, Track, Train  # noqa: E402
from tb_exudyn.structure import simply_supported_modes  # noqa: E402

pytestmark = pytest.mark.exudyn

COMPONENTS = ("y", "z", "rx", "ry", "rz")


def reference_15dof(car, track_half_gauge_unused: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """Independent linear 15-DOF car (body, two bogies; y, z, roll, pitch, yaw each) with the
    wheelsets fixed to a rigid track (the reference study's model). Linear point kinematics of a
    rigid body: a point at p from the CG moves by (y, z) + theta x p, i.e.
    dy = y + rz px - rx pz, dz = z + rx py - ry px. Springs per side act in y and z between their
    end points: secondary at the bogie centres, +-b_s, at the secondary height; primary at the axles,
    +-b_p, at the wheelset centre height. Returns (frequencies [Hz], eigenvectors (15, 15))."""
    gm = car.geometry
    s, a = gm.half_bogie_spacing, gm.half_wheelbase
    z_w = gm.wheel_radius
    z_t = z_w + gm.bogie_cg_above_axle
    z_s = z_t + gm.secondary_above_bogie_cg
    z_c = z_s + gm.body_cg_above_secondary
    n = 15
    K = np.zeros((n, n))

    def point_rows(body: int, p: tuple[float, float, float]) -> tuple[np.ndarray, np.ndarray]:
        ry_, rz_ = np.zeros(n), np.zeros(n)
        if body < 0:  # the rigid track: no motion
            return ry_, rz_
        o = 5 * body
        px, py, pz = p
        ry_[o + 0], ry_[o + 4], ry_[o + 2] = 1.0, px, -pz
        rz_[o + 1], rz_[o + 2], rz_[o + 3] = 1.0, py, -px
        return ry_, rz_

    def spring(b0: int, p0, b1: int, p1, k_y: float, k_z: float) -> None:
        y0, z0 = point_rows(b0, p0)
        y1, z1 = point_rows(b1, p1)
        K[:, :] += k_y * np.outer(y1 - y0, y1 - y0) + k_z * np.outer(z1 - z0, z1 - z0)

    for i, xb in enumerate((s, -s)):
        bogie = 1 + i
        for side in (1.0, -1.0):
            b = side * gm.half_secondary_span
            spring(0, (xb, b, z_s - z_c), bogie, (0.0, b, z_s - z_t), car.secondary.k_y, car.secondary.k_z)
            for xa in (a, -a):
                bp = side * gm.half_primary_span
                spring(-1, (0.0, 0.0, 0.0), bogie, (xa, bp, z_w - z_t), car.primary.k_y, car.primary.k_z)
    M = np.diag([car.body.mass, car.body.mass, car.body.inertia_roll, car.body.inertia_pitch, car.body.inertia_yaw]
                + 2 * [car.bogie.mass, car.bogie.mass, car.bogie.inertia_roll, car.bogie.inertia_pitch,
                       car.bogie.inertia_yaw])
    w2, vec = la.eigh(K, M)
    return np.sqrt(w2) / (2 * np.pi), vec


def exudyn_car_modes(car, k_contact: float) -> tuple[np.ndarray, np.ndarray]:
    """Eigenfrequencies [Hz] of the Exudyn model's 15 modes that live in the car body and bogies
    (kinetic-energy fraction in their y, z, rx, ry, rz coordinates), with those 15-coordinate
    parts of the eigenvectors; from mbs.ComputeLinearizedSystem at the reference configuration,
    the car on the rigid approach track."""
    section = BeamSection(E=3.45e10, G=1.4e10, area=8.9, I_y=10.9, I_z=86.0, J=22.6, mass_per_length=3.4e4,
                          rot_mass_per_length=3.8e5)
    sc = Scenario(
        name="eigen", speed_kmh=100.0, train=Train(vehicles=(car,)),
        bridge=SimpleBeam(name="b", spans=(32.0,), girder=section), track=Track(lead_in=60.0, run_out=5.0),
        analysis=Analysis(contact_stiffness_z=k_contact, contact_stiffness_y=k_contact, mode_max_frequency=30.0),
    )
    modes = simply_supported_modes((32.0,), 3.45e10 * 10.9, 3.45e10 * 86.0, 1.4e10 * 22.6, 3.4e4, 3.8e5, 0.0, 30.0)
    model = build_model(sc, modal_bridge=modes, warn=False)
    M, K, _ = model.linearized_system(0.0)
    idx = []
    for b in model.parts.bodies:
        if b.name.split(".")[1] in ("body", "bogie1", "bogie2"):
            nodes = model.node_indices(b.node)
            idx += [int(nodes[c]) for _, c in b.components]
    assert len(idx) == 15
    w2, vec = la.eig(K, M)
    w2, vec = w2.real, vec.real
    energy = np.einsum("ij,ij->j", vec, M @ vec)
    part = vec[idx]
    frac = np.einsum("ij,ij->j", part, M[np.ix_(idx, idx)] @ part) / energy
    keep = np.argsort(frac)[-15:]
    assert frac[keep].min() > 0.5, "car modes not separated from wheelset/decoupled modes"
    order = keep[np.argsort(w2[keep])]
    return np.sqrt(w2[order]) / (2 * np.pi), part[:, order]


def _label(v: np.ndarray) -> str:
    """Name a vertical mode by its dominant coordinate: body / bogie, bounce (z) / pitch (ry)."""
    names = {1: "body bounce", 3: "body pitch", 6: "bogie1 bounce", 8: "bogie1 pitch", 11: "bogie2 bounce",
             13: "bogie2 pitch"}
    return names[max(names, key=lambda i: abs(v[i]) * (1.0 if i in (1, 6, 11) else 8.0))]


def test_car15_converges_to_the_15dof_model(ice_motor, ice_trailer):
    """Exact problem: the 15 body-and-bogie eigenfrequencies of an ICE motor car and trailer
    (docs/references.md, vehicles) on rigid track, Exudyn rigid bodies with wheelsets in linear contact of stiffness
    k = 2e7 ... 2e10 N/m (per wheel vertically, per wheelset laterally). Reference: the independent
    linear 15-DOF model above with the wheelsets fixed to the track (the limit k -> infinity).
    Tolerance: within 0.5 % for every mode at the default k = 2e9 N/m (the acceptance criterion),
    and the largest error falls with k (a compliant contact in series with the primary springs
    lowers the frequencies by O(k_primary / k)). Prints the vertical modes (bounce, pitch of body
    and bogies) for comparison with Zeng et al. 2014 (0.84 / 0.97 / 4.78 / 6.28 Hz, motor car)."""
    for car in (ice_motor, ice_trailer):
        f_ref, v_ref = reference_15dof(car)
        errors = []
        for k in (2e7, 2e8, 2e9, 2e10):
            f, _ = exudyn_car_modes(car, k)
            errors.append(np.abs(f / f_ref - 1.0).max())
        assert all(e1 < e0 for e0, e1 in zip(errors[:-1], errors[1:])), errors
        assert errors[2] < 5e-3, errors
        assert errors[3] < 1e-3, errors
        # vertical modes of the reference: energy in z and ry of body and bogies
        vertical = [i for i in range(15) if np.sum(v_ref[[1, 3, 6, 8, 11, 13], i] ** 2) / np.sum(v_ref[:, i] ** 2) > 0.99]
        f_exu, _ = exudyn_car_modes(car, 2e9)
        labels = [_label(v_ref[:, i]) for i in vertical]
        print(f"\n{car.name}: vertical modes, reference 15-DOF / Exudyn (k = 2e9) [Hz]: "
              + ", ".join(f"{lab} {fr:.3f} / {fe:.3f}" for lab, fr, fe in zip(labels, f_ref[vertical], f_exu[vertical]))
              + "; largest error of the 15 modes for k = 2e7, 2e8, 2e9, 2e10: " + ", ".join(f"{e:.1e}" for e in errors))


def test_car15_vertical_frequencies_match_published_motor_car(ice_motor):
    """Exact problem: vertical eigenfrequencies of the ICE motor car on rigid track (k = 2e9).
    Reference: Zeng et al., Shock and Vibration 2014, 304219, Table 1 (docs/references.md, vehicles): car body
    bounce 0.84 Hz, pitch 0.97 Hz, bogie bounce 4.78 Hz, bogie pitch 6.28 Hz, from the same
    (summed) vertical stiffnesses. Compared as sets: by its mode shape the 4.78 Hz mode is the
    bogie pitch and 6.28 Hz the bounce (bounce sqrt((4 k_p + 2 k_s) / m) / 2 pi = 6.27 Hz; pitch
    sqrt(4 k_p a^2 / I) / 2 pi = 4.78 Hz): the published labels are swapped. Tolerance 2 %: the
    published values are given to 2-3 digits."""
    f, _ = exudyn_car_modes(ice_motor, 2e9)
    f_ref, v_ref = reference_15dof(ice_motor)
    vertical = [i for i in range(15) if np.sum(v_ref[[1, 3, 6, 8, 11, 13], i] ** 2) / np.sum(v_ref[:, i] ** 2) > 0.99]
    fv = f[vertical]
    # body bounce, body pitch, bogie bounce (two bogies), bogie pitch (two bogies)
    assert len(fv) == 6
    published = np.array([0.84, 0.97, 4.78, 4.78, 6.28, 6.28])
    assert np.allclose(np.sort(fv), published, rtol=0.02), np.sort(fv)
