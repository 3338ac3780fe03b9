"""The one schema of a result (tb_exudyn.results.schema): every array a result type holds is in its
schema, its npz file and its NetCDF export, by construction.

The arrays are found by walking the result's dataclass fields (every field annotated as an ndarray,
and a time history's channel mapping), not from the schema or a list written here: a field added to
RandomResponse or TimeHistory without a schema entry fails ``test_every_array_field_is_declared``,
and one the export leaves out fails the NetCDF tests. The values must come back bit for bit (the
export and the npz store the doubles unchanged: no tolerance applies).
"""

from __future__ import annotations

import dataclasses
import importlib.util
from pathlib import Path
from typing import Any, Mapping

import numpy as np
import pytest

from tb_exudyn.results import RandomResponse, TimeHistory, load_results
from tb_exudyn.results.schema import DIM_SIZES, RANDOM_RESPONSE, TIME_HISTORY, members

_spec = importlib.util.spec_from_file_location(
    "synthetic_results", Path(__file__).resolve().parents[1] / "plotting" / "synthetic_results.py")
synthetic = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(synthetic)


def _array_fields(cls: type) -> list[str]:
    """The dataclass fields of ``cls`` annotated as arrays (``np.ndarray``, ``NDArray``, or None; not a
    mapping of arrays, a time history's channels)."""
    return [f.name for f in dataclasses.fields(cls)
            if "ndarray" in str(f.type).lower() and not str(f.type).startswith("Mapping")]


def _schema_of(cls: type) -> dict[str, Any]:
    return {v.name: v for v in cls.schema}


def test_every_array_field_is_declared():
    """RandomResponse: each array field is a schema variable (and nothing else is); TimeHistory: its
    time is, and its channels are the schema's ``values``."""
    assert sorted(_array_fields(RandomResponse)) == sorted(_schema_of(RandomResponse))
    assert RandomResponse.schema is RANDOM_RESPONSE and TimeHistory.schema is TIME_HISTORY
    assert _array_fields(TimeHistory) == ["time"] and set(_schema_of(TimeHistory)) == {"time", "values"}
    for v in (*RANDOM_RESPONSE, *TIME_HISTORY):
        assert all(d in DIM_SIZES for d in v.dims), v.name


def _full_pem() -> RandomResponse:
    """The synthetic PEM result with every array field it lacks filled (shapes from the schema's dims:
    a field without a schema entry cannot be filled and fails here), kept PSD rows for two channels."""
    r = synthetic.pem_response()
    rng = np.random.default_rng(3)
    ns = 4
    size = {"time": r.time.size, "channel": len(r.channels), "frequency": r.freq.size, "psd_channel": 2,
            "type": 2, "sample": ns, "bound": 2}
    schema = _schema_of(RandomResponse)
    fill: dict[str, Any] = {}
    for name in _array_fields(RandomResponse):
        if getattr(r, name) is None:
            assert name in schema, f"RandomResponse.{name} is an array with no schema entry"
            fill[name] = rng.random(tuple(size[d] for d in schema[name].dims))
    fill["psd"] = r.psd[[1, 3]]
    return dataclasses.replace(r, **fill, n_samples=ns, psd_channels=(r.channels[1], r.channels[3]),
                               types=("german_low.vertical", "german_low.alignment"))


def _results() -> list[Any]:
    return [synthetic.pem_response(), synthetic.mc_response(), _full_pem(), synthetic.time_history()]


def _held(result: Any) -> dict[str, np.ndarray]:
    """Every array the result object holds, from its fields: RandomResponse's array fields; a
    TimeHistory's time and each channel (``values`` row by row)."""
    out = {name: getattr(result, name) for name in _array_fields(type(result)) if getattr(result, name) is not None}
    for f in dataclasses.fields(result):
        value = getattr(result, f.name)
        if isinstance(value, Mapping) and value and all(isinstance(a, np.ndarray) for a in value.values()):
            out.update({f"{f.name}[{k}]": a for k, a in value.items()})
    return out


def _check_dataset(result: Any, ds: Any) -> None:
    schema = _schema_of(type(result))
    for key, a in _held(result).items():
        if key.startswith("channels["):  # a time history's channel: a row of 'value'
            got = ds[schema["values"].labelled_name].sel(channel=key[len("channels["):-1]).values
        else:
            if a.size == 0:  # no element (Monte Carlo's freq and df): nothing to hold
                continue
            v = schema[key]
            dims = [d if d != "psd_channel" or result.psd_channels is not None else "channel" for d in v.dims]
            got = ds[v.labelled_name].transpose(*dims).values
        assert got.shape == a.shape and np.array_equal(got, a, equal_nan=True), key


@pytest.mark.parametrize("which", range(4))
def test_the_labelled_form_holds_every_array(which):
    pytest.importorskip("xarray")
    r = _results()[which]
    _check_dataset(r, r.to_xarray())


@pytest.mark.parametrize("which", range(4))
def test_the_netcdf_file_holds_every_array(tmp_path, which):
    """Written with h5netcdf (the default engine) and read back with xarray."""
    xr = pytest.importorskip("xarray")
    pytest.importorskip("h5netcdf")
    from tb_exudyn.results.export import export_netcdf

    r = _results()[which]
    path = export_netcdf(r, tmp_path / "r.nc")
    with xr.open_dataset(path, engine="h5netcdf") as back:
        _check_dataset(r, back.load())


@pytest.mark.parametrize("which", range(4))
def test_the_npz_folder_holds_every_array(tmp_path, which):
    """Saved and loaded: every array held comes back, and the file's members are the schema's."""
    r = _results()[which]
    back = load_results(r.save(tmp_path / "r"))
    want, got = _held(r), _held(back)
    assert set(got) == set(want)
    for key, a in want.items():
        assert np.array_equal(got[key], a, equal_nan=True), key
    with np.load(tmp_path / "r" / "arrays.npz") as npz:
        assert set(npz.files) <= set(members(type(r).schema)) and set(npz.files) == set(r.arrays())


def test_a_channel_subset_slices_every_array_over_channels():
    """plotting.data.channel_subset (what a figure worker receives): every array with a channel dim
    has the chosen rows, in the chosen order (found from the fields: an array left unsliced keeps the
    full channel count and fails here); the kept PSD rows follow."""
    from tb_exudyn.plotting import data

    r = _full_pem()
    chosen = [r.channels[3], r.channels[1]]
    sub = data.channel_subset(r, chosen)
    rows = [r.index(c) for c in chosen]
    schema = _schema_of(RandomResponse)
    for name, a in _held(r).items():
        if "channel" in schema[name].dims:
            axis = schema[name].dims.index("channel")
            assert np.array_equal(getattr(sub, name), np.take(a, rows, axis=axis)), name
    assert sub.psd_channels == tuple(chosen) and np.array_equal(sub.psd, r.psd[[1, 0]])
