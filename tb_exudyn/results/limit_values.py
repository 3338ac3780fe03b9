"""The limits the code checks compare with: the limit files in use and a criterion's limit at a location.

:func:`default_limits` reads every limit file of the model library (models/limits/, or
``$TB_EXUDYN_MODELS/limits``; two of one name refused: :func:`unique_names`), :func:`limit_sets` resolves
what a caller gives (None, names, paths, LimitSets), and :func:`limit_at` is a criterion's limit on one
channel of a result with the words saying what it was computed from (a fixed value, a speed band, grades,
or a share of the static axle load: :func:`static_axle_load`). The checks themselves:
:mod:`tb_exudyn.results.checks`.
"""

from __future__ import annotations

import math
import os
import re
from typing import Any

from ..errors import ScenarioError, SettingError
from ..scenario.limits import Criterion, GradedLimit, LimitSet, load_limits
from ..scenario.registry import model_files, models_dir
from ..scenario.schema import source_file

_CAR = re.compile(r"car(\d+)\.axle(\d+)\.")


def static_axle_load(result: Any, car: int, axle: int) -> tuple[float | None, str]:
    """Static load [N] of axle ``axle`` of car ``car`` (1-based) and where it comes from: the mean of the
    axle's vertical wheel forces at t = 0 (the static equilibrium on the approach) when the result has
    them, else the vehicle's weight shared by its axles (car15: four; a sprung mass or moving force: one)."""
    prefix = f"car{car}.axle{axle}"
    names = [n for n in (f"{prefix}.left.force_z", f"{prefix}.right.force_z", f"{prefix}.force_z")
             if n in result.channels]
    if names:
        value = float(sum(result.mean[result.index(n), 0] for n in names))
        return value, "the model's static wheel loads (mean at t = 0)"
    sc = result.scenario
    if sc is None or car > len(sc.train.vehicles):
        return None, "no vehicle data"
    v = sc.train.vehicles[car - 1]
    g = sc.analysis.gravity
    if hasattr(v, "force"):
        return float(v.force), "the moving force"
    if hasattr(v, "wheel_mass"):
        return float((v.mass + v.wheel_mass) * g), "the sprung mass's weight"
    if hasattr(v, "body") and hasattr(v, "bogie") and hasattr(v, "wheelset"):
        return float((v.body.mass + 2 * v.bogie.mass + 4 * v.wheelset.mass) * g / 4), "the car's weight / 4 axles"
    return None, f"vehicle kind {getattr(v, 'kind', '?')!r} without a static axle load rule"


def limit_at(c: Criterion, result: Any, channel: str) -> tuple[float, str]:
    sc = result.scenario
    speed = None if sc is None else sc.speed_kmh
    kind = c.limit.kind
    if kind == "static_load":
        m = _CAR.match(channel)
        if m is None:
            return math.nan, "no axle in the channel name"
        axle, source = static_axle_load(result, int(m.group(1)), int(m.group(2)))
        if axle is None:
            return math.nan, source
        value = c.limit_value(static_axle_load=axle, static_wheel_load=axle / 2)
        return value, f"{c.limit.factor:g} ({c.limit.constant:g} N + {c.limit.coefficient:.4g} x {c.limit.reference} " \
                      f"{axle if c.limit.reference == 'static_axle_load' else axle / 2:.5g} N, {source})"
    if kind == "speed_bands":
        value = c.limit_value(speed_kmh=speed)
        return value, f"speed band of {speed:g} km/h"
    if kind == "grades":
        lim = c.limit
        assert isinstance(lim, GradedLimit)
        return c.limit_value(), "grades " + ", ".join(f"{lab} <= {v:g}" for lab, v in zip(lim.labels, lim.values))
    return c.limit_value(), "fixed"


def default_limits() -> list[LimitSet]:
    """Every limit file of the model library (models/limits/, or ``$TB_EXUDYN_MODELS/limits``), read and
    validated: the first file that is not valid raises its ScenarioError (file, key, what is allowed),
    and so does a library without any limit file (no verdict could be given). Callers that give verdicts
    after a run (the command line, :func:`tb_exudyn.methods.sweep.run_sweep`) call it before the run."""
    files = model_files("limits")
    if not files:
        folder = models_dir() / "limits"
        env = os.environ.get("TB_EXUDYN_MODELS")
        allowed = "a limits/ folder with at least one limit file (*.toml)"
        if env:
            raise SettingError("environment", "TB_EXUDYN_MODELS", env, allowed, "no limit file")
        raise ScenarioError(str(folder), "<file>", str(folder), allowed, "no limit file")
    return unique_names([load_limits(path) for _, path in sorted(files.items())])


def unique_names(sets: list[LimitSet]) -> list[LimitSet]:
    """The sets, refused when two share a name (their verdicts, named <name>/<id>, would overwrite each other)."""
    seen: dict[str, LimitSet] = {}
    for ls in sets:
        if ls.name in seen:
            other = source_file(seen[ls.name]) or "a LimitSet given in Python"
            allowed = f"a name no other limit file uses (also in {other})"
            if source_file(ls) is None:
                raise SettingError("checks", "limits", ls.name, allowed, "duplicate limits name")
            raise ScenarioError(source_file(ls), "name", ls.name, allowed, "duplicate limits name")
        seen[ls.name] = ls
    return sets


def limit_sets(limits: Any) -> list[LimitSet]:
    if limits is None:
        return default_limits()
    items = limits if isinstance(limits, (list, tuple)) else [limits]
    out = []
    for item in items:
        if isinstance(item, LimitSet):
            if any(c.structural for c in item.criteria):
                raise SettingError("checks", "limits", item.name, "limit sets of criteria on a result's channels (a "
                                   "statistic each: models/limits)", "structural criteria (the EN 1991-2 check's)")
            out.append(item)
        elif isinstance(item, str) or hasattr(item, "__fspath__"):
            out.append(load_limits(item))
        else:
            raise SettingError("checks", "limits", type(item).__name__,
                               "None (every shipped file), a limit file name or path, a LimitSet, or a list of them")
    return unique_names(out)


__all__ = ["default_limits", "limit_at", "limit_sets", "static_axle_load", "unique_names"]
