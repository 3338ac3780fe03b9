"""Frame bridges: piers, footing springs, bearings with height, eccentric added mass.

Each reference is an independent small solver written in the test: the closed-form cantilever
frequency, the characteristic determinant of a beam on a rotational spring, the 6-DOF rigid
girder on its bearing springs, and the 3 x 3 lateral-vertical-torsion problem of a simply
supported span carrying an eccentric mass.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
import scipy.linalg as la
from scipy.optimize import brentq

from tb_exudyn.scenario.model import AddedMass, BeamSection, Bearings, Frame, Pier
from tb_exudyn.structure.assembly import assemble_pier
from tb_exudyn.structure.fe import bridge_modes, modal_bridge, solve_modes

GIRDER = BeamSection(E=3.45e10, G=1.4375e10, area=8.8889, I_y=10.947, I_z=86.216, J=22.650,
                     mass_per_length=2.2222e4, rot_mass_per_length=2.429e5)
PIER_SECTION = BeamSection(E=3.25e10, G=1.354e10, area=10.0, I_y=8.0, I_z=30.0, J=20.0,
                           mass_per_length=2.5e4, rot_mass_per_length=9.5e4)
H = 15.0
BETA1 = 1.8751040687119611  # first root of 1 + cos(b) cosh(b) = 0


def _top_direction(modes, k: int) -> str:
    """'x' or 'y': the direction the pier top moves in mode k."""
    top = modes.model.pier_top_nodes[0]
    ux, uy = modes.shapes[6 * top, k], modes.shapes[6 * top + 1, k]
    return "x" if abs(ux) > abs(uy) else "y"


def test_pier_cantilever_first_bending_frequencies():
    """A 15 m pier alone, clamped footing: first bending frequency
    f = 1.8751^2 sqrt(E I / (m H^4)) / (2 pi), lateral (y) with I_z and longitudinal (x) with I_y.
    Acceptance asks 0.5 %; 8 Hermite elements are within ~1e-6, so 1e-4 is used."""
    modes = solve_modes(assemble_pier(Pier(height=H, section=PIER_SECTION), 8), 40.0)
    s = PIER_SECTION
    expected = {
        "x": BETA1**2 * math.sqrt(s.E * s.I_y / (s.mass_per_length * H**4)) / (2 * math.pi),
        "y": BETA1**2 * math.sqrt(s.E * s.I_z / (s.mass_per_length * H**4)) / (2 * math.pi),
    }
    got = {_top_direction(modes, k): modes.frequencies[k] for k in range(2)}
    assert got["x"] == pytest.approx(expected["x"], rel=1e-4)
    assert got["y"] == pytest.approx(expected["y"], rel=1e-4)
    assert modes.mode_types[:2] == ("pier", "pier")


def _spring_base_frequency(ei: float, m: float, height: float, k_rot: float) -> float:
    """First frequency of a uniform cantilever on a rotational base spring (Euler-Bernoulli):
    w = A cos bx + B sin bx + C cosh bx + D sinh bx with w(0) = 0, E I w''(0) = k w'(0),
    w''(H) = w'''(H) = 0; the lowest root of the 4 x 4 determinant, found by scanning."""

    def det(b: float) -> float:
        c, s, ch, sh = math.cos(b * height), math.sin(b * height), math.cosh(b * height), math.sinh(b * height)
        a = np.array([
            [1.0, 0.0, 1.0, 0.0],
            [-ei * b * b, -k_rot * b, ei * b * b, -k_rot * b],
            [-c, -s, ch, sh],
            [s, -c, sh, ch],
        ])
        return float(np.linalg.det(a))

    grid = np.linspace(0.05, BETA1, 400) / height
    vals = [det(b) for b in grid]
    i = next(i for i in range(len(grid) - 1) if vals[i] * vals[i + 1] < 0)
    b = brentq(det, grid[i], grid[i + 1], xtol=1e-14)
    return b * b * math.sqrt(ei / m) / (2 * math.pi)


def test_pier_on_rotational_footing_spring():
    """Footing on springs (translations rigid, rotation k = E I_z / H): the first lateral
    frequency drops by about a third; reference from the characteristic determinant of the
    Euler-Bernoulli beam on a rotational spring (independent solver above). Tolerance 1e-4
    (discretisation ~1e-6)."""
    s = PIER_SECTION
    k_rot = s.E * s.I_z / H
    pier = Pier(height=H, section=s, footing="springs", k_translation=math.inf, k_rotation=k_rot)
    modes = solve_modes(assemble_pier(pier, 8), 40.0)
    lateral = [modes.frequencies[k] for k in range(3) if _top_direction(modes, k) == "y"][0]
    ref = _spring_base_frequency(s.E * s.I_z, s.mass_per_length, H, k_rot)
    assert lateral == pytest.approx(ref, rel=1e-4)
    clamped = BETA1**2 * math.sqrt(s.E * s.I_z / (s.mass_per_length * H**4)) / (2 * math.pi)
    assert lateral < 0.8 * clamped


def _one_span_frame(girder: BeamSection, bearings: Bearings, added: AddedMass = AddedMass(),
                    n_el: int = 16) -> Frame:
    return Frame(name="one_span", spans=(32.0,), girder=girder, pier=Pier(height=H, section=PIER_SECTION),
                 bearings=bearings, added_mass=added, elements_per_span=n_el)


def test_stiff_girder_on_elastic_bearings_moves_as_a_rigid_body():
    """One span on elastic bearings at both abutments, 1.5 m below the shear centre, girder made
    1e4 times stiffer: its six lowest modes are the rigid-body modes of the girder on the 2 x 4
    bearing springs. Reference: the 6 x 6 rigid-body problem (mass, inertia m L^3 / 12 and I_p L
    about the centre; each bearing point at (x_b, 0, -1.5) restrained in x (fixed end k_x, sliding
    end free), y, z and in rx). Couplings through the bearing height (x with pitch, y with roll)
    are included. The girder's own flexibility shifts the rigid frequencies by ~(f / f_girder)^2
    ~ 3e-5, hence the tolerance 2e-4."""
    stiff = dataclasses.replace(GIRDER, E=GIRDER.E * 1e4, G=GIRDER.G * 1e4)
    hb, kx, ky, kz, krx = 1.5, 1.0e8, 5.0e7, 2.0e8, 1.0e9
    bearings = Bearings(k_x_fixed=kx, k_x_sliding=0.0, k_y=ky, k_z=kz, k_rx=krx, height=hb)
    fe = bridge_modes(_one_span_frame(stiff, bearings), 50.0)

    span, m, ip = 32.0, GIRDER.mass_per_length, GIRDER.rot_mass_per_length
    mass6 = np.diag([m * span, m * span, m * span, ip * span, m * span**3 / 12, m * span**3 / 12])
    k6 = np.zeros((6, 6))
    for xb, k_long in ((0.0, kx), (span, 0.0)):
        d = np.array([xb - span / 2, 0.0, -hb])  # bearing point from the centre
        skew = np.array([[0, -d[2], d[1]], [d[2], 0, -d[0]], [-d[1], d[0], 0]])
        b = np.zeros((4, 6))
        b[:3, :3] = np.eye(3)
        b[:3, 3:] = -skew  # r x d = -d x r
        b[3, 3] = 1.0
        k6 += b.T @ np.diag([k_long, ky, kz, krx]) @ b
    ref = np.sqrt(la.eigh(k6, mass6, eigvals_only=True)) / (2 * math.pi)
    assert fe.frequencies[:6] == pytest.approx(ref, rel=2e-4)


def test_eccentric_added_mass_couples_lateral_bending_and_torsion():
    """One span, rigid supports at the shear centre (bearing height 0), girder plus an added mass
    1.2e4 kg/m at lateral offset 2.5 m and height 1.14 m (polar moment 1.4e5 kg m^2/m).
    Each sin(j pi x / L) mode solves the 3 x 3 problem
    diag(E I_z k^4, E I_y k^4, G J k^2) a = omega^2 M a with
    M = [[m, 0, -m_a h], [0, m, m_a e], [-m_a h, m_a e, I_p + I_a + m_a (e^2 + h^2)]]
    (m = girder + added mass; the longitudinal motion of the mass is neglected, as in the
    element). The six lowest modes (j <= 3) match within 1e-3 (96 elements: the torsion part's
    error is at most ~(3 pi / 96)^2 / 24 = 4e-4). The rail line (e_r = 2.5, h_r = 1.64) of the first
    mode follows the analytic shape (a_v - h_r a_t, a_w + e_r a_t) sin(pi x / L), mass-normalised
    by (L / 2) a^T M a = 1, to the same accuracy."""
    added = AddedMass(mass_per_length=1.2e4, rot_mass_per_length=1.4e5, offset=2.5, height=1.14)
    bearings = Bearings(k_x_fixed=math.inf, k_x_sliding=0.0, height=0.0)
    frame = dataclasses.replace(_one_span_frame(GIRDER, bearings, added, n_el=96), track_offset=2.5, track_height=1.64)
    mb = modal_bridge(frame, 45.0)

    span = 32.0
    m_a, e, h, i_a = added.mass_per_length, added.offset, added.height, added.rot_mass_per_length
    m = GIRDER.mass_per_length + m_a
    mass3 = np.array([[m, 0, -m_a * h], [0, m, m_a * e],
                      [-m_a * h, m_a * e, GIRDER.rot_mass_per_length + i_a + m_a * (e * e + h * h)]])
    ref, vecs = [], []
    for j in range(1, 7):
        k = j * math.pi / span
        stiff3 = np.diag([GIRDER.E * GIRDER.I_z * k**4, GIRDER.E * GIRDER.I_y * k**4, GIRDER.G * GIRDER.J * k**2])
        lam, vec = la.eigh(stiff3, mass3)
        ref.extend(np.sqrt(lam) / (2 * math.pi))
        vecs.extend((j, vec[:, i]) for i in range(3))
    order = np.argsort(ref)
    ref = np.array(ref)[order][:6]
    got = np.array([f for f, t in zip(mb.frequencies, mb.mode_types) if t != "longitudinal"])[:6]
    assert got == pytest.approx(ref, rel=1e-3)

    j, a = vecs[order[0]]
    a = a / math.sqrt(0.5 * span * a @ mass3 @ a)
    x = np.linspace(0.0, span, 41)
    sin = np.sin(j * math.pi * x / span)
    shapes = mb.rail_shapes(x)
    first = [k for k, t in enumerate(mb.mode_types) if t != "longitudinal"][0]
    y_ref, z_ref = (a[0] - 1.64 * a[2]) * sin, (a[1] + 2.5 * a[2]) * sin
    sign = np.sign(shapes.y[20, first] * y_ref[20])
    scale = np.abs(y_ref).max()
    assert np.abs(sign * shapes.y[:, first] - y_ref).max() < 1e-3 * scale
    assert np.abs(sign * shapes.z[:, first] - z_ref).max() < 1e-3 * scale


def test_sparse_shift_invert_and_dense_solvers_agree(monkeypatch):
    """The same frame (3 spans on 2 piers, 381 free DOFs) solved densely (scipy.linalg.eigh) and
    by shift-invert Lanczos (eigsh, forced by lowering the dense limit; 25 modes below 40 Hz, so
    the first request of 24 modes has to grow): frequencies agree to 1e-9 relative and the
    mass-normalised modes to 1e-6 of their largest entry (well-separated modes; both solvers
    converge to ~1e-12)."""
    import tb_exudyn.structure.fe as fe

    frame = Frame(name="three_spans", spans=(32.0, 32.0, 32.0), girder=GIRDER,
                  pier=Pier(height=H, section=PIER_SECTION),
                  bearings=Bearings(height=1.5), added_mass=AddedMass(mass_per_length=1.1e4, height=1.14),
                  elements_per_span=16, elements_per_pier=8)
    dense = bridge_modes(frame, 40.0)
    monkeypatch.setattr(fe, "_DENSE_LIMIT", 0)
    sparse = bridge_modes(frame, 40.0)
    assert dense.n_modes == sparse.n_modes > 24
    assert sparse.frequencies == pytest.approx(dense.frequencies, rel=1e-9)
    gaps = np.diff(dense.frequencies) / dense.frequencies[1:]
    ok = np.concatenate([[gaps[0] > 1e-3], (gaps[:-1] > 1e-3) & (gaps[1:] > 1e-3), [gaps[-1] > 1e-3]])
    a, b = dense.shapes[:, ok], sparse.shapes[:, ok]
    assert np.abs(a - b).max() < 1e-6 * np.abs(a).max()
