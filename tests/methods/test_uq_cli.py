"""``tb-exudyn uq``: bad uncertain files refused in one line with nothing written; an interrupted study
resumed gives the same result bitwise; the result does not depend on the number of workers; it saves,
loads and labels (issue 46)."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

import tb_exudyn as tbx
from tb_exudyn.cli import main
from tb_exudyn.methods.uq import UqMethod
from tb_exudyn.results.uq import UQ_SCHEMA, load_uq
from tb_exudyn.scenario.uncertain import check_uncertain

sys.path.insert(0, str(Path(__file__).parent))
from test_uq_sprung_mass import KEYS, scenario  # noqa: E402

pytestmark = pytest.mark.exudyn

BAD = {
    "unknown key": ('[uncertain."bridge.girder.EE"]\ndistribution = "normal"\ncov = 0.1\n', "unknown key"),
    "bad distribution": ('[uncertain."bridge.girder.E"]\ndistribution = "weibull"\ncov = 0.1\n',
                         "unknown distribution"),
    "negative cov": ('[uncertain."bridge.girder.E"]\ndistribution = "lognormal"\ncov = -0.1\n', "not positive"),
    "lognormal of a zero key": ('[uncertain."bridge.girder.shear_area_factor"]\ndistribution = "lognormal"\n'
                                'std = 0.1\n', "lognormal: a positive mean"),
    "bounds outside the range": ('[uncertain."bridge.damping_ratio"]\ndistribution = "uniform"\n'
                                 'bounds = [-0.01, 0.05]\n', "does not allow"),
    "normal leaving the range": ('[uncertain."bridge.girder.E"]\ndistribution = "normal"\ncov = 0.3\n',
                                 "does not allow"),
    "a key that changes the run": ('[uncertain."speed_kmh"]\ndistribution = "normal"\ncov = 0.05\n',
                                   "changes the run"),
    "no table": ('[certain]\nx = 1\n', "one table"),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_bad_uncertain_file_is_one_line_and_writes_nothing(case, tmp_path, capsys):
    text, match = BAD[case]
    f = tmp_path / "u.toml"
    f.write_text(text)
    out = tmp_path / "out"
    assert main(["uq", "quick", "--uncertain-file", str(f), "--out", str(out), "--no-progress"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and match in err, err
    assert not out.exists()


def test_uncertain_file_that_is_a_folder_is_refused(tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["uq", "quick", "--uncertain-file", str(tmp_path), "--out", str(out), "--no-progress"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and str(tmp_path) in err and "directory" in err, err
    assert not out.exists()


def test_bad_order_names_the_option(tmp_path, capsys):
    f = tmp_path / "u.toml"
    f.write_text('[uncertain."bridge.damping_ratio"]\ndistribution = "uniform"\nrelative_bounds = [-0.2, 0.2]\n')
    assert main(["uq", "quick", "--uncertain-file", str(f), "--order", "99", "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err.strip()
    assert "--order" in err and len(err.splitlines()) == 1
    assert not (tmp_path / "o").exists()


def _arrays(r):
    return {v.name: np.asarray(r.data[v.name]) for v in UQ_SCHEMA}


def test_interrupted_study_resumes_bitwise_and_workers_do_not_matter(tmp_path, monkeypatch):
    """Stop after 7 of 16 nodes (KeyboardInterrupt, as Ctrl-C), resume: every array equal bitwise to an
    uninterrupted study's, and to one on two workers."""
    sc = scenario()
    keys = check_uncertain(sc, KEYS, "test")
    kw = dict(order=3, progress=False, channels=["car1.body.acc_z"], window=(2.5, 10.0))
    whole = tbx.run_uq(sc, keys, workers=1, out=tmp_path / "a", **kw)
    reduce = UqMethod.reduce
    seen = []

    def stopping(self, state, i, task, result):
        if len(seen) == 7:
            raise KeyboardInterrupt
        seen.append(i)
        reduce(self, state, i, task, result)

    monkeypatch.setattr(UqMethod, "reduce", stopping)
    with pytest.raises(KeyboardInterrupt):
        tbx.run_uq(sc, keys, workers=1, out=tmp_path / "b", **kw)
    monkeypatch.setattr(UqMethod, "reduce", reduce)
    resumed = tbx.run_uq(sc, keys, workers=1, out=tmp_path / "b", resume=True, **kw)
    assert resumed.provenance["tasks_from_checkpoint"] >= 7
    two = tbx.run_uq(sc, keys, workers=2, **kw)
    a = _arrays(whole)
    for other in (resumed, two, load_uq(tmp_path / "b" / "uq")):
        b = _arrays(other)
        for name in a:
            assert np.array_equal(a[name], b[name], equal_nan=True), name
    ds = load_uq(tmp_path / "a" / "uq").to_xarray()
    assert ds["mean_sigma"].dims == ("channel", "time") and list(ds["key"].values) == list(KEYS)


def test_cli_study_writes_result_and_figures(tmp_path, capsys):
    """The command on the sprung mass: its table, the result folder and the two figures."""
    from tb_exudyn.scenario import save_scenario

    path = save_scenario(scenario(), tmp_path / "s.toml")
    path.write_text(path.read_text() + '\n[uncertain."train.vehicles.0.damping"]\ndistribution = "uniform"\n'
                    'relative_bounds = [-0.2, 0.2]\n')
    out = tmp_path / "out"
    assert main(["uq", str(path), "--order", "2", "--workers", "1", "--out", str(out), "--no-progress",
                 "--channels", "car1.body.acc_z"]) == 0
    text = capsys.readouterr().out
    assert "car1.body.acc_z [m/s^2]" in text and "3 nodes" in text and "uq.html" in text
    assert (out / "uq" / "meta.json").is_file() and (out / "uq_sobol.png").stat().st_size > 0
    assert (out / "uq_band.car1.body.acc_z.png").stat().st_size > 0
    assert (out / "uq.html").read_text().index("<section id=\"verdict\">") < (out / "uq.html").read_text().index("<section id=\"loo\">")
    r = load_uq(out / "uq")
    assert r.quantity("max_sigma:car1.body.acc_z")["sobol_first"]["train.vehicles.0.damping"] > 0.999


def test_run_uq_takes_a_table_and_checks_it_before_any_run(tmp_path):
    """run_uq with an [uncertain] table as a dict: a bad key is refused naming it, nothing written."""
    with pytest.raises(tbx.ScenarioError, match="run_uq: key 'uncertain.bridge.girder.EE'.*unknown key"):
        tbx.run_uq(scenario(), {"bridge.girder.EE": {"distribution": "normal", "cov": 0.1}}, out=tmp_path / "o")
    with pytest.raises(tbx.ScenarioError, match="not positive"):
        tbx.run_uq(scenario(), {"bridge.damping_ratio": {"distribution": "normal", "cov": -0.1}}, out=tmp_path / "o")
    assert not (tmp_path / "o").exists()


def test_saved_result_is_checked_when_loaded(tmp_path):
    """A saved result loads back equal; one whose sigma was made negative is refused naming the array."""
    from tb_exudyn.errors import ResultsError
    from tb_exudyn.results.uq import UqResult

    rng = np.random.default_rng(1)
    nt, nc, nq, nk, nn = 5, 2, 3, 2, 4
    shapes = {"time": (nt,), "mean_sigma": (nc, nt), "std_sigma": (nc, nt), "mean_response": (nc, nt),
              "sigma_band": (3, nc, nt), "quantity_mean": (nq,), "quantity_std": (nq,), "quantity_band": (3, nq), "sobol_first": (nk, nq),
              "sobol_total": (nk, nq), "loo": (nq,), "pf": (1,), "node_values": (nn, nk), "node_weights": (nn,),
              "node_quantities": (nn, nq)}
    data = {k: np.abs(rng.standard_normal(v)) for k, v in shapes.items()}
    data["time"] = np.arange(nt) * 0.1
    r = UqResult(scenario=scenario(), keys=({"key": "a"}, {"key": "b"}), channels=("c1", "c2"), units=("m", "m"),
                 quantities=("q1", "q2", "q3"), criteria=("crit",), data=data)
    r.save(tmp_path / "uq")
    back = load_uq(tmp_path / "uq")
    assert all(np.array_equal(back.data[k], data[k]) for k in data) and back.criteria == ("crit",)
    data["std_sigma"][0, 0] = -1.0
    r.save(tmp_path / "bad")
    with pytest.raises(ResultsError, match="std_sigma.*negative"):
        load_uq(tmp_path / "bad")


def test_bad_set_names_the_option(tmp_path, capsys):
    f = tmp_path / "u.toml"
    f.write_text('[uncertain."bridge.damping_ratio"]\ndistribution = "uniform"\nrelative_bounds = [-0.2, 0.2]\n')
    assert main(["uq", "quick", "--uncertain-file", str(f), "--set", "bridge.damping_ratio=-1",
                 "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err.strip()
    assert "--set" in err and "bridge.damping_ratio" in err and len(err.splitlines()) == 1, err
    assert not (tmp_path / "o").exists()
