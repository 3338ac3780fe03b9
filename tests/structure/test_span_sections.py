"""Sections per span (issue 29) for the ``simple_beam`` and ``frame`` kinds: ``[[girders]]``, one per span.

Problem: two spans, 32 m of the li_zhu_2011 girder and 24 m of a second section (I_y x 2, I_z x 0.5,
J x 3, mass x 1.3, polar mass x 1.2), 32 elements per span; (a) as a simple_beam (ideal supports),
(b) as a frame on one pier 2 m high of a pier section 1000 times stiffer than li_zhu's, clamped,
bearings rigid at the shear centre (height 0) and no added mass: the spans are then simply supported
on (nearly) rigid supports.
Reference: each span alone as a simply supported Euler-Bernoulli beam with St-Venant torsion, written
here: f_j = (j pi / L)^2 sqrt(E I / m) / 2 pi in bending (vertical: I_y; lateral: I_z) and
f_j = (j pi / L) sqrt(G J / I_p) / 2 pi in torsion, of THAT span's section; the modes of both spans
together, per direction, in ascending order.
Tolerances: bending 1e-5 relative (cubic Hermite elements: error O((k h)^4), measured at most 1e-6 for
these modes; the frame's piers, 1000 times stiffer, add at most 2e-6 measured); torsion
1.5 (k h)^2 / 24 relative (the twist is linear in an element with a consistent polar mass, whose
frequency error is (k h)^2 / 24, k = j pi / L, h = L / 32: 1.6e-3 for the 24 m span's second mode).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from tb_exudyn.scenario import load_bridge
from tb_exudyn.scenario.model import SimpleBeam
from tb_exudyn.structure import modal_bridge

SPANS = (32.0, 24.0)
N_EL = 32
F_MAX = 60.0


def _sections():
    g1 = load_bridge("li_zhu_2011_bridge").girder
    g2 = g1.replace(I_y=2.0 * g1.I_y, I_z=0.5 * g1.I_z, J=3.0 * g1.J, mass_per_length=1.3 * g1.mass_per_length,
                    rot_mass_per_length=1.2 * g1.rot_mass_per_length)
    return g1, g2


def _closed_form(sections) -> dict[str, list[tuple[float, float]]]:
    """direction -> [(f [Hz], relative tolerance)] of every mode below F_MAX, both spans, ascending."""
    out: dict[str, list[tuple[float, float]]] = {"vertical": [], "lateral": [], "torsion": []}
    for L, g in zip(SPANS, sections):
        for j in range(1, 50):
            k = j * math.pi / L
            for d, f in (("vertical", k * k * math.sqrt(g.E * g.I_y / g.mass_per_length) / (2 * math.pi)),
                         ("lateral", k * k * math.sqrt(g.E * g.I_z / g.mass_per_length) / (2 * math.pi)),
                         ("torsion", k * math.sqrt(g.G * g.J / g.rot_mass_per_length) / (2 * math.pi))):
                tol = 1.5 * (k * L / N_EL) ** 2 / 24 if d == "torsion" else 1e-5
                if f <= F_MAX:
                    out[d].append((f, tol))
    return {d: sorted(v) for d, v in out.items()}


def _bridges():
    g1, g2 = _sections()
    simple = SimpleBeam(name="two_sections", spans=SPANS, girders=(g1, g2), elements_per_span=N_EL)
    fr = load_bridge("li_zhu_2011_bridge")
    stiff = fr.pier.section.replace(E=1e3 * fr.pier.section.E, G=1e3 * fr.pier.section.G)
    frame = fr.replace(spans=SPANS, girder=None, girders=(g1, g2), code=None, elements_per_span=N_EL,
                       pier=fr.pier.replace(section=stiff, footing="fixed", height=2.0),
                       bearings=fr.bearings.replace(height=0.0),
                       added_mass=fr.added_mass.replace(mass_per_length=0.0, rot_mass_per_length=0.0))
    return {"simple_beam": simple, "frame": frame}


@pytest.mark.parametrize("kind", ["simple_beam", "frame"])
def test_each_span_has_its_own_sections_frequencies(kind):
    bridge = _bridges()[kind]
    mb = modal_bridge(bridge, F_MAX)
    want = _closed_form(bridge.sections)
    for d, rows in want.items():
        got = sorted(f for f, t in zip(mb.frequencies, mb.mode_types) if t == d)
        assert len(got) == len(rows), (d, got, rows)
        for g, (f, tol) in zip(got, rows):
            assert abs(g - f) <= tol * f, (kind, d, g, f)
    # not one section for both: the first vertical mode of each span lies in that span alone
    names = list(mb.station_names)
    mid1, mid2 = names.index("span1.mid"), names.index("span2.mid")
    z = mb.station_shapes[:, 1, :]
    first = [k for k, t in enumerate(mb.mode_types) if t == "vertical"][:2]
    spans = sorted(0 if abs(z[mid1, k]) > abs(z[mid2, k]) else 1 for k in first)
    assert spans == [0, 1]
    for k in first:
        small, big = sorted((abs(z[mid1, k]), abs(z[mid2, k])))
        assert small <= 1e-3 * big


def test_closed_form_modes_take_a_section_per_span():
    """The library's closed form (builder.closed_form_modes, the FE's check) of the same simple_beam gives
    the frequencies written here to round-off (1e-12: the same formula)."""
    from tb_exudyn.builder import closed_form_modes

    bridge = _bridges()["simple_beam"]
    cf = closed_form_modes(bridge, F_MAX)
    want = _closed_form(bridge.sections)
    for d, rows in want.items():
        got = sorted(f for f, t in zip(cf.frequencies, cf.mode_types) if t == d)
        np.testing.assert_allclose(got, [f for f, _ in rows], rtol=1e-12)


def test_one_girder_is_every_span_section():
    fr = load_bridge("li_zhu_2011_bridge")
    assert fr.sections == (fr.girder,) * 3 and fr.section_key(2) == "girder"
    g1, g2 = _sections()
    b = _bridges()["simple_beam"]
    assert b.sections == (g1, g2) and b.section_key(1) == "girders[1]"


def test_mass_case_of_a_section_per_span():
    """EN 1991-2 mass cases (scenario.with_mass_case) of single_span_32m's data with two spans of two
    sections: the ballast (11 677.75 kg/m at 1800 kg/m^3, upper case 2000 kg/m^3) lies on each span alike,
    so each section's mass per length gains dm = 11 677.75 (2000 / 1800 - 1) kg/m and its polar mass the
    same ratio (exact arithmetic of the data: 1e-12)."""
    from tb_exudyn.scenario import with_mass_case

    base = load_bridge("single_span_32m")
    g1, g2 = _sections()
    two = base.replace(spans=SPANS, girder=None, girders=(g1, g2))
    upper = with_mass_case(two, "upper")
    dm = 11677.75 * (2000.0 / 1800.0 - 1.0)
    for before, after in zip(two.girders, upper.girders):
        assert after.mass_per_length == pytest.approx(before.mass_per_length + dm, rel=1e-12)
        ratio = after.mass_per_length / before.mass_per_length
        assert after.rot_mass_per_length == pytest.approx(before.rot_mass_per_length * ratio, rel=1e-12)
    assert upper.code.ballast_density == pytest.approx(2000.0, rel=1e-12)
