"""What the methods share: the mean task, the checkpoint identity, the provenance of a result."""

from __future__ import annotations

import hashlib
import json
from dataclasses import dataclass
from functools import lru_cache
from importlib import metadata
from pathlib import Path
from typing import Any, Mapping, Sequence

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


@lru_cache(maxsize=1)
def source_digest() -> str:
    """A hash of tb_exudyn's own source files: a checkpoint made by other code (a development
    version between releases) is not resumed, though its version number is the same."""
    root = Path(__file__).resolve().parents[1]
    h = hashlib.sha256()
    for path in sorted(root.rglob("*.py")):
        h.update(path.relative_to(root).as_posix().encode("utf-8") + b"\0" + path.read_bytes() + b"\0")
    return h.hexdigest()[:16]


def spectra_identity(names: Sequence[str]) -> dict[str, str]:
    """The spectra a scenario names, each as its full value (``repr`` of the frozen dataclass: every
    parameter, a table's points), so that a changed spectrum file or formula is another computation."""
    from ..track import get_spectrum

    return {name: repr(get_spectrum(name)) for name in names}


def fingerprint_identity(scenario_toml: str, *, method: str, engine: str, engine_options: Mapping[str, Any],
                         method_options: Mapping[str, Any], spectra: Sequence[str] = ()) -> dict[str, Any]:
    """Everything that changes a number of a computation (the checkpoint's fingerprint): the scenario
    (resolved TOML: vehicles, bridge, track and analysis inline), the spectra it names (their values),
    the method and its options, the engine and its options, the package versions and tb_exudyn's
    source (:func:`source_digest`). Not in it: how the work runs (workers, executor, slices, the
    output folder), which changes no number."""
    return {"scenario": scenario_toml, "method": method, "engine": engine, "engine_options": dict(engine_options),
            "method_options": dict(method_options), "spectra": spectra_identity(spectra),
            "versions": {**package_versions(), "tb_exudyn_source": source_digest()}}


def mean_of(mean: Mapping[str, np.ndarray]) -> np.ndarray:
    """The mean channels (n_ch, n_t) of a mean task's result."""
    return mean["mean"]


def merge_provenance(mean: Mapping[str, np.ndarray], engine: Mapping[str, Any], extra: Mapping[str, Any]
                     ) -> dict[str, Any]:
    """A result's provenance: the mean run's, the engine's description, the method's ``extra``."""
    return {
        **json.loads(str(mean["provenance"])),
        **engine,
        "mean_engine": "exudyn",
        "mean_seconds": float(mean["seconds"]),
        **extra,
    }


__all__ = ["MeanTask", "fingerprint_identity", "mean_of", "merge_provenance", "package_versions", "source_digest",
           "spectra_identity"]
