"""The static deformation checks (tb_exudyn.codes.deformation) against closed forms written here.

Problem: one simply supported Euler-Bernoulli span (L = 32 m, the girder of single_span_32m, 64 elements) under
LM71 (EN 1991-2 6.3.2: four 250 kN axles 1.6 m apart, 80 kN/m from 0.8 m beyond the outer axles, unlimited).
References, computed in the tests from the beam's own closed forms and a brute-force placement of the load:
- mid-span deflection of the track line 2.5 m off the axis: the four axles centred on mid-span and the
  distributed load over the rest of the span (the influence line is positive and symmetric, so this is the
  worst place): bending sum P a (3 L^2 - 4 a^2) / (48 EI) plus q (3 L^2 c^2 / 2 - c^4) / (48 EI) on each side,
  c = L/2 - 3.2 m, and the torsion e theta(L/2) of the torques e P;
- end rotation of the track line: theta_A = P b (L^2 - b^2) / (6 EI L) (b from the far support) plus the
  torsion's e^2 P b / (GJ L), the distributed load's integrals, placed at every 0.1 m;
- twist: the girder as a shaft fixed against torsion at both ends (GJ); a torque T at a gives
  theta(x) = T x (L - a) / (GJ L) for x <= a and T a (L - x) / (GJ L) beyond; the track 2.5 m off the axis turns
  its loads into torques T = e P; the rails 1.435 m apart twist by 1.435 |theta(x) - theta(x + 3 m)| (bending
  moves both rails alike), placed at every 0.1 m, the distributed load where adverse;
- the first lateral frequency: f = (pi / 2 L^2) sqrt(E I_z / m).
The finite elements are exact for these at the nodes (cubic bending, linear twist), the influence lines are
integrated on a 0.1 m grid (trapezoid: relative error ~ (0.1 / 32)^2); the tolerances say why.
"""

import math

import numpy as np
import pytest

from tb_exudyn.codes import deformation as dfm
from tb_exudyn.codes import en1991 as code
from tb_exudyn.scenario.girders import SimpleBeam
from tb_exudyn.scenario.sections import BeamSection
from tb_exudyn.structure import modal_bridge

L, E, I_Y, I_Z, G, J, M, E_OFF = 32.0, 3.45e10, 10.947, 86.216, 1.4375e10, 22.650, 33900.0, 2.5
P, Q = 250e3, 80e3


def beam(offset=E_OFF):
    sec = BeamSection(E=E, G=G, area=8.8889, I_y=I_Y, I_z=I_Z, J=J, mass_per_length=M, rot_mass_per_length=383040.5)
    return SimpleBeam(name="ss32", spans=(L,), girder=sec, damping_ratio=0.02, track_offset=offset,
                      track_height=1.64, elements_per_span=64)


@pytest.fixture(scope="module")
def result():
    return dfm.static_deformations(beam())


def test_mid_span_deflection_and_phi(result):
    ei = E * I_Y
    a = np.array([L / 2 - 2.4, L / 2 - 0.8])  # the axles left of mid-span; the right ones mirror them
    points = 2 * sum(P * x * (3 * L**2 - 4 * x**2) / (48 * ei) for x in a)
    c = L / 2 - 3.2
    udl = 2 * Q * (1.5 * L**2 * c**2 - c**4) / (48 * ei)
    # the track line 2.5 m off the axis also moves by e theta: the torque e P of each load twists the girder,
    # theta(L/2) = T a / (2 GJ) for a torque T at a <= L/2 (shaft fixed at both ends), symmetric
    gj = G * J
    torsion = E_OFF**2 * (2 * sum(P * x / (2 * gj) for x in a) + 2 * Q * c**2 / (4 * gj))
    expected = points + udl + torsion
    got = result.deflection[0][0]  # the largest over the stations: mid-span
    assert got == pytest.approx(expected, rel=1e-4)  # FE exact at the nodes, trapezoid on 0.1 m: ~1e-5
    assert result.deflection_x[0][0] == pytest.approx(L / 2)
    # Phi_2 and Phi_3 of 6.4.5.2 with L_Phi = L (a simply supported span)
    phi2 = min(1.67, max(1.0, 1.44 / (math.sqrt(L) - 0.2) + 0.82))
    phi3 = min(2.0, max(1.0, 2.16 / (math.sqrt(L) - 0.2) + 0.73))
    assert dfm.dynamic_factor(beam(), "careful")[0] == pytest.approx(phi2, rel=1e-12)
    assert dfm.dynamic_factor(beam(), "standard")[0] == pytest.approx(phi3, rel=1e-12)
    alpha = 1.21
    assert alpha * phi3 * got == pytest.approx(alpha * phi3 * expected, rel=1e-4)  # what the check compares with L/600


def test_end_rotation(result):
    ei = E * I_Y
    best = 0.0
    for x0 in np.arange(-5.6, L + 0.8, 0.1):  # the first axle's position
        axles = x0 + np.array([0.0, 1.6, 3.2, 4.8])
        on = axles[(axles >= 0) & (axles <= L)]
        b = L - on
        # bending, and the torsion of the track line e theta'(0) = e^2 P b / (GJ L) (shaft fixed at both ends)
        rot = sum(P * (bb * (L**2 - bb**2) / (6 * ei * L) + E_OFF**2 * bb / (G * J * L)) for bb in b)
        integral = lambda bb: (L**2 * bb**2 / 2 - bb**4 / 4) / (6 * ei * L) + E_OFF**2 * bb**2 / (2 * G * J * L)  # noqa: E731
        lo, hi = max(0.0, x0 - 0.8), min(L, x0 + 5.6)  # the distributed load outside [lo, hi]
        udl = integral(L) - (integral(L - lo) - integral(L - hi)) if hi > lo else integral(L)
        best = max(best, rot + Q * udl)
    # bending alone agrees to 6e-6; the torsion's slope at the end is the first element's mean (the twist is
    # linear in an element), so the distributed load inside that element (0.5 m) is missed: e^2 q l / (2 GJ)
    # = 3.8e-7 rad, 1.0e-3 of the total
    assert result.end_rotation[0] == pytest.approx([best, best], rel=1.2e-3)


def test_twist_of_an_eccentric_track(result):
    gj = G * J

    def theta(x, a):  # rotation at x under a unit torque at a, shaft fixed at 0 and L
        x = np.asarray(x, dtype=float)
        inside = (x >= 0) & (x <= L)
        out = np.where(x <= a, x * (L - a), a * (L - x)) / (gj * L)
        return np.where(inside, out, 0.0)

    ds = 0.1
    s = np.arange(0.0, L + ds / 2, ds)
    best = 0.0
    for x in np.arange(-3.0, L + 1e-9, 0.5):  # the first rail section, on the element nodes (0.5 m)
        eta = GAUGE_TWIST * (theta(x, s) - theta(x + 3.0, s)) * E_OFF  # twist per unit vertical load at s
        for sign in (1.0, -1.0):
            e = sign * eta
            pos = np.maximum(e, 0.0)
            for x0 in np.arange(-5.6, L + 0.8, ds):
                axles = x0 + np.array([0.0, 1.6, 3.2, 4.8])
                pts = sum(P * np.interp(a, s, e, left=0.0, right=0.0) for a in axles)
                out = (s < x0 - 0.8) | (s > x0 + 5.6)
                udl = Q * np.trapezoid(np.where(out, pos, 0.0), s)
                best = max(best, pts + udl)
    assert result.twist[0] == pytest.approx(best, rel=2e-3)  # the test's masked trapezoid vs the cumulative one
    # a centred track twists nothing
    assert dfm.static_deformations(beam(offset=0.0)).twist[0] < 1e-6 * best


GAUGE_TWIST = 1.435


def test_first_lateral_frequency():
    mb = modal_bridge(beam(), 60.0)
    f_fe = dfm.first_lateral_frequency(mb.frequencies, mb.mode_types)
    f_exact = math.pi / (2 * L**2) * math.sqrt(E * I_Z / M)
    assert f_fe == pytest.approx(f_exact, rel=1e-4)  # 64 cubic elements: the first mode to ~1e-8


def test_line_operator_is_the_modes_rail_shape():
    """The functional of the line's displacement applied to the mode shapes gives the modal bridge's rail
    shapes (the same interpolation), so the static and dynamic checks read the same line."""
    from tb_exudyn.structure.fe import bridge_modes
    modes = bridge_modes(beam(), 60.0)
    mb = modal_bridge(beam(), 60.0)
    x = np.linspace(0.3, L - 0.3, 17)
    op = dfm.line_operator(modes.model, x, E_OFF, 1.64)
    np.testing.assert_allclose(op @ modes.shapes, mb.rail_shapes(x).z, atol=1e-12 * np.abs(modes.shapes).max())


def test_envelope_of_a_sine_influence_line():
    """eta(s) = sin(pi s / 32) on a 32 m line (zero beyond): LM71 centred, 250 kN sum sin(pi a / 32) at
    a = 16 +- 0.8, 16 +- 2.4 plus 80 kN/m x 2 (32 / pi)(1 - cos(pi 12.8 / 32)); SW/0 placed by brute force
    (every 0.1 m, the blocks' integrals in closed form). The grid's trapezoid is within (0.1/32)^2 / 12."""
    ds, length = 0.1, 32.0
    s = np.arange(0.0, length + ds / 2, ds)
    eta = np.sin(np.pi * s / length)[:, None]
    hi, lo = dfm.envelope(eta, ds, dfm.LM71)
    axles = 16.0 + np.array([-2.4, -0.8, 0.8, 2.4])
    lm71 = 250e3 * np.sin(np.pi * axles / length).sum() + 80e3 * 2 * (length / np.pi) * (1 - np.cos(np.pi * 12.8 / length))
    assert hi[0] == pytest.approx(lm71, rel=1e-5) and lo[0] == pytest.approx(0.0, abs=1e-6)

    def block(a, b):  # closed-form integral of eta over [a, b] clipped to the line
        a, b = max(a, 0.0), min(b, length)
        return 0.0 if b <= a else (length / np.pi) * (np.cos(np.pi * a / length) - np.cos(np.pi * b / length))

    sw0 = max(133e3 * (block(x0, x0 + 15.0) + block(x0 + 20.3, x0 + 35.3)) for x0 in np.arange(-35.3, length, ds))
    hi, lo = dfm.envelope(eta, ds, dfm.SW0)
    assert hi[0] == pytest.approx(sw0, rel=1e-5)


def test_continuous_girder_takes_sw0_too():
    from tb_exudyn.scenario.io import load_bridge
    b = load_bridge("continuous_3x32m")
    sd = dfm.static_deformations(b)
    assert sd.loads == ("LM71", "SW/0") and all(j.size == 0 for j in sd.joint_rotation)
    only_lm71 = dfm.static_deformations(b, (dfm.LM71,))
    assert np.all(sd.deflection[0] >= only_lm71.deflection[0])  # the envelope of both is at least LM71's
    assert dfm.determinant_length(b)[0] == pytest.approx(1.3 * 32.0)  # Table 6.2: three spans, k = 1.3
