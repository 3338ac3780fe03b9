"""CSV and MATLAB export: files load back equal to the result (CSV exactly: repr-precision floats)."""

from __future__ import annotations

import csv
import importlib.util
import json
import tomllib
from pathlib import Path

import numpy as np
import pytest
import scipy.io

from tb_exudyn.results import export
from tb_exudyn.results.export import export_csv, export_mat, read_csv
from tb_exudyn.scenario import scenario_from_dict

_spec = importlib.util.spec_from_file_location(
    "synthetic_results", Path(__file__).resolve().parents[1] / "plotting" / "synthetic_results.py")
synthetic = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(synthetic)


def _csv_columns(path):
    """Read with the csv module (independently of read_csv): header and float columns."""
    with open(path, newline="") as fh:
        rows = [r for r in csv.reader(fh) if r and not r[0].startswith("#")]
    return rows[0], np.array(rows[1:], dtype=float).T


def test_random_response_csv_is_exact(tmp_path):
    r = synthetic.pem_response()
    files = export_csv(r, tmp_path)
    assert [p.name for p in files] == ["mean.csv", "std.csv"]
    for path, values in zip(files, (r.mean, r.std)):
        header, cols = _csv_columns(path)
        assert header == ["time [s]"] + [f"{c} [{u}]" for c, u in zip(r.channels, r.units)]
        assert np.array_equal(cols[0], r.time) and np.array_equal(cols[1:], values)  # bit for bit
        t, names, back = read_csv(path)
        assert np.array_equal(t, r.time) and np.array_equal(back, values) and names == header[1:]
    first = files[1].read_text().splitlines()[0]
    assert first.startswith("#") and "0-12 Hz" in first and "sigma" in first
    assert not list(tmp_path.glob(".*"))


def test_time_history_csv_is_exact(tmp_path):
    th = synthetic.time_history()
    (path,) = export_csv(th, tmp_path / "sub")
    header, cols = _csv_columns(path)
    assert header[1] == "bridge.span1.mid.acc_z [m/s^2]"
    assert np.array_equal(cols[1:], np.array([th[c] for c in th.names]))


def test_random_response_mat_round_trip(tmp_path):
    r = synthetic.mc_response()
    path = export_mat(r, tmp_path / "mc.mat")
    m = scipy.io.loadmat(path)
    assert np.array_equal(m["mean_response"], r.mean) and np.array_equal(m["std_response"], r.std)
    for name in ("std_ci", "mean_ci", "samples"):
        assert np.array_equal(m[name], getattr(r, name)), name
    assert np.array_equal(m["time"].ravel(), r.time) and np.array_equal(m["min_wheel_force"].ravel(), r.min_wheel_force)
    assert np.array_equal(m["band"].ravel(), r.band) and m["n_samples"].item() == r.n_samples
    assert [str(c[0]) for c in m["channels"].ravel()] == list(r.channels)
    assert [str(u[0]) for u in m["units"].ravel()] == list(r.units)
    assert "psd" not in m and str(m["method"][0]) == "monte_carlo"
    sc = scenario_from_dict(tomllib.loads(str(m["scenario_toml"][0])), "mat")
    assert sc == r.scenario
    assert json.loads(str(m["provenance_json"][0])) == r.provenance


def test_pem_mat_keeps_the_psd_and_time_history_mat(tmp_path):
    r = synthetic.pem_response()
    m = scipy.io.loadmat(export_mat(r, tmp_path / "pem.mat"))
    assert m["psd"].shape == r.psd.shape and np.array_equal(m["psd"], r.psd)
    assert np.array_equal(m["freq"].ravel(), r.freq) and np.array_equal(m["df"].ravel(), r.df)
    th = synthetic.time_history()
    m = scipy.io.loadmat(export_mat(th, tmp_path / "th.mat"))
    assert np.array_equal(m["values"], np.array([th[c] for c in th.names]))
    assert str(m["kind"][0]) == "time_history"


def test_a_failed_write_leaves_no_file(tmp_path, monkeypatch):
    def broken(fh, data, **kw):
        fh.write(b"MATLAB 5.0 half a file")
        raise OSError("disk full")

    monkeypatch.setattr(export.scipy.io, "savemat", broken)
    with pytest.raises(OSError, match="disk full"):
        export_mat(synthetic.time_history(), tmp_path / "th.mat")
    assert not list(tmp_path.iterdir())
