"""What the methods share: the analysis set-up (modes, grid, damping guard), the mean task, the
checkpoint identity, the provenance of a result."""

from __future__ import annotations

import dataclasses
import hashlib
import json
import warnings
from dataclasses import dataclass
from functools import lru_cache
from importlib import metadata
from pathlib import Path
from typing import Any, Mapping, Sequence

import numpy as np

from .._version import __version__
from ..builder import build_model
from ..builder.system_modes import damping_guard, system_modes
from ..errors import SettingError
from ..scenario import Scenario
from ..scenario.model import Analysis
from ..system.damping_guard import DampingWarning, merged_messages
from ..system.modes import ModeTable
from ..track import get_spectrum
from .adaptive_grid import points_needed, scenario_grid_problem
from .grid import FrequencyGrid, scenario_grid


class LightlyDampedModeWarning(UserWarning):
    """A mode in the analysed band decays slower than the run lasts (the damping guard)."""


@dataclass(frozen=True)
class AnalysisSetup:
    """What a random analysis knows before any run: the system's modes, the frequency grid, the
    damping guard's warnings (with the channel patterns each affects).

    Attributes
    ----------
    modes : the modes of the vehicles on rigid track and of the bridge alone (t = 0)
    grid : the PEM grid (adaptive grids are placed for the modes at t = 0 and with the train
        standing centred on the bridge)
    damping : the damping guard's warnings (:func:`tb_exudyn.builder.system_modes.damping_guard`)
    model : the built model they come from (in the parent process only: its channels, outputs and
        derived channels are the workers')
    scenario : the scenario analysed: the one given or, with ``least_count``, its adaptive grid's
        ``analysis.n_freq`` raised to what the grid's rules need
    """

    modes: ModeTable
    grid: FrequencyGrid
    damping: tuple[DampingWarning, ...]
    model: Any = None
    scenario: Any = None

    def messages(self) -> list[str]:
        """The damping guard's warnings, one line per set of equal modes."""
        return merged_messages(self.damping)

    def provenance(self) -> dict[str, Any]:
        """The damping warnings and the modal table (vehicle and bridge modes in the analysed band,
        ``damped_modes``: what the report lists) as plain data."""
        band = (self.grid.band[0], self.grid.band[1])
        table = self.modes.of_kind("vehicle", "bridge").in_band(*band)
        warned = {(round(w.frequency, 9), w.label) for w in self.damping}
        rows = [{"frequency": float(f), "damping_ratio": float(z), "label": str(lab),
                 "context": "vehicles on rigid track, bridge alone (t = 0)",
                 "warning": "lightly damped: decays slower than the run lasts"
                 if (round(float(f), 9), str(lab)) in warned else ""}
                for f, z, lab in zip(table.frequency, table.damping_ratio, table.label)]
        return {"damping_warnings": [dataclasses.asdict(w) for w in self.damping], "damped_modes": rows}


def analysis_setup(scenario: Scenario, *, warn: bool = True, least_count: bool = False) -> AnalysisSetup:
    """The modes, the grid and the damping guard of ``scenario`` (one model build and two modal
    analyses, about a second for the reference study); with ``warn`` the guard's warnings are issued
    as :class:`LightlyDampedModeWarning`. With ``least_count`` an adaptive grid whose
    ``analysis.n_freq`` is below what its rules need gets that count instead of the error (a speed
    sweep: the band, the run and the train's spread change with the speed); ``setup.scenario`` is
    the scenario analysed."""
    model = build_model(scenario, warn=False)
    table = system_modes(scenario, model=model)
    modes = None
    if scenario.analysis.freq_spacing == "adaptive":
        centred = system_modes(scenario, (scenario.bridge.length + scenario.train.length) / 2, model=model)
        modes = [(float(f), float(z)) for tab in (table, centred)
                 for f, z, kind in zip(tab.frequency, tab.damping_ratio, tab.kind) if kind in ("vehicle", "bridge")]
        if least_count:
            needed = points_needed(scenario_grid_problem(scenario, modes))
            if scenario.analysis.n_freq < needed:
                scenario = scenario.replace(analysis=scenario.analysis.replace(n_freq=needed))
    grid = scenario_grid(scenario, modes)
    setup = AnalysisSetup(modes=table, grid=grid, damping=tuple(damping_guard(scenario, table=table, model=model)),
                          model=model, scenario=scenario)
    if warn:
        for message in setup.messages():
            warnings.warn(message, LightlyDampedModeWarning, stacklevel=3)
    return setup


@dataclass(frozen=True)
class MeanTask:
    """The mean task a method asks for (PEM always; Monte Carlo on a linear engine), run by the driver's
    worker as the built engine's :meth:`~tb_exudyn.engines.base.Engine.mean`: the deterministic run
    (gravity, static start, no irregularity) of the engine, that is Exudyn's run on the Exudyn engine,
    on the dense engine by default and with ``BatchedOptions(mean="exudyn")``; the batched engine's
    linear model under the dead loads by default (:mod:`tb_exudyn.engines.batched.mean`; Exudyn's run
    where that does not apply) and the dense engine's with ``DenseOptions(mean="linear")``. The
    provenance's ``mean_engine`` says which."""


def whole_number(value: Any, where: str, key: str, low: int, high: float | None = None) -> int:
    """``value`` as an int in [``low``, ``high``], else a SettingError naming ``key``."""
    if (isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < low
            or (high is not None and value > high)):
        raise SettingError(where, key, value, f"a whole number >= {low}" + (f" and <= {high:.0f}" if high else ""))
    return int(value)


def analysis_high(name: str) -> float | None:
    """The upper bound the scenario schema allows for ``analysis.<name>`` (the same bound for the
    function argument that overrides it: ``n_samples``, ``seed``, a sweep's ``n_freq``; one home,
    the schema)."""
    check = next(f.metadata.get("check") for f in dataclasses.fields(Analysis) if f.name == name)
    return getattr(check, "high", None)


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
    own = json.loads(str(mean["provenance"]))
    return {
        **own,
        **engine,
        "mean_engine": own.get("mean_engine", "exudyn"),
        "mean_seconds": float(mean["seconds"]),
        **extra,
    }


__all__ = ["AnalysisSetup", "LightlyDampedModeWarning", "MeanTask", "analysis_high", "analysis_setup",
           "fingerprint_identity", "mean_of", "merge_provenance", "package_versions", "source_digest", "spectra_identity",
           "whole_number"]
