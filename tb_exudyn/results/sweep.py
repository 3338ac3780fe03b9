"""A speed sweep's result: per speed the summary of its PEM, with speed as a dim.

:class:`SweepResult` is what :func:`tb_exudyn.methods.sweep.run_sweep` returns (the computation stays
there): per speed the summary of its PEM (``summaries``, :func:`tb_exudyn.methods.sweep.speed_summary`),
the key quantities, the resonance speeds (:class:`Resonance`) and the base scenario.

The table is declared once (:data:`SWEEP_SCHEMA`, :class:`tb_exudyn.results.schema.Variable` over
the dims ``speed``, ``quantity`` and ``criterion``) and drives both of its forms:

- the rows (:meth:`SweepResult.rows`, :func:`sweep_rows`, ``speed_sweep.csv``: :func:`write_sweep`),
  one per speed, a column ``<name>`` per speed variable, ``<quantity>_<name>`` per key quantity and
  ``<criterion>_<name>`` per code criterion, in the order of the schema; the names are composed here only:
  a speed's code checks travel labelled, one :class:`CriterionValues` per criterion (its fields the
  variables over ``criterion``; :func:`criterion_values` of a speed's checks, kept in its summary as
  :func:`checks_text`, read back by :func:`read_checks`, and :meth:`SweepResult.criterion_values`);
- the labelled form (:meth:`SweepResult.to_xarray`): each variable over its dims, the speeds [km/h],
  quantities (with their channel pattern, description and SI unit) and criteria as coordinates, the
  base scenario (TOML), the provenance and the resonance speeds (JSON) as attributes.

The warnings of the speeds are grouped once per kind (:func:`grouped_warnings`). The figure is
:func:`tb_exudyn.plotting.plot_speed_sweep` (``result.plot()``), the page
:func:`tb_exudyn.report.write_sweep_report`.
"""

from __future__ import annotations

import fnmatch
import importlib
import json
import math
import re
from dataclasses import asdict, dataclass, field, fields
from pathlib import Path
from typing import Any, Mapping, Sequence

import numpy as np

from ..scenario import Scenario, scenario_to_toml
from ..storage import json_default
from .base import figures
from .checks import GRID_ERROR_TOLERANCE
from .export import write_table_csv
from .schema import Variable, need_xarray

#: the sweep's table in its output folder
SWEEP_TABLE = "speed_sweep.csv"
_S, _Q, _C = ("speed",), ("speed", "quantity"), ("speed", "criterion")
#: every column of the sweep's table, in the table's order: per speed (``speed_kmh`` is the dim's
#: coordinate), per key quantity, per code criterion; units "quantity" are the quantity's own SI unit,
#: "" a text column
SWEEP_SCHEMA: tuple[Variable, ...] = (
    Variable("speed_kmh", _S, "train speed", units="km/h", coordinate=True, label="speed"),
    Variable("f_min_hz", _S, "lower edge of the speed's band", units="Hz"),
    Variable("f_max_hz", _S, "upper edge of the speed's band", units="Hz"),
    Variable("n_freq", _S, "number of frequencies of the speed's grid", units="1"),
    Variable("lead_in_m", _S, "track before the bridge at that speed", units="m"),
    Variable("max_abs_mean", _Q, "largest |mean| over the quantity's channels and time", units="quantity"),
    Variable("max_sigma", _Q, "largest sigma over the quantity's channels and time", units="quantity"),
    Variable("max_abs_mean_plus_3sigma", _Q, "largest |mean| + 3 sigma over the quantity's channels and time",
             units="quantity"),
    Variable("channel", _Q, "the channel of the largest |mean| + 3 sigma"),
    Variable("grid_error", _Q, "largest estimated grid error of the quantity's channels (NaN: not estimated)",
             units="1", finite=False),
    Variable("channels_grid_error_over_tolerance", _S, "channels whose grid error exceeds the tolerance "
             "(NaN: not estimated)", units="1", finite=False),
    Variable("utilisation", _C, "estimate over the limit at the deciding location", units="1", finite=False),
    Variable("probability", _C, "probability of exceeding the limit in one passage (NaN: not a random process)",
             units="1", finite=False),
    Variable("estimate", _C, "the criterion's estimate at the deciding location (SI, in 'unit')", finite=False),
    Variable("limit", _C, "the criterion's limit (SI, in 'unit')", finite=False),
    Variable("unit", _C, "SI unit of the estimate and the limit"),
    Variable("channel", _C, "the deciding channel"),
    Variable("verdict", _C, "OK, EXCEEDS or NOT EVALUATED"),
    Variable("title", _C, "what the criterion checks"),
    Variable("caveats", _C, "kinds of the caveats that could change the verdict"),
    Variable("reason", _C, "why the criterion was not evaluated"),
    Variable("checks_exceeding", _S, "number of criteria whose verdict is EXCEEDS", units="1"),
    Variable("seconds", _S, "run time of the speed", units="s", finite=False),
)
_BY_DIMS = {dims: tuple(v for v in SWEEP_SCHEMA if v.dims == dims) for dims in (_S, _Q, _C)}


@dataclass(frozen=True)
class CriterionValues:
    """One code criterion at one speed, at its deciding location: the variables of :data:`SWEEP_SCHEMA` over
    ``criterion``, field for field (tests/results/test_sweep_schema.py)."""

    utilisation: float
    probability: float
    estimate: float
    limit: float
    unit: str
    channel: str
    verdict: str
    title: str = ""
    caveats: str = ""
    reason: str = ""


def criterion_values(table: Any) -> dict[str, CriterionValues]:
    """A result's code checks (a :class:`~tb_exudyn.results.checks_table.ChecksTable`) as the sweep keeps them: per
    criterion that applies, at its deciding location (``table.worst()``), the estimate over the limit, the
    probability of exceeding the limit in one passage (NaN where it is not a random process), the estimate and
    the limit (SI, in ``unit``), the channel, the verdict, what it checks, the kinds of the caveats that could
    change the verdict ("; " separated) and why it was not evaluated."""
    out = {}
    for r in table.worst():
        out[r.criterion] = CriterionValues(
            utilisation=float(r.estimate / r.limit if math.isfinite(r.limit) and r.limit != 0 else math.nan),
            probability=math.nan if r.probability is None else float(r.probability), estimate=float(r.estimate),
            limit=float(r.limit), unit=str(r.unit), channel=str(r.channel), verdict=str(r.verdict), title=str(r.title),
            caveats="; ".join(dict.fromkeys(k.kind for k in r.caveats if k.changes_verdict)),
            reason="; ".join(k.text for k in r.caveats if k.kind in ("statistic", "model"))
            if r.verdict == "NOT EVALUATED" else "")
    return out


def checks_text(values: Mapping[str, CriterionValues]) -> str:
    """The values as a speed's summary keeps them (JSON: criterion -> its fields; checkpointable)."""
    return json.dumps({c: asdict(v) for c, v in values.items()})


def read_checks(summary: Mapping[str, Any]) -> dict[str, CriterionValues]:
    """A speed summary's code checks (its ``checks``, :func:`checks_text`), criterion by criterion."""
    names = {f.name for f in fields(CriterionValues)}
    return {c: CriterionValues(**{k: v for k, v in d.items() if k in names})
            for c, d in json.loads(str(summary["checks"])).items()}


def _speed_text(v: float) -> str:
    return f"{v:g}"  # a speed as its folder is named (tb_exudyn.methods.speed_series.speed_label)


@dataclass(frozen=True)
class Resonance:
    """A resonance speed v = f_n d / i: the loads spaced d apart passing a bridge mode of frequency
    f_n every i-th period."""

    direction: str
    frequency: float  # [Hz]
    distance_name: str  # "car length" or "bogie spacing"
    distance: float  # [m]
    order: int
    speed_kmh: float


@dataclass(frozen=True)
class SweepResult:
    """A speed sweep: per speed the summary of its PEM (:func:`speed_summary`), the key
    quantities, the resonance speeds and the base scenario."""

    base: Scenario
    speeds: tuple[float, ...]
    summaries: tuple[dict[str, np.ndarray], ...]
    quantities: tuple[tuple[str, str, str], ...]
    resonances: tuple[Resonance, ...]
    provenance: dict[str, Any] = field(default_factory=dict)

    def rows(self) -> list[dict[str, Any]]:
        """The table, one row per speed (:func:`sweep_rows`)."""
        return sweep_rows(self)

    def criterion_values(self) -> list[dict[str, CriterionValues]]:
        """Per speed its code criteria's values (:class:`CriterionValues`), by criterion."""
        return [read_checks(s) for s in self.summaries]

    def criteria(self) -> list[str]:
        """The code criteria of the table, in the order first met (those of any speed)."""
        return list(dict.fromkeys(c for values in self.criterion_values() for c in values))

    def to_xarray(self) -> Any:
        """The table as an :class:`xarray.Dataset` over ``speed``, ``quantity`` and ``criterion``
        (:data:`SWEEP_SCHEMA`; the module docstring): every column of :meth:`rows`."""
        return sweep_dataset(self)

    def quantity_text(self, key: str) -> str:
        """What key quantity ``key`` is, without the SI unit its description ends with (figures and
        the report show it in display units)."""
        what = next(q[2] for q in self.quantities if q[0] == key)
        return re.sub(r" *\[[^]]*\]$", "", what)

    def quantity_unit(self, key: str) -> str:
        """The SI unit of key quantity ``key``'s channels ("" when no speed has one)."""
        pattern = next(q[1] for q in self.quantities if q[0] == key)
        for s in self.summaries:
            for name, unit in zip(s["channels"], s["units"]):
                if fnmatch.fnmatchcase(str(name), pattern):
                    return str(unit)
        return ""

    def plot(self, **options: Any) -> Any:
        """The sweep's figure (:func:`tb_exudyn.plotting.plot_speed_sweep`, a matplotlib Figure; matplotlib
        loaded now, :func:`tb_exudyn.results.base.figures`)."""
        return figures().plot_speed_sweep(self, **options)


def sweep_rows(result: SweepResult) -> list[dict[str, Any]]:
    """The table (:data:`SWEEP_SCHEMA`'s columns): one row per speed (its band, number of frequencies
    and approach, from the speed rule); per key quantity the largest |mean|, sigma and |mean| + 3
    sigma over its channels and time, the channel of the largest |mean| + 3 sigma and the largest
    estimated grid error of its channels (NaN: not estimated); the number of channels whose grid
    error exceeds GRID_ERROR_TOLERANCE; then per criterion its :class:`CriterionValues` as the columns
    ``<criterion>_<name>``, the number of criteria that EXCEED and the run time."""
    rows = []
    for v, s in zip(result.speeds, result.summaries):
        names = list(s["channels"])
        row: dict[str, Any] = {"speed_kmh": v, "f_min_hz": float(s["band"][0]), "f_max_hz": float(s["band"][1]),
                               "n_freq": int(s["n_freq"]), "lead_in_m": float(np.asarray(s.get("lead_in", math.nan)))}
        for key, pattern, _ in result.quantities:
            idx = [i for i, n in enumerate(names) if fnmatch.fnmatchcase(n, pattern)]
            j = idx[int(np.argmax(s["max_design"][idx]))]
            values = {"max_abs_mean": float(s["max_abs_mean"][idx].max()), "max_sigma": float(s["max_sigma"][idx].max()),
                      "max_abs_mean_plus_3sigma": float(s["max_design"][j]), "channel": names[j],
                      "grid_error": float(np.max(s["grid_error"][idx]))}
            row.update({f"{key}_{c.name}": values[c.name] for c in _BY_DIMS[_Q]})
        ge = np.asarray(s["grid_error"], dtype=float)
        row["channels_grid_error_over_tolerance"] = float("nan") if np.all(np.isnan(ge)) else \
            int(np.sum(ge > GRID_ERROR_TOLERANCE))
        checks = read_checks(s)
        for c, values in checks.items():
            row.update({f"{c}_{v.name}": getattr(values, v.name) for v in _BY_DIMS[_C]})
        row["checks_exceeding"] = float(sum(values.verdict == "EXCEEDS" for values in checks.values()))
        row["seconds"] = float(s["seconds"])
        rows.append(row)
    return rows


def _column(values: list[Any]) -> np.ndarray:
    """A column over speeds (and quantities or criteria): text when any value is, missing ones "" or NaN."""
    flat = [x for x in np.ravel(np.array(values, dtype=object))]
    if any(isinstance(x, str) for x in flat):
        return np.array([["" if x is None else str(x) for x in r] if isinstance(r, list) else
                         ("" if r is None else str(r)) for r in values])
    return np.array([[math.nan if x is None else float(x) for x in r] if isinstance(r, list) else
                     (math.nan if r is None else float(r)) for r in values], dtype=float)


def sweep_dataset(result: SweepResult) -> Any:
    """:meth:`SweepResult.to_xarray`: every variable of :data:`SWEEP_SCHEMA` from the rows."""
    xr = need_xarray("SweepResult.to_xarray")
    rows, checks = result.rows(), result.criterion_values()
    keys, criteria = [q[0] for q in result.quantities], result.criteria()
    coords: dict[str, Any] = {
        "speed": ("speed", np.array([r["speed_kmh"] for r in rows], dtype=float), {"units": "km/h"}),
        "quantity": ("quantity", keys), "criterion": ("criterion", criteria),
        "pattern": ("quantity", [q[1] for q in result.quantities], {"long_name": "the quantity's channel pattern"}),
        "what": ("quantity", [result.quantity_text(k) for k in keys], {"long_name": "what the quantity is"}),
        "unit": ("quantity", [result.quantity_unit(k) for k in keys], {"long_name": "SI unit of the quantity"}),
    }
    data: dict[str, Any] = {}
    for v in SWEEP_SCHEMA:
        if v.coordinate:
            continue
        attrs = {"long_name": v.long_name, **({"units_coordinate": "unit"} if v.units == "quantity" else
                                              {"units": v.units} if v.units else {})}
        if v.dims == _S:
            values = [r.get(v.name) for r in rows]
        elif v.dims == _Q:
            values = [[r.get(f"{n}_{v.name}") for n in keys] for r in rows]
        else:
            values = [[getattr(at.get(c), v.name, None) for c in criteria] for at in checks]
        name = v.name if v.dims == _S else f"{v.dims[1]}_{v.name}"  # channel: quantity_channel, criterion_channel
        data[name] = (v.dims, _column(values), attrs)
    attrs = {"title": f"tb_exudyn speed sweep, scenario {result.base.name}", "kind": "speed_sweep",
             "scenario_toml": scenario_to_toml(result.base),
             "provenance_json": json.dumps(result.provenance, sort_keys=True, default=json_default),
             "resonances_json": json.dumps([asdict(r) for r in result.resonances], default=json_default)}
    return xr.Dataset(data, coords=coords, attrs=attrs)


def speeds_text(speeds: Sequence[float], among: Sequence[float]) -> str:
    """``speeds`` (a subset of the sweep's ``among``) in few words: "every speed (160-350 km/h)",
    "160-200, 250 km/h" (runs of neighbours in the sweep's order as first-last)."""
    if len(among) > 1 and set(speeds) == set(among):
        return f"every speed ({_speed_text(min(among))}-{_speed_text(max(among))} km/h)"
    index = {v: i for i, v in enumerate(among)}
    order = sorted(set(speeds), key=lambda v: index.get(v, len(among)))
    runs: list[list[float]] = []
    for v in order:
        if runs and index.get(v) is not None and index.get(runs[-1][-1]) == index[v] - 1:
            runs[-1].append(v)
        else:
            runs.append([v])
    return ", ".join(_speed_text(r[0]) if len(r) == 1 else f"{_speed_text(r[0])}-{_speed_text(r[-1])}"
                     for r in runs) + " km/h"


def _category(name: str) -> type[Warning]:
    """The warning class of a speed's warning ("module:qualname"; UserWarning when it cannot be found)."""
    module, _, qualname = name.partition(":")
    try:
        obj: Any = importlib.import_module(module)
        for part in qualname.split("."):
            obj = getattr(obj, part)
    except (ImportError, AttributeError, ValueError):
        return UserWarning
    return obj if isinstance(obj, type) and issubclass(obj, Warning) else UserWarning


def _kind_words(category: type[Warning]) -> str:
    """'LightlyDampedModeWarning' -> 'lightly damped mode'; UserWarning -> 'note'."""
    words = re.sub(r"(?<!^)(?=[A-Z])", " ", category.__name__.removesuffix("Warning")).lower().strip()
    return words if words and category is not UserWarning else "note"


def grouped_warnings(result: SweepResult) -> list[tuple[type[Warning], str]]:
    """The sweep's warnings once per kind (the warning's class; a note on a scenario key: that key), in
    the order first raised: (class,
    "<kind> at <speeds>[, N messages]: <the first message, as raised at the first speed>"); a band cut
    at 0.1 / time_step by the speed rule is one more ("speed rule at ..."). Each speed's messages in
    full are in its summary (``warnings``) and on the sweep's page."""
    kinds: dict[str, tuple[list[float], list[str]]] = {}
    for v, s in zip(result.speeds, result.summaries):
        messages = [str(m) for m in s.get("warnings", ())]
        names = [str(k) for k in s.get("warning_kinds", ())] or ["builtins:UserWarning"] * len(messages)
        for message, kind in zip(messages, names):
            text = re.sub(r" \(at [0-9.e+-]+ km/h\)$", "", message)
            key = re.match(r"((?:track|analysis|bridge|train)\.[A-Za-z0-9_.]+) ", text)  # a note on one key: its kind
            speeds, texts = kinds.setdefault(kind + (f"|{key.group(1)}" if key else ""), ([], []))
            if v not in speeds:
                speeds.append(v)
            if text not in texts:
                texts.append(text)
    out = []
    cut = result.provenance.get("band_capped_kmh") or []
    if cut:
        an = result.base.analysis
        out.append((UserWarning, f"speed rule at {speeds_text(cut, result.speeds)}: the band is capped at "
                    f"{0.1 / an.time_step:g} Hz (0.1 / analysis.time_step), so the scenario's shortest wavelengths "
                    f"are left out there (the grid table of the report)"))
    for kind, (speeds, texts) in kinds.items():
        category = _category(kind.partition("|")[0])
        more = f", {len(texts)} messages" if len(texts) > 1 else ""
        out.append((category, f"{_kind_words(category)} at {speeds_text(speeds, result.speeds)}{more}: {texts[0]}"))
    return out


def write_sweep(result: SweepResult, folder: str | Path) -> Path:
    """The table as ``folder/speed_sweep.csv`` (the figure: :func:`tb_exudyn.plotting.plot_speed_sweep`)."""
    return write_table_csv(result.rows(), Path(folder) / SWEEP_TABLE)


__all__ = ["SWEEP_SCHEMA", "SWEEP_TABLE", "CriterionValues", "Resonance", "SweepResult", "checks_text", "criterion_values",
           "read_checks", "grouped_warnings", "speeds_text", "sweep_dataset",
           "sweep_rows", "write_sweep"]
