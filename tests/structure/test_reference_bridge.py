"""The reference study's bridge (Li & Zhu: 3 x 32 m simply supported spans on 15 m piers) with
the calibrated substructure: its first lateral mode must lie at the study's 3.33 Hz.

The girder comes from models/bridges/li_zhu_2011_bridge.toml (docs/references.md, bridges). The paper
gives no pier or bearing data, so the values below are a calibration (see the structure report):
a round-ended solid pier 7.0 m x 3.0 m (section properties computed in the test from that shape),
bearings 2.3 m below the girder's shear centre, and a pile-group footing whose rotational
stiffness k_r is the one calibrated parameter. Reference: the paper's 3.33 Hz.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from tb_exudyn.scenario import load_bridge
from tb_exudyn.scenario.model import BeamSection
from tb_exudyn.structure import bridge_modes

WIDTH, THICKNESS = 7.0, 3.0  # round-ended pier: transverse width, longitudinal thickness [m]
K_ROTATION = 2.3e11  # footing rotational stiffness [N m/rad], calibrated
BEARING_HEIGHT = 2.3  # girder shear centre above the pier top [m]


def round_ended_section(width: float, thickness: float) -> tuple[float, float, float]:
    """(A, I_y, I_z) of a rectangle (width - thickness) x thickness with two half discs of
    diameter ``thickness`` at its ends; I_z about the longitudinal-vertical plane's normal
    (lateral bending), I_y for longitudinal bending."""
    r, a = thickness / 2, width - thickness
    half, c = math.pi * r * r / 2, 4 * r / (3 * math.pi)
    area = a * thickness + math.pi * r * r
    i_z = thickness * a**3 / 12 + 2 * (math.pi * r**4 / 8 - half * c * c + half * (a / 2 + c) ** 2)
    i_y = a * thickness**3 / 12 + math.pi * r**4 / 4
    return area, i_y, i_z


def calibrated_bridge():
    base = load_bridge("li_zhu_2011_bridge")
    area, i_y, i_z = round_ended_section(WIDTH, THICKNESS)
    section = BeamSection(E=3.25e10, G=3.25e10 / 2.4, area=area, I_y=i_y, I_z=i_z, J=41.0,
                          mass_per_length=2500.0 * area, rot_mass_per_length=2500.0 * (i_y + i_z))
    pier = dataclasses.replace(base.pier, section=section, footing="springs", k_translation=math.inf,
                               k_rotation=K_ROTATION, cap_mass=0.0)
    return dataclasses.replace(base, pier=pier, bearings=dataclasses.replace(base.bearings, height=BEARING_HEIGHT))


def test_round_ended_section_properties():
    """The section formula against its limits: a round-ended section with zero straight part is a
    disc (A = pi r^2, I = pi r^4 / 4), and the 7 x 3 m pier has A = 19.07 m^2, I_z = 66.25 m^4."""
    area, i_y, i_z = round_ended_section(3.0, 3.0)
    assert area == pytest.approx(math.pi * 1.5**2) and i_y == pytest.approx(math.pi * 1.5**4 / 4)
    assert i_z == pytest.approx(math.pi * 1.5**4 / 4)
    area, i_y, i_z = round_ended_section(WIDTH, THICKNESS)
    assert (area, i_y, i_z) == pytest.approx((19.069, 12.976, 66.250), abs=1e-3)


def test_first_lateral_mode_at_the_studys_frequency():
    """First lateral mode of the calibrated bridge at 3.33 Hz (Li & Zhu). Tolerance 0.3 %: k_r is
    rounded to two digits (0.1 % in frequency) and the 16/8-element mesh is converged to 1e-5.
    The mode is the in-phase sway of all three girders on both piers: it carries most (> 60 %) of
    the lateral effective mass. The piers make the bridge laterally softer than the girder alone
    (14.4 Hz simply supported), and longitudinal pier sway comes first (below the lateral mode)."""
    modes = bridge_modes(calibrated_bridge(), 30.0)
    lateral = modes.mode_types.index("lateral")
    assert modes.frequencies[lateral] == pytest.approx(3.33, rel=3e-3)
    share = modes.effective_masses[lateral, 0] / modes.total_masses[0]
    assert share > 0.6
    assert modes.mode_types[:2] == ("longitudinal", "longitudinal")
    vertical = np.array([f for f, t in zip(modes.frequencies, modes.mode_types) if t == "vertical"])
    assert 4.7 < vertical[0] < 5.2  # girder alone 5.12 Hz; the bearing height couples it with longitudinal sway


def test_solved_modes_are_kept_by_their_inputs_and_solved_again_when_these_change():
    """Problem: bridge_modes keeps its last results by (bridge data, max_frequency, max_modes), for a
    sweep's speeds and a check's trains. Reference: the uncached solve, solve_modes(assemble(bridge)),
    on the calibrated bridge. Exact: the same data must give the very same object, bitwise the
    uncached modes, with read-only arrays (a caller writing into shared modes would corrupt the
    next); other limits or data (a 1 % stiffer footing) must be solved again, never served."""
    from tb_exudyn.structure import assemble, solve_modes

    bridge = calibrated_bridge()
    first = bridge_modes(bridge, 30.0)
    assert bridge_modes(calibrated_bridge(), 30.0) is first  # equal data, another object: kept
    direct = solve_modes(assemble(bridge), 30.0)
    assert np.array_equal(first.frequencies, direct.frequencies) and np.array_equal(first.shapes, direct.shapes)
    for a in (first.frequencies, first.shapes, first.effective_masses, first.model.coordinates, first.model.mass.data):
        with pytest.raises(ValueError, match="read-only"):
            a[...] = 0.0
    assert bridge_modes(bridge, 20.0).frequencies.size < first.frequencies.size  # other limit
    assert bridge_modes(bridge, 30.0, max_modes=3).frequencies.size == 3
    stiffer = dataclasses.replace(bridge, pier=dataclasses.replace(bridge.pier, k_rotation=1.01 * K_ROTATION))
    other = bridge_modes(stiffer, 30.0)
    assert other is not first and other.frequencies[0] > first.frequencies[0]
