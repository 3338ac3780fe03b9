"""What the methods share: the mean task, the checkpoint identity, the provenance of a result."""

from __future__ import annotations

import json
from dataclasses import dataclass
from importlib import metadata
from typing import Any, Mapping

import numpy as np

from .._version import __version__


@dataclass(frozen=True)
class MeanTask:
    """The mean: Exudyn's deterministic run (gravity, static start, no irregularity) on the worker's
    built model (:meth:`tb_exudyn.engines.base.Engine.mean`)."""


def package_versions() -> dict[str, str]:
    """The versions of the packages whose code computes a number (without importing them)."""
    out = {"tb_exudyn": __version__}
    for name in ("exudyn", "numpy", "scipy"):
        try:
            out[name] = metadata.version(name)
        except metadata.PackageNotFoundError:  # pragma: no cover - a broken installation
            out[name] = "unknown"
    return out


def fingerprint_identity(scenario_toml: str, *, method: str, engine: str, engine_options: Mapping[str, Any],
                         method_options: Mapping[str, Any]) -> dict[str, Any]:
    """Everything that changes a number of a computation: the scenario (as TOML), the method and its
    options, the engine and its options, the package versions (the checkpoint's fingerprint)."""
    return {"scenario": scenario_toml, "method": method, "engine": engine, "engine_options": dict(engine_options),
            "method_options": dict(method_options), "versions": package_versions()}


def mean_of(mean: Mapping[str, np.ndarray]) -> np.ndarray:
    """The mean channels (n_ch, n_t) of a mean task's result."""
    return mean["mean"]


def merge_provenance(mean: Mapping[str, np.ndarray], engine: Mapping[str, Any], extra: Mapping[str, Any]
                     ) -> dict[str, Any]:
    """A result's provenance: the mean run's, the engine's description, the method's ``extra``."""
    own = json.loads(str(mean["provenance"]))
    return {
        **own,
        **engine,
        "mean_engine": own.get("mean_engine", "exudyn"),
        "mean_seconds": float(mean["seconds"]),
        **extra,
    }


__all__ = ["MeanTask", "fingerprint_identity", "mean_of", "merge_provenance", "package_versions"]
