"""Rail-level mode shapes along the track and output stations of the finite-element ModalBridge.

References: the sine modes of a simply supported span (closed form, amplitude sqrt(2 / (m L))),
the finite-element nodal values themselves (the interpolation must reproduce them exactly), and
finite differences of the evaluated shapes (for the slopes).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from tb_exudyn.scenario.model import BeamSection, SimpleBeam
from tb_exudyn.structure.fe import bridge_modes, line_shape_evaluator, modal_bridge_from_modes

L = 32.0
GIRDER = BeamSection(E=3.45e10, G=1.4375e10, area=8.8889, I_y=10.947, I_z=86.216, J=22.650,
                     mass_per_length=3.39e4, rot_mass_per_length=3.8304e5)
E_R, H_R = 2.5, 1.64
BRIDGE = SimpleBeam(name="rail", spans=(L, 24.0), girder=GIRDER, elements_per_span=32,
                    track_offset=E_R, track_height=H_R)


@pytest.fixture(scope="module")
def modes():
    return bridge_modes(BRIDGE, 40.0)


@pytest.fixture(scope="module")
def mb(modes):
    return modal_bridge_from_modes(modes)


def test_sine_modes_at_rail_level(mb):
    """First vertical, lateral and torsional mode of the 32 m span: rail displacements
    (dy, dz) = (v - h theta, w + e theta) with v, w, theta = sqrt(2 / (m L)) sin(pi x / L)
    (sqrt(2 / (I_p L)) for torsion), and their slopes pi / L cos(...), e.g. a torsion mode moves
    the rail by -h theta laterally and e theta vertically. 32 elements (h = 1 m, k h = pi / 32):
    Hermite bending shapes are within ~1e-5 of the amplitude (tolerance 1e-4, slopes 1e-3);
    the linear twist interpolates sin with error (k h)^2 / 8 = 1.2e-3 (tolerance 2e-3) and its
    slope is constant per element, error up to k h / 2 = 0.05 of the peak slope (tolerance 0.06).
    x = L itself is left out: it is also the start of span 2, which owns that point."""
    x = np.linspace(0.0, L, 97)[:-1]
    s = mb.rail_shapes(x)
    k = math.pi / L
    for kind, amp, comps, tol, dtol in (
        ("vertical", math.sqrt(2 / (GIRDER.mass_per_length * L)), (0.0, 1.0, 0.0), 1e-4, 1e-3),
        ("lateral", math.sqrt(2 / (GIRDER.mass_per_length * L)), (1.0, 0.0, 0.0), 1e-4, 1e-3),
        ("torsion", math.sqrt(2 / (GIRDER.rot_mass_per_length * L)), (-H_R, E_R, 1.0), 2e-3, 6e-2),
    ):
        i = mb.mode_types.index(kind)
        sign = np.sign(s.y[48, i] * comps[0] + s.z[48, i] * comps[1] + s.rx[48, i] * comps[2])
        for got, dgot, c in ((s.y, s.dy, comps[0]), (s.z, s.dz, comps[1]), (s.rx, s.drx, comps[2])):
            scale = amp * max(1.0, abs(c))
            assert np.abs(sign * got[:, i] - c * amp * np.sin(k * x)).max() < tol * scale, kind
            assert np.abs(sign * dgot[:, i] - c * amp * k * np.cos(k * x)).max() < dtol * scale * k, kind


def test_interpolation_reproduces_nodal_values_and_is_zero_off_the_bridge(modes, mb):
    """At every girder node the evaluated rail shape equals the nodal DOFs combined as
    (uy - h rx, uz + e rx, rx) (round-off, 1e-12 of the largest value); off the bridge (x < 0,
    x > length) every shape and slope is exactly zero."""
    model = modes.model
    nodes = model.girder.nodes[:32, 0]  # first span, start nodes of its elements
    x = model.coordinates[nodes, 0]
    s = mb.rail_shapes(x)
    phi = modes.shapes
    y = phi[6 * nodes + 1] - H_R * phi[6 * nodes + 3]
    z = phi[6 * nodes + 2] + E_R * phi[6 * nodes + 3]
    scale = np.abs(phi).max()
    assert np.abs(s.y - y).max() < 1e-12 * scale
    assert np.abs(s.z - z).max() < 1e-12 * scale
    assert np.abs(s.rx - phi[6 * nodes + 3]).max() < 1e-12 * scale
    off = mb.rail_shapes(np.array([-10.0, -1e-9, mb.length + 1e-9, 1e6]))
    for a in (off.y, off.z, off.rx, off.dy, off.dz, off.drx):
        assert np.all(a == 0.0)


def test_slopes_are_derivatives_of_the_values(mb):
    """Central differences (step 1e-4 m, error ~1e-8 relative) of y, z, rx inside elements equal
    the evaluated slopes dy, dz, drx to 1e-6 of the largest slope."""
    x = np.array([1.3, 7.77, 15.9, 33.1, 50.05])
    step = 1e-4
    a, b, c = mb.rail_shapes(x - step), mb.rail_shapes(x + step), mb.rail_shapes(x)
    for lo, hi, d in ((a.y, b.y, c.dy), (a.z, b.z, c.dz), (a.rx, b.rx, c.drx)):
        fd = (hi - lo) / (2 * step)
        assert np.abs(fd - d).max() < 1e-6 * np.abs(d).max()


def test_stations_and_truncation(modes, mb):
    """Stations: quarter points and midspan of each span on the girder axis, equal to the line
    evaluator at offset 0 and height 0 (round-off). truncated(n) keeps the first n columns of
    every output (exact slices)."""
    assert mb.station_names == ("span1.q1", "span1.mid", "span1.q3", "span2.q1", "span2.mid", "span2.q3")
    axis = line_shape_evaluator(modes.model, modes.shapes)
    xs = np.array([8.0, 16.0, 24.0, 38.0, 44.0, 50.0])
    r = axis(xs)
    assert np.allclose(mb.station_shapes[:, 0, :], r.y, rtol=0, atol=1e-14)
    assert np.allclose(mb.station_shapes[:, 1, :], r.z, rtol=0, atol=1e-14)
    assert np.allclose(mb.station_shapes[:, 2, :], r.rx, rtol=0, atol=1e-14)
    t = mb.truncated(3)
    x = np.linspace(-1.0, 60.0, 33)
    full, part = mb.rail_shapes(x), t.rail_shapes(x)
    outputs = ("y", "z", "rx", "dy", "dz", "drx")
    for f, p in zip((getattr(full, a) for a in outputs), (getattr(part, a) for a in outputs)):
        assert p.shape == (33, 3) and np.array_equal(p, f[:, :3])
    assert t.node_shapes.shape[2] == 3 and t.effective_masses.shape == (3, 3)


def test_frame_stations_include_pier_tops():
    """A frame reports its pier tops ('pier1.top', ...) with the (uy, uz, rx) of the top node."""
    from tb_exudyn.scenario.model import Bearings, Frame, Pier

    pier = Pier(height=15.0, section=BeamSection(E=3.25e10, G=1.354e10, area=19.0, I_y=13.0, I_z=66.0, J=42.0,
                                                 mass_per_length=4.77e4, rot_mass_per_length=2.0e5))
    frame = Frame(name="f", spans=(32.0, 32.0, 32.0), girder=GIRDER, pier=pier, bearings=Bearings(height=1.5),
                  elements_per_span=8, elements_per_pier=4)
    modes = bridge_modes(frame, 12.0)
    mb = modal_bridge_from_modes(modes)
    assert mb.station_names[-2:] == ("pier1.top", "pier2.top")
    top = modes.model.pier_top_nodes[1]
    assert np.array_equal(mb.station_shapes[-1], modes.shapes[[6 * top + 1, 6 * top + 2, 6 * top + 3]])
    assert mb.node_masses.sum() == pytest.approx(3 * 32.0 * GIRDER.mass_per_length + 2 * 15.0 * 4.77e4, rel=1e-12)
