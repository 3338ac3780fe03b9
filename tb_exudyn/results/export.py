"""Export results: labelled arrays (xarray, NetCDF), CSV tables and MATLAB .mat files.

The npz folder stays the native format; :func:`export` is what ``tb-exudyn export DIR --format
netcdf|csv|mat --output FILE`` calls. Every file is written atomically (temporary file, then rename).
:func:`export` never destroys: it refuses, before any work, a target inside a result or checkpoint
folder, one that is not a regular file (FIFO, device, folder) and an existing file without
``overwrite`` (the CSV's sidecar likewise); NetCDF is made in memory and then written by Python, so
that a full disk is one clear error and leaves no temporary file (:func:`netcdf_content`).

Labelled arrays: ``result.to_xarray()`` (:func:`tb_exudyn.results.schema.to_xarray`, the result's
schema) gives an :class:`xarray.Dataset` of every array of the result, with dims ``channel``,
``time``, ``frequency`` (PEM), ``type`` (irregularity spectra of ``var_by_type``), ``bound``
(lower/upper of Monte Carlo confidence intervals) and ``sample``; per channel the coordinates
``unit`` (SI) and ``label`` (readable description); variable attributes say what each array is and
its unit; the dataset attributes hold the band, the method, the sample count, the provenance (JSON
text) and the scenario (TOML text). The NetCDF file is that dataset.

NetCDF backend: **h5netcdf** (NetCDF4 = HDF5 files, through h5py), with zlib level 1 and the
shuffle filter on the large arrays, one chunk per channel. Measured on the li_zhu_2011 PEM result
(471 channels x 200 frequencies x 557 times, float64): xarray's scipy backend writes NetCDF3, which
has no compression, 425 MB; NetCDF4 with compression 108 MB (zlib level 4: 106.8 MB for twice the
write time). netCDF4 (Unidata's library) writes the same bytes with the same chunks (108.1 MB) but
brings its own copy of the netCDF-C and HDF5 libraries, and took 4.7 s to write against 3.5 s;
h5netcdf is pure Python on h5py (the HDF5 binding of scientific Python), maintained with xarray, and
writes valid NetCDF4 that netCDF-C tools read. ``engine="netcdf4"`` or ``"scipy"`` (NetCDF3, no
compiled dependency beyond scipy) may be chosen instead. The packages are optional:
``pip install "tb_exudyn[netcdf]"`` (xarray, h5netcdf, h5py).

CSV: readable by plain ``pandas.read_csv(path)``: no comment line; a header row ``time [s]`` then
one column per channel and statistic with its unit, ``<channel> [<unit>]`` (one run) or
``<channel> mean [<unit>]`` and ``<channel> sigma [<unit>]`` (random response); what the file holds
(method, band, scenario) goes to a sidecar ``<file>.json``. Numbers are written with Python's
``repr`` (the shortest text that reads back as the same double), so :func:`read_csv` gives exactly
the stored values.

MATLAB: every array of the result plus channel names and units (cell arrays of char), the scenario
as TOML text and the provenance as JSON text. ``mean`` and ``std`` are stored as ``mean_response``
and ``std_response`` (a variable named ``mean`` would hide MATLAB's function of that name).
"""

from __future__ import annotations

import io
import json
from pathlib import Path
from typing import Any, Literal, Sequence, Union

import numpy as np
import scipy.io

from .._version import __version__
from ..atomic import write_text_atomic
from ..errors import CapabilityError, SettingError
from ..files import MIB, Content, output_targets, write_output
from ..scenario import scenario_to_toml
from ..system.labels import channel_label
from ..storage import json_default
from .random_response import RandomResponse
from .time_history import TimeHistory

Result = Union[RandomResponse, TimeHistory]
Format = Literal["netcdf", "csv", "mat"]
FORMATS: tuple[str, ...] = ("netcdf", "csv", "mat")
NETCDF_ENGINES: tuple[str, ...] = ("h5netcdf", "netcdf4", "scipy")

#: names of RandomResponse arrays in the .mat file (others keep their attribute name)
MAT_NAMES = {"mean": "mean_response", "std": "std_response"}


# ============================================================================================ labelled arrays
def _labels(names: Sequence[str]) -> list[str]:
    return [channel_label(n) for n in names]


def netcdf_content(result: Result, engine: str = "h5netcdf", complevel: int = 1,
                   where: str = "export_netcdf") -> tuple[Content, int]:
    """The NetCDF file of the result's labelled form (``result.to_xarray()``): (its bytes, their size) for "h5netcdf"
    and "scipy", which write it in memory; (a writer of a file name, an upper bound of its size:
    the uncompressed arrays and attributes plus 5 % and 1 MiB) for "netcdf4", which writes files
    only, and for "h5netcdf" with an xarray that returns bytes from the scipy engine only (before
    2025; then the free space is checked against that bound before HDF5 writes the file).

    In memory, the HDF5 library never writes to the disk: on a full disk it fails inside HDF5,
    without an error Python could catch, and can crash the process (exit 139 was measured); the
    bytes are then written by Python (:func:`tb_exudyn.files.write_output`), whose errors are
    ordinary. Writing in memory with h5netcdf took 2.6 s against 3.2 s for the same file on disk
    (100 channels x 200 frequencies x 557 times, 76 MB written).
    """
    if engine not in NETCDF_ENGINES:
        raise SettingError(where, "engine", engine, ", ".join(NETCDF_ENGINES))
    ds = result.to_xarray()
    module = {"h5netcdf": "h5netcdf", "netcdf4": "netCDF4", "scipy": "scipy"}[engine]
    try:
        __import__(module)
    except ImportError:
        raise CapabilityError(where, "engine", engine, 'pip install "tb_exudyn[netcdf]"',
                              f"the {module} package is not installed") from None
    encoding = {}
    if engine != "scipy":
        for name, var in ds.data_vars.items():
            if var.size >= 4096:
                chunks = tuple(1 if d in ("channel", "psd_channel", "sample", "type", "bound") else n
                               for d, n in zip(var.dims, var.shape))
                encoding[name] = {"zlib": True, "complevel": complevel, "shuffle": True, "chunksizes": chunks}
    else:  # NetCDF3 has no string or int64 arrays of this kind: JSON-safe attributes only
        ds.attrs["band_hz"] = list(ds.attrs.get("band_hz", []))
    def to_file(tmp: Path) -> None:
        ds.to_netcdf(tmp, engine=engine, encoding=encoding or None)

    bound = int(ds.nbytes * 1.05) + sum(len(str(v)) for v in ds.attrs.values()) + MIB
    if engine == "netcdf4":
        return to_file, bound
    try:
        data = memoryview(ds.to_netcdf(None, engine=engine, encoding=encoding or None))
    except ValueError:  # xarray < 2025: "invalid engine for creating bytes", raised before any work
        return to_file, bound
    return data, data.nbytes


def export_netcdf(result: Result, path: str | Path, engine: str = "h5netcdf", complevel: int = 1) -> Path:
    """Write the result's labelled form (``result.to_xarray()``) as NetCDF (see the module docstring for the backend),
    atomically (:func:`netcdf_content`: in memory, then to the file). ``engine``: "h5netcdf"
    (NetCDF4, compressed), "netcdf4" (the same, through Unidata's library) or "scipy" (NetCDF3,
    uncompressed). Replaces ``path``; :func:`export` checks the target first."""
    path = Path(path)
    content, size = netcdf_content(result, engine, complevel)
    write_output([(path, content)], named=path, overwrite=True, where="export_netcdf", key="path",
                 size=None if not callable(content) else size)
    return path


# ============================================================================================ CSV
def csv_content(name: str, time: np.ndarray, names: Sequence[str], units: Sequence[str], values: np.ndarray,
                comment: str = "") -> tuple[bytes, bytes]:
    """The bytes of the CSV file ``name`` of :func:`write_csv` and of its sidecar."""
    values = np.asarray(values, dtype=float)
    if values.shape != (len(names), np.size(time)):
        raise ValueError(f"values have shape {values.shape}, expected ({len(names)}, {np.size(time)})")
    header = ["time [s]"] + [f"{n} [{u}]" for n, u in zip(names, units)]
    for h in header:
        if "," in h or '"' in h or "\n" in h:
            raise ValueError(f"column {h!r} holds a comma, quote or line break")
    buf = io.StringIO()
    buf.write(",".join(header) + "\n")
    table = np.vstack([np.asarray(time, dtype=float)[None, :], values]).T.tolist()
    buf.writelines(",".join(map(repr, row)) + "\n" for row in table)
    sidecar = {"file": name, "about": comment, "columns": [{"header": h, "name": n, "unit": u}
                                                           for h, n, u in zip(header, ["time", *names], ["s", *units])]}
    return buf.getvalue().encode("utf-8"), json.dumps(sidecar, indent=1).encode("utf-8")


def write_csv(path: str | Path, time: np.ndarray, names: Sequence[str], units: Sequence[str],
              values: np.ndarray, comment: str = "") -> Path:
    """Write ``values`` (n_columns, n_t) against ``time`` as CSV (repr-precision floats), atomically.

    The header is ``time [s]`` and ``<name> [<unit>]``; no comment line (pandas.read_csv reads it
    with defaults). ``comment`` (what the file holds) goes to the sidecar ``<path>.json`` with the
    columns' names and units. Both files are written as one (both or neither) and replaced if they
    exist; :func:`export` checks the targets first.
    """
    path = Path(path)
    table, sidecar = csv_content(path.name, time, names, units, values, comment)
    write_output([(path, table), (sidecar_path(path), sidecar)], named=path, overwrite=True, where="write_csv",
                 key="path")
    return path


def sidecar_path(path: str | Path) -> Path:
    """The JSON file beside a CSV file that says what it holds: ``<file>.json``."""
    path = Path(path)
    return path.with_name(path.name + ".json")


def write_table_csv(rows: Sequence[dict[str, Any]], path: str | Path) -> Path:
    """Write a table (one dict per row, the first row's keys as header) as CSV, atomically."""
    import csv

    buf = io.StringIO()
    writer = csv.DictWriter(buf, fieldnames=list(rows[0]), lineterminator="\n")
    writer.writeheader()
    writer.writerows(rows)
    return write_text_atomic(path, buf.getvalue())


def read_csv(path: str | Path) -> tuple[np.ndarray, list[str], np.ndarray]:
    """Read a file written by :func:`write_csv` (or an older one with a leading # line): (time,
    column headers without time, values (nc, nt))."""
    lines = [ln for ln in Path(path).read_text(encoding="utf-8").splitlines() if ln and not ln.startswith("#")]
    header = lines[0].split(",")
    table = np.array([[float(x) for x in ln.split(",")] for ln in lines[1:]], dtype=float).reshape(-1, len(header))
    return table[:, 0], header[1:], table[:, 1:].T


def _about(result: Result, what: str) -> str:
    name = result.scenario.name if result.scenario is not None else "unknown scenario"
    return f"tb_exudyn {what}; scenario {name}"


def csv_columns(result: Result) -> tuple[list[str], list[str], np.ndarray, str]:
    """(column names, units, values (n_columns, nt), what the table holds) of the one-file CSV:
    a run's channels, or each channel's mean and sigma side by side."""
    if isinstance(result, TimeHistory):
        names = list(result.names)
        values = np.array([result[n] for n in names], dtype=float).reshape(len(names), np.size(result.time))
        return names, [result.unit(n) for n in names], values, _about(result, "time history of one run")
    band = f"{result.band[0]:.6g}-{result.band[1]:.6g} Hz"
    names = [f"{c} {stat}" for c in result.channels for stat in ("mean", "sigma")]
    units = [u for u in result.units for _ in range(2)]
    values = np.stack([result.mean, result.std], axis=1).reshape(-1, result.time.size)
    return names, units, values, _about(result, f"{result.method} mean and standard deviation sigma(t) over {band} "
                                                 "(one-sided PSD per Hz)")


def export_csv_file(result: Result, path: str | Path) -> list[Path]:
    """One CSV file of the result (:func:`csv_columns`) and its sidecar; returns both paths."""
    names, units, values, about = csv_columns(result)
    path = write_csv(path, result.time, names, units, values, about)
    return [path, sidecar_path(path)]


def export_csv(result: Result, folder: str | Path) -> list[Path]:
    """Write the result's histories as CSV into ``folder`` (``history.csv``, or ``mean.csv`` and
    ``std.csv``), each with its sidecar; returns the CSV files written."""
    folder = Path(folder)
    if isinstance(result, TimeHistory):
        names, units, values, about = csv_columns(result)
        return [write_csv(folder / "history.csv", result.time, names, units, values, about)]
    band = f"{result.band[0]:.6g}-{result.band[1]:.6g} Hz"
    return [
        write_csv(folder / "mean.csv", result.time, result.channels, result.units, result.mean,
                  _about(result, f"{result.method} mean response")),
        write_csv(folder / "std.csv", result.time, result.channels, result.units, result.std,
                  _about(result, f"{result.method} standard deviation sigma(t) over {band} (one-sided PSD per Hz)")),
    ]


# ============================================================================================ MATLAB
def mat_dict(result: Result) -> dict[str, Any]:
    """The variables of the .mat file of a result."""
    out: dict[str, Any] = {}
    if isinstance(result, TimeHistory):
        names = list(result.names)
        out["kind"] = "time_history"
        out.update(result.arrays())
        units = [result.unit(n) for n in names]
    else:
        names, units = list(result.channels), list(result.units)
        out["kind"] = "random_response"
        out["method"] = result.method
        for attr, a in result.arrays().items():  # every array of the schema the result holds
            out[MAT_NAMES.get(attr, attr)] = np.asarray(a)
        out["band"] = np.asarray(result.band, dtype=float)
        out["types"] = np.array(list(result.types), dtype=object)
        out["n_samples"] = result.n_samples
    out["channels"] = np.array(names, dtype=object)
    out["units"] = np.array(units, dtype=object)
    out["labels"] = np.array(_labels(names), dtype=object)
    out["scenario_toml"] = "" if result.scenario is None else scenario_to_toml(result.scenario)
    out["provenance_json"] = json.dumps(result.provenance, sort_keys=True, default=json_default)
    return out


def mat_content(result: Result) -> bytes:
    """The bytes of the MATLAB .mat file (v5, compressed) of :func:`mat_dict`."""
    buf = io.BytesIO()
    scipy.io.savemat(buf, mat_dict(result), do_compression=True, oned_as="row")
    return buf.getvalue()


def export_mat(result: Result, path: str | Path) -> Path:
    """Write every array of the result to a MATLAB .mat file (v5, compressed) at ``path``, atomically
    (replaced if it exists; :func:`export` checks the target first)."""
    path = Path(path)
    write_output([(path, mat_content(result))], named=path, overwrite=True, where="export_mat", key="path")
    return path


# ============================================================================================ one entry point
def export(result: Result, format: str, path: str | Path, *, overwrite: bool = False, where: str = "export",
           key: str = "path") -> list[Path]:
    """Write ``result`` to ``path`` as ``format`` ("netcdf", "csv" or "mat"); returns the files
    written (CSV: the table and its ``.json`` sidecar). The call behind ``tb-exudyn export``.

    Before anything is computed the target (and the CSV's sidecar) is checked
    (:func:`tb_exudyn.files.output_targets`): refused inside a result or checkpoint folder, when it
    is not a regular file (FIFO, device, folder, ...), and when it exists unless ``overwrite``. The
    files are then written whole or not at all, the free space checked first
    (:func:`tb_exudyn.files.write_output`). Every refusal or failure is an OutputFolderError naming
    the file and ``where``/``key`` (the caller and its argument)."""
    if format not in FORMATS:
        raise SettingError(where, "format", format, ", ".join(FORMATS))
    path = Path(path)
    named = [path, sidecar_path(path)] if format == "csv" else [path]
    targets = output_targets(path, sidecars=named[1:], overwrite=overwrite, where=where, key=key)
    size = None
    if format == "netcdf":
        content, size = netcdf_content(result, where=where)
        items: list[tuple[Path, Content]] = [(targets[0], content)]
        size = size if callable(content) else None
    elif format == "csv":
        names, units, values, about = csv_columns(result)
        table, sidecar = csv_content(path.name, result.time, names, units, values, about)
        items = [(targets[0], table), (targets[1], sidecar)]
    else:
        items = [(targets[0], mat_content(result))]
    write_output(items, named=path, overwrite=overwrite, where=where, key=key, size=size)
    return named


__all__ = ["FORMATS", "MAT_NAMES", "NETCDF_ENGINES", "csv_columns", "csv_content", "export", "export_csv",
           "export_csv_file", "export_mat", "export_netcdf", "mat_content", "mat_dict", "netcdf_content", "read_csv",
           "sidecar_path", "write_csv", "write_table_csv"]
