"""The records of an EN 1991-2 check and their two forms, from the one schema.

A check (:class:`tb_exudyn.codes.check.CheckResult`) holds one :class:`CheckRecord` per train, speed and
mass case: the criterion evaluated (the deck acceleration of the check's track form), the load model, the
train, speed, mass case, track form, location, value, limit, utilisation, verdict and caveats, the row's
other quantities (damping, cut-off, mid-span peaks, phi'_dyn, phi'', the enhancement) and, where the PEM of
the track irregularity was run, its :class:`StochasticValues`.

Their variables are declared once (:data:`tb_exudyn.results.schema.CHECK_RECORD`, the verdicts per
criterion :data:`~tb_exudyn.results.schema.CHECK_CRITERIA`) and drive

- the table (``check.csv``: :func:`records_csv`, :func:`table_cells`; the columns :func:`record_columns`),
  each column a variable's values (``acc_z_mid_span`` one column per span, the stochastic ones empty where
  not computed); a record read by a column's name (``record["max_deck_acc_z"]``) is that cell;
- the labelled form (:func:`check_dataset`, ``CheckResult.to_xarray()``, NetCDF through
  :func:`tb_exudyn.results.export.export_netcdf`): every variable over ``row`` (``span``), the train, speed
  and case as coordinates, the verdicts over ``criterion``, the settings as attributes.
"""

from __future__ import annotations

import csv
import io
import math
from dataclasses import dataclass
from typing import Any, Iterator, Mapping, Sequence

import numpy as np

from .._version import __version__
from .schema import CHECK_CRITERIA, CHECK_RECORD, Variable, need_xarray

VERDICT_OK, VERDICT_EXCEEDS = "ok", "exceeds"
_BY_NAME = {v.name: v for v in CHECK_RECORD}
_SPANS = "acc_z_mid_span"


@dataclass(frozen=True)
class StochasticValues:
    """The PEM of the track irregularity on a vehicle model at one speed (tb_exudyn.codes.stochastic): the
    probability of exceeding the limit in one passage, the level exceeded with the target probability
    [m/s^2], the deciding deck channel, the largest |mean| there [m/s^2], the verdict, its caveats and the
    PEM's frequency count."""

    p_exceed: float
    level_at_target: float
    location: str
    mean_acc: float
    verdict: str
    caveats: str
    n_freq: int


@dataclass(frozen=True)
class CheckRecord(Mapping[str, Any]):
    """One row of the check: ``criterion`` (limit file/criterion) evaluated for ``train`` under
    ``load_model`` at ``speed_kmh`` in mass case ``case`` on a ``track`` form: ``value`` at ``location``
    against ``limit``; ``utilisation`` and ``verdict`` follow from them. Read by a column of check.csv
    (a Mapping: ``record["max_deck_acc_z"]``, ``record.get("p_exceed")``) it gives that cell (None: empty)."""

    criterion: str
    load_model: str
    train: str
    speed_kmh: float
    case: str
    track: str
    location: str
    value: float
    limit: float
    damping_ratio: float
    cutoff_hz: float
    acc_z_mid_span: tuple[float, ...]
    disp_z_mid: float
    phi_dyn: float
    phi_irregularity: float
    enhancement: float
    value_with_phi2: float
    caveats: str = ""
    stochastic: StochasticValues | None = None

    @property
    def utilisation(self) -> float:
        return self.value / self.limit if self.limit > 0 else math.inf

    @property
    def verdict(self) -> str:
        return VERDICT_EXCEEDS if self.value > self.limit else VERDICT_OK

    def _read(self, v: Variable) -> Any:
        obj: Any = self
        for part in (v.attribute or v.name).split("."):
            obj = None if obj is None else getattr(obj, part)
        return obj

    def columns(self) -> tuple[str, ...]:
        return record_columns(len(self.acc_z_mid_span))

    def __getitem__(self, column: str) -> Any:
        if column.startswith(_SPANS) and column[len(_SPANS):].isdigit():
            i = int(column[len(_SPANS):]) - 1
            if 0 <= i < len(self.acc_z_mid_span):
                return self.acc_z_mid_span[i]
        v = _BY_NAME.get(column)
        if v is None or not v.in_table or v.name == _SPANS:
            raise KeyError(column)
        return self._read(v)

    def __iter__(self) -> Iterator[str]:
        return iter(self.columns())

    def __len__(self) -> int:
        return len(self.columns())


def record_columns(n_spans: int) -> tuple[str, ...]:
    """check.csv's columns for a bridge of ``n_spans`` spans, in :data:`CHECK_RECORD`'s order."""
    out: list[str] = []
    for v in CHECK_RECORD:
        if v.in_table:
            out += [f"{_SPANS}{i + 1}" for i in range(n_spans)] if v.name == _SPANS else [v.name]
    return tuple(out)


def _cell(x: Any) -> str:
    """A value as check.csv writes it: a float by its repr (every digit), None empty, else its text."""
    if x is None:
        return ""
    return repr(float(x)) if isinstance(x, float) else str(x)


def table_cells(records: Sequence[CheckRecord]) -> tuple[tuple[str, ...], list[list[Any]]]:
    """The table's columns and per record its values in that order (None where empty)."""
    columns = records[0].columns() if records else record_columns(0)
    return columns, [[r[c] for c in columns] for r in records]


def records_csv(records: Sequence[CheckRecord]) -> str:
    """check.csv's text: a header of :func:`record_columns`, one line per record."""
    columns, rows = table_cells(records)
    buf = io.StringIO()
    writer = csv.writer(buf, lineterminator="\n")
    writer.writerow(columns)
    writer.writerows([[_cell(x) for x in row] for row in rows])
    return buf.getvalue()


def _values(values: list[Any]) -> np.ndarray:
    """A variable's values: text when any is, None "" (text) or NaN (numbers)."""
    flat = list(np.ravel(np.array(values, dtype=object)))
    if any(isinstance(x, str) for x in flat):
        return np.array([[("" if x is None else str(x)) for x in r] if isinstance(r, (list, tuple)) else
                         ("" if r is None else str(r)) for r in values])
    return np.array([[math.nan if x is None else float(x) for x in r] if isinstance(r, (list, tuple)) else
                     (math.nan if r is None else float(r)) for r in values], dtype=float)


def check_dataset(result: Any) -> Any:
    """``CheckResult.to_xarray()``: an :class:`xarray.Dataset` of every variable of :data:`CHECK_RECORD` over
    ``row`` (``span``) and of :data:`CHECK_CRITERIA` over ``criterion`` (values in SI units, unchanged), the
    check's settings as attributes."""
    xr = need_xarray("CheckResult.to_xarray")
    records: Sequence[CheckRecord] = result.rows
    n_spans = len(records[0].acc_z_mid_span) if records else 0
    coords: dict[str, Any] = {"row": ("row", np.arange(len(records))),
                              "span": ("span", np.arange(1, n_spans + 1), {"long_name": "span along the track"})}
    data: dict[str, Any] = {}
    for v in CHECK_RECORD:
        values = _values([r._read(v) for r in records])
        if v.name == _SPANS:
            values = values.reshape(len(records), n_spans)
        target = coords if v.coordinate else data
        target[v.labelled_name] = (v.dims, values, v.attrs())
    verdicts = list(getattr(result, "criteria", ()))
    coords["criterion"] = ("criterion", [c.criterion for c in verdicts])
    for v in CHECK_CRITERIA:
        data[v.labelled_name] = (v.dims, _values([getattr(c, v.name) for c in verdicts]), v.attrs())
    attrs = {"title": f"tb_exudyn EN 1991-2 check, bridge {result.bridge}", "kind": "en1991_check",
             "source": f"tb_exudyn {__version__}", "bridge": result.bridge,
             "line_speed_kmh": float(result.line_speed_kmh), "track": result.track,
             "construction": result.construction, "damping_basis": result.damping_basis,
             "cutoff_hz": float(result.cutoff_hz), "cutoff_basis": result.cutoff_basis,
             "mode_frequencies_hz": np.asarray(result.mode_frequencies, dtype=float),
             "cases": ", ".join(result.cases), "stochastic_basis": result.stochastic_basis,
             "target_probability": math.nan if result.target_probability is None else float(result.target_probability)}
    return xr.Dataset(data, coords=coords, attrs=attrs)


__all__ = ["CheckRecord", "StochasticValues", "VERDICT_EXCEEDS", "VERDICT_OK", "check_dataset", "record_columns",
           "records_csv", "table_cells"]
