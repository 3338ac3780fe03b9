"""The uncertainty study as a :class:`~tb_exudyn.methods.driver.Method`: non-intrusive polynomial
chaos over PEM runs.

The nodes of the expansion (:func:`tb_exudyn.methods.uq.pce.nodes`) are the tasks, as a sweep's
speeds are: each node is the whole PEM of the base scenario with the node's key values set through
the ``--set`` mechanism (:func:`tb_exudyn.scenario.uncertain.check_value`: every node's scenario is
built and checked by the schema in the plan, before any work), run in one worker in one column slice
on the batched engine (:class:`UqWorker`); its summary (:func:`.summary.node_summary`: sigma(t), the
mean and the code checks) is checkpointed, so that an interrupted study resumes node by node, and
the nodes are reduced in task order, so that the result does not depend on the number of workers.
The expansion of every quantity over the nodes (:func:`.summary.expand`) makes the
:class:`~tb_exudyn.results.uq.UqResult`.
"""

from __future__ import annotations

import os
import time as _time
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Mapping, Sequence

import numpy as np

from ...engines import DEFAULT_ENGINE, check_engine
from ...errors import ScenarioError, SettingError
from ...execution import Execution, RunFiles, Task
from ...results.uq import UQ_FOLDER, UqResult
from ...scenario import Scenario, scenario_to_toml
from ...scenario.io import as_scenario
from ...scenario.uncertain import UncertainKey, apply_values, check_uncertain
from .. import pem, warm_up
from ..common import fingerprint_identity
from ..sweep import check_values, key_patterns
from ..driver import RunPlan, drive
from . import pce
from .summary import expand, keys_json, loo_warnings, node_summary

#: keys that would change the run's output times (every node must share them): refused as uncertain
FIXED_KEYS = ("speed_kmh", "track.lead_in", "track.run_out", "bridge.spans")
#: key prefixes refused likewise (the analysis; the train's layout, but for its vehicles' parameters)
FIXED_PREFIXES = ("analysis.",)


def fixed_key(key: str) -> bool:
    """Whether ``key`` would change the run's output times or channels (:data:`FIXED_KEYS`)."""
    return (any(key == f or key.startswith(f + ".") for f in FIXED_KEYS) or key.startswith(FIXED_PREFIXES)
            or (key.startswith("train.") and not key.startswith("train.vehicles.")))


#: the column slices of a node's PEM (one: a node is one worker's task, as a sweep's speed)
NODE_SLICES = (1.0,)


@dataclass(frozen=True)
class NodeTask:
    """The PEM of one node (run in a worker); its repr (the scenario, engine, options) is its digest."""

    scenario: Scenario
    engine: str
    options: Any


@dataclass(frozen=True)
class UqWorker:
    """The study's worker (:class:`~tb_exudyn.methods.driver.Worker`): each task a node's whole PEM."""

    def setup(self) -> None:
        return None

    def work(self, _: Any, task: Task) -> dict[str, np.ndarray]:
        nt: NodeTask = task.data
        start, clock = _time.time(), _time.perf_counter()
        execution = Execution(workers=1, progress=False, slices=NODE_SLICES, where="run_uq")
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            result = pem.run(nt.scenario, nt.engine, execution, options=nt.options, keep_psd=False)
        pem_end = _time.perf_counter()
        summary = node_summary(result, check_values)
        # when and where the node ran (the timeline; not a number of the result): the wall clock at its
        # start [s since the epoch], the worker's process id, its PEM and its summary (the checks) [s]
        summary["timeline"] = np.array([start, os.getpid(), pem_end - clock, _time.perf_counter() - pem_end])
        summary["warnings"] = np.array(list(dict.fromkeys(str(w.message) for w in caught  # not the pool's ResourceWarnings
                                                          if not issubclass(w.category, ResourceWarning))),
                                        dtype=str).reshape(-1)
        return summary


def check_keys(keys: Sequence[UncertainKey], where: str) -> None:
    """Refuse keys that would change the run's output times (:data:`FIXED_KEYS`) and repeated keys."""
    seen = set()
    for uk in keys:
        if fixed_key(uk.key):
            raise SettingError(where, "keys", uk.key, "a key that leaves the run's output times alone (not the speed, "
                               "the track's lengths, the analysis, the spans or the train's layout)", "changes the run")
        if uk.key in seen:
            raise SettingError(where, "keys", uk.key, "each key once", "repeated key")
        seen.add(uk.key)


def node_scenarios(scenario: Scenario, keys: Sequence[UncertainKey], values: np.ndarray) -> list[Scenario]:
    """Each node's scenario: the keys' values (key x node) set through the --set mechanism (the ballast's
    density with the bridge's mass following it: :func:`~tb_exudyn.scenario.uncertain.apply_values`),
    checked by the schema (a value it refuses: ScenarioError naming ``uncertain.<key>`` and the node)."""
    out = []
    for n in range(values.shape[1]):
        settings = [(uk.key, float(values[j, n])) for j, uk in enumerate(keys)]
        try:
            out.append(apply_values(scenario, settings))
        except ScenarioError as exc:
            raise ScenarioError(scenario.where, f"uncertain.{exc.key}", exc.value, exc.allowed,
                                f"node {n} of the design reaches a value the key does not allow ({exc.reason})") from None
    return out


def check_window(window: Any) -> None:
    """``window`` None or (t0, t1), finite, 0 <= t0 < t1; SettingError naming run_uq's ``window``."""
    if window is None:
        return
    ok = (isinstance(window, (tuple, list)) and len(window) == 2
          and all(isinstance(t, (int, float)) and not isinstance(t, bool) and np.isfinite(t) for t in window)
          and 0 <= window[0] < window[1])
    if not ok:
        raise SettingError("run_uq", "window", window, "(t0, t1) [s], 0 <= t0 < t1")


@dataclass
class UqState:
    """The plan's design (germs, germ nodes, weights, key values) and each node's summary."""

    germs: list[Any]
    x: np.ndarray
    weights: np.ndarray | None
    values: np.ndarray
    summaries: list[dict[str, np.ndarray]]
    t0: float
    wall0: float = 0.0


@dataclass(frozen=True)
class UqMethod:
    """The uncertainty study as a driver method; see :func:`run_uq` (the same arguments)."""

    scenario: Scenario
    keys: tuple[UncertainKey, ...]
    order: int = 3
    design_name: str = "tensor"
    n_nodes: int | None = None
    engine: str = DEFAULT_ENGINE
    options: Any = None
    channels: Sequence[str] | None = None
    window: tuple[float, float] | None = None

    def design(self) -> tuple[Any, ...]:
        """The checks and the design: (order, node count, engine class, base scenario, germs, germ nodes,
        weights, key values (key x node), every node's scenario). Errors name run_uq's arguments or the
        uncertain key; nothing is run."""
        order, n_nodes = pce.check_design(self.order, self.design_name, self.n_nodes, "run_uq")
        check_window(self.window)
        check_keys(self.keys, "run_uq")
        cls = check_engine(self.engine, self.scenario, self.options)
        patterns = tuple(q[1] for q in key_patterns(self.scenario, self.channels))
        base = self.scenario.replace(analysis=self.scenario.analysis.replace(channels=patterns))
        germs = [pce.key_germ(uk) for uk in self.keys]
        x, w = pce.nodes(germs, order, self.design_name, n_nodes)
        values = np.stack([pce.key_value(uk, x[j]) for j, uk in enumerate(self.keys)])
        return order, n_nodes, cls, base, germs, x, w, values, node_scenarios(base, self.keys, values)

    def plan_checks(self) -> None:
        """What :meth:`plan` checks, without a run (the command line, before it creates --out)."""
        self.design()

    def plan(self, execution: Execution) -> RunPlan:
        t0, wall0 = _time.perf_counter(), _time.time()
        order, n_nodes, cls, base, germs, x, w, values, scenarios = self.design()
        warm_up.start(cls, self.options, execution.announce)  # a cold cache compiled once, beside the set-up
        tasks = [Task(f"node-{n:05d}", NodeTask(sc, self.engine, self.options)) for n, sc in enumerate(scenarios)]
        identity = fingerprint_identity(
            scenario_to_toml(base), method="uq", engine=self.engine, engine_options=cls.describe_options(self.options),
            method_options={"keys": keys_json(self.keys), "order": order, "design": self.design_name, "nodes": n_nodes,
                            "window": None if self.window is None else list(self.window)},
            spectra=base.track.irregularities)
        state = UqState(germs, x, w, values, [{} for _ in tasks], t0, wall0)
        return RunPlan(files=RunFiles(UQ_FOLDER, "checkpoint-uq"), tasks=tasks, identity=identity, state=state,
                       worker=UqWorker(), desc=f"uq: {len(tasks)} PEM nodes ({self.engine})")

    def reduce(self, state: UqState, i: int, task: Task, result: dict[str, np.ndarray]) -> None:
        state.summaries[i] = result

    def finish(self, state: UqState, stats: dict[str, Any]) -> UqResult:
        first = state.summaries[0]
        for n, s in enumerate(state.summaries):
            if s["std"].shape != first["std"].shape or not np.array_equal(s["time"], first["time"]):
                raise ScenarioError(self.scenario.where, "uncertain", [k.key for k in self.keys],
                                    "keys that leave the run's output times and channels alone",
                                    f"node {n} has other output times or channels")
        arrays = expand(state.germs, self.order, state.x, state.weights, state.summaries, self.window)
        names, crit = arrays.pop("quantities"), arrays.pop("criteria")
        w = state.weights if state.weights is not None else np.full(state.x.shape[1], np.nan)
        arrays.update(time=first["time"], node_values=state.values.T.copy(), node_weights=np.asarray(w, dtype=float))
        notes = loo_warnings(names, arrays["loo"], arrays["quantity_mean"], arrays["quantity_std"])
        node_notes = list(dict.fromkeys(str(m) for s in state.summaries for m in s["warnings"]))
        result = UqResult(
            scenario=self.scenario, keys=tuple(keys_json(self.keys)), channels=tuple(map(str, first["channels"])),
            units=tuple(map(str, first["units"])), quantities=tuple(names), criteria=tuple(crit), data=arrays,
            provenance={"seconds": _time.perf_counter() - state.t0, "engine": self.engine, "order": self.order,
                        "design": self.design_name, "n_nodes": int(state.x.shape[1]), "warnings": notes + node_notes,
                        "node_seconds": [float(s["seconds"]) for s in state.summaries],
                        "node_timeline": node_timeline(state), **stats})
        for message in notes:
            warnings.warn(message, UserWarning, stacklevel=2)
        return result

    def save(self, result: UqResult, out: Path) -> None:
        result.save(out / UQ_FOLDER)


def node_timeline(state: UqState) -> dict[str, list[float]]:
    """Per node: its start after the study's (``start`` [s]; a resumed node's is that of the run that
    computed it), its worker (``worker``: 0, 1, ... in the order the workers first appear), its PEM
    (``pem``: set-up, model, mean, columns, the grid error) and its summary (``summary``: the checks) [s].
    Empty lists for nodes of a checkpoint that predates the timeline."""
    rows = [s["timeline"] for s in state.summaries if "timeline" in s]
    if len(rows) != len(state.summaries):
        return {"start": [], "worker": [], "pem": [], "summary": []}
    pids = list(dict.fromkeys(int(r[1]) for r in rows))
    return {"start": [round(float(r[0]) - state.wall0, 3) for r in rows], "worker": [pids.index(int(r[1])) for r in rows],
            "pem": [round(float(r[2]), 4) for r in rows], "summary": [round(float(r[3]), 4) for r in rows]}


def run_uq(scenario: Scenario | str | Path, keys: Sequence[UncertainKey] | Mapping[str, Any], *, order: int = 3, design: str = "tensor",
           nodes: int | None = None, engine: str = DEFAULT_ENGINE, options: Any = None,
           channels: Sequence[str] | None = None, window: tuple[float, float] | None = None, workers: int | None = None, executor: Any = None,
           out: str | Path | None = None, resume: bool = False, progress: bool = True, overwrite: bool = False,
           keep_checkpoint: bool = False) -> UqResult:
    """Polynomial chaos over PEM runs of ``scenario`` (a Scenario, or a scenario's name or file) under the
    uncertain ``keys`` (module docstring).

    keys : :class:`~tb_exudyn.scenario.uncertain.UncertainKey` (:func:`~tb_exudyn.scenario.uncertain.load_study`),
        or an ``[uncertain]`` table as a dict (``{"bridge.girder.E": {"distribution": "lognormal", "cov": 0.05}}``)
    order : the expansion's total degree; design : "tensor" or "sparse" Gauss quadrature (order + 1
        points per key), or "sobol" (``nodes`` points, default twice the basis, least squares)
    channels : channel patterns (default the sweep's key quantities)
    window : (t0, t1) [s]: the times over which a channel's max sigma is taken (default the whole run)
    workers, executor, out, resume, progress, overwrite, keep_checkpoint : as :func:`tb_exudyn.run_sweep`;
        the nodes are the tasks; ``out/uq`` the result, ``out/checkpoint-uq`` the nodes' checkpoint
    """
    scenario = as_scenario(scenario, "run_uq")
    if isinstance(keys, Mapping):  # an [uncertain] table as a dict
        keys = check_uncertain(scenario, dict(keys), "run_uq")
    execution = Execution(workers=workers, executor=executor, out=out, resume=resume, progress=progress,
                          where="run_uq", overwrite=overwrite, keep_checkpoint=keep_checkpoint)
    return drive(UqMethod(scenario, tuple(keys), order, design, nodes, engine, options, channels, window), execution)


__all__ = ["FIXED_KEYS", "FIXED_PREFIXES", "fixed_key", "NODE_SLICES", "NodeTask", "UqMethod", "node_timeline", "UqWorker", "check_keys", "node_scenarios", "run_uq"]
