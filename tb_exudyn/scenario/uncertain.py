"""Uncertain scenario keys as data: the ``[uncertain]`` table of a scenario or of a separate TOML file.

Each entry names a scenario key by the same dotted path as ``--set`` (``bridge.girder.E``,
``bridge.damping_ratio``, ``train.vehicles.0.secondary.k_z``, ``track.irregularity_level``) and gives
it a distribution; the keys are independent. ``bridge.code.ballast_density`` is the ballast's density,
with the bridge's ballast mass following it (:func:`apply_values`)::

    [uncertain."bridge.girder.E"]
    distribution = "lognormal"
    cov = 0.10                      # coefficient of variation; the mean is the scenario's value

    [uncertain."bridge.damping_ratio"]
    distribution = "uniform"
    relative_bounds = [-0.2, 0.2]   # the scenario's value x (1 - 0.2) ... x (1 + 0.2)

The parameters (all optional unless a distribution needs them):

- ``mean`` (absolute; default the scenario's value), and ``cov`` (relative to the mean) or ``std``
  (absolute): normal, lognormal (the mean and std of the variable itself, not of its logarithm),
  truncated normal (of the parent normal), uniform (a half-width of sqrt(3) std about the mean);
- ``bounds = [low, high]`` (absolute) or ``relative_bounds = [a, b]`` (the scenario's value x (1 + a)
  ... x (1 + b)): uniform, truncated normal.

Checked as any scenario key (:func:`check_uncertain`, before any work): the key must be a number of
the scenario (its value found through :func:`tb_exudyn.scenario.io.with_settings`, the ``--set``
mechanism); the parameters finite, cov and std > 0, bounds ordered; a lognormal needs a positive mean;
the values the study can reach (the bounds, or the 1e-6 and 1 - 1e-6 quantiles of an unbounded
distribution, :data:`TAIL`) must be allowed by the schema. Each error is one ScenarioError naming the
file and ``uncertain.<key>``. The distributions themselves are built by :mod:`tb_exudyn.methods.uq`
(chaospy), which imports this module.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from statistics import NormalDist
from typing import Any

from . import model as m
from ..errors import SettingError
from .code_data import with_ballast_density
from .errors import ScenarioError
from .io import resolve_model_path, scenario_from_dict, with_settings
from .schema import to_dict
from .toml_io import read_toml

#: the distributions a key may have
DISTRIBUTIONS: tuple[str, ...] = ("normal", "lognormal", "uniform", "truncated_normal")
#: the parameters an entry may give
PARAMETERS: tuple[str, ...] = ("distribution", "mean", "cov", "std", "bounds", "relative_bounds")
#: the tail probability at each end of an unbounded distribution whose quantile must stay in the key's range
TAIL = 1e-6
#: the ballast's density as an uncertain key: the bridge's ballast mass follows it
#: (:func:`~tb_exudyn.scenario.code_data.with_ballast_density`), within the code data's density range
BALLAST_DENSITY = "bridge.code.ballast_density"
#: at most this many uncertain keys (a tensor or sparse grid grows fast with the dimension)
MAX_KEYS = 12


@dataclass(frozen=True)
class UncertainKey:
    """One uncertain key, its parameters absolute: ``mean``, ``std`` (NaN for a uniform given by bounds)
    and ``low``, ``high`` (the support: -inf, inf for normal, 0, inf for lognormal)."""

    key: str
    distribution: str
    mean: float
    std: float
    low: float
    high: float
    nominal: float

    def reach(self) -> tuple[float, float]:
        """The lowest and highest value the study can reach (the bounds, or the :data:`TAIL` quantiles)."""
        if self.distribution in ("uniform", "truncated_normal"):
            return self.low, self.high
        if self.distribution == "normal":
            z = NormalDist().inv_cdf(1 - TAIL)
            return self.mean - z * self.std, self.mean + z * self.std
        mu, s = lognormal_parameters(self.mean, self.std)
        z = NormalDist().inv_cdf(1 - TAIL)
        return math.exp(mu - z * s), math.exp(mu + z * s)


def lognormal_parameters(mean: float, std: float) -> tuple[float, float]:
    """(mu, sigma) of log X for a lognormal X of the given mean and standard deviation."""
    s2 = math.log1p((std / mean) ** 2)
    return math.log(mean) - s2 / 2, math.sqrt(s2)


def apply_values(scenario: m.Scenario, settings: Any) -> m.Scenario:
    """The scenario with the uncertain keys' values ((dotted key, value), ...) set: through the --set
    mechanism (:func:`~tb_exudyn.scenario.io.with_settings`, every value checked by the schema), but
    :data:`BALLAST_DENSITY`, the ballast's density, whose ballast mass the bridge's mass follows
    (:func:`~tb_exudyn.scenario.code_data.with_ballast_density`; alone, the key would only say at which
    density the model's mass is). ScenarioError naming the key when the schema refuses a value."""
    settings = list(settings)
    for key, value in settings:
        if key == BALLAST_DENSITY:
            scenario = scenario.replace(bridge=with_ballast_density(scenario.bridge, float(value)))
    return with_settings(scenario, [(k, v) for k, v in settings if k != BALLAST_DENSITY])


def nominal_value(scenario: m.Scenario, key: str, where: str) -> float:
    """The scenario's value of the dotted ``key`` (a number); ScenarioError naming ``where`` otherwise
    (and for :data:`BALLAST_DENSITY` on a bridge without ballast: the key would change nothing)."""
    if key == BALLAST_DENSITY and (scenario.bridge.code is None or scenario.bridge.code.ballast_mass_per_length <= 0):
        raise ScenarioError(where, f"uncertain.{key}", None, "a bridge with ballast (bridge.code.ballast_mass_per_length "
                            "> 0)", "no ballast on this bridge")
    node: Any = to_dict(scenario)
    try:  # the --set mechanism: an unknown key or index is its error
        with_settings(scenario, [(key, _probe(node, key))])
    except ScenarioError as exc:
        raise ScenarioError(where, f"uncertain.{key}", exc.key, exc.allowed, exc.reason) from None
    for part in key.split("."):
        node = node[int(part)] if isinstance(node, list) else (node or {}).get(part)
    if isinstance(node, bool) or not isinstance(node, (int, float)) or not math.isfinite(node):
        raise ScenarioError(where, f"uncertain.{key}", node, "a key whose value is a finite number",
                            "not a numeric key")
    return float(node)


def _probe(data: Any, key: str) -> Any:
    """The key's own value when it exists (setting it changes nothing), else 0 (with_settings names it)."""
    node = data
    for part in key.split("."):
        if isinstance(node, list) and part.isdigit() and int(part) < len(node):
            node = node[int(part)]
        elif isinstance(node, dict) and part in node:
            node = node[part]
        else:
            return 0
    return node


def _number(entry: dict, name: str, where: str, key: str) -> float | None:
    value = entry.get(name)
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise ScenarioError(where, f"uncertain.{key}.{name}", value, "a finite number", "wrong type")
    return float(value)


def _pair(entry: dict, name: str, where: str, key: str) -> tuple[float, float] | None:
    value = entry.get(name)
    if value is None:
        return None
    ok = isinstance(value, list) and len(value) == 2 and all(
        isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) for v in value)
    if not ok or value[0] >= value[1]:
        raise ScenarioError(where, f"uncertain.{key}.{name}", value, "[low, high], two finite numbers, low < high",
                            "bad bounds")
    return float(value[0]), float(value[1])


def parse_key(key: str, entry: Any, nominal: float, where: str) -> UncertainKey:
    """One ``[uncertain."KEY"]`` entry as an :class:`UncertainKey` (absolute parameters), checked."""
    name = f"uncertain.{key}"
    if not isinstance(entry, dict):
        raise ScenarioError(where, name, entry, "a table with distribution = ...", "wrong type")
    unknown = sorted(set(entry) - set(PARAMETERS))
    if unknown:
        raise ScenarioError(where, f"{name}.{unknown[0]}", entry[unknown[0]], ", ".join(PARAMETERS), "unknown key")
    dist = entry.get("distribution")
    if dist not in DISTRIBUTIONS:
        raise ScenarioError(where, f"{name}.distribution", dist, ", ".join(map(repr, DISTRIBUTIONS)),
                            "unknown distribution")
    mean = _number(entry, "mean", where, key)
    mean = nominal if mean is None else mean
    cov, std = _number(entry, "cov", where, key), _number(entry, "std", where, key)
    if cov is not None and std is not None:
        raise ScenarioError(where, name, entry, "cov or std, not both", "both given")
    for label, v in (("cov", cov), ("std", std)):
        if v is not None and v <= 0:
            raise ScenarioError(where, f"{name}.{label}", v, "> 0", "not positive")
    if cov is not None:
        if mean == 0:
            raise ScenarioError(where, f"{name}.cov", cov, "std (absolute) for a key whose mean is 0",
                                "a cov of a zero mean")
        std = cov * abs(mean)
    bounds, rel = _pair(entry, "bounds", where, key), _pair(entry, "relative_bounds", where, key)
    if bounds is not None and rel is not None:
        raise ScenarioError(where, name, entry, "bounds or relative_bounds, not both", "both given")
    if rel is not None:
        if nominal == 0:
            raise ScenarioError(where, f"{name}.relative_bounds", list(rel), "bounds (absolute) for a key whose "
                                "value is 0", "relative to 0")
        bounds = tuple(sorted((nominal * (1 + rel[0]), nominal * (1 + rel[1]))))  # type: ignore[assignment]
    return _absolute(key, dist, mean, std, bounds, nominal, where, entry)


def _absolute(key: str, dist: str, mean: float, std: float | None, bounds: tuple[float, float] | None,
              nominal: float, where: str, entry: dict) -> UncertainKey:
    name = f"uncertain.{key}"
    if dist in ("normal", "lognormal") and (std is None or bounds is not None):
        raise ScenarioError(where, name, entry, f"{dist}: cov or std (and mean), no bounds", "bad parameters")
    if dist == "lognormal" and mean <= 0:
        raise ScenarioError(where, f"{name}.mean", mean, "lognormal: a positive mean (a key that may be 0 or "
                            "negative: normal, uniform or truncated_normal)", "not positive")
    if dist == "uniform":
        if (bounds is None) == (std is None):
            raise ScenarioError(where, name, entry, "uniform: bounds or relative_bounds, or cov or std", "bad parameters")
        if bounds is None:
            half = math.sqrt(3.0) * std  # type: ignore[operator]
            bounds = (mean - half, mean + half)
        return UncertainKey(key, dist, (bounds[0] + bounds[1]) / 2, (bounds[1] - bounds[0]) / math.sqrt(12.0),
                            bounds[0], bounds[1], nominal)
    if dist == "truncated_normal":
        if std is None or bounds is None:
            raise ScenarioError(where, name, entry, "truncated_normal: cov or std (and mean) and bounds",
                                "bad parameters")
        return UncertainKey(key, dist, mean, std, bounds[0], bounds[1], nominal)
    low = 0.0 if dist == "lognormal" else -math.inf
    return UncertainKey(key, dist, mean, std, low, math.inf, nominal)  # type: ignore[arg-type]


def check_reach(scenario: m.Scenario, uk: UncertainKey, where: str) -> None:
    """The lowest and highest value ``uk`` reaches, each set on the scenario through the schema."""
    for value in uk.reach():
        check_value(scenario, uk.key, value, where, uk.distribution)


def check_value(scenario: m.Scenario, key: str, value: float, where: str, what: str) -> m.Scenario:
    """The scenario with ``key`` = ``value`` (the --set mechanism); ScenarioError naming ``where`` and
    ``uncertain.<key>`` when the schema refuses the value. Returns the new scenario."""
    try:
        return apply_values(scenario, [(key, float(value))])
    except ScenarioError as exc:
        raise ScenarioError(where, f"uncertain.{key}", value, exc.allowed,
                            f"{what} reaches a value the key does not allow ({exc.reason})") from None


def check_uncertain(scenario: m.Scenario, table: Any, where: str) -> tuple[UncertainKey, ...]:
    """The ``[uncertain]`` table (a dict of dotted key -> entry) read and checked against the scenario."""
    if not isinstance(table, dict) or not table:
        raise ScenarioError(where, "uncertain", table, "a table of at least one dotted scenario key",
                            "no uncertain key")
    if len(table) > MAX_KEYS:
        raise ScenarioError(where, "uncertain", sorted(table), f"at most {MAX_KEYS} keys", "too many keys")
    keys = []
    for key, entry in table.items():
        uk = parse_key(key, entry, nominal_value(scenario, key, where), where)
        check_reach(scenario, uk, where)
        keys.append(uk)
    return tuple(keys)


def load_uncertain(path: str | Path, scenario: m.Scenario) -> tuple[UncertainKey, ...]:
    """The ``[uncertain]`` table of the TOML file ``path`` (its only table), checked against ``scenario``."""
    data = read_toml(Path(path))
    extra = sorted(set(data) - {"uncertain"})
    if extra or "uncertain" not in data:
        raise ScenarioError(str(path), extra[0] if extra else "uncertain", data.get(extra[0]) if extra else None,
                            "one table, [uncertain]", "unknown key" if extra else "missing")
    return check_uncertain(scenario, data["uncertain"], str(path))


def load_study(path_or_name: str | Path, uncertain_file: str | Path | None = None,
               settings: Any = ()) -> tuple[m.Scenario, tuple[UncertainKey, ...]]:
    """A scenario file (or library name) with its ``[uncertain]`` table, or the table of
    ``uncertain_file`` (which then replaces the scenario's); ``settings``: ``--set`` pairs applied first."""
    path = resolve_model_path(path_or_name, "scenarios")
    data = read_toml(path)
    table = data.pop("uncertain", None)
    scenario = scenario_from_dict(data, str(path))
    for key, value in settings or ():
        try:
            scenario = with_settings(scenario, [(key, value)])
        except ScenarioError as exc:
            raise SettingError("load_study", "settings", f"{key}={value}", f"{exc.key}: {exc.allowed}",
                               exc.reason) from None
    if uncertain_file is not None:
        return scenario, load_uncertain(uncertain_file, scenario)
    if table is None:
        raise ScenarioError(str(path), "uncertain", None, "an [uncertain] table in the scenario, or an uncertain "
                            "file (uncertain_file)", "no uncertain keys")
    return scenario, check_uncertain(scenario, table, str(path))


__all__ = ["BALLAST_DENSITY", "DISTRIBUTIONS", "apply_values", "MAX_KEYS", "PARAMETERS", "TAIL", "UncertainKey", "check_uncertain", "check_value",
           "load_study", "load_uncertain", "lognormal_parameters", "nominal_value", "parse_key"]
