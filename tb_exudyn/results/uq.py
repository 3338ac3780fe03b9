"""The result of an uncertainty study (:func:`tb_exudyn.run_uq`): PEM under uncertain scenario keys.

One labelled schema (:data:`UQ_SCHEMA`) drives the npz members, the load-time checks and
:meth:`UqResult.to_xarray` (NetCDF). Over the uncertain keys theta (the expansion's moments, the bands
from the surrogate):

- per channel and time: the mean over theta of sigma(t) (``mean_sigma``) and of the mean response
  (``mean_response``), the standard deviation over theta of sigma(t) (``std_sigma``), and the 5, 50
  and 95 % points of sigma(t) (``sigma_band``);
- per quantity (``max_sigma:<channel>``: the largest sigma over the crossing; ``probability:<criterion>``:
  the probability of exceeding the criterion's limit in one passage at its deciding location;
  ``estimate:<criterion>``: the criterion's estimate): its mean and standard deviation over theta, the
  Sobol first-order and total indices per key, and the surrogate's leave-one-out error (relative to
  the variance);
- per quantity, its 5, 50 and 95 % points over theta (``quantity_band``; for ``estimate:<criterion>``
  the distribution over the keys of the level exceeded with the target probability);
- per criterion: P_f = E_theta[P(exceed | theta)] (``pf``);
- the nodes: each key's value and the quadrature weight (NaN for a least-squares design) of every node,
  and every quantity at every node.
"""

from __future__ import annotations

import json
import math
import re
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Mapping

import numpy as np

from .._version import __version__
from ..scenario import Scenario, scenario_to_toml
from ..scenario.io import scenario_from_dict
from ..scenario.limits import FixedLimit, GradedLimit, quantity
from ..storage import (
    Member,
    NpzFile,
    check_members,
    check_values,
    json_default,
    load_json,
    save_result_folder,
)
from .base import figures
from .checks import DEFAULT_TARGET_PROBABILITY, default_limits
from .schema import Variable, need_xarray

#: the result folder's name in an output folder
UQ_FOLDER = "uq"
#: the percentiles of sigma(t) in ``sigma_band``
PERCENTILES = (5.0, 50.0, 95.0)
#: the leave-one-out error above which the result warns that the surrogate is not accurate
LOO_WARNING = 0.01

_CT = ("channel", "time")
#: every array of a :class:`UqResult`
UQ_SCHEMA: tuple[Variable, ...] = (
    Variable("time", ("time",), "output time", units="s", required=True, coordinate=True),
    Variable("mean_sigma", _CT, "mean over the uncertain keys of sigma(t)", units_coordinate="unit", required=True,
             nonnegative=True),
    Variable("std_sigma", _CT, "standard deviation over the uncertain keys of sigma(t)", units_coordinate="unit",
             required=True, nonnegative=True),
    Variable("mean_response", _CT, "mean over the uncertain keys of the mean response", units_coordinate="unit",
             required=True),
    Variable("sigma_band", ("percentile", "channel", "time"), "5, 50 and 95 % points of sigma(t) over the keys",
             units_coordinate="unit", required=True),
    Variable("quantity_mean", ("quantity",), "mean over the uncertain keys", required=True, finite=False),
    Variable("quantity_std", ("quantity",), "standard deviation over the uncertain keys", required=True, finite=False),
    Variable("quantity_band", ("percentile", "quantity"), "5, 50 and 95 % points of each quantity over the keys",
             finite=False),  # not in a result of the first version: NaN when loaded from one
    Variable("sobol_first", ("key", "quantity"), "first-order Sobol index", units="1", required=True, finite=False),
    Variable("sobol_total", ("key", "quantity"), "total Sobol index", units="1", required=True, finite=False),
    Variable("loo", ("quantity",), "leave-one-out error of the surrogate, relative to the variance", units="1",
             required=True, finite=False),
    Variable("pf", ("criterion",), "P_f = E_theta[P(exceed | theta)] in one passage", units="1", required=True,
             finite=False),
    Variable("node_values", ("node", "key"), "each key's value at each node", required=True),
    Variable("node_weights", ("node",), "quadrature weight of each node (NaN: least squares)", units="1",
             required=True, finite=False),
    Variable("node_quantities", ("node", "quantity"), "each quantity at each node", required=True, finite=False),
)
_SIZES = {"time": "nt", "channel": "nc", "percentile": 3, "quantity": "nq", "key": "nk", "criterion": "ncr",
          "node": "nn"}


@dataclass(frozen=True)
class UqResult:
    """An uncertainty study's result (module docstring); ``keys``: each uncertain key as a dict
    (key, distribution, mean, std, low, high, nominal)."""

    scenario: Scenario
    keys: tuple[dict[str, Any], ...]
    channels: tuple[str, ...]
    units: tuple[str, ...]
    quantities: tuple[str, ...]
    criteria: tuple[str, ...]
    data: Mapping[str, np.ndarray]
    provenance: dict[str, Any] = field(default_factory=dict)
    schema: tuple[Variable, ...] = UQ_SCHEMA

    def __getattr__(self, name: str) -> np.ndarray:
        data = self.__dict__.get("data")
        if data is not None and name in data:
            return data[name]
        raise AttributeError(name)

    @property
    def key_names(self) -> tuple[str, ...]:
        return tuple(k["key"] for k in self.keys)

    def index(self, channel: str) -> int:
        return self.channels.index(channel)

    def quantity(self, name: str) -> dict[str, Any]:
        """One quantity's mean, std, its 5, 50 and 95 % points over the keys (``band``, :data:`PERCENTILES`),
        Sobol indices (per key name) and leave-one-out error."""
        q = self.quantities.index(name)
        return {"mean": float(self.data["quantity_mean"][q]), "std": float(self.data["quantity_std"][q]),
                "band": tuple(map(float, self.data["quantity_band"][:, q])),
                "sobol_first": dict(zip(self.key_names, map(float, self.data["sobol_first"][:, q]))),
                "sobol_total": dict(zip(self.key_names, map(float, self.data["sobol_total"][:, q]))),
                "loo": float(self.data["loo"][q])}

    def plot_sobol(self, quantities: Any = None) -> Any:
        """The Sobol bars (:func:`tb_exudyn.plotting.plot_uq_sobol`, a matplotlib Figure)."""
        return figures().plot_uq_sobol(self, quantities)

    def plot_band(self, channel: str) -> Any:
        """``channel``'s sigma(t) band over the keys (:func:`tb_exudyn.plotting.plot_uq_band`)."""
        return figures().plot_uq_band(self, channel)

    def to_xarray(self) -> Any:
        """The result as an :class:`xarray.Dataset` (:data:`UQ_SCHEMA`)."""
        xr = need_xarray("UqResult.to_xarray")
        coords: dict[str, Any] = {"channel": ("channel", list(self.channels)),
                                  "unit": ("channel", list(self.units)), "percentile": ("percentile", list(PERCENTILES)),
                                  "quantity": ("quantity", list(self.quantities)), "key": ("key", list(self.key_names)),
                                  "criterion": ("criterion", list(self.criteria)),
                                  "node": ("node", np.arange(self.data["node_weights"].size))}
        out: dict[str, Any] = {}
        for v in self.schema:
            a = np.asarray(self.data[v.name])
            if v.coordinate:
                coords[v.labelled_name] = (v.labelled_name, a, v.attrs())
            elif a.size:
                out[v.labelled_name] = (v.dims, a, v.attrs())
        attrs = {"title": f"tb_exudyn uncertainty study, scenario {self.scenario.name}", "source": f"tb_exudyn {__version__}",
                 "kind": "uq", "scenario_toml": scenario_to_toml(self.scenario),
                 "keys_json": json.dumps(self.keys, default=json_default),
                 "provenance_json": json.dumps(self.provenance, sort_keys=True, default=json_default)}
        return xr.Dataset({k: v for k, v in out.items() if all(d in coords or d == "time" for d in v[0])},
                          coords=coords, attrs=attrs)

    def save(self, folder: str | Path) -> Path:
        """Write ``folder`` (``arrays.npz``, ``meta.json``) whole or not at all."""
        meta = {"kind": "uq", "version": __version__, "scenario_toml": scenario_to_toml(self.scenario),
                "keys": list(self.keys), "channels": list(self.channels), "units": list(self.units),
                "quantities": list(self.quantities), "criteria": list(self.criteria), "provenance": self.provenance}
        return save_result_folder(folder, {v.name: np.asarray(self.data[v.name]) for v in self.schema}, meta)


def criteria_info() -> dict[str, tuple[str, str, float]]:
    """Per criterion of the default limits (those the study's nodes were checked against, as a sweep's
    speeds are): what it checks, its quantity's unit and its pass/fail limit (a fixed limit's value, a
    graded one's last; NaN for a limit that depends on the run, e.g. on the axle load)."""
    out = {}
    for limit_set in default_limits():
        for c in limit_set.criteria:
            lim = c.limit
            value = getattr(lim, "value", None) if isinstance(lim, FixedLimit) else (
                lim.values[-1] if isinstance(lim, GradedLimit) else None)
            out[f"{limit_set.name}/{c.id}"] = (c.title, quantity(c.quantity).unit,
                                               math.nan if value is None else float(value))
    return out


def pf_verdicts(result: UqResult, target: float | None = None) -> list[dict[str, Any]]:
    """Per criterion of the limits: P_f = E_theta[P(exceed | theta)] (``result.pf``, the expansion's
    mean of the quantity ``probability:<criterion>``), the largest P(exceed | theta) at any node, the
    mean, std and 5, 50 and 95 % points over theta of the estimate (the level exceeded with the target
    probability, SI units; ``estimate_band``)
    and the verdict against ``target`` (default the checks' target probability per passage):
    EXCEEDS when P_f > target, OK when P_f <= target, NOT EVALUATED when P_f is not finite (a criterion
    not evaluated at some node); with the criterion's title, unit and limit (:func:`criteria_info`)."""
    target = DEFAULT_TARGET_PROBABILITY if target is None else float(target)
    out = []
    info = criteria_info()
    nodes = np.asarray(result.data["node_quantities"], dtype=float)
    for c, pf in zip(result.criteria, np.asarray(result.data["pf"], dtype=float)):
        name = f"probability:{c}"
        at_nodes = nodes[:, result.quantities.index(name)] if name in result.quantities else np.array([np.nan])
        est = (result.quantity(f"estimate:{c}") if f"estimate:{c}" in result.quantities
               else {"mean": np.nan, "std": np.nan, "band": (np.nan,) * len(PERCENTILES)})
        verdict = "NOT EVALUATED" if not np.isfinite(pf) else ("EXCEEDS" if pf > target else "OK")
        out.append({"criterion": c, "pf": float(pf), "target": target, "verdict": verdict,
                    "node_max": float(np.max(at_nodes)) if np.all(np.isfinite(at_nodes)) else float("nan"),
                    "estimate_mean": est["mean"], "estimate_std": est["std"], "estimate_band": est["band"],
                    **dict(zip(("title", "unit", "limit"), info.get(c, ("", "", math.nan))))})
    return out


#: a number in a warning: the same warning at another node differs in them (a mode's growth over the run)
_NUMBER = re.compile(r"[-+]?\d+(?:\.\d+)?(?:e[-+]?\d+)?")


def loo_notes(result: UqResult) -> list[str]:
    """The note (empty: none) when no quantity that varies over the keys has a leave-one-out error: the
    surrogate's accuracy is then unknown. A quadrature design of one key has as many nodes as basis
    terms (order + 1), which leaves no residual to estimate it from."""
    std, loo = np.asarray(result.data["quantity_std"], float), np.asarray(result.data["loo"], float)
    varies = np.isfinite(std) & (std > 0)
    if not varies.any() or np.isfinite(loo[varies]).any():
        return []
    n = result.provenance.get("n_nodes")
    more = 2 * int(n) if isinstance(n, int) and n > 0 else 16  # twice the nodes: above the basis size here
    return [f"the surrogate's error is unknown: no leave-one-out error could be estimated ({n if n else '?'} "
            f"nodes, {result.provenance.get('design', '?')} design; no more nodes than basis terms?): use --design sobol "
            f"--nodes {more}"]


def warning_groups(result: UqResult) -> list[tuple[str, list[str]]]:
    """The study's warnings (:func:`loo_notes`, then ``provenance["warnings"]``: the surrogate's, then the
    nodes' runs'), those that differ only in their numbers as one: (the first as raised, every distinct
    message), in the order first raised."""
    groups: dict[str, list[str]] = {}
    for m in [*loo_notes(result), *map(str, result.provenance.get("warnings", ()))]:
        texts = groups.setdefault(_NUMBER.sub("#", m), [])
        if m not in texts:
            texts.append(m)
    return [(texts[0], texts) for texts in groups.values()]


def load_uq(folder: str | Path) -> UqResult:
    """A result written by :meth:`UqResult.save` (its arrays checked against :data:`UQ_SCHEMA`)."""
    folder = Path(folder)
    meta = load_json(folder / "meta.json")
    sizes = {"nc": len(meta["channels"]), "nq": len(meta["quantities"]), "nk": len(meta["keys"]),
             "ncr": len(meta["criteria"])}
    with NpzFile(folder / "arrays.npz") as npz:
        members = {v.name: _member(v) for v in UQ_SCHEMA}
        check_members(npz, members, sizes, {})
        data = {v.name: npz.read(v.name) for v in UQ_SCHEMA if v.required or v.name in npz.headers}
    data.setdefault("quantity_band", np.full((len(PERCENTILES), sizes["nq"]), np.nan))
    check_values(folder / "arrays.npz", data, members)
    scenario = scenario_from_dict(tomllib.loads(meta["scenario_toml"]), str(folder), resolve_names=False)
    return UqResult(scenario=scenario, keys=tuple(meta["keys"]), channels=tuple(meta["channels"]),
                    units=tuple(meta["units"]), quantities=tuple(meta["quantities"]), criteria=tuple(meta["criteria"]),
                    data=data, provenance=meta.get("provenance", {}))


def _member(v: Variable) -> Member:
    return Member(tuple(_SIZES[d] for d in v.dims), required=v.required, finite=v.finite, nonnegative=v.nonnegative,
                  max_abs=v.max_abs)


__all__ = ["LOO_WARNING", "PERCENTILES", "UQ_FOLDER", "UQ_SCHEMA", "UqResult", "criteria_info", "load_uq", "loo_notes", "pf_verdicts", "warning_groups"]
