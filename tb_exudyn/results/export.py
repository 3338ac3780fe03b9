"""Export results to CSV and MATLAB .mat files (the npz folder stays the native format).

CSV: one row per output time, a ``time [s]`` column then one column per channel, headed
``<channel> [<unit>]``, after one ``#`` comment line saying what the file holds. Numbers are written
with Python's ``repr`` (the shortest text that reads back as the same double), so reading a file
back gives exactly the stored values. A TimeHistory gives ``history.csv``; a RandomResponse
``mean.csv`` and ``std.csv`` (sigma(t) over the stated band).

MATLAB: every array of the result plus channel names and units (cell arrays of char), the scenario
as TOML text and the provenance as JSON text. ``mean`` and ``std`` are stored as ``mean_response``
and ``std_response`` (a variable named ``mean`` would hide MATLAB's function of that name).
All files are written atomically (temporary file, then rename).
"""

from __future__ import annotations

import io
import json
from pathlib import Path
from typing import Any, Sequence, Union

import numpy as np
import scipy.io

from ..scenario import scenario_to_toml
from .random_response import OPTIONAL_ARRAYS, RandomResponse
from ..atomic import write_atomic, write_text_atomic
from .storage import json_default
from .time_history import TimeHistory

Result = Union[RandomResponse, TimeHistory]

#: names of RandomResponse arrays in the .mat file (others keep their attribute name)
MAT_NAMES = {"mean": "mean_response", "std": "std_response"}
_OPTIONAL = OPTIONAL_ARRAYS


def write_csv(path: str | Path, time: np.ndarray, names: Sequence[str], units: Sequence[str],
              values: np.ndarray, comment: str) -> Path:
    """Write ``values`` (n_channels, n_t) against ``time`` as CSV (repr-precision floats), atomically."""
    path = Path(path)
    values = np.asarray(values, dtype=float)
    if values.shape != (len(names), np.size(time)):
        raise ValueError(f"values have shape {values.shape}, expected ({len(names)}, {np.size(time)})")
    buf = io.StringIO()
    buf.write("# " + comment.replace("\n", " ") + "\n")
    buf.write(",".join(["time [s]"] + [f"{n} [{u}]" for n, u in zip(names, units)]) + "\n")
    table = np.vstack([np.asarray(time, dtype=float)[None, :], values]).T.tolist()
    buf.writelines(",".join(map(repr, row)) + "\n" for row in table)
    text = buf.getvalue().encode("utf-8")
    write_atomic(path, lambda fh: fh.write(text))
    return path


def write_table_csv(rows: Sequence[dict[str, Any]], path: str | Path) -> Path:
    """Write a table (one dict per row, the first row's keys as header) as CSV, atomically."""
    import csv

    buf = io.StringIO()
    writer = csv.DictWriter(buf, fieldnames=list(rows[0]), lineterminator="\n")
    writer.writeheader()
    writer.writerows(rows)
    return write_text_atomic(path, buf.getvalue())


def read_csv(path: str | Path) -> tuple[np.ndarray, list[str], np.ndarray]:
    """Read a file written by :func:`write_csv`: (time, column headers without time, values (nc, nt))."""
    lines = [ln for ln in Path(path).read_text(encoding="utf-8").splitlines() if ln and not ln.startswith("#")]
    header = lines[0].split(",")
    table = np.array([[float(x) for x in ln.split(",")] for ln in lines[1:]], dtype=float).reshape(-1, len(header))
    return table[:, 0], header[1:], table[:, 1:].T


def export_csv(result: Result, folder: str | Path) -> list[Path]:
    """Write the result's histories as CSV into ``folder``; returns the files written."""
    folder = Path(folder)
    name = result.scenario.name if result.scenario is not None else "unknown scenario"
    if isinstance(result, TimeHistory):
        names = list(result.names)
        values = np.array([result[n] for n in names], dtype=float).reshape(len(names), np.size(result.time))
        return [write_csv(folder / "history.csv", result.time, names, [result.unit(n) for n in names], values,
                          f"tb_exudyn time history of one run; scenario {name}")]
    band = f"{result.band[0]:.6g}-{result.band[1]:.6g} Hz"
    return [
        write_csv(folder / "mean.csv", result.time, result.channels, result.units, result.mean,
                  f"tb_exudyn {result.method} mean response; scenario {name}"),
        write_csv(folder / "std.csv", result.time, result.channels, result.units, result.std,
                  f"tb_exudyn {result.method} standard deviation sigma(t) over {band} (one-sided PSD per Hz); "
                  f"scenario {name}"),
    ]


def mat_dict(result: Result) -> dict[str, Any]:
    """The variables of the .mat file of a result."""
    out: dict[str, Any] = {}
    if isinstance(result, TimeHistory):
        names = list(result.names)
        out["kind"] = "time_history"
        out["time"] = np.asarray(result.time, dtype=float)
        out["values"] = np.array([result[n] for n in names], dtype=float).reshape(len(names), np.size(result.time))
        units = [result.unit(n) for n in names]
    else:
        names, units = list(result.channels), list(result.units)
        out["kind"] = "random_response"
        out["method"] = result.method
        for attr in ("time", "mean", "std", "freq", "df"):
            out[MAT_NAMES.get(attr, attr)] = np.asarray(getattr(result, attr), dtype=float)
        for attr in _OPTIONAL:
            if getattr(result, attr) is not None:
                out[attr] = np.asarray(getattr(result, attr))
        out["band"] = np.asarray(result.band, dtype=float)
        out["types"] = np.array(list(result.types), dtype=object)
        out["n_samples"] = result.n_samples
    out["channels"] = np.array(names, dtype=object)
    out["units"] = np.array(units, dtype=object)
    out["scenario_toml"] = "" if result.scenario is None else scenario_to_toml(result.scenario)
    out["provenance_json"] = json.dumps(result.provenance, sort_keys=True, default=json_default)
    return out


def export_mat(result: Result, path: str | Path) -> Path:
    """Write every array of the result to a MATLAB .mat file (v5, compressed) at ``path``, atomically."""
    path = Path(path)
    data = mat_dict(result)
    write_atomic(path, lambda fh: scipy.io.savemat(fh, data, do_compression=True, oned_as="row"))
    return path


__all__ = ["MAT_NAMES", "export_csv", "export_mat", "mat_dict", "read_csv", "write_csv", "write_table_csv"]
