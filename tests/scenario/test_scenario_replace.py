"""``replace()`` on the scenario dataclasses checks each value as the TOML loader does (issue 27).

Problem: ``Scenario.replace`` and the nested dataclasses' ``replace`` given values of the wrong type
(a str, a bool, None, complex, NaN, an array for a number; 8.5 for an integer; a dict for a nested
table). Reference: the loader's rules (tb_exudyn/scenario/schema.py ``convert``: a bool is not a
number, an integer field takes 8.0 as 8 but refuses 8.5), and the error contract: a ScenarioError
``TYPE.replace: key 'KEY' = VALUE: ...`` naming the key. The accepted values are compared exactly
(no tolerance: a checked copy must hold the value given, converted to the field's type).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from tb_exudyn.scenario import ScenarioError, load_scenario


@pytest.fixture(scope="module")
def quick():
    return load_scenario("quick")


REFUSED = [
    ("speed_kmh", "300", "wrong type"),
    ("speed_kmh", True, "wrong type"),
    ("speed_kmh", None, "wrong type"),
    ("speed_kmh", 300 + 0j, "wrong type"),
    ("speed_kmh", math.nan, "out of range"),
    ("speed_kmh", math.inf, "out of range"),
    ("speed_kmh", np.array([300.0]), "wrong type"),
    ("speed_kmh", np.array(300.0), "wrong type"),
    ("speed_kmh", np.bool_(True), "wrong type"),
    ("speed_kmh", -1.0, "out of range"),
    ("name", 3, "wrong type"),
    ("analysis", {"n_freq": 50}, "a dict is not taken"),
    ("bridge", "single_span_32m", "wrong type"),
    ("track", None, "wrong type"),
    ("no_such_key", 1.0, "unknown key"),
]


@pytest.mark.parametrize("key, value, reason", REFUSED, ids=[f"{k}={v!r}" for k, v, _ in REFUSED])
def test_scenario_replace_refuses_a_wrong_value(quick, key, value, reason):
    with pytest.raises(ScenarioError) as err:
        quick.replace(**{key: value})
    text = str(err.value)
    assert text.startswith(f"Scenario.replace: key '{key}' = "), text
    assert reason in text and len(text.splitlines()) == 1, text


ANALYSIS_REFUSED = [
    ("n_freq", 8.5, "wrong type"),
    ("n_freq", True, "wrong type"),
    ("n_freq", "50", "wrong type"),
    ("n_freq", 10**400, "out of range"),
    ("n_freq", 0, "out of range"),
    ("freq_spacing", np.array([1, 2]), "unknown value"),
    ("freq_spacing", 1, "unknown value"),
    ("channels", "*", "wrong type"),
    ("channels", [1], "wrong type"),
    ("output_step", 0.0015, "not a multiple"),  # a cross-field rule, named where it was changed
]


@pytest.mark.parametrize("key, value, reason", ANALYSIS_REFUSED, ids=[f"{k}={v!r}" for k, v, _ in ANALYSIS_REFUSED])
def test_nested_replace_refuses_a_wrong_value(quick, key, value, reason):
    with pytest.raises(ScenarioError) as err:
        quick.analysis.replace(**{key: value})
    text = str(err.value)
    assert text.startswith("Analysis.replace: key '"), text
    assert key in text and reason in text, text


def test_a_vehicle_list_item_must_be_a_vehicle(quick):
    with pytest.raises(ScenarioError, match=r"Train.replace: key 'vehicles\[1\]'"):
        quick.train.replace(vehicles=[quick.train.vehicles[0], {"kind": "moving_force"}])


def test_accepted_values_are_converted_to_the_field_type(quick):
    """What the loader accepts is accepted, as the field's type: an int for a float, 8.0 for an
    integer, a list for a tuple, numpy scalars; the file the scenario came from is kept."""
    sc = quick.replace(speed_kmh=300)
    assert sc.speed_kmh == 300.0 and type(sc.speed_kmh) is float
    assert quick.replace(speed_kmh=np.float64(280.0)).speed_kmh == 280.0
    an = quick.analysis.replace(n_freq=8.0, channels=["car1.*"])
    assert an.n_freq == 8 and type(an.n_freq) is int and an.channels == ("car1.*",)
    assert type(quick.analysis.replace(n_freq=np.int64(50)).n_freq) is int
    assert quick.replace(analysis=an).analysis == an
    assert sc.source_file == quick.source_file is not None
    assert quick.replace().speed_kmh == quick.speed_kmh
