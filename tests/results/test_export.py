"""Exports: labelled arrays (to_xarray, NetCDF), CSV for pandas and MATLAB files load back equal to the
result (CSV exactly: repr-precision floats; NetCDF and MAT bit for bit: they store the doubles)."""

from __future__ import annotations

import csv
import importlib.util
import json
import tomllib
from pathlib import Path

import numpy as np
import pytest
import scipy.io

from tb_exudyn.errors import OutputFolderError, SettingError
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
    assert first.startswith("time [s],")  # no comment line: what the file holds is in the sidecar
    about = json.loads(export.sidecar_path(files[1]).read_text())
    assert "0-12 Hz" in about["about"] and "sigma" in about["about"]
    assert about["columns"][2] == {"header": "car1.body.acc_y [m/s^2]", "name": "car1.body.acc_y", "unit": "m/s^2"}
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


# ------------------------------------------------------------------------------------------ labelled arrays
xr = pytest.importorskip("xarray")


def test_to_xarray_of_a_pem_result():
    r = synthetic.pem_response()
    ds = r.to_xarray()
    assert dict(ds.sizes) == {"channel": 4, "time": r.time.size, "frequency": 6}
    assert list(ds.channel.values) == list(r.channels) and list(ds.unit.values) == list(r.units)
    assert ds.label.sel(channel="car1.axle1.force_y").item() == "car 1, axle 1, lateral wheel-rail force"
    assert np.array_equal(ds.time.values, r.time) and np.array_equal(ds.frequency.values, r.freq)
    assert np.array_equal(ds["mean"].values, r.mean) and np.array_equal(ds["std"].values, r.std)
    assert np.array_equal(ds.psd.transpose("channel", "frequency", "time").values, r.psd)
    assert np.array_equal(ds.df.values, r.df)
    # labelled access: a channel and a time by name, not by index
    i = r.index("car1.body.acc_y")
    assert ds["std"].sel(channel="car1.body.acc_y", time=0.5).item() == r.std[i, int(np.argmin(abs(r.time - 0.5)))]
    assert ds.time.attrs["units"] == "s" and ds.frequency.attrs["units"] == "Hz"
    assert ds["std"].attrs["units_coordinate"] == "unit" and ds.psd_unit.values[1] == "(m/s^2)^2/Hz"
    assert list(ds.attrs["band_hz"]) == list(r.band) and ds.attrs["method"] == "pem"
    assert json.loads(ds.attrs["provenance_json"]) == r.provenance
    assert scenario_from_dict(tomllib.loads(ds.attrs["scenario_toml"]), "nc") == r.scenario


def test_to_xarray_of_monte_carlo_and_of_a_run():
    mc = synthetic.mc_response()
    ds = mc.to_xarray()
    assert list(ds.bound.values) == ["lower", "upper"] and ds.sizes["sample"] == mc.n_samples
    assert np.array_equal(ds.std_ci.values, mc.std_ci) and np.array_equal(ds.mean_ci.values, mc.mean_ci)
    assert np.array_equal(ds.samples.values, mc.samples) and np.array_equal(ds.min_wheel_force.values, mc.min_wheel_force)
    assert "frequency" not in ds.dims and ds.attrs["n_samples"] == mc.n_samples
    th = synthetic.time_history()
    ds = th.to_xarray()
    assert np.array_equal(ds.value.sel(channel="car1.axle1.force_y").values, th["car1.axle1.force_y"])
    assert ds.attrs["kind"] == "time_history"


def test_var_by_type_has_a_type_dimension():
    r = synthetic.pem_response()
    vbt = np.stack([0.25 * r.std ** 2, 0.75 * r.std ** 2])
    r = type(r)(**{**r.__dict__, "var_by_type": vbt, "types": ("german_low.vertical", "german_low.alignment")})
    ds = r.to_xarray()
    assert list(ds.type.values) == ["german_low.vertical", "german_low.alignment"]
    assert np.array_equal(ds.var_by_type.sel(type="german_low.alignment").values, vbt[1])


@pytest.mark.parametrize("engine", ["h5netcdf", "scipy"])
def test_netcdf_reads_back_with_xarray(tmp_path, engine):
    pytest.importorskip(engine)
    for r in (synthetic.pem_response(), synthetic.mc_response(), synthetic.time_history()):
        path = export.export_netcdf(r, tmp_path / "r.nc", engine=engine)
        with xr.open_dataset(path, engine=engine) as back:
            back = back.load()
        want = r.to_xarray()
        for name in want.data_vars:
            assert np.array_equal(back[name].values, want[name].values), name  # the doubles, bit for bit
        assert list(back.channel.values) == list(want.channel.values)
        assert list(back.unit.values) == list(want.unit.values)
        assert np.array_equal(back.time.values, want.time.values)
        assert back.attrs["scenario_toml"] == want.attrs["scenario_toml"]
        if "band_hz" in want.attrs:
            assert list(np.atleast_1d(back.attrs["band_hz"])) == list(want.attrs["band_hz"])
    assert not list(tmp_path.glob(".*"))


def test_csv_reads_with_pandas_defaults(tmp_path):
    """pandas.read_csv(path) with no arguments: the header is the first line, units in the headers.
    Values are compared to rtol 1e-15: pandas before 3.0 parses floats by default with a fast
    parser that may differ from the exact double by 1 ulp (pandas 3 reads them exactly)."""
    pd = pytest.importorskip("pandas")
    r = synthetic.pem_response()
    path, sidecar = export.export(r, "csv", tmp_path / "pem.csv")
    table = pd.read_csv(path)
    assert list(table.columns[:3]) == ["time [s]", "bridge.span1.mid.acc_z mean [m/s^2]",
                                       "bridge.span1.mid.acc_z sigma [m/s^2]"]
    assert len(table.columns) == 1 + 2 * len(r.channels)
    for i, (c, u) in enumerate(zip(r.channels, r.units)):
        assert np.allclose(table[f"{c} mean [{u}]"], r.mean[i], rtol=1e-15, atol=0)
        assert np.allclose(table[f"{c} sigma [{u}]"], r.std[i], rtol=1e-15, atol=0)
    assert np.allclose(table["time [s]"], r.time, rtol=1e-15, atol=0)
    assert json.loads(sidecar.read_text())["columns"][0]["unit"] == "s"
    th = synthetic.time_history()
    (path, _) = export.export(th, "csv", tmp_path / "th.csv")
    assert list(pd.read_csv(path).columns) == ["time [s]"] + [f"{c} [{th.unit(c)}]" for c in th.names]


def test_export_entry_point(tmp_path):
    r = synthetic.mc_response()
    (mat,) = export.export(r, "mat", tmp_path / "mc.mat")
    m = scipy.io.loadmat(mat)
    assert np.array_equal(m["std_response"], r.std)
    assert [str(x[0]) for x in m["labels"].ravel()][1] == "car 1, body, lateral acceleration"
    (nc,) = export.export(r, "netcdf", tmp_path / "mc.nc")
    assert nc.stat().st_size > 0
    with pytest.raises(SettingError, match="key 'format' = 'xlsx'.*allowed: netcdf, csv, mat"):
        export.export(r, "xlsx", tmp_path / "mc.xlsx")
    with pytest.raises(OutputFolderError, match="is a directory, not a regular file"):
        export.export(r, "csv", tmp_path)


def test_netcdf_without_bytes_from_xarray_is_a_checked_file(tmp_path, monkeypatch):
    """xarray before 2025 returns bytes from the scipy engine only (ValueError otherwise): the
    export then writes the file through HDF5, after checking the free space against the
    uncompressed size (+5 %, +1 MiB), so that HDF5 never meets a full disk it could crash on."""
    import tb_exudyn.files as files
    from tb_exudyn.errors import OutputFolderError

    to_netcdf = xr.Dataset.to_netcdf

    def old_xarray(self, path=None, *args, **kwargs):
        if path is None and kwargs.get("engine") != "scipy":
            raise ValueError("invalid engine for creating bytes with to_netcdf: 'h5netcdf'")
        return to_netcdf(self, path, *args, **kwargs)

    monkeypatch.setattr(xr.Dataset, "to_netcdf", old_xarray)
    r = synthetic.pem_response()
    (path,) = export.export(r, "netcdf", tmp_path / "r.nc")
    with xr.open_dataset(path, engine="h5netcdf") as back:
        assert np.array_equal(back["std"].values, r.std) and np.array_equal(back["psd"].values, r.psd)
    bound = r.to_xarray().nbytes * 1.05 + (1 << 20)
    # the compressed file would fit, the bound does not: refused before HDF5 writes anything
    monkeypatch.setattr(files, "_free_space", lambda folder: (int(bound) - 1, 4096))
    with pytest.raises(OutputFolderError, match=r"r2\.nc'.*needs .* free"):
        export.export(r, "netcdf", tmp_path / "r2.nc")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["r.nc"]
