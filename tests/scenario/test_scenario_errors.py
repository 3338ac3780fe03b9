"""Bad scenario input: every class of mistake gives a ScenarioError naming file, key and value.

The reference is the error contract itself (README 'Scenario files'): the message must contain the
file name, the dotted key path, the offending value and what is allowed.
"""

from __future__ import annotations

import copy
import tomllib

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import tb_exudyn as tbx
from tb_exudyn.scenario import ScenarioError, model_files
from tb_exudyn.scenario.toml_io import dumps_toml

BASE = tomllib.loads(model_files("scenarios")["quick"].read_text())


def _write(tmp_path, data, name="bad.toml"):
    path = tmp_path / name
    path.write_text(dumps_toml(data))
    return path


def _with(data, path, value):
    out = copy.deepcopy(data)
    node = out
    for key in path[:-1]:
        node = node[key]
    if value is _DELETE:
        del node[path[-1]]
    else:
        node[path[-1]] = value
    return out


_DELETE = object()

# (key path in the file, bad value, text the message must contain besides file/key)
CASES = [
    (("analysis", "time_stepp"), 0.001, "unknown key"),
    (("speed_kmh",), _DELETE, "missing key"),
    (("speed_kmh",), "fast", "wrong type"),
    (("speed_kmh",), 0.0, "out of range"),
    (("speed_kmh",), -250.0, "out of range"),
    (("track", "lead_in"), -5.0, "out of range"),
    (("analysis", "n_freq"), 2.5, "wrong type"),
    (("analysis", "freq_spacing"), "cubic", "unknown value"),
    (("analysis", "freq_max"), 150.0, "time step"),
    (("analysis", "output_step"), 0.0015, "not a multiple"),
    (("track", "irregularities"), ["german_low.vertikal"], "unknown spectrum"),
    (("train", "vehicles"), ["ice_motr"], "unknown vehicle name"),
    (("train", "vehicles"), [], "empty train"),
    (("bridge",), "no_such_bridge", "unknown bridge name"),
    (("bridge",), {"kind": "suspension", "name": "x"}, "unknown kind"),
    (("track", "wavelength_min"), 500.0, "empty wavelength band"),
]


@pytest.mark.parametrize("path,value,reason", CASES, ids=[".".join(c[0]) + ":" + c[2] for c in CASES])
def test_bad_input_names_file_key_and_value(tmp_path, path, value, reason):
    data = _with(BASE, path, value)
    file = _write(tmp_path, data)
    with pytest.raises(ScenarioError) as info:
        tbx.load_scenario(file)
    msg = str(info.value)
    assert str(file) in msg
    assert reason in msg
    assert path[-1] in msg
    if value is not _DELETE and not isinstance(value, (list, dict)):
        assert repr(value) in msg or str(value) in msg
    assert "allowed:" in msg


def _inline_car(**changes):
    car = tomllib.loads(model_files("vehicles")["ice_motor"].read_text())
    for dotted, v in changes.items():
        sec, key = dotted.split("__")
        car[sec][key] = v
    return car


@pytest.mark.parametrize(
    "section,key,value",
    [("body", "mass", 0.0), ("bogie", "inertia_pitch", -1.0), ("primary", "k_z", 0.0), ("geometry", "length", -24.0)],
)
def test_non_positive_vehicle_data_is_rejected(tmp_path, section, key, value):
    data = _with(BASE, ("train", "vehicles"), [_inline_car(**{f"{section}__{key}": value})])
    file = _write(tmp_path, data)
    with pytest.raises(ScenarioError, match=rf"train\.vehicles\[0\]\.{section}\.{key}"):
        tbx.load_scenario(file)


def test_vehicle_longer_than_the_track(tmp_path):
    car = _inline_car(geometry__half_bogie_spacing=200.0, geometry__length=500.0)
    file = _write(tmp_path, _with(BASE, ("train", "vehicles"), [car]))
    with pytest.raises(ScenarioError, match="vehicle longer than the track"):
        tbx.load_scenario(file)


def test_bridge_with_a_zero_span(tmp_path):
    bridge = tomllib.loads(model_files("bridges")["single_span_32m"].read_text())
    bridge["spans"] = [32.0, 0.0]
    file = _write(tmp_path, _with(BASE, ("bridge",), bridge))
    with pytest.raises(ScenarioError, match=r"'bridge\.spans\[1\]' = 0\.0"):
        tbx.load_scenario(file)


def test_toml_syntax_error_and_missing_file(tmp_path):
    bad = tmp_path / "broken.toml"
    bad.write_text("speed_kmh = = 3\n")
    with pytest.raises(ScenarioError, match="syntax error"):
        tbx.load_scenario(bad)
    with pytest.raises(ScenarioError, match="file not found"):
        tbx.load_scenario(tmp_path / "nothing.toml")


POSITIVE_KEYS = [
    ("speed_kmh",),
    ("track", "lead_in"),
    ("track", "half_gauge"),
    ("analysis", "time_step"),
    ("analysis", "pem_amplitude"),
    ("analysis", "contact_stiffness_z"),
]


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(
    key=st.sampled_from(POSITIVE_KEYS),
    value=st.one_of(st.floats(max_value=0.0, allow_nan=False), st.just(float("nan")), st.just(float("-inf"))),
)
def test_any_non_positive_value_is_rejected(tmp_path, key, value):
    """Hypothesis: any value <= 0 (or nan, -inf) of a quantity that must be positive is refused with
    the key path in the message."""
    file = _write(tmp_path, _with(BASE, key, value), name="h.toml")
    with pytest.raises(ScenarioError) as info:
        tbx.load_scenario(file)
    assert ".".join(key) in str(info.value)
