"""Trains as compositions (issue 29): vehicle models, axle-load sets and articulated sets in one train file.

References: hand statics of each part, written here. An axle-load set's loads are as given. An
articulated set of n bodies on n + 1 two-axle bogies: a body on two pivots with its centre of gravity
midway puts half its weight on each bogie, so an end bogie carries half a body and an inner bogie half
of each of its two neighbours; each bogie adds its own mass and its two wheelsets, shared by its two
axles. Positions: bogie j's axles at j p and j p + w (p pivot spacing, w wheelbase) from the set's
first axle; a part's first axle trails the train's by the lengths of the parts ahead. The loads are
sums and products of the data (relative 1e-12: round-off of a few operations).
"""

from __future__ import annotations

import numpy as np
import pytest

from tb_exudyn.codes.trains import composition_table, load_train, resolve_trains, train_files
from tb_exudyn.errors import ScenarioError

G = 9.81

MIXED = """name = "mixed"
[[cars]]
name = "loco"
axles = [0.0, 2.5, 10.0]
axle_loads = [200e3, 190e3, 180e3]
length = 14.0

[[cars]]
bodies = 3
pivot_spacing = 16.0
wheelbase = 2.5
body_mass = [20000.0, 30000.0, 26000.0]
bogie_mass = 2500.0
wheelset_mass = 1500.0
length = 54.0

[[cars]]
vehicle = "ice_trailer"
"""


def test_mixed_composition_by_hand(tmp_path):
    p = tmp_path / "mixed.toml"
    p.write_text(MIXED)
    t = load_train(p)
    # the articulated set: bogie loads (half of each neighbouring body + bogie + 2 wheelsets), per axle / 2
    bodies = (20000.0, 30000.0, 26000.0)
    bogie = [0.5 * b for b in (bodies[0], bodies[0] + bodies[1], bodies[1] + bodies[2], bodies[2])]
    per_axle = [G * (s + 2500.0 + 2 * 1500.0) / 2 for s in bogie]
    set_x = 14.0 + np.array([0.0, 2.5, 16.0, 18.5, 32.0, 34.5, 48.0, 50.5])
    # ice_trailer: axles 0, 2.5, 17.375, 19.875 m, (44000 + 2 x 2400 + 4 x 2400) g / 4 each
    ice_x = 68.0 + np.array([0.0, 2.5, 17.375, 19.875])
    ice = (44000.0 + 2 * 2400.0 + 4 * 2400.0) * G / 4
    np.testing.assert_allclose(t.positions, np.concatenate([[0.0, 2.5, 10.0], set_x, ice_x]), rtol=0, atol=1e-12)
    np.testing.assert_allclose(t.loads, [200e3, 190e3, 180e3] + [q for q in per_axle for _ in (0, 1)] + [ice] * 4,
                               rtol=1e-12)
    # the set's weight is its bodies, bogies and wheelsets
    assert sum(t.loads[3:11]) == pytest.approx(G * (sum(bodies) + 4 * (2500.0 + 2 * 1500.0)), rel=1e-12)
    assert [(p.kind, p.n_axles, p.n_bodies, p.n_bogies) for p in t.parts] == [
        ("axle_loads", 3, 1, 0), ("articulated", 8, 3, 4), ("vehicle", 4, 1, 2)]
    assert [p.first_axle for p in t.parts] == [0.0, 14.0, 68.0]
    assert t.vehicles == ()  # not every car a vehicle model: no stochastic rows
    assert t.regular_length == 16.0  # the most frequent body length
    assert "articulated" in composition_table(t)


def test_thalys_articulated_train():
    """models/trains/thalys_pba.toml: 26 axles (Bo'Bo' + 9 x 2' + Bo'Bo'), 386 t (the data sheet's empty
    mass, within round-off of the data's sums), 200 m over its ends (2.575 m power-car overhangs), its
    largest axle load 17 t; the set's end bogies carry half a body, the inner ones a whole one."""
    t = load_train(train_files()["thalys_pba"])
    assert t.n_axles == 26 and [p.kind for p in t.parts] == ["axle_loads", "articulated", "axle_loads"]
    assert t.total_load / G == pytest.approx(386e3, rel=1e-12)
    assert t.length + 2 * 2.575 == pytest.approx(200.0, abs=1e-9)
    assert max(t.loads) == pytest.approx(17e3 * G, rel=1e-12)
    end, inner = G * (24275.0 / 2 + 3000.0 + 3200.0) / 2, G * (24275.0 + 3000.0 + 3200.0) / 2
    np.testing.assert_allclose(t.loads[4:22], [end] * 2 + [inner] * 14 + [end] * 2, rtol=1e-12)
    assert t.regular_length == 18.7
    assert [x.name for x in resolve_trains(["thalys_pba"])] == ["thalys_pba"]


@pytest.mark.parametrize("car, key, words", [
    ("bodies = 2\npivot_spacing = 18.7\nwheelbase = 3.0\nbogie_mass = 3e3\nwheelset_mass = 1.6e3\nlength = 41.0",
     "cars[0].body_mass", "a number > 0"),
    ("bodies = 2\npivot_spacing = 18.7\nwheelbase = 30.0\nbody_mass = 2e4\nbogie_mass = 3e3\nwheelset_mass = 1.6e3\n"
     "length = 41.0", "cars[0].wheelbase", "bogies overlap"),
    ("bodies = 2\npivot_spacing = 18.7\nwheelbase = 3.0\nbody_mass = [2e4]\nbogie_mass = 3e3\nwheelset_mass = 1.6e3\n"
     "length = 41.0", "cars[0].body_mass", "a list of 2 numbers"),
    ("bodies = 2\npivot_spacing = 18.7\nwheelbase = 3.0\nbody_mass = 2e4\nbogie_mass = 3e3\nwheelset_mass = 1.6e3\n"
     "length = 20.0", "cars[0].length", "shorter than its axles"),
    ("axles = [0.0, 3.0]\naxle_load = 1e5\naxle_loads = [1e5, 1e5]\nlength = 5.0", "cars[0].axle_loads", "not both"),
    ("axles = [0.0, 3.0, 2.0]\naxle_load = 1e5\nlength = 5.0", "cars[0].axles", "ascending"),
    ("axles = [0.0, 3.0]\naxle_load = 1e5", "cars[0].length", "missing key"),
    ("axles = [0.0]\naxle_load = 1e5\nlength = 5.0\nvehicle = \"ice_motor\"", "cars[0]", "two kinds of car"),
    ("count = 2", "cars[0]", "no kind of car"),
    ("bodies = 2\npivot_spacing = 18.7\nwheelbase = 3.0\nbody_mass = 2e4\nbogie_mass = 3e3\nwheelset_mass = 1.6e3\n"
     "length = 41.0\naxle_load = 1e5", "cars[0].axle_load", "unknown key"),
])
def test_bad_composition_names_file_and_key(tmp_path, car, key, words):
    p = tmp_path / "bad.toml"
    p.write_text(f'name = "bad"\n[[cars]]\n{car}\n')
    with pytest.raises(ScenarioError) as info:
        load_train(p)
    text = str(info.value)
    assert str(p) in text and f"key '{key}'" in text and words in text and "\n" not in text


def test_show_a_train(capsys):
    """`tb-exudyn show thalys_pba` prints the composition and its axle loads; a scenario's name is a scenario."""
    from tb_exudyn.cli import main
    from tb_exudyn.codes.trains import train_view

    assert main(["show", "thalys_pba"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("train thalys_pba: 26 axles") and "articulated" in out and "axle loads [kN]" in out
    assert train_view("quick") is None and train_view("no_such_train") is None
