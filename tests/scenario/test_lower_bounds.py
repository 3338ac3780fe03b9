"""Lower bounds of masses, inertias and stiffnesses (issue 49): a value a few orders of magnitude below
any real vehicle or bridge is a slip of units, refused on loading with one line naming the file, the
key and the range, exit 2 from the command line.

References: the bounds and their reasons are stated beside them (tb_exudyn.scenario.schema: the
lightest vehicle part weighs about 1e3 kg, the softest suspension spring about 1e5 N/m, bridge
materials 1e9 N/m^2 and up). Here (a) every shipped vehicle, bridge and scenario still loads, and each
bounded value shipped lies at least two orders of magnitude above its bound (so the bound refuses no
real data: a margin, not a tolerance); (b) a value 1e-3 of the bound, or 1e-300, is refused naming the
key, in Python, in a file and on the command line.
"""

from __future__ import annotations

import dataclasses

import pytest

from tb_exudyn.errors import ScenarioError
from tb_exudyn.scenario import load_bridge, load_scenario, load_vehicle, model_files, save_scenario
from tb_exudyn.scenario.schema import (BRIDGE_AREA, BRIDGE_MASS_PER_LENGTH, BRIDGE_MODULUS, BRIDGE_ROT_MASS,
                                       BRIDGE_SECOND_MOMENT, VEHICLE_INERTIA, VEHICLE_MASS, VEHICLE_MASS_OR_0,
                                       VEHICLE_STIFFNESS, VEHICLE_STIFFNESS_OR_0)

BOUNDED = (VEHICLE_INERTIA, VEHICLE_MASS, VEHICLE_MASS_OR_0, VEHICLE_STIFFNESS, VEHICLE_STIFFNESS_OR_0,
           BRIDGE_AREA, BRIDGE_MASS_PER_LENGTH, BRIDGE_MODULUS, BRIDGE_ROT_MASS, BRIDGE_SECOND_MOMENT)


def _bounded_values(obj, path=""):
    """(key path, value, check) of every bounded number in a loaded model."""
    if dataclasses.is_dataclass(obj):
        for f in dataclasses.fields(obj):
            value, check = getattr(obj, f.name), f.metadata.get("check")
            key = f"{path}.{f.name}" if path else f.name
            if check in BOUNDED and isinstance(value, float):
                yield key, value, check
            else:
                yield from _bounded_values(value, key)
    elif isinstance(obj, tuple):
        for i, item in enumerate(obj):
            yield from _bounded_values(item, f"{path}[{i}]")


def _shipped():
    for name in model_files("vehicles"):
        yield f"vehicle {name}", load_vehicle(name)
    for name in model_files("bridges"):
        yield f"bridge {name}", load_bridge(name)
    for name in model_files("scenarios"):
        yield f"scenario {name}", load_scenario(name)


def test_every_shipped_model_loads_two_orders_above_every_lower_bound():
    seen = set()
    for label, model in _shipped():
        for key, value, check in _bounded_values(model):
            seen.add(check)
            if value == 0.0 and check.zero:
                continue
            assert value >= 100.0 * check.low, f"{label}: {key} = {value} within two orders of its bound {check.low}"
    # the shipped data reach the vehicles' and the bridges' bounds (not only one family of them)
    assert {VEHICLE_INERTIA, VEHICLE_MASS, VEHICLE_STIFFNESS, BRIDGE_MODULUS, BRIDGE_SECOND_MOMENT, BRIDGE_AREA,
            BRIDGE_MASS_PER_LENGTH, BRIDGE_ROT_MASS} <= seen


@pytest.mark.parametrize("part, key", [
    ("bogie", "inertia_pitch"), ("bogie", "mass"), ("body", "inertia_roll"), ("wheelset", "mass"),
    ("wheelset", "inertia_roll"), ("primary", "k_z"), ("secondary", "k_y"),
])
def test_a_vehicle_value_below_its_bound_is_refused_naming_the_key(part, key):
    car = load_vehicle("ice_motor")
    table = getattr(car, part)
    check = next(f.metadata["check"] for f in dataclasses.fields(table) if f.name == key)
    for value in (1e-300, 1e-3 * check.low):
        with pytest.raises(ScenarioError) as err:
            table.replace(**{key: value})
        assert err.value.key == key and f">= {check.low:g}" in err.value.allowed
        assert "slip of units" in str(err.value) and "\n" not in str(err.value)
    table.replace(**{key: check.low})  # the bound itself is allowed
    with pytest.raises(ScenarioError) as err:  # above the upper bound: the lower bound's reason is not given
        table.replace(**{key: 1e30})
    assert "out of range" in str(err.value) and "slip of units" not in str(err.value)


@pytest.mark.parametrize("key", ["E", "G", "area", "I_y", "I_z", "J", "mass_per_length", "rot_mass_per_length"])
def test_a_bridge_section_value_below_its_bound_is_refused_naming_the_key(key):
    girder = load_bridge("single_span_32m").girder
    check = next(f.metadata["check"] for f in dataclasses.fields(girder) if f.name == key)
    with pytest.raises(ScenarioError) as err:
        girder.replace(**{key: 1e-3 * check.low})
    assert err.value.key == key and "slip of units" in str(err.value)


def test_zero_stays_allowed_where_it_means_no_part():
    """A longitudinal primary spring of 0 (none) and a sprung mass without a wheel mass stay valid; a
    value between 0 and the bound does not."""
    creep = load_vehicle("ice_motor_creep")
    assert creep.primary.replace(k_x=0.0).k_x == 0.0
    with pytest.raises(ScenarioError, match="0 or >= 100"):
        creep.primary.replace(k_x=1e-300)
    sprung = load_vehicle("yang_yau_1997")
    assert sprung.replace(wheel_mass=0.0).wheel_mass == 0.0
    with pytest.raises(ScenarioError, match="0 or >= 1"):
        sprung.replace(wheel_mass=1e-300)


def test_the_command_line_refuses_a_bogie_inertia_of_1e_300_in_a_file(tmp_path, capsys):
    """The issue's probe: `modes` and `run` answered for a bogie pitch inertia of 1e-300 kg m^2. Now
    both exit 2 with one line naming the file, the key and the range, before any work."""
    from tb_exudyn.cli import main

    sc = load_scenario("li_zhu_2011")
    cars = list(sc.train.vehicles)
    cars[0] = cars[0].replace(bogie=cars[0].bogie.replace(inertia_pitch=1.0))
    path = save_scenario(sc.replace(train=sc.train.replace(vehicles=tuple(cars))), tmp_path / "light.toml")
    path.write_text(path.read_text().replace("inertia_pitch = 1.0\n", "inertia_pitch = 1e-300\n", 1))
    for argv in (["modes", str(path)], ["run", str(path), "--out", str(tmp_path / "o"), "--no-figures"]):
        capsys.readouterr()
        assert main(argv) == 2
        err = capsys.readouterr().err.strip()
        assert len(err.splitlines()) == 1 and str(path) in err, err
        assert "train.vehicles[0].bogie.inertia_pitch" in err and ">= 0.1" in err, err
    assert not (tmp_path / "o").exists()
