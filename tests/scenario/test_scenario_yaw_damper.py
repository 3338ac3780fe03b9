"""The optional yaw-damper table of a car15 (Car15.yaw_damper): absent by default, read from TOML,
validated like every other field, and written back by save_scenario."""

from __future__ import annotations

import tomllib

import pytest

from tb_exudyn.scenario import ScenarioError, YawDamper, load_scenario, load_vehicle, model_files, save_scenario
from tb_exudyn.scenario.toml_io import dumps_toml

MOTOR = tomllib.loads(model_files("vehicles")["ice_motor"].read_text())


def test_absent_by_default_in_every_shipped_car():
    """No shipped vehicle has a yaw damper: no source gives one (see the report of issue 14)."""
    for name in ("ice_motor", "ice_trailer", "ave_s103"):
        assert load_vehicle(name).yaw_damper is None


def test_read_validated_and_written_back(tmp_path):
    data = dict(MOTOR, yaw_damper={"c_x": 2.5e5, "half_span": 1.35})
    path = tmp_path / "car.toml"
    path.write_text(dumps_toml(data))
    car = load_vehicle(path)
    assert car.yaw_damper == YawDamper(c_x=2.5e5, half_span=1.35)
    sc = load_scenario("quick")
    sc = sc.replace(train=sc.train.replace(vehicles=(car,)))
    again = load_scenario(save_scenario(sc, tmp_path / "sc.toml"))
    assert again == sc
    # and without one, the saved file has no yaw_damper table and loads equal
    plain = load_scenario("quick")
    text = (save_scenario(plain, tmp_path / "plain.toml")).read_text()
    assert "yaw_damper" not in text and load_scenario(tmp_path / "plain.toml") == plain


@pytest.mark.parametrize("table, key", [
    ({"c_x": -1.0, "half_span": 1.3}, "yaw_damper.c_x"),
    ({"c_x": 0.0, "half_span": 1.3}, "yaw_damper.c_x"),
    ({"c_x": 1e5, "half_span": 0.0}, "yaw_damper.half_span"),
    ({"c_x": 1e5}, "yaw_damper.half_span"),
    ({"c_x": 1e5, "half_span": 1.3, "k_series": 1e7}, "yaw_damper.k_series"),
    (3.0, "yaw_damper"),
])
def test_bad_tables_name_the_key(tmp_path, table, key):
    path = tmp_path / "bad_car.toml"
    path.write_text(dumps_toml(dict(MOTOR, yaw_damper=table)))
    with pytest.raises(ScenarioError) as err:
        load_vehicle(path)
    assert key in str(err.value) and "bad_car.toml" in str(err.value)
