"""Bridge guards of issue 27: a degenerate bridge is a one-line user error naming the bridge key to
change, and a bridge (or train) too large for the memory is refused before it is assembled.

References: the error contract (a ScenarioError naming file, key, value, allowed); for the size
estimate, the finite-element solve itself (tb_exudyn.structure.fe.solve_modes) on the same model, so
the counts of a SimpleBeam are compared exactly (its spans are independent components, solved alone
by both); a Frame's estimate is an upper one (compared as >=, and within a factor 2 so that it is no
mere bound); the coordinates per vehicle are compared exactly with built models.
"""

from __future__ import annotations

import dataclasses
import pickle

import pytest

from tb_exudyn.errors import ResourceError, ScenarioError, UserError
from tb_exudyn.scenario import load_scenario
from tb_exudyn.scenario.model import BeamSection, Bearings, Frame, Pier, SimpleBeam
from tb_exudyn.structure import StructureError, located, modal_bridge
from tb_exudyn.structure.fe import bridge_modes, solve_modes
from tb_exudyn.structure.size import BridgeSizeError, bridge_size, check_bridge_size, estimate_modes

GIRDER = BeamSection(E=3.45e10, G=1.4375e10, area=8.8889, I_y=10.947, I_z=86.216, J=22.650,
                     mass_per_length=3.39e4, rot_mass_per_length=383040.5)
PIER = Pier(height=15.0, section=BeamSection(E=3.25e10, G=1.354e10, area=19.0, I_y=13.0, I_z=66.0,
                                             J=42.0, mass_per_length=4.77e4, rot_mass_per_length=2.0e5))
FRAME = Frame(name="frame", spans=(32.0, 32.0, 32.0), girder=GIRDER, pier=PIER, bearings=Bearings(height=1.5),
              elements_per_span=8, elements_per_pier=4)


def _unchecked(section: BeamSection, **changes) -> BeamSection:
    """The section with ``changes`` set past the schema: the schema's lower bounds (tb_exudyn.scenario.schema
    BRIDGE_MODULUS, BRIDGE_SECOND_MOMENT) refuse a modulus of 1e-20 first; the structure's own guard
    stays for data that reach it by another way, and is tested on such a section."""
    out = dataclasses.replace(section)
    for key, value in changes.items():
        object.__setattr__(out, key, value)
    return out


def test_the_schema_refuses_a_section_too_soft_before_the_structure_sees_it():
    """E, G and I_y of 1e-20 are slips of units: refused at construction, naming the key and the bound."""
    for key in ("E", "G", "I_y"):
        with pytest.raises(ScenarioError) as err:
            dataclasses.replace(GIRDER, **{key: 1e-20})
        assert err.value.key == key and ">= 1e" in err.value.allowed and "slip of units" in str(err.value)


def _error(bridge) -> StructureError:
    with pytest.raises(StructureError) as err:
        modal_bridge(bridge, 30.0)
    return err.value


def test_structure_error_is_a_user_error_that_pickles():
    err = _error(SimpleBeam(name="soft", spans=(32.0,), girder=_unchecked(GIRDER, E=1e-20)))
    assert isinstance(err, ScenarioError) and isinstance(err, UserError) and isinstance(err, ValueError)
    again = pickle.loads(pickle.dumps(err))
    assert type(again) is StructureError and str(again) == str(err) and again.key == err.key


@pytest.mark.parametrize("bridge, key", [
    (SimpleBeam(name="b", spans=(32.0,), girder=_unchecked(GIRDER, E=1e-20)), "girder.E"),
    (SimpleBeam(name="b", spans=(32.0,), girder=_unchecked(GIRDER, I_y=1e-20)), "girder.I_y"),
    (SimpleBeam(name="b", spans=(32.0,), girder=_unchecked(GIRDER, G=1e-20)), "girder.G"),
    (dataclasses.replace(FRAME, bearings=Bearings(height=1.5, k_x_fixed=0.0)), "bearings.k_x_fixed"),
    (dataclasses.replace(FRAME, bearings=Bearings(height=1.5, k_rx=0.0)), "bearings.k_rx"),
    (dataclasses.replace(FRAME, pier=dataclasses.replace(PIER, footing="springs", k_translation=0.0, k_rotation=0.0)),
     "pier.k_"),
])
def test_a_mechanism_names_the_key_that_lets_it_move(bridge, key):
    """Problem: a bridge with a free direction (a bearing or footing stiffness 0) or a section too
    soft for its mass (a modulus of 1e-20 N/m^2). The error names that key (and the bridge)."""
    err = _error(bridge)
    assert err.key.startswith(key), str(err)
    assert "mechanism" in str(err) and f"bridge '{bridge.name}'" in str(err)


def test_overflowing_section_names_the_extreme_value():
    err = _error(SimpleBeam(name="b", spans=(32.0,), girder=dataclasses.replace(GIRDER, E=1e308)))
    assert err.key == "girder.E" and "overflow" in str(err)


def test_located_in_the_scenario_or_in_the_bridge_file(tmp_path):
    """An inline bridge's error names the scenario's file and bridge.KEY; a bridge read from its own
    file names that file and the key in it; the cut-off names analysis.mode_max_frequency."""
    sc = load_scenario("quick")
    err = StructureError("bridge 'x'", "girder.E", 1e-20, "more", "mechanism")
    inline = located(err, sc.replace(bridge=dataclasses.replace(sc.bridge)))  # a copy: no file of its own
    assert inline.file == sc.source_file and inline.key == "bridge.girder.E" and "bridge 'x'" in str(inline)
    own = located(err, sc)
    assert own.file.endswith("single_span_32m.toml") and own.key == "girder.E"
    cut = located(StructureError("bridge 'x'", "max_frequency", 1.0, "more"), sc)
    assert cut.file == sc.source_file and cut.key == "analysis.mode_max_frequency"


@pytest.mark.parametrize("spans", [(32.0,), (32.0,) * 7, (24.0, 32.0, 24.0, 31.3)])
def test_simple_beam_mode_count_is_exact(spans):
    bridge = SimpleBeam(name="b", spans=spans, girder=GIRDER)
    assert estimate_modes(bridge, 60.0, 0, solve_modes) == bridge_modes(bridge, 60.0).n_modes


@pytest.mark.parametrize("n_spans", [2, 3, 6])
def test_frame_mode_count_is_an_upper_estimate(n_spans):
    bridge = dataclasses.replace(FRAME, spans=(32.0,) * n_spans)
    real = bridge_modes(bridge, 60.0).n_modes
    est = estimate_modes(bridge, 60.0, 0, solve_modes)
    assert real <= est <= 2 * real, (real, est)


def test_max_modes_caps_the_estimate():
    bridge = SimpleBeam(name="b", spans=(32.0,) * 50, girder=GIRDER)
    assert bridge_size(bridge, 60.0, 30, solve_modes).n_modes == 30


def test_too_large_a_bridge_is_refused_and_the_count_given_fits():
    """With a limit of 1 GB, the estimate (a n^2 + b n bytes for n equal spans) gives the largest span
    count that fits: that count passes the same check, one more span is refused."""
    limit = 10**9
    big = SimpleBeam(name="long", spans=(32.0,) * 1000, girder=GIRDER)
    with pytest.raises(BridgeSizeError) as err:
        check_bridge_size(big, 60.0, 0, solve_modes, limit)
    assert isinstance(err.value, ResourceError) and err.value.key == "spans"
    fit = int(str(err.value).split("about ")[-1].split(" such spans")[0])
    assert 10 < fit < 1000
    check_bridge_size(dataclasses.replace(big, spans=(32.0,) * fit), 60.0, 0, solve_modes, limit)
    with pytest.raises(BridgeSizeError):
        check_bridge_size(dataclasses.replace(big, spans=(32.0,) * (fit + 1)), 60.0, 0, solve_modes, limit)


def test_the_machine_limit_refuses_1000_spans_before_assembly(monkeypatch):
    """modal_bridge itself refuses (the estimate against the memory available, here set to 4 GB)."""
    monkeypatch.setattr("tb_exudyn.structure.size.available_memory", lambda: (4 * 10**9, "4 GB (test)"))
    with pytest.raises(BridgeSizeError, match="4 GB"):
        modal_bridge(SimpleBeam(name="long", spans=(32.0,) * 1000, girder=GIRDER), 60.0)


@pytest.mark.parametrize("spans", [3, 10])
def test_the_scenario_check_refuses_a_mechanism_before_building(spans):
    """check_scenario_size (what run and modes do first): a small bridge is solved whole (3 spans), a
    larger one (10 spans, beyond the size where the mode count is estimated) by its span on the
    abutments, which is a mechanism when every span is (the same bearings carry each)."""
    from tb_exudyn.structure.guards import check_scenario_size

    sc = load_scenario("li_zhu_2011")
    bridge = sc.bridge.replace(spans=(32.0,) * spans, bearings=sc.bridge.bearings.replace(k_rx=0.0))
    if spans == 3:
        assert bridge_size(bridge, 100.0, 0, solve_modes).upper  # small: no count made, solved whole below
    with pytest.raises(StructureError) as err:
        check_scenario_size(sc.replace(bridge=bridge))
    assert err.value.key == "bearings.k_rx" and "mechanism" in str(err.value)
