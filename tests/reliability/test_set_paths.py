"""Paths on the command line (issue 49): a file named in ``--set`` is found from the working folder, as a
shell user expects (not from the scenario's folder); every "not found" names the path it tried; no
message cuts a file name, and a typed value is shown whole up to SHOWN_TEXT_LIMIT characters.

The scenario and the files are laid out in folders of their own, so that resolving from the scenario's
folder and from the working folder give different paths: the test fails if the wrong one is used.
"""

from __future__ import annotations

import os

import pytest

from tb_exudyn.cli import main
from tb_exudyn.errors import SHOWN_VALUE_LIMIT, ScenarioError, format_message, short_repr
from tb_exudyn.scenario import load_bridge, load_scenario, save_scenario
from tb_exudyn.scenario.io import from_working_folder, with_settings
from tb_exudyn.scenario.registry import model_files


@pytest.fixture
def layout(tmp_path, monkeypatch):
    """tmp/sc/s.toml (the scenario), tmp/my/x.toml (a bridge: the shipped continuous girder renamed),
    and the working folder tmp."""
    (tmp_path / "sc").mkdir()
    (tmp_path / "my").mkdir()
    scenario = save_scenario(load_scenario("quick"), tmp_path / "sc" / "s.toml")
    text = model_files("bridges")["continuous_3x32m"].read_text()
    (tmp_path / "my" / "x.toml").write_text(text.replace('name = "continuous_3x32m"', 'name = "mine_from_cwd"', 1))
    monkeypatch.chdir(tmp_path)
    return tmp_path, scenario


def _one_line(capsys) -> str:
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "Traceback" not in err, err
    return err


def test_a_set_file_is_found_from_the_working_folder(layout, capsys):
    tmp, scenario = layout
    assert main(["show", str(scenario), "--set", "bridge=my/x.toml"]) == 0
    assert "mine_from_cwd" in capsys.readouterr().out
    # the same from the shipped scenario's name (its file is in the package's models/)
    assert main(["show", "quick", "--set", "bridge=my/x.toml"]) == 0
    assert "mine_from_cwd" in capsys.readouterr().out


def test_a_set_file_that_is_missing_names_the_path_tried(layout, capsys):
    tmp, scenario = layout
    assert main(["show", str(scenario), "--set", "bridge=sc/x.toml"]) == 2
    err = _one_line(capsys)
    assert str(tmp / "sc" / "x.toml") in err and "file not found" in err and "'bridge=sc/x.toml'" in err
    # a scenario file given relative to the working folder: the message names where it looked
    assert main(["show", "sc/missing.toml"]) == 2
    err = _one_line(capsys)
    assert "sc/missing.toml" in err and str(tmp / "sc" / "missing.toml") in err and "file not found" in err


def test_a_bad_value_in_a_set_file_names_that_file_and_its_key(layout, capsys):
    tmp, scenario = layout
    bad = tmp / "my" / "soft.toml"
    bad.write_text((tmp / "my" / "x.toml").read_text().replace("E = 3.45e10", "E = 3.45e4", 1))
    assert "E = 3.45e4" in bad.read_text()
    assert main(["modes", str(scenario), "--set", "bridge=my/soft.toml"]) == 2
    err = _one_line(capsys)
    assert str(bad) in err and "E" in err and ">= 1e+07" in err


def test_names_of_models_and_absolute_paths_are_kept():
    assert from_working_folder("continuous_3x32m") == "continuous_3x32m"
    assert from_working_folder("/abs/x.toml") == "/abs/x.toml"
    assert from_working_folder(["a.toml", "ice_motor", 3]) == [os.path.abspath("a.toml"), "ice_motor", 3]
    assert from_working_folder("tables/modes.csv") == os.path.abspath("tables/modes.csv")
    sc = with_settings(load_scenario("quick"), [("bridge", "continuous_3x32m")])
    assert sc.bridge == load_bridge("continuous_3x32m")


def test_a_long_file_name_is_never_cut(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    deep = "/".join(["a_rather_long_folder_name_for_a_test"] * 8) + "/bridge.toml"
    assert len(deep) > SHOWN_VALUE_LIMIT
    assert main(["show", "quick", "--set", f"bridge={deep}"]) == 2
    err = _one_line(capsys)
    assert str(tmp_path / deep) in err
    with pytest.raises(ScenarioError) as exc:
        load_bridge(tmp_path / deep)
    assert str(exc.value).count(str(tmp_path / deep)) == 2 and "..." not in str(exc.value)


def test_a_bad_value_is_shown_whole_up_to_the_limit(capsys):
    """A typed value (a name, a typo) is shown whole up to SHOWN_TEXT_LIMIT characters (60: longer is a list
    pasted into one option, e.g. 1001 speeds, whose start says what it was), a path always whole."""
    name = "x" * 30  # no such spectrum: a --set value of 55 characters
    assert main(["show", "quick", "--set", f"track.irregularities=['{name}']"]) == 2
    err = _one_line(capsys)
    assert name in err and "..." not in err.split("(allowed")[0]
    assert short_repr("y" * (SHOWN_VALUE_LIMIT - 2)) == repr("y" * (SHOWN_VALUE_LIMIT - 2))
    cut = short_repr("y" * 10_000)
    assert len(cut) == SHOWN_VALUE_LIMIT and cut.endswith("...")
    assert "\n" not in format_message("f.toml", "k", "a\nb" * 500, "anything")
