"""The Python API's errors are the library's (issue 49): what a user can pass wrong to a public call is
either accepted as meant or refused with a tb_exudyn error naming the call, the argument and what to pass.

- A scenario's name or file where a Scenario is expected is loaded (every public entry point that
  runs a scenario: simulate, run_pem, run_monte_carlo, run_deterministic, run_sweep); any other type is
  an ArgumentTypeError, which is also a TypeError.
- A channel by a non-string key (``result[0]``) is an ArgumentTypeError naming what is allowed.
- ``save_scenario`` onto a folder (or a FIFO, or under a file) is refused naming the path, and
  nothing is left beside it.

The entry points are checked up to the method they hand to the driver (the driver is replaced by a
recorder): what is asserted is which scenario they run, not a result.
"""

from __future__ import annotations

import os
import pickle
from pathlib import Path

import pytest

import tb_exudyn
from tb_exudyn.errors import ArgumentTypeError, OutputFolderError, SettingError, UserError
from tb_exudyn.results import load_results
from tb_exudyn.scenario import load_scenario, save_scenario

from .cases import CHANNELS, rr_arrays, rr_meta, th_arrays, th_meta, write_result


class _Handed(Exception):
    """Raised by the recorder in place of the driver: carries the method handed to it."""


def _record(method, execution=None):
    raise _Handed(method)


def _handed_scenario(call) -> object:
    with pytest.raises(_Handed) as got:
        call()
    return got.value.args[0].scenario


@pytest.fixture
def recorder(monkeypatch):
    import tb_exudyn.methods as methods
    import tb_exudyn.methods.sweep as sweep
    import tb_exudyn.methods.uq.method as uq

    for module in (methods, sweep, uq):
        monkeypatch.setattr(module, "drive", _record)


ENTRY_POINTS = {
    "simulate": lambda sc: tb_exudyn.simulate(sc, "pem"),
    "run_pem": lambda sc: tb_exudyn.run_pem(sc, progress=False),
    "run_monte_carlo": lambda sc: tb_exudyn.run_monte_carlo(sc, n_samples=2, progress=False),
    "run_sweep": lambda sc: __import__("tb_exudyn.methods.sweep").methods.sweep.run_sweep(sc, [200.0, 250.0]),
    "run_uq": lambda sc: __import__("tb_exudyn.methods.uq.method").methods.uq.method.run_uq(
        sc, {"bridge.girder.E": {"distribution": "lognormal", "cov": 0.05}}, order=1),
}


@pytest.mark.parametrize("name", ENTRY_POINTS)
def test_a_scenario_name_or_file_is_loaded(name, recorder, tmp_path):
    quick = load_scenario("quick")
    assert _handed_scenario(lambda: ENTRY_POINTS[name]("quick")) == quick
    path = save_scenario(quick, tmp_path / "mine.toml")
    for given in (path, str(path)):
        handed = _handed_scenario(lambda: ENTRY_POINTS[name](given))
        assert handed == quick and handed.source_file == str(path)


def test_run_deterministic_loads_a_name(monkeypatch):
    import tb_exudyn.methods.deterministic as det

    def build(scenario):
        raise _Handed(scenario)

    monkeypatch.setattr(det, "build_model", build)
    with pytest.raises(_Handed) as got:
        tb_exudyn.run_deterministic("quick")
    assert got.value.args[0] == load_scenario("quick")


@pytest.mark.parametrize("name", [*ENTRY_POINTS, "run_deterministic"])
@pytest.mark.parametrize("wrong", [None, 3, {"name": "quick"}, ["quick"]])
def test_any_other_type_is_a_type_error_saying_what_to_pass(name, wrong):
    call = ENTRY_POINTS.get(name) or (lambda sc: tb_exudyn.run_deterministic(sc))
    with pytest.raises(ArgumentTypeError) as err:
        call(wrong)
    e = err.value
    assert isinstance(e, TypeError) and isinstance(e, UserError) and e.key == "scenario"
    assert "Scenario" in e.allowed and "name" in e.allowed and type(wrong).__name__ in str(e)
    assert "\n" not in str(e) and str(pickle.loads(pickle.dumps(e))) == str(e)


def test_an_unknown_name_is_the_library_error_naming_the_names():
    with pytest.raises(UserError, match=r"unknown scenario name \(allowed: one of \w+, \w+, \w+, \.\.\. \(\d+ in all\)"):
        tb_exudyn.run_pem("no_such_scenario", progress=False)  # the three closest names and the count
    with pytest.raises(UserError, match=r"one of quick, "):
        tb_exudyn.run_pem("quik", progress=False)


@pytest.mark.parametrize("kind", ["random_response", "time_history"])
@pytest.mark.parametrize("key", [0, -1, 1.5, None, slice(0, 2), ("a",)])
def test_a_channel_by_a_non_string_key_is_a_type_error(kind, key, tmp_path):
    arrays, meta = (rr_arrays(), rr_meta()) if kind == "random_response" else (th_arrays(), th_meta())
    result = load_results(write_result(tmp_path / "r", arrays, meta))
    for call in (lambda: result[key], lambda: result.index(key), lambda: result.unit(key)):
        with pytest.raises(ArgumentTypeError) as err:
            call()
        e = err.value
        assert isinstance(e, TypeError) and e.key == "channel" and "result.channel_names" in e.allowed
        assert repr(CHANNELS[0]) in e.allowed and type(key).__name__ in str(e)
    if isinstance(key, int):
        assert f"result.channel_names[{key}]" in str(err.value)
    assert result.index(CHANNELS[1]) == 1  # names still work
    with pytest.raises(KeyError, match="no channel"):  # an unknown name stays a KeyError
        result["bridge.nothing"]


def _entries(folder: Path) -> list[str]:
    return sorted(os.listdir(folder))


def test_save_onto_a_folder_is_refused_naming_it_and_leaves_nothing(tmp_path):
    sc = load_scenario("quick")
    (tmp_path / "a_folder").mkdir()
    before = _entries(tmp_path)
    for target in (tmp_path / "a_folder", str(tmp_path / "a_folder")):
        with pytest.raises(SettingError) as err:
            save_scenario(sc, target)
        assert err.value.key == "path" and str(tmp_path / "a_folder") in str(err.value)
        assert "is a folder" in str(err.value) and "quick.toml" in err.value.allowed
    assert _entries(tmp_path) == before and _entries(tmp_path / "a_folder") == []


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no FIFOs here")
def test_save_onto_a_fifo_or_under_a_file_is_refused_and_leaves_nothing(tmp_path):
    sc = load_scenario("quick")
    os.mkfifo(tmp_path / "pipe.toml")
    (tmp_path / "plain").write_text("x")
    before = _entries(tmp_path)
    with pytest.raises(SettingError, match="no regular file") as err:
        save_scenario(sc, tmp_path / "pipe.toml")
    assert str(tmp_path / "pipe.toml") in str(err.value)
    with pytest.raises(OutputFolderError) as err:
        save_scenario(sc, tmp_path / "plain" / "x.toml")
    assert str(tmp_path / "plain" / "x.toml") in str(err.value) and "\n" not in str(err.value)
    assert _entries(tmp_path) == before and (tmp_path / "plain").read_text() == "x"


def test_save_with_a_wrong_type_is_a_type_error(tmp_path):
    sc = load_scenario("quick")
    with pytest.raises(ArgumentTypeError, match="path"):
        save_scenario(sc, 3)
    with pytest.raises(ArgumentTypeError, match="scenario"):
        save_scenario({"name": "x"}, tmp_path / "x.toml")
    assert _entries(tmp_path) == []
    assert load_scenario(save_scenario("quick", tmp_path / "q.toml")) == sc  # a name is loaded, then saved
