"""The one labelled schema of every result: each array a result holds, declared once.

A :class:`Variable` says of one array its name (the result's attribute and the npz member), its
dims (``channel``, ``time``, ``frequency``, ``sample``, ``type``, ``bound``, ``psd_channel``; a
sweep's ``speed``, ``quantity``, ``criterion``: :data:`tb_exudyn.results.sweep.SWEEP_SCHEMA`), its
unit (fixed, e.g. "s", or per channel: the ``unit`` coordinate), what it is, and what its stored
values must be (finite, >= 0, largest magnitude). The tuple of a result type
(:data:`RANDOM_RESPONSE`, :data:`TIME_HISTORY`) drives

- its npz members and their load-time checks (:func:`members`: :class:`tb_exudyn.storage.Member`
  per array, dims as the size names ``nt``, ``nc``, ... of the files);
- its labelled form (:func:`to_xarray`, ``result.to_xarray()``, the NetCDF export): every array of
  ``result.arrays()`` becomes a variable or coordinate with its dims, the channel names, units and
  readable labels are coordinates, the band, method, sample count, provenance (JSON text) and
  scenario (TOML text) attributes. So an array added to a result type and its schema is stored,
  loaded and exported alike; an array added to the type alone is refused by the test of the schema
  (tests/results/test_schema.py).

An array of no element (a Monte Carlo result's ``freq`` and ``df``) has no labelled form: a
dimension of length 0 carries nothing, and NetCDF3 cannot write one.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from typing import Any, Mapping, Sequence

import numpy as np

from .._version import __version__
from ..errors import CapabilityError
from ..scenario import scenario_to_toml
from ..storage import MAX_SQUARE, MAX_VALUE, Member, json_default
from ..system.labels import channel_label

#: labelled dim -> the size name of the npz files (an int: a fixed length)
DIM_SIZES: dict[str, int | str] = {"time": "nt", "channel": "nc", "frequency": "nf", "psd_channel": "npsd",
                                   "type": "ntypes", "sample": "ns", "bound": 2}
#: the labels of the two ends of a confidence interval (dim ``bound``)
BOUNDS = ("lower", "upper")


@dataclass(frozen=True)
class Variable:
    """One array of a result.

    name: the result's attribute and npz member; dims: labelled dims (:data:`DIM_SIZES`);
    long_name: what it is ("{band}" and "{mean_kind}" are filled in by :func:`to_xarray`);
    units: a fixed SI unit, or units_coordinate: the coordinate holding each channel's unit;
    coordinate: the array is the coordinate of ``label`` (``time``, ``frequency``);
    label: its name in the labelled dataset (default: ``name``); required, finite, nonnegative,
    max_abs: what a stored array must be (:class:`tb_exudyn.storage.Member`; a sweep's variables, over
    ``speed``, ``quantity`` and ``criterion``, and a check's, over ``row``, ``span`` and ``criterion``, are
    CSV columns and have no npz member); attribute, in_table: a table's (:data:`CHECK_RECORD`)."""

    name: str
    dims: tuple[str, ...]
    long_name: str
    units: str = ""
    units_coordinate: str = ""
    required: bool = False
    finite: bool = True
    nonnegative: bool = False
    max_abs: float = MAX_VALUE
    coordinate: bool = False
    label: str = ""
    #: a table's variable (the check's: :data:`CHECK_RECORD`): the record's attribute it reads (a dotted
    #: path; default ``name``), and whether it is a column of the table's CSV file or of its labelled form only
    attribute: str = ""
    in_table: bool = True

    @property
    def labelled_name(self) -> str:
        return self.label or self.name

    @property
    def member(self) -> Member:
        return Member(tuple(DIM_SIZES[d] for d in self.dims), required=self.required, finite=self.finite,
                      nonnegative=self.nonnegative, max_abs=self.max_abs)

    def attrs(self) -> dict[str, str]:
        out = {"long_name": self.long_name}
        if self.units:
            out["units"] = self.units
        if self.units_coordinate:
            out["units_coordinate"] = self.units_coordinate
        return out


_CT, _U = ("channel", "time"), "unit"
#: every array of a :class:`~tb_exudyn.results.random_response.RandomResponse`, in file order (a name
#: bound on first use in this order: ``nt`` by time, ``nf`` by freq)
RANDOM_RESPONSE: tuple[Variable, ...] = (
    Variable("time", ("time",), "output time", units="s", required=True, coordinate=True),
    Variable("mean", _CT, "mean response ({mean_kind})", units_coordinate=_U, required=True),
    Variable("std", _CT, "standard deviation sigma(t) over {band}", units_coordinate=_U, required=True,
             nonnegative=True),
    Variable("freq", ("frequency",), "analysed frequency", units="Hz", required=True, nonnegative=True,
             coordinate=True, label="frequency"),
    Variable("df", ("frequency",), "quadrature width of each frequency", units="Hz", required=True, nonnegative=True),
    Variable("psd", ("psd_channel", "frequency", "time"), "one-sided PSD per Hz, sigma^2(t) = sum_f psd df",
             units_coordinate="psd_unit", nonnegative=True, max_abs=MAX_SQUARE),
    Variable("var_by_type", ("type", "channel", "time"), "variance contributed by each irregularity type",
             units_coordinate="unit (squared)", nonnegative=True, max_abs=MAX_SQUARE),
    Variable("std_ci", ("bound", "channel", "time"), "95 % confidence interval of sigma", units_coordinate=_U,
             nonnegative=True),
    Variable("mean_ci", ("bound", "channel", "time"), "95 % confidence interval of the mean", units_coordinate=_U),
    Variable("min_wheel_force", ("sample",), "minimum vertical wheel-rail force per sample (NaN: no wheel force)",
             units="N", finite=False),
    Variable("samples", ("sample", "channel", "time"), "Monte Carlo samples", units_coordinate=_U, finite=False),
    Variable("mean_rate", _CT, "time derivative of the mean", units_coordinate="unit (per second)", finite=False),
    Variable("std_rate", _CT, "standard deviation of the channel's time derivative",
             units_coordinate="unit (per second)", nonnegative=True),
    Variable("rho", _CT, "correlation of the channel with its time derivative at the same time", units="1",
             finite=False),
    Variable("bandwidth", _CT, "Vanmarcke's bandwidth delta of the time-dependent PSD", units="1", finite=False),
    Variable("sample_min", ("sample", "channel"), "every sample's minimum over the record", units_coordinate=_U,
             finite=False),
    Variable("sample_max", ("sample", "channel"), "every sample's maximum over the record", units_coordinate=_U,
             finite=False),
)
#: every array of a :class:`~tb_exudyn.results.time_history.TimeHistory` (``values``: the channels'
#: values stacked in channel order; its labelled name is ``value``)
TIME_HISTORY: tuple[Variable, ...] = (
    Variable("time", ("time",), "output time", units="s", required=True, coordinate=True),
    Variable("values", _CT, "channel value of one run", units_coordinate=_U, required=True, label="value"),
)


_R = ("row",)
#: the check's table (:class:`tb_exudyn.results.check_records.CheckRecord`, one per train, speed and mass
#: case; dims ``row`` and ``span``, the bridge's spans along the track), in check.csv's column order:
#: ``acc_z_mid_span`` is the columns acc_z_mid_span1 ... n; the stochastic columns read the record's
#: ``stochastic`` values (empty where not computed); the last ones are the record's as the results schema
#: names every criterion's (criterion, load model, track, utilisation, caveats): its labelled form only
CHECK_RECORD: tuple[Variable, ...] = (
    Variable("train", _R, "train (moving forces: its axle loads)", coordinate=True),
    Variable("speed_kmh", _R, "train speed", units="km/h", coordinate=True),
    Variable("case", _R, "mass case of the bridge (EN 1991-2 6.4.6.3.2)", coordinate=True),
    Variable("damping_ratio", _R, "bridge damping ratio (Table 6.6 or given, eq. 6.13 added where asked)", units="1"),
    Variable("cutoff_hz", _R, "the modes' cut-off frequency", units="Hz"),
    Variable("acc_z_mid_span", ("row", "span"), "peak |vertical acceleration| at mid-span along the track",
             units="m/s^2"),
    Variable("max_deck_acc_z", _R, "peak |vertical deck acceleration|, largest over the deck stations",
             units="m/s^2", attribute="value"),
    Variable("max_deck_acc_z_location", _R, "the deck station of the largest peak", attribute="location"),
    Variable("disp_z_mid", _R, "largest peak |vertical displacement| at a mid-span", units="m"),
    Variable("phi_dyn", _R, "phi'_dyn = max |y_dyn / y_stat| - 1, largest over the mid-spans", units="1"),
    Variable("phi_irregularity", _R, "phi'' of EN 1991-2 Annex C", units="1"),
    Variable("enhancement", _R, "1 + phi'_dyn + k phi''", units="1"),
    Variable("limit", _R, "the criterion's limit", units="m/s^2"),
    Variable("verdict", _R, "ok or exceeds: the peak against the limit"),
    Variable("max_deck_acc_z_with_phi2", _R, "peak x (1 + k phi''), the code's allowance for the irregularity",
             units="m/s^2", attribute="value_with_phi2"),
    Variable("p_exceed", _R, "probability of exceeding the limit in one passage (PEM; NaN: not computed)",
             units="1", finite=False, attribute="stochastic.p_exceed"),
    Variable("level_at_target", _R, "level exceeded with the target probability per passage (PEM)", units="m/s^2",
             finite=False, attribute="stochastic.level_at_target"),
    Variable("stochastic_location", _R, "the deck channel deciding the stochastic values",
             attribute="stochastic.location"),
    Variable("stochastic_mean_acc", _R, "largest |mean| there: the vehicle model's deterministic run", units="m/s^2",
             finite=False, attribute="stochastic.mean_acc"),
    Variable("stochastic_verdict", _R, "the stochastic values' verdict", attribute="stochastic.verdict"),
    Variable("stochastic_caveats", _R, "kinds of the caveats that could change it", attribute="stochastic.caveats"),
    Variable("stochastic_n_freq", _R, "frequencies of the PEM run", units="1", finite=False,
             attribute="stochastic.n_freq"),
    Variable("criterion", _R, "the criterion (limit file/criterion)", in_table=False, label="row_criterion"),
    Variable("load_model", _R, "the load model", in_table=False),
    Variable("track", _R, "the track form the limit is of", in_table=False),
    Variable("utilisation", _R, "value over limit", units="1", finite=False, in_table=False),
    Variable("caveats", _R, "what could change the verdict", in_table=False),
)
#: the check's verdict per EN 1990 A2.4.4 criterion (:class:`tb_exudyn.codes.criteria.CriterionVerdict`,
#: dim ``criterion``: labelled ``criterion_<name>``)
CHECK_CRITERIA: tuple[Variable, ...] = tuple(
    Variable(name, ("criterion",), what, units=units, finite=False, label=f"criterion_{name}") for name, what, units in (
        ("title", "what the criterion checks", ""), ("clause", "the code's clause", ""),
        ("load_model", "the load model", ""), ("value", "the deciding value (in 'unit')", ""),
        ("limit", "the limit (in 'unit')", ""), ("unit", "SI unit of the value and the limit", ""),
        ("bound", "upper: value <= limit; lower: value >= limit; compare: no limit", ""),
        ("utilisation", "value / limit (upper), limit / value (lower)", "1"), ("verdict", "the verdict", ""),
        ("case", "the deciding case", ""), ("location", "the deciding location", ""),
        ("caveats", "what it leaves out or why not evaluated", "")))


def members(schema: Sequence[Variable]) -> dict[str, Member]:
    """The npz members of a schema (name -> :class:`~tb_exudyn.storage.Member`), in file order."""
    return {v.name: v.member for v in schema}


def optional_names(schema: Sequence[Variable]) -> tuple[str, ...]:
    """The arrays a result of the schema may lack (None on the result, no member in the file)."""
    return tuple(v.name for v in schema if not v.required)


# ============================================================================================ labelled form
def need_xarray(what: str) -> Any:
    """The xarray module; CapabilityError naming ``what`` and how to install it otherwise."""
    try:
        import xarray
    except ImportError:
        raise CapabilityError(what, "xarray", "not installed", 'pip install "tb_exudyn[netcdf]" (xarray, h5netcdf, h5py)',
                              "labelled arrays need the xarray package") from None
    return xarray


def _dim_coordinates(dim: str, n: int, result: Any) -> tuple[Any, ...]:
    if dim == "psd_channel":
        return ("psd_channel", list(result.psd_channels))
    if dim == "type":
        return ("type", list(result.types), {"long_name": "irregularity spectrum"})
    if dim == "bound":
        return ("bound", list(BOUNDS))
    if dim == "sample":
        return ("sample", np.arange(n))
    raise ValueError(f"dim {dim!r} has no coordinate rule")  # a bug: a schema dim without one


def to_xarray(result: Any) -> Any:
    """The result as an :class:`xarray.Dataset`: every array of ``result.arrays()`` under its schema
    (``result.schema``), values unchanged (SI units); see the module docstring."""
    xr = need_xarray("to_xarray")
    arrays: Mapping[str, np.ndarray] = result.arrays()
    names = list(result.channel_names)
    units = [result.unit(n) for n in names]
    scenario = result.scenario
    random = result.kind.random
    coords: dict[str, Any] = {
        "channel": ("channel", names),
        "unit": ("channel", units, {"long_name": "SI unit of the channel"}),
        "label": ("channel", [channel_label(n) for n in names], {"long_name": "what the channel measures"}),
    }
    context = {"band": "", "mean_kind": ""}
    if random:
        coords["psd_unit"] = ("channel", [f"({u})^2/Hz" for u in units])
        context = {"band": f"{result.band[0]:.6g}-{result.band[1]:.6g} Hz",
                   "mean_kind": result.kind.mean}
    data: dict[str, Any] = {}
    for v in result.schema:
        a = arrays.get(v.name)
        if a is None or np.size(a) == 0:
            continue
        dims = list(v.dims)
        if "psd_channel" in dims and getattr(result, "psd_channels", None) is None:
            dims[dims.index("psd_channel")] = "channel"  # every channel's map: rows as the channels
        for dim, n in zip(dims, np.shape(a)):
            if dim not in coords and dim not in ("time", "frequency"):
                coords[dim] = _dim_coordinates(dim, n, result)
        attrs = {k: s.format(**context) for k, s in v.attrs().items()}
        if v.coordinate:
            coords[v.labelled_name] = (v.labelled_name, np.asarray(a, dtype=float), attrs)
        else:
            data[v.labelled_name] = (tuple(dims), np.asarray(a), attrs)
    attrs: dict[str, Any] = {
        "title": f"tb_exudyn {result.method if random else 'time history'} result"
                 + (f", scenario {scenario.name}" if scenario is not None else ""),
        "source": f"tb_exudyn {__version__}",
        "scenario": "" if scenario is None else scenario.name,
        "scenario_toml": "" if scenario is None else scenario_to_toml(scenario),
        "provenance_json": json.dumps(result.provenance, sort_keys=True, default=json_default),
        "time_origin": "t = 0 s when the train's first axle is at x = -lead_in (lead_in m before the bridge)",
        "kind": "random_response" if random else "time_history",
    }
    if random:
        attrs.update({"method": result.method, "band_hz": np.asarray(result.band, dtype=float),
                      "n_samples": int(result.n_samples), "types": ", ".join(result.types)})
    return xr.Dataset(data, coords=coords, attrs=attrs)


__all__ = ["BOUNDS", "CHECK_CRITERIA", "CHECK_RECORD", "DIM_SIZES", "RANDOM_RESPONSE", "TIME_HISTORY", "Variable", "members", "need_xarray",
           "optional_names", "to_xarray"]
