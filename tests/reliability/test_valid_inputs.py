"""The defences let valid data through unchanged, and errors raised after loading name the file.

- A loaded scenario remembers its file (``Scenario.source_file``): errors the builder raises later
  name it instead of ``<scenario>``; it is kept by ``replace`` and pickling, ignored by ``==`` and
  not saved.
- Result folders that are valid but unusual (Fortran-ordered or big-endian arrays written by plain
  numpy, every optional array, empty frequency arrays, string arrays in a checkpoint file) load
  exactly.
- A spectrum table with rows in any order is read in order of frequency (documented behaviour).
"""

from __future__ import annotations

import json
import pickle

import numpy as np
import pytest

from tb_exudyn.results import load_results
from tb_exudyn.storage import load_npz
from tb_exudyn.scenario import load_scenario, save_scenario, scenario_to_toml
from tb_exudyn.system.channels import CHANNEL_NAME_RULE, is_channel_name

from .cases import CHANNELS, NT, rr_arrays, rr_meta, th_arrays, th_meta, write_result


def test_a_loaded_scenario_remembers_its_file(tmp_path):
    built = load_scenario("quick").replace(speed_kmh=200.0)
    path = save_scenario(built, tmp_path / "mine.toml")
    sc = load_scenario(path)
    assert sc.source_file == str(path) and sc.where == str(path)
    changed = sc.replace(speed_kmh=210.0)
    assert changed.source_file == str(path) and pickle.loads(pickle.dumps(changed)).source_file == str(path)
    assert sc == built and hash(sc) == hash(built) and scenario_to_toml(sc) == scenario_to_toml(built)
    assert str(path) not in scenario_to_toml(sc)
    fresh = load_scenario("quick").replace(name="made_here")
    import dataclasses

    in_python = dataclasses.replace(fresh)  # plain dataclasses.replace drops it: a scenario built in Python
    assert in_python.source_file is None and in_python.where == "scenario 'made_here'"


def test_a_result_remembers_the_file_its_scenario_came_from(tmp_path):
    f = write_result(tmp_path / "pem", rr_arrays(), rr_meta())
    assert load_results(f).scenario.source_file == str(f / "meta.json")


@pytest.mark.exudyn
def test_errors_found_when_the_model_is_built_name_the_scenario_file(tmp_path, capsys):
    """A pattern in analysis.channels that matches no channel, and a lead-in shorter than ten time
    steps, are found by the builder after loading: the message names the file, not <scenario>."""
    from tb_exudyn.cli import main

    sc = load_scenario("quick")
    bad_channels = save_scenario(sc.replace(analysis=sc.analysis.replace(channels=("car1.boddy.*",))),
                                 tmp_path / "typo.toml")
    short = save_scenario(sc.replace(track=sc.track.replace(lead_in=0.2, taper_length=0.0)), tmp_path / "short.toml")
    for path, key in ((bad_channels, "analysis.channels[0]"), (short, "track.lead_in")):
        assert main(["run", str(path), "--method", "det", "--out", str(tmp_path / "o"), "--no-figures"]) == 2
        err = capsys.readouterr().err
        assert f"{path}: key '{key}'" in err and "<scenario>" not in err and "Traceback" not in err
    assert not (tmp_path / "o" / "det").exists()


@pytest.mark.exudyn
def test_channel_names_of_the_catalogue_follow_the_rule():
    from tb_exudyn.builder import channel_list

    names = [n for n, _ in channel_list(load_scenario("li_zhu_2011"))]
    assert names and all(is_channel_name(n) for n in names), CHANNEL_NAME_RULE
    assert not any(is_channel_name(n) for n in ("a/b", "a..b", ".a", "a.", "", "é", "a b", "a" * 201))


def test_unusual_but_valid_arrays_load_exactly(tmp_path):
    """Fortran order and big-endian floats, as plain numpy may write them, read back bit for bit."""
    rng = np.random.default_rng(1)
    arrays = th_arrays()
    arrays["values"] = np.asfortranarray(rng.standard_normal((2, NT)))
    arrays["time"] = arrays["time"].astype(">f8")
    f = write_result(tmp_path / "det", arrays, th_meta())
    th = load_results(f)
    assert np.array_equal(np.array([th[c] for c in CHANNELS]), arrays["values"])
    assert np.array_equal(th.time, arrays["time"])


def test_a_monte_carlo_response_with_every_optional_array_loads_exactly(tmp_path):
    rng = np.random.default_rng(2)
    n = 4
    arrays = {"time": np.arange(NT) * 0.01, "mean": rng.standard_normal((2, NT)), "std": rng.random((2, NT)),
              "freq": np.zeros(0), "df": np.zeros(0), "std_ci": rng.random((2, 2, NT)),
              "mean_ci": rng.random((2, 2, NT)), "min_wheel_force": np.array([1.0, np.nan, 3.0, 4.0]),
              "samples": rng.standard_normal((n, 2, NT))}
    f = write_result(tmp_path / "mc", arrays, rr_meta(method="monte_carlo", n_samples=n, types=[]))
    r = load_results(f)
    for name, value in arrays.items():
        assert np.array_equal(getattr(r, name), value, equal_nan=True), name
    assert r.n_samples == n and r.method == "monte_carlo"


def test_checkpoint_style_npz_with_strings_loads(tmp_path):
    """load_npz (also used for checkpoint task files) reads fixed-width string arrays and scalars."""
    path = tmp_path / "task.npz"
    np.savez(path, names=np.array(CHANNELS, dtype=str), n=np.int64(3), v=np.ones((2, 3)))
    out = load_npz(path)
    assert list(out["names"]) == list(CHANNELS) and int(out["n"]) == 3 and out["v"].shape == (2, 3)


def test_spectrum_table_rows_in_any_order(tmp_path):
    """Rows given by decreasing frequency (increasing wavelength) are sorted: the table is the same
    as the one written in order, value for value."""
    from tb_exudyn.track import user_table_spectrum

    rows = [(2.0, 1e-8), (10.0, 1e-6), (5.0, 1e-7), (50.0, 1e-5)]
    (tmp_path / "shuffled.csv").write_text("wavelength,psd\n" + "".join(f"{w},{p}\n" for w, p in rows))
    (tmp_path / "sorted.csv").write_text("wavelength,psd\n" + "".join(f"{w},{p}\n" for w, p in sorted(rows, reverse=True)))
    a = user_table_spectrum(tmp_path / "shuffled.csv", "vertical", "m")
    b = user_table_spectrum(tmp_path / "sorted.csv", "vertical", "m")
    assert a.omega == b.omega and a.values == b.values
    assert list(a.omega) == sorted(a.omega) and a.values[0] == 1e-5


def test_meta_json_written_by_save_is_within_the_limits(tmp_path):
    """What tb_exudyn writes, it reads: a saved result's meta.json passes the loader's own checks."""
    from tb_exudyn.storage import MAX_JSON_DEPTH, json_depth

    f = write_result(tmp_path / "pem", rr_arrays(), rr_meta())
    r = load_results(f)
    r.save(tmp_path / "again")
    meta = json.loads((tmp_path / "again" / "meta.json").read_text())
    assert json_depth(meta) <= MAX_JSON_DEPTH
    back = load_results(tmp_path / "again")
    assert np.array_equal(back.psd, r.psd) and back.scenario == r.scenario
