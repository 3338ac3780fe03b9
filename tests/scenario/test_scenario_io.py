"""Scenario data model: every model file loads, TOML round trip, replace()."""

from __future__ import annotations

import math
import tomllib

import pytest

import tb_exudyn as tbx
from tb_exudyn.scenario import (
    Car15,
    Frame,
    ScenarioError,
    SimpleBeam,
    load_bridge,
    load_vehicle,
    model_files,
    save_scenario,
    scenario_from_dict,
)
from tb_exudyn.scenario.model import BRIDGE_KINDS


@pytest.mark.parametrize("name", sorted(model_files("scenarios")))
def test_every_scenario_file_loads_and_round_trips(name, tmp_path):
    """Load a library scenario, save it (resolved, vehicles and bridge inline), load again: the two
    frozen dataclass trees must be equal (exact: the TOML writer prints floats with repr, which
    round-trips every float64 exactly, and inf is written as TOML's inf)."""
    sc = tbx.load_scenario(name)
    path = save_scenario(sc, tmp_path / f"{name}.toml")
    again = tbx.load_scenario(path)
    assert again == sc
    assert again.train.vehicles == sc.train.vehicles


@pytest.mark.parametrize("name", sorted(model_files("vehicles")))
def test_every_vehicle_file_loads(name):
    v = load_vehicle(name)
    assert v.name == name
    assert v.source, "every model file cites its source"


@pytest.mark.parametrize("name", sorted(model_files("bridges")))
def test_every_bridge_file_loads(name):
    b = load_bridge(name)
    assert isinstance(b, tuple(BRIDGE_KINDS.values()))
    assert b.name == name
    assert b.source, "every model file cites its source"


def test_models_with_unsourced_values_say_check():
    """Convention: a model file whose values are not all from its source says [check] in its notes."""
    for category in ("vehicles", "bridges"):
        for name, path in model_files(category).items():
            text = path.read_text()
            if "[check]" in text:
                data = tomllib.loads(text)
                assert "[check]" in data.get("notes", ""), f"{path}: [check] values must be named in notes"


def test_reference_study_scenario_matches_the_paper():
    """li_zhu_2011 as section 4.1 of the study states it: ICE M+T+T+M at 220 km/h, 3 x 32 m spans on
    15 m piers, track 2.5 m off the centre line, 100 m before and 50 m after, 200 frequencies 0.3-60 Hz,
    vertical, alignment and cross-level from the German low-interference spectrum."""
    sc = tbx.load_scenario("li_zhu_2011")
    assert [v.name for v in sc.train.vehicles] == ["ice_motor", "ice_trailer", "ice_trailer", "ice_motor"]
    assert sc.speed_kmh == 220.0 and math.isclose(sc.speed, 220 / 3.6)
    assert isinstance(sc.bridge, Frame) and sc.bridge.spans == (32.0, 32.0, 32.0)
    assert sc.bridge.pier.height == 15.0 and sc.bridge.track_offset == 2.5
    assert (sc.track.lead_in, sc.track.run_out) == (100.0, 50.0)
    a = sc.analysis
    assert (a.freq_min, a.freq_max, a.n_freq) == (0.3, 60.0, 200)
    assert sc.track.irregularities == ("german_low.vertical", "german_low.alignment", "german_low.cross_level")


def test_ice_car_geometry():
    """Axle positions from the ICE geometry: 2 (8.6875 + 1.25) + 4.9 = 24.775 m between first axles of
    neighbouring cars (docs/references.md, vehicles); axles of one car at 0, 2.5, 17.375, 19.875 m."""
    car = load_vehicle("ice_motor")
    assert isinstance(car, Car15)
    assert car.axle_offsets == pytest.approx((0.0, 2.5, 17.375, 19.875), abs=1e-12)
    sc = tbx.load_scenario("li_zhu_2011")
    pos = sc.train.axle_positions
    assert len(pos) == 16
    assert pos[4] == pytest.approx(24.775, abs=1e-12)
    assert sc.train.length == pytest.approx(3 * 24.775 + 19.875, abs=1e-9)
    assert sc.train.mass == pytest.approx(2 * (48000 + 6400 + 9600) + 2 * (44000 + 4800 + 9600), rel=1e-12)


def test_replace_returns_a_validated_copy():
    sc = tbx.load_scenario("quick")
    faster = sc.replace(speed_kmh=300.0)
    assert faster.speed_kmh == 300.0 and sc.speed_kmh == 250.0
    assert faster.train is sc.train
    with pytest.raises(ScenarioError, match="freq_max"):
        sc.replace(analysis=sc.analysis.replace(time_step=0.01))


def test_scenario_built_in_python_equals_loaded():
    """A scenario built from plain dicts in Python (as examples do) equals the TOML one."""
    sc = tbx.load_scenario("quick")
    data = tomllib.loads((model_files("scenarios")["quick"]).read_text())
    assert scenario_from_dict(data) == sc
