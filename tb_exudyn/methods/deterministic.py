"""The deterministic run: gravity on, the train starting in static equilibrium on the approach.

Always an Exudyn run of the full model (:func:`~tb_exudyn.engines.exudyn_runs.run_model`): without an
excitation it is the Exudyn engine's mean (PEM's and Monte Carlo's mean task on that engine; the
batched engine's mean is its own linear model's by default, :mod:`tb_exudyn.engines.batched.mean`,
``mean_engine`` in a result's provenance says which); with a sampled profile it is one sample of the
Exudyn Monte Carlo. The vehicles start from their exact static equilibrium on the rigid approach
track (nothing bounces at t = 0), the bridge at rest and unloaded. As a method of its own
(:class:`DeterministicMethod`, ``simulate(scenario, "deterministic")``) it runs through the driver in
this process, without a checkpoint.
"""

from __future__ import annotations

import time as _time
from collections import defaultdict
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ..builder import TrainBridgeModel, build_model
from ..engines.exudyn_runs import SolverSettings, run_model
from ..errors import CapabilityError, SettingError
from ..execution import Execution, RunFiles, Task
from ..execution.resources import check_run_length
from ..results.time_history import TimeHistory
from ..scenario import Scenario
from ..scenario.io import as_scenario
from ..system.excitation import Excitation
from .driver import RunPlan


def run_deterministic(
    scenario: Scenario | str | Path,
    excitation: Excitation | None = None,
    *,
    settings: SolverSettings | None = None,
    model: TrainBridgeModel | None = None,
) -> TimeHistory:
    """The train crossing the bridge under gravity, starting in static equilibrium.

    Parameters
    ----------
    scenario : the scenario, or a scenario's name or TOML file (loaded)
    excitation : None (smooth track: the mean response) or a deterministic profile / harmonic
    settings : Exudyn's solver settings (defaults measured to be converged)
    model : a model already built from this scenario, to re-run without rebuilding

    Returns
    -------
    TimeHistory with the channels of ``scenario.analysis.channels`` at ``analysis.output_step``.

    Raises
    ------
    SimulationIncomplete if the integration does not reach its end time.
    """
    start = _time.perf_counter()
    scenario = as_scenario(scenario, "run_deterministic")
    if model is None:
        model = build_model(scenario)
    elif model.scenario != scenario:
        raise SettingError("run_deterministic", "model", "a model of another scenario",
                           "a model built from this scenario (build_model(scenario))")
    build = _time.perf_counter() - start
    th, _ = run_model(model, excitation, gravity=True, initial="static", settings=settings)
    th.provenance["build_time_s"] = build
    th.provenance["total_time_s"] = _time.perf_counter() - start
    return th


@dataclass(frozen=True)
class DeterministicMethod:
    """The deterministic run as a :class:`~tb_exudyn.methods.driver.Method` (and its own worker: one
    task, in this process): ``engine`` must be "exudyn", ``options`` its :class:`SolverSettings`."""

    scenario: Scenario
    engine: str = "exudyn"
    options: SolverSettings | None = None
    excitation: Excitation | None = None

    def plan(self, execution: Execution) -> RunPlan:
        if self.engine != "exudyn":
            raise CapabilityError("simulate", "engine", self.engine,
                                  "'exudyn' (the deterministic run is an Exudyn run)")
        check_run_length(self.scenario)
        return RunPlan(files=RunFiles("det"), tasks=[Task("det", None)], identity=None, state={}, worker=self,
                       desc="deterministic run", in_process=True)

    def setup(self) -> None:
        return None

    def work(self, built: None, task: Task) -> TimeHistory:
        return run_deterministic(self.scenario, self.excitation, settings=self.options)

    def reduce(self, state: dict[str, TimeHistory], i: int, task: Task, result: TimeHistory) -> None:
        state["result"] = result

    def finish(self, state: dict[str, TimeHistory], stats: dict[str, Any]) -> TimeHistory:
        return state["result"]

    def save(self, result: TimeHistory, out: Path) -> None:
        result.save(out / "det")


def _group(name: str) -> str:
    """'bridge.span1.mid.acc_z' -> 'bridge.span1.mid'; 'car1.axle1.left.force_z' -> 'car1.axle1'."""
    parts = name.split(".")
    if parts[0] == "bridge":
        return ".".join(parts[:3])
    return ".".join(parts[:2])


def summarize(th: TimeHistory) -> str:
    """Peaks per channel group: for every channel its largest magnitude (signed), time and unit."""
    groups: dict[str, list[str]] = defaultdict(list)
    for name in th.channels:
        groups[_group(name)].append(name)
    title = th.scenario.name if th.scenario is not None else "time history"
    lines = [
        f"{title}: {len(th.channels)} channels, t = {th.time[0]:.3g} ... {th.time[-1]:.4g} s "
        f"({th.time.size} samples)"
    ]
    steps, run = th.provenance.get("steps"), th.provenance.get("run_time_s")
    if steps and run:
        lines.append(f"run: {steps} steps in {run:.3g} s ({1e6 * run / steps:.0f} us/step)")
    width = max((len(n) for n in th.channels), default=10)
    for group, names in groups.items():
        lines.append(f"{group}:")
        for name in names:
            value, t = th.peak(name)
            lines.append(f"  {name:<{width}}  peak {value: .4e} {th.unit(name):<8} at t = {t:.3f} s")
    return "\n".join(lines)


__all__ = ["DeterministicMethod", "run_deterministic", "summarize"]
