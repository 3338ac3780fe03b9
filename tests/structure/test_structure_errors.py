"""Bad bridge data gives a StructureError that names the bridge and what is wrong, never a failed
eigen-solve. The reference is the error contract: a ValueError subclass whose message names the
bridge, the offending key (data errors) or the unsupported motion (mechanisms)."""

from __future__ import annotations

import copy
import dataclasses
import math

import pytest

from tb_exudyn.scenario import ScenarioError

from tb_exudyn.scenario.model import BeamSection, Bearings, Frame, Pier, SimpleBeam
from tb_exudyn.structure import StructureError, modal_bridge

SECTION = BeamSection(E=3.45e10, G=1.4375e10, area=8.8889, I_y=10.947, I_z=86.216, J=22.650,
                      mass_per_length=3.39e4, rot_mass_per_length=3.8e5)
PIER = Pier(height=15.0, section=BeamSection(E=3.25e10, G=1.354e10, area=19.0, I_y=13.0, I_z=66.0,
                                             J=42.0, mass_per_length=4.77e4, rot_mass_per_length=2.0e5))
FRAME = Frame(name="bad_frame", spans=(32.0, 32.0), girder=SECTION, pier=PIER,
              bearings=Bearings(height=1.5), elements_per_span=8, elements_per_pier=4)


def _frame(**bearing_changes) -> Frame:
    return dataclasses.replace(FRAME, bearings=dataclasses.replace(FRAME.bearings, **bearing_changes))


def test_structure_error_is_a_value_error():
    assert issubclass(StructureError, ValueError)


BAD_DATA = [
    (lambda: SimpleBeam(name="zero_span", spans=(32.0, 0.0), girder=SECTION), ["spans[1]", "> 0"]),
    (lambda: SimpleBeam(name="no_span", spans=(), girder=SECTION), ["spans", "no spans"]),
    (lambda: SimpleBeam(name="nan_span", spans=(math.nan,), girder=SECTION), ["spans[0]"]),
    (lambda: SimpleBeam(name="neg_ei", spans=(32.0,), girder=dataclasses.replace(SECTION, I_y=-1.0)), ["I_y"]),
    (lambda: _frame(k_y=-1.0e8), ["k_y", ">= 0"]),
    (lambda: dataclasses.replace(FRAME, pier=dataclasses.replace(PIER, k_rotation=-5.0, footing="springs")),
     ["k_rotation"]),
    (lambda: dataclasses.replace(FRAME, pier=dataclasses.replace(PIER, height=0.0)), ["height"]),
]


@pytest.mark.parametrize("make, words", BAD_DATA)
def test_bad_data_is_refused_when_built(make, words):
    """Zero, missing, NaN or negative values: the dataclass refuses them on construction, naming the key
    (a ScenarioError is a ValueError, like StructureError)."""
    with pytest.raises(ScenarioError) as err:
        make()
    for w in words:
        assert w in str(err.value)


@pytest.mark.parametrize(
    "field, value, words",
    [("spans", (32.0, 0.0), ["bad_frame", "spans[1]", "> 0"]), ("spans", (), ["bad_frame", "no spans"])],
)
def test_structure_checks_data_that_bypassed_validation(field, value, words):
    """Defence in depth: data changed behind the dataclass's back (object.__setattr__) is still caught by
    the structural model with a StructureError naming the bridge and the key, not a failed eigen-solve."""
    bridge = copy.copy(FRAME)
    object.__setattr__(bridge, field, value)
    with pytest.raises(StructureError) as err:
        modal_bridge(bridge, 30.0)
    for w in words:
        assert w in str(err.value)


@pytest.mark.parametrize(
    "bridge, words",
    [
        # no supports at all: every bearing free
        (_frame(k_x_fixed=0.0, k_x_sliding=0.0, k_y=0.0, k_z=0.0, k_rx=0.0), ["bad_frame", "mechanism", "girder"]),
        # nothing holds the girders longitudinally
        (_frame(k_x_fixed=0.0, k_x_sliding=0.0), ["mechanism", "girder", "ux"]),
        # bearings 1.5 m below the shear centre, no torsional restraint: the girders roll
        (_frame(k_rx=0.0), ["mechanism", "girder", "rx"]),
        # piers standing free on their footing springs
        (dataclasses.replace(FRAME, pier=dataclasses.replace(PIER, footing="springs", k_translation=0.0,
                                                              k_rotation=0.0)), ["mechanism", "pier"]),
    ],
)
def test_mechanisms_are_reported_before_the_eigen_solve_fails(bridge, words):
    """A structure with a zero-stiffness motion: the shifted factorisation (K + s M, s > 0) exists,
    the zero mode is found and reported with where it moves, instead of an ARPACK or
    factorisation error."""
    with pytest.raises(StructureError) as err:
        modal_bridge(bridge, 30.0)
    for w in words:
        assert w in str(err.value)


def test_bad_frequency_settings():
    """max_frequency must be > 0; a cut-off below the lowest mode is an error naming that mode."""
    ok = SimpleBeam(name="ok", spans=(32.0,), girder=SECTION)
    with pytest.raises(StructureError, match="max_frequency"):
        modal_bridge(ok, 0.0)
    with pytest.raises(StructureError, match="no mode below"):
        modal_bridge(ok, 1.0)
    with pytest.raises(StructureError, match="not a bridge"):
        modal_bridge("li_zhu_2011_bridge", 30.0)  # type: ignore[arg-type]


def test_valid_frame_passes():
    """The same frame with its default (rigid) bearings and clamped piers is fine: the error tests
    above fail for their own reason only."""
    mb = modal_bridge(FRAME, 10.0)
    assert mb.n_modes > 0 and mb.frequencies[0] > 0.5
