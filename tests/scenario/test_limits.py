"""Limit files (models/limits/*.toml), their loader and the quantity vocabulary (tb_exudyn.scenario.limits).

The values are checked against the codes' values of docs/references.md (code limits), typed again here.
"""

from __future__ import annotations

import math
import shutil
import tomllib
import typing

import pytest

from tb_exudyn.errors import SettingError
from tb_exudyn.results import limit_values
from tb_exudyn.results.checks import default_limits
from tb_exudyn.scenario import ScenarioError, list_models, model_files
from tb_exudyn.scenario.limits import (
    QUANTITIES,
    STATISTICS,
    Criterion,
    FixedLimit,
    GradedLimit,
    SpeedBandLimit,
    StaticLoadLimit,
    channels_for,
    limits_from_dict,
    load_limits,
)

SHIPPED = sorted(model_files("limits"))


def test_the_three_limit_files_are_shipped_and_listed():
    assert {"en1990_deck", "running_safety", "ride_comfort"} <= set(SHIPPED)
    listed = {e.name for e in list_models() if e.category == "limits"}
    assert listed == set(SHIPPED)
    assert all(e.description for e in list_models() if e.category == "limits")


@pytest.mark.parametrize("name", SHIPPED)
def test_every_limit_file_loads(name):
    limits = load_limits(name)
    assert limits.name == name and limits.source and limits.description
    for c in limits.criteria:
        assert c.quantity in QUANTITIES and c.clause and c.source
        assert not c.check or c.note  # the loader enforces it; the shipped files follow it
    assert load_limits(model_files("limits")[name]) == limits  # by path, the same


def test_en1990_deck_values():
    """EN 1990 Annex A2, A2.4.4.2 (docs/references.md, code limits): 3.5 m/s^2 ballasted, 5.0 direct-fastened,
    on the code-range-filtered deck acceleration; twist over 3 m 4.5 / 3.0 / 1.5 mm for V <= 120, <= 200,
    > 200 km/h; total 7.5 mm."""
    deck = load_limits("en1990_deck")
    bal, df = deck.criterion("deck_acc_ballasted"), deck.criterion("deck_acc_direct_fastened")
    assert (bal.limit_value(), df.limit_value()) == (3.5, 5.0)
    assert bal.quantity == df.quantity == "deck_acc_z_en1990" and bal.statistic == "max_abs"
    twist = deck.criterion("deck_twist_3m")
    assert [twist.limit_value(speed_kmh=v) for v in (80.0, 160.0, 300.0)] == [4.5e-3, 3.0e-3, 1.5e-3]
    assert deck.criterion("deck_twist_3m_total").limit_value() == 7.5e-3
    assert twist.unit == "m"


def test_speed_band_lookup_boundaries():
    """Upper ends inclusive: 120 km/h is in the first band, 120.001 in the second; the last band has no
    upper end; a missing speed is a one-line SettingError naming speed_kmh."""
    twist = load_limits("en1990_deck").criterion("deck_twist_3m")
    cases = {1.0: 4.5e-3, 120.0: 4.5e-3, 120.001: 3.0e-3, 200.0: 3.0e-3, 200.001: 1.5e-3, 500.0: 1.5e-3}
    for v, expected in cases.items():
        assert twist.limit_value(speed_kmh=v) == expected, v
    with pytest.raises(SettingError) as info:
        twist.limit_value()
    assert info.value.key == "speed_kmh"


def test_running_safety_values():
    """Q/P 0.8 and GB 5599-85 1.0 / 1.2; dP/P 0.6 and 0.60 / 0.65; H: Prud'homme 0.85 (10 + P/3) kN with P
    the static axle load and EN 14363 alpha (10 + 2 Q0/3) kN with Q0 the static wheel load: at P = 160 kN
    (Q0 = 80 kN) 53.83 kN and 63.33 kN (the same bracket: P/3 = 2 Q0/3)."""
    rs = load_limits("running_safety")
    assert rs.criterion("derailment_high_speed").limit_value() == 0.8
    gb = rs.criterion("derailment_gb5599").limit
    assert isinstance(gb, GradedLimit) and gb.values == (1.0, 1.2)
    assert rs.criterion("unloading_high_speed").limit_value() == 0.6
    assert rs.criterion("unloading_gb5599").limit.values == (0.6, 0.65)
    prud = rs.criterion("lateral_force_prudhomme")
    assert prud.limit_value(static_axle_load=160e3) == pytest.approx(0.85 * (10e3 + 160e3 / 3), rel=1e-15)
    en = rs.criterion("lateral_force_en14363")
    assert en.limit_value(static_wheel_load=80e3) == pytest.approx(10e3 + 2 * 80e3 / 3, rel=1e-15)
    assert en.statistic == "sliding_mean_max_abs" and en.averaging_length == 2.0 and en.band == (0.0, 20.0)
    with pytest.raises(SettingError) as info:
        prud.limit_value(static_wheel_load=80e3)  # the axle load is what this form needs
    assert info.value.key == "static_axle_load"


def test_ride_comfort_values_and_grades():
    """TB 10621 1.3 / 1.0 m/s^2; EN 1990 b_v 1.0 / 1.3 / 2.0; Sperling < 2.5 excellent, 2.5-2.75 good,
    2.75-3.0 acceptable over 5 s windows. A value on a grade's upper end belongs to that grade."""
    rc = load_limits("ride_comfort")
    assert rc.criterion("body_acc_z_tb10621").limit_value() == 1.3
    assert rc.criterion("body_acc_y_tb10621").limit_value() == 1.0
    assert rc.criterion("body_acc_z_en1990").limit.values == (1.0, 1.3, 2.0)
    sperling = rc.criterion("sperling_z_gb5599")
    assert sperling.window == 5.0 and sperling.statistic == "window_max" and sperling.limit_value() == 3.0
    grade = sperling.limit.grade
    assert [grade(w) for w in (2.0, 2.5, 2.6, 2.75, 2.9, 3.01)] == [
        "excellent", "excellent", "good", "good", "acceptable", None]
    assert {c.quantity for c in rc.for_quantity("sperling_y")} == {"sperling_y"}


# ============================================================================================ vocabulary
def test_statistic_type_is_the_vocabulary():
    hints = typing.get_type_hints(Criterion)
    assert typing.get_args(hints["statistic"]) == ("",) + tuple(STATISTICS)  # '': a structural criterion


CHANNEL_QUANTITY = {
    "bridge.span2.mid.acc_z": "deck_acc_z",
    "bridge.span1.q1.acc_z_en1990": "deck_acc_z_en1990",
    "bridge.span3.q3.twist_3m": "deck_twist_3m",
    "car1.axle1.left.force_z": "wheel_force_z",
    "car2.axle4.right.force_z": "wheel_force_z",
    "car1.axle1.force_z": "wheel_force_z",  # sprung mass / moving force
    "car1.axle3.force_y": "axle_force_y",
    "car1.axle1.unloading": "wheel_unloading",
    "car4.axle2.left.derailment": "derailment_coefficient",
    "car1.body.acc_z": "body_acc_z",
    "car1.body.acc_y": "body_acc_y",
    "car1.body.acc_z_wb": "body_acc_z_wb",
    "car3.body.acc_y_wd": "body_acc_y_wd",
    "car1.body.sperling_z": "sperling_z",
    "car1.body.sperling_y": "sperling_y",
}


def test_each_channel_carries_exactly_one_quantity():
    """Channel names (tb_exudyn/system/channels.py naming and the proposed derived names) map to one
    quantity each; other channels of the catalogue map to none."""
    for channel, expected in CHANNEL_QUANTITY.items():
        hits = [q.name for q in QUANTITIES.values() if q.matches(channel)]
        assert hits == [expected], (channel, hits)
    for other in ("bridge.span1.mid.acc_y", "bridge.pier1.top.acc_z", "car1.bogie1.acc_z", "car1.axle1.acc_z",
                  "car1.body.vel_z", "car1.body.acc_rx"):
        assert not any(q.matches(other) for q in QUANTITIES.values()), other
    assert channels_for("body_acc_z", list(CHANNEL_QUANTITY)) == ["car1.body.acc_z"]
    assert all(q.unit and q.description for q in QUANTITIES.values())
    assert "Q per wheel is not" in QUANTITIES["axle_force_y"].description


# ============================================================================================ bad input
GOOD = {
    "name": "bad", "description": "d", "source": "s",
    "criteria": [
        {"id": "a", "title": "t", "clause": "c", "source": "s", "quantity": "body_acc_z", "statistic": "max_abs",
         "limit": {"kind": "fixed", "value": 1.0}},
        {"id": "b", "title": "t", "clause": "c", "source": "s", "quantity": "deck_twist_3m", "statistic": "max_abs",
         "limit": {"kind": "speed_bands", "speed_max_kmh": [120.0, float("inf")], "values": [4.5e-3, 3.0e-3]}},
    ],
}


def _toml(data: dict) -> str:
    from tb_exudyn.scenario.toml_io import dumps_toml

    return dumps_toml(data)


def _bad(path, change) -> ScenarioError:
    data = tomllib.loads(_toml(GOOD))
    change(data)
    path.write_text(_toml(data))
    with pytest.raises(ScenarioError) as info:
        load_limits(path)
    return info.value


def test_the_good_file_loads(tmp_path):
    path = tmp_path / "good.toml"
    path.write_text(_toml(GOOD))
    limits = load_limits(path)
    assert isinstance(limits.criteria[1].limit, SpeedBandLimit)


@pytest.mark.parametrize("change,key,words", [
    (lambda d: d["criteria"][0].update(quantity="deck_acc"), "criteria[0].quantity", "unknown quantity"),
    (lambda d: d["criteria"][1].pop("clause"), "criteria[1].clause", "missing key"),
    (lambda d: d["criteria"][0].update(statistic="p99"), "criteria[0].statistic", "unknown value"),
    (lambda d: d["criteria"][0].update(limit={"kind": "table", "value": 1.0}), "criteria[0].limit.kind", "unknown kind"),
    (lambda d: d["criteria"][1]["limit"].update(speed_max_kmh=[120.0, 200.0, float("inf")]), "criteria[1].limit.values", "length mismatch"),
    (lambda d: d["criteria"][1]["limit"].update(speed_max_kmh=[120.0, 300.0], values=[1.0, 2.0]),
     "criteria[1].limit.speed_max_kmh", "no limit"),
    (lambda d: d["criteria"][0].update(check=True), "criteria[0].note", "empty"),
    (lambda d: d["criteria"][1].update(id="a"), "criteria[1].id", "duplicate id"),
    (lambda d: d["criteria"][0].update(statistic="rms_window"), "criteria[0].window", "missing window"),
    (lambda d: d["criteria"][0].update(colour="red"), "criteria[0].colour", "unknown key"),
    (lambda d: d["criteria"][0].update(band=[20.0, 1.0]), "criteria[0].band", "bad band"),
    # issue 27: every value a verdict needs, present, of its type, finite, > 0 for an upper bound
    (lambda d: d["criteria"][0]["limit"].update(value=-1.0), "criteria[0].limit.value", "not a positive limit"),
    (lambda d: d["criteria"][0]["limit"].update(value=0.0), "criteria[0].limit.value", "not a positive limit"),
    (lambda d: d["criteria"][0]["limit"].update(value="1.0"), "criteria[0].limit.value", "wrong type"),
    (lambda d: d["criteria"][0]["limit"].update(value=float("nan")), "criteria[0].limit.value", "nan is never evaluated"),
    (lambda d: d["criteria"][0]["limit"].update(value=float("inf")), "criteria[0].limit.value", "inf always passes"),
    (lambda d: d["criteria"][0]["limit"].pop("value"), "criteria[0].limit.value", "missing key"),
    (lambda d: d["criteria"][1]["limit"].update(values=[4.5e-3, float("inf")]), "criteria[1].limit.values[1]",
     "inf always passes"),
    (lambda d: d["criteria"][1]["limit"].update(values=[4.5e-3, 0.0]), "criteria[1].limit.values[1]", "not a positive limit"),
    (lambda d: d["criteria"][0].update(limit={"kind": "grades", "labels": ["a", "b"], "values": [1.0, float("nan")]}),
     "criteria[0].limit.values[1]", "nan is never evaluated"),
    (lambda d: d["criteria"][0].update(limit={"kind": "grades", "labels": ["a", "b"], "values": [-2.0, -1.0]}),
     "criteria[0].limit.values[0]", "not a positive limit"),
    (lambda d: d["criteria"][0].update(limit={"kind": "grades", "labels": ["a", "a"], "values": [1.0, 2.0]}),
     "criteria[0].limit.labels[1]", "duplicate label"),
    (lambda d: d["criteria"][0].update(statistic="min", limit={"kind": "grades", "labels": ["a"], "values": [1.0]}),
     "criteria[0].limit.kind", "grades with a lower bound"),
    (lambda d: d["criteria"][0].update(quantity="axle_force_y", limit={
        "kind": "static_load", "reference": "static_axle_load", "factor": 1.0, "constant": 0.0, "coefficient": 0.0}),
     "criteria[0].limit.coefficient", "the limit is 0"),
    (lambda d: d["criteria"][0].update(quantity="axle_force_y", limit={
        "kind": "static_load", "reference": "static_axle_load", "factor": 0.0, "constant": 1e4, "coefficient": 0.0}),
     "criteria[0].limit.factor", "out of range"),
    (lambda d: d["criteria"][0].update(statistic="window_max", window=5.0), "criteria[0].statistic",
     "not a statistic of 'body_acc_z'"),
    (lambda d: d["criteria"][0].update(quantity="sperling_z"), "criteria[0].statistic",
     "not a statistic of 'sperling_z'"),
    (lambda d: d["criteria"][0].update(window=5.0), "criteria[0].window", "would be ignored"),
    (lambda d: d["criteria"][0].update(averaging_length=2.0), "criteria[0].averaging_length", "would be ignored"),
    (lambda d: d.update(criteria=[]), "criteria", "at least one"),
    (lambda d: d.pop("criteria"), "criteria", "missing key"),
    (lambda d: d.update(name="My limits"), "name", "bad identifier"),
])
def test_bad_limit_file_is_a_one_line_error_naming_file_and_key(tmp_path, change, key, words):
    err = _bad(tmp_path / "bad_limits.toml", change)
    text = str(err)
    assert "bad_limits.toml" in err.file and err.key == key, text
    assert words in text and "\n" not in text


def test_unknown_limit_name_lists_the_names():
    with pytest.raises(ScenarioError) as info:
        load_limits("en1991_deck")
    assert "en1990_deck" in str(info.value)


def test_python_construction_is_validated_too():
    with pytest.raises(ScenarioError, match="unknown quantity"):
        Criterion(id="x", title="t", clause="c", source="s", quantity="speed", statistic="max",
                  limit=FixedLimit(value=1.0))
    with pytest.raises(ScenarioError, match="not increasing"):
        GradedLimit(labels=("a", "b"), values=(2.0, 1.0))
    assert StaticLoadLimit(reference="static_axle_load", factor=1.0, constant=0.0, coefficient=0.5).value_at(
        static_axle_load=10.0) == 5.0
    assert limits_from_dict(GOOD).criteria[0].limit == FixedLimit(value=1.0)


# ============================================================================================ issue 27
def test_a_lower_bound_may_be_zero_or_negative_an_upper_bound_not(tmp_path):
    """Statistic 'min' is a lower bound (STATISTICS): 0 N on the wheel load (no loss of contact) and a negative
    bound are limits; every other statistic compares a largest value with an upper bound, which must be > 0."""
    for value in (0.0, -5e3):
        data = tomllib.loads(_toml(GOOD))
        data["criteria"][0].update(quantity="wheel_force_z", statistic="min", limit={"kind": "fixed", "value": value})
        path = tmp_path / "lower.toml"
        path.write_text(_toml(data))
        c = load_limits(path).criteria[0]
        assert c.lower_bound and c.limit_value() == value
    with pytest.raises(ScenarioError, match="not a positive limit"):
        Criterion(id="x", title="t", clause="c", source="s", quantity="wheel_force_z", statistic="max",
                  limit=FixedLimit(value=0.0))
    with pytest.raises(ScenarioError, match="inf always passes"):
        FixedLimit(value=float("inf"))


def test_the_shipped_files_follow_the_rules_they_are_checked_by():
    """Every shipped criterion: limit values finite and > 0 (none is a lower bound), window_max exactly on the
    Sperling indices. The rules were written after reading them: none of them is refused."""
    for name in SHIPPED:
        for c in load_limits(name).criteria:
            values = getattr(c.limit, "values", None) or (getattr(c.limit, "value", None),)
            if c.limit.kind != "static_load":
                assert all(math.isfinite(v) and v > 0 for v in values), (name, c.id)
            assert (c.statistic == "window_max") == c.quantity.startswith("sperling"), (name, c.id)
            assert not c.lower_bound


def _library(tmp_path, monkeypatch):
    """A copy of the shipped model library as TB_EXUDYN_MODELS; returns its limits/ folder."""
    from tb_exudyn.scenario import models_dir

    shutil.copytree(models_dir(), tmp_path / "models")
    monkeypatch.setenv("TB_EXUDYN_MODELS", str(tmp_path / "models"))
    return tmp_path / "models" / "limits"


def test_default_limits_are_the_library_files_read_through_the_same_checks(tmp_path, monkeypatch):
    """default_limits (the sets the CLI, run_sweep and the report load before any work) reads every file of
    the library in use; a broken one is its ScenarioError."""
    limits = _library(tmp_path, monkeypatch)
    assert [ls.name for ls in default_limits()] == SHIPPED
    path = limits / "ride_comfort.toml"
    path.write_text(path.read_text().replace("value = 1.3\n", "value = nan\n", 1))
    with pytest.raises(ScenarioError) as info:
        default_limits()
    assert info.value.file == str(path) and info.value.key == "criteria[0].limit.value"


def test_a_library_without_limit_files_is_refused(tmp_path, monkeypatch):
    """No limit file would mean no verdict at all, with exit 0: the environment variable is named."""
    limits = _library(tmp_path, monkeypatch)
    for p in limits.glob("*.toml"):
        p.unlink()
    with pytest.raises(SettingError) as info:
        default_limits()
    assert info.value.key == "TB_EXUDYN_MODELS" and "no limit file" in str(info.value)
    assert limit_values.limit_sets([]) == []  # an explicit empty list is the caller's choice


def test_two_limit_files_of_one_name_are_refused(tmp_path, monkeypatch):
    """Verdicts are named <file name>/<criterion id>: two files of one name would overwrite each other's rows
    (e.g. the sweep's columns)."""
    limits = _library(tmp_path, monkeypatch)
    copy = limits / "zz_copy.toml"
    shutil.copyfile(limits / "ride_comfort.toml", copy)
    with pytest.raises(ScenarioError) as info:
        default_limits()
    assert info.value.file == str(copy) and info.value.key == "name" and "ride_comfort.toml" in str(info.value)
    same = load_limits("ride_comfort")
    with pytest.raises(SettingError, match="duplicate limits name"):
        limit_values.limit_sets([same, limits_from_dict(tomllib.loads((limits / "ride_comfort.toml").read_text()))])
