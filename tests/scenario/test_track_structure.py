"""Track structures as data (models/tracks, scenario key track.structure): the library files read, every
value carries its source, the default keeps today's model, and bad track data is one line and exit 2."""

from __future__ import annotations

import re

import pytest

from tb_exudyn.cli import main
from tb_exudyn.scenario import load_scenario, list_models, model_files
from tb_exudyn.scenario.schema import to_dict
from tb_exudyn.scenario.track_structure import load_track_structure


def test_the_library_holds_both_structures_and_lists_them():
    assert {"ballasted_uic60", "slab_track"} <= set(model_files("tracks"))
    listed = {e.name: e.description for e in list_models() if e.category == "tracks"}
    assert listed["ballasted_uic60"] and listed["slab_track"]
    b = load_track_structure("ballasted_uic60")
    assert b.kind == "ballasted" and b.spacing == 0.6 and b.rail.mass_per_length == pytest.approx(60.21)
    assert load_track_structure("slab_track").kind == "slab"


@pytest.mark.parametrize("name", ["ballasted_uic60", "slab_track"])
def test_every_value_names_its_source(name):
    """Each numeric line of a track file has a comment (its source, [check] where recalled or inferred)."""
    text = model_files("tracks")[name].read_text()
    numeric = [line for line in text.splitlines() if re.match(r"^\s*\w+\s*=\s*[-+0-9.]", line)]
    assert numeric and all("#" in line and len(line.split("#", 1)[1].strip()) > 5 for line in numeric), numeric


def test_the_chain_from_the_rail_down():
    b = load_track_structure("ballasted_uic60")
    assert b.chain("rigid") == ((6.5e7, 7.5e4, 170.0), (1.8e8, 5.88e4, 0.0))
    assert b.chain("subgrade") == ((6.5e7, 7.5e4, 170.0), (1.8e8, 5.88e4, 683.4), (6.5e7, 3.1e4, 0.0))
    assert b.depth == pytest.approx(0.172 + 0.01 + 0.22 + 0.35)


def test_no_structure_is_todays_scenario():
    """The default (empty) changes nothing; a named one is kept in the scenario's plain form."""
    sc = load_scenario("li_zhu_2011")
    assert sc.track.structure == ""
    with_track = sc.replace(track=sc.track.replace(structure="ballasted_uic60"))
    plain = to_dict(with_track)
    assert plain["track"]["structure"] == "ballasted_uic60"
    plain["track"]["structure"] = ""
    assert plain == to_dict(sc)


def _track_file(tmp_path, name="t", **changes):
    """A copy of ballasted_uic60 with ``changes`` ({"section.key": value or None to drop a section})."""
    text = model_files("tracks")["ballasted_uic60" if not changes.pop("slab", False) else "slab_track"].read_text()
    for key, value in changes.items():
        section, _, field = key.rpartition(".")
        if value is None:  # drop the table
            text = re.sub(rf"\n\[{field}\]\n(.*\n)*?(?=\n\[|\Z)", "\n", text + "\n")
            continue
        pattern = rf"(\[{section}\]\n(?:.*\n)*?){field}\s*=\s*[^#\n]+" if section else rf"(?m)^(){field}\s*=\s*[^#\n]+"
        text, n = re.subn(pattern, lambda m: f"{m.group(1)}{field} = {value} ", text, count=1)
        assert n == 1, key
    path = tmp_path / f"{name}.toml"
    path.write_text(text)
    return path


@pytest.mark.parametrize("changes, scenario, expect", [
    ({"pad.stiffness": "-6.5e7"}, "li_zhu_2011", "pad.stiffness"),
    ({"ballast.stiffness": "0.0"}, "li_zhu_2011", "ballast.stiffness"),
    ({"spacing": "0.0"}, "li_zhu_2011", "spacing"),
    ({"spacing": "4.0"}, "quick:bridge.spans=[3.5]", "support spacing longer than a span"),
    ({"slab": True, "base": None}, "li_zhu_2011", "a slab track without a base"),
    ({"sleeper.thickness": "1.2"}, "li_zhu_2011", "does not fit the bridge's track height"),
    ({}, "yang_yau_sprung_mass", "does not fit the bridge's track height"),
])
def test_bad_track_data_is_one_line_and_exit_2(tmp_path, capsys, changes, scenario, expect):
    path = _track_file(tmp_path, **changes)
    scenario, _, extra = scenario.partition(":")
    args = ["show", scenario, "--set", f"track.structure={str(path)!r}".replace("'", '"')]
    if extra:
        args += ["--set", extra]
    assert main(args) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and expect in err and "Traceback" not in err, err
    assert str(path) in err or "track.structure" in err, err


def test_a_car_whose_contacts_the_track_does_not_carry_is_refused(tmp_path, capsys):
    """The track layer carries vertical contacts (sprung masses, moving forces, the wheels of car15 and the
    articulated sets) and the wheelsets' lateral contact, not the creep cars' general rows: a creep car must
    not run with its creep forces on the deck (one line, exit 2, also where the library builds;
    tests/builder/test_track_scenario.py and tests/engines/test_track_car15.py run the ones it carries)."""
    out = tmp_path / "out"
    assert main(["run", "li_zhu_2011_creep", "--set", "track.structure=ballasted_uic60", "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "train.vehicles" in err and "creep rows" in err, err
    assert not out.exists()
    from tb_exudyn.builder import build_model
    from tb_exudyn.scenario import ScenarioError

    sc = load_scenario("li_zhu_2011_creep")
    with pytest.raises(ScenarioError, match="train.vehicles"):
        build_model(sc.replace(track=sc.track.replace(structure="ballasted_uic60")))


def test_show_describes_the_track_structure(capsys):
    assert main(["show", "li_zhu_2011", "--set", "track.structure=slab_track"]) == 0
    out = capsys.readouterr().out
    assert "(derived) track structure" in out and "slab, 0.65 m, 0.737 m deep" in out and "mortar 9e+08 N/m" in out
    assert main(["show", "li_zhu_2011"]) == 0
    assert "(derived) track structure" not in capsys.readouterr().out
