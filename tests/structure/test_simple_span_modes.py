"""A simply supported span (SimpleBeam): frequencies, mesh convergence, static deflection.

The girder is the 32 m box girder of the Xia/Zhang research code (docs/references.md, bridges) with its total
vibrating mass of 3.39e4 kg/m. References are closed forms evaluated in the tests:
bending f_j = (j pi / L)^2 sqrt(E I / m) / (2 pi), torsion f_j = (j pi / L) sqrt(G J / I_p) / (2 pi),
static midspan deflection P L^3 / (48 E I) and its modal series
(2 P L^3 / (pi^4 E I)) sum over odd j of 1 / j^4 (docs/references.md, validation case 1).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from tb_exudyn.scenario.model import BeamSection, SimpleBeam
from tb_exudyn.structure.assembly import assemble
from tb_exudyn.structure.fe import bridge_modes, modal_bridge, solve_modes, static_displacement

L = 32.0
GIRDER = BeamSection(E=3.45e10, G=1.4375e10, area=8.8889, I_y=10.947, I_z=86.216, J=22.650,
                     mass_per_length=3.39e4, rot_mass_per_length=3.8304e5)


def _span(n_el: int, section: BeamSection = GIRDER) -> SimpleBeam:
    return SimpleBeam(name="span", spans=(L,), girder=section, elements_per_span=n_el)


def _bending(j: int, inertia: float, s: BeamSection = GIRDER) -> float:
    return (j * math.pi / L) ** 2 * math.sqrt(s.E * inertia / s.mass_per_length) / (2 * math.pi)


def _torsion(j: int, s: BeamSection = GIRDER) -> float:
    return (j * math.pi / L) * math.sqrt(s.G * s.J / s.rot_mass_per_length) / (2 * math.pi)


def _of_type(modes, kind: str) -> np.ndarray:
    return np.array([f for f, t in zip(modes.frequencies, modes.mode_types) if t == kind])


def test_first_five_vertical_lateral_torsion_frequencies():
    """First 5 vertical (I_y), lateral (I_z) and torsional modes of one 32 m span within 0.1 %.

    128 elements: the linear torsion element's frequency error is about (k h)^2 / 24, for the
    5th mode k h = 5 pi / 128, i.e. 0.06 % (< 0.1 %); the Hermite bending error is ~(k h)^4,
    far below. Mode types come from the kinetic-energy classification, so this also checks it.
    """
    modes = bridge_modes(_span(128), 370.0)
    for kind, ref in (
        ("vertical", [_bending(j, GIRDER.I_y) for j in range(1, 6)]),
        ("lateral", [_bending(j, GIRDER.I_z) for j in range(1, 6)]),
        ("torsion", [_torsion(j) for j in range(1, 6)]),
    ):
        got = _of_type(modes, kind)[:5]
        assert got.size == 5, kind
        assert np.max(np.abs(got / ref - 1.0)) < 1e-3, (kind, got, ref)


@pytest.mark.parametrize("kind, inertia, order", [("vertical", GIRDER.I_y, 4.0), ("torsion", None, 2.0)])
def test_mesh_convergence_rate(kind, inertia, order):
    """Frequency error of mode 3 with 8, 16, 32 elements: Hermite cubic bending with consistent
    mass converges as h^4, linear torsion as h^2 (eigenvalue error O(h^(2(p+1-m)))). The observed
    rate log2(e_h / e_(h/2)) must be within 0.1 of the theory (the pre-asymptotic drift at
    8 elements, k h = 3 pi / 8, is a few hundredths; the errors, 1e-7 and more, are far above
    round-off)."""
    ref = _bending(3, inertia) if inertia else _torsion(3)
    errors = []
    for n in (8, 16, 32):
        f = _of_type(bridge_modes(_span(n), 1.2 * ref * 1.5), kind)[2]
        errors.append(abs(f / ref - 1.0))
    rates = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    assert np.all(np.abs(rates - order) < 0.1), (errors, rates)


def test_static_midspan_deflection_direct_and_modal():
    """Central point load P on one span (16 elements, node at midspan).

    Direct FE static solution: the Hermite element is nodally exact for point loads, so
    w(L/2) = P L^3 / (48 E I) to round-off (1e-10 relative).
    Modal sum w = sum_k phi_k(L/2)^2 P / omega_k^2 over the vertical modes: it follows the
    closed-form truncated series (2 P L^3 / (pi^4 E I)) sum_{j odd <= J} 1 / j^4 to the FE
    frequency error of those modes (< 1e-4 for j <= 7 with 16 elements), converges
    monotonically to P L^3 / (48 E I) as modes are added, and with all vertical modes of the
    model equals the direct FE solution to round-off (1e-9).
    """
    p = 1.0e6
    model = assemble(_span(16))
    mid = int(np.argmin(np.abs(model.coordinates[:, 0] - L / 2)))
    load = np.zeros(model.n_dof)
    load[model.dof(mid, "uz")] = p
    exact = p * L**3 / (48 * GIRDER.E * GIRDER.I_y)
    w_direct = static_displacement(model, load)[model.dof(mid, "uz")]
    assert w_direct == pytest.approx(exact, rel=1e-10)

    modes = solve_modes(model, 1e5)
    vertical = [k for k, t in enumerate(modes.mode_types) if t == "vertical"]
    phi = modes.shapes[model.dof(mid, "uz"), vertical]
    terms = phi**2 * p / modes.omega[vertical] ** 2
    partial = np.cumsum(terms)
    series = 2 * p * L**3 / (math.pi**4 * GIRDER.E * GIRDER.I_y) * np.cumsum(
        [1.0 / j**4 if j % 2 else 0.0 for j in range(1, 8)]
    )
    assert np.allclose(partial[:7], series, rtol=1e-4)
    errors = np.abs(partial[::2] - exact)  # even modes add nothing at midspan
    assert np.all(np.diff(errors) <= 1e-15 * exact)
    assert partial[-1] == pytest.approx(w_direct, rel=1e-9)


def test_timoshenko_span_matches_shear_beam_closed_form():
    """Shear-flexible span (shear area factor 0.4) without rotary inertia of bending:
    omega_j^2 = E I k^4 / (m (1 + E I k^2 / (G A_s))), k = j pi / L (Timoshenko beam with the
    rotary inertia term dropped, as in the element). First 3 vertical modes within 0.1 %
    (64 elements; the discretisation error is of the Euler-Bernoulli size, ~1e-7).
    The shear correction itself is 3.5 % to 25 %, so the test cannot pass without it."""
    section = BeamSection(**{**GIRDER.__dict__, "shear_area_factor": 0.4})
    modes = bridge_modes(_span(64, section), 60.0)
    got = _of_type(modes, "vertical")[:3]
    a_s = 0.4 * GIRDER.area
    ref = []
    for j in (1, 2, 3):
        k = j * math.pi / L
        ei = GIRDER.E * GIRDER.I_y
        ref.append(math.sqrt(ei * k**4 / (GIRDER.mass_per_length * (1 + ei * k**2 / (GIRDER.G * a_s)))) / (2 * math.pi))
    assert np.max(np.abs(got / np.array(ref) - 1)) < 1e-3
    assert got[0] < 0.97 * _bending(1, GIRDER.I_y)


def test_effective_mass_of_the_first_vertical_mode():
    """A simply supported uniform span's first mode carries 8 / pi^2 = 81.06 % of the span's mass
    as effective mass (closed form: (integral of m sin)^2 / integral of m sin^2). The FE value
    (16 elements) matches to the shape's discretisation error (1e-4); its lateral and torsional
    effective masses are zero (decoupled)."""
    modes = bridge_modes(_span(16), 10.0)
    assert modes.mode_types[0] == "vertical"
    assert modes.effective_masses[0, 1] == pytest.approx(8 / math.pi**2 * GIRDER.mass_per_length * L, rel=1e-4)
    assert modes.effective_masses[0, 0] < 1e-9 * modes.effective_masses[0, 1]


def test_modal_bridge_of_two_spans_keeps_equal_spans_apart():
    """Two equal independent spans have equal frequencies; the model solves its independent parts
    separately, so each mode lives on one span (station shapes zero on the other), as the
    closed form's modes do. Frequencies agree with simply_supported_modes' closed form (0.01 %
    at 32 elements for the first 4 modes)."""
    bridge = SimpleBeam(name="two", spans=(L, L), girder=GIRDER, elements_per_span=32, damping_ratio=0.02)
    mb = modal_bridge(bridge, 16.0)
    assert mb.mode_types[:2] == ("vertical", "vertical")
    assert mb.frequencies[:2] == pytest.approx([_bending(1, GIRDER.I_y)] * 2, rel=1e-4)
    mid1 = mb.station_names.index("span1.mid")
    mid2 = mb.station_names.index("span2.mid")
    z1, z2 = mb.station_shapes[mid1, 1, :2], mb.station_shapes[mid2, 1, :2]
    assert np.all(np.abs(z1 * z2) < 1e-12)  # each mode on one span only
    assert np.all(mb.damping_ratios == 0.02)


def test_rayleigh_damping_as_modal_ratios():
    """Rayleigh damping C = alpha M + beta K is diagonal in mass-normalised modes with
    zeta_k = alpha / (2 w_k) + beta w_k / 2; coefficients fitted to zeta at f1 and f2 reproduce
    zeta there exactly and give less in between (round-off tolerance). modal_bridge(rayleigh=...)
    uses those ratios instead of the bridge's damping_ratio."""
    from tb_exudyn.structure import rayleigh_coefficients, rayleigh_damping_ratios

    alpha, beta = rayleigh_coefficients(2.0, 20.0, 0.05)
    w = 2 * math.pi * np.array([2.0, 20.0, 6.0])
    z = rayleigh_damping_ratios(w, alpha, beta)
    assert z[:2] == pytest.approx([0.05, 0.05], rel=1e-12)
    assert z[2] < 0.05
    mb = modal_bridge(_span(16), 30.0, rayleigh=(alpha, beta))
    assert mb.damping_ratios == pytest.approx(alpha / (2 * mb.omega) + beta * mb.omega / 2, rel=1e-12)


def test_modal_report_table():
    """The report lists every mode once with its frequency, type, energy fractions (summing to 1)
    and effective-mass percentages; the first row of a simple span is the 81.06 % vertical mode."""
    from tb_exudyn.structure import modal_report

    rep = modal_report(bridge_modes(_span(16), 30.0))
    lines = rep.table().splitlines()
    assert len(lines) == 2 + rep.frequencies.size
    assert "vertical" in lines[2] and "81.06" in lines[2]
    assert np.allclose(rep.energy_fractions.sum(axis=1), 1.0)
    assert len(rep.table(3).splitlines()) == 5
