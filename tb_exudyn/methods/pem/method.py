"""PEM as a :class:`~tb_exudyn.methods.driver.Method`: its plan (checks, set-up, fingerprint, tasks,
sizing), its worker (the engine, the memory check), its work (a task's columns into a
:class:`~.columns.PsdReducer`), its reduce (into :class:`PemState`) and its finish (the
RandomResponse)."""

from __future__ import annotations

import json
import time as _time
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from ...engines import check_engine, make_engine
from ...engines.exudyn_runs import linear_model
from ...engines.linear_model import LinearModel
from ...execution import Execution, RunFiles, Task
from ...execution.resources import check_memory, check_run_length, memory_limit, scenario_where
from ...results.random_response import RandomResponse
from ...scenario import Scenario, scenario_to_toml
from ...system.derived import derived_provenance
from ..common import AnalysisSetup, MeanTask, analysis_setup, fingerprint_identity, merge_provenance
from ..driver import RunPlan, drive
from .. import warm_up
from ...errors import SettingError
from ..grid import (band_mask, check_grid_against_spectra, estimate_cells, local_grids, local_node_factors, locally_refined_variance,
                    midpoint_grid, refined_variance)
from ..adaptive_grid import scenario_grid_problem
from ..grid_error import DEFAULT_GRID_ESTIMATE, GRID_ESTIMATES, GridError, grid_error_from_sigma, local_method
from ..reduction import (REDUCTION_FORMAT, ReductionPlan, engine_plan, finish_pem, finish_pem_task, mean_rows,
                         model_plan, ratio_coefficients)
from .channels import GridErrorWarning, check_psd_channels, grid_error_messages, prepare_sweep, psd_rows, psd_z_rows
from .columns import ColumnTask, PemTask, PsdReducer, column_frequencies, column_slices, harmonic_columns, pem_tasks
from .columns import slice_weights
from .sizing import PSD_STORAGE, PemSizing, pem_memory


@dataclass
class PemState:
    """What PEM's reduce accumulates (in this process) and its finish reads.

    The set-up's part (``setup`` ... ``psd_names``) is known before the run; the mean task's result
    gives ``mean``, ``rows``, ``coef`` and the shapes of ``var`` (sigma^2 per type, (n_types, n_ch,
    n_t)), ``sums`` (the Rice rate's, the ratios' and Sperling's sums) and ``psd`` (the kept maps);
    every column task adds to them, the grid error's midpoint tasks to ``var_mid`` and, for the local
    estimate (``estimate`` "local", ``cells``: chosen of all), the grid tasks' node sums to ``var_nodes``."""

    setup: AnalysisSetup
    plan: ReductionPlan
    spectra: dict[str, Any]
    grid_error: bool
    rows_kept: list[int]
    ptasks: int
    t0: float
    scenario: Scenario  # the analysed one (with ``least_count``, its n_freq raised)
    mean: dict[str, np.ndarray] | None = None
    rows: Any = None
    coef: Any = None
    var: np.ndarray | None = None
    var_mid: np.ndarray | None = None
    var_nodes: np.ndarray | None = None
    estimate: str = DEFAULT_GRID_ESTIMATE
    cells: tuple[int, int] = (0, 0)
    sums: dict[str, np.ndarray] = field(default_factory=dict)
    psd: np.ndarray | None = None
    describe: dict[str, Any] | None = None


@dataclass(frozen=True)
class PemMethod:
    """The PEM sweep of ``scenario`` on ``engine`` (see :func:`tb_exudyn.run_pem`); ``least_count``:
    an adaptive grid gets at least the count its rules need (:func:`..common.analysis_setup`; the
    result's scenario then has that ``analysis.n_freq``)."""

    scenario: Scenario
    engine: str
    options: Any = None
    keep_psd: bool = True
    psd_channels: Any = "key"
    grid_error: bool | str | None = None  # or the estimate's name (GRID_ESTIMATES)
    least_count: bool = False

    # ------------------------------------------------------------------ in this process, before the run
    def plan(self, execution: Execution) -> RunPlan:
        t0 = _time.perf_counter()
        scenario = self.scenario
        check_run_length(scenario)
        cls = check_engine(self.engine, scenario, self.options)
        warm_up.start(cls, self.options, execution.announce)  # a first run's compile, beside the set-up below
        spectra = prepare_sweep(scenario)
        setup = analysis_setup(scenario, least_count=self.least_count)
        scenario, grid = setup.scenario, setup.grid
        check_grid_against_spectra(grid, scenario, spectra)
        estimate, grid_error = _estimate(self.grid_error, cls, execution.where)
        grid_error = grid_error and grid.rule == "trapezoid" and grid.f.size > 1
        mid_grids, cells, nodes = [], (0, 0), {}
        if grid_error and estimate == "local":
            table = setup.modes.of_kind("vehicle", "bridge")  # the modes at t = 0
            problem = scenario_grid_problem(scenario, list(zip(table.frequency, table.damping_ratio)))
            chosen = estimate_cells(grid, problem)
            # the midpoints a sweep of their own; the nodes' sums T from the grid's own columns
            mid_grids, cells = [("pemm", local_grids(grid, chosen)[0])], (int(chosen.sum()), chosen.size)
            nodes = local_node_factors(grid, chosen)
        elif grid_error:
            mid_grids = [("pemm", midpoint_grid(grid))]
        psd_spec = tuple(self.psd_channels) if isinstance(self.psd_channels, (list, tuple)) else self.psd_channels
        check_psd_channels(None, psd_spec, execution.where)  # the form, before anything is built
        identity = fingerprint_identity(
            scenario_to_toml(scenario), method="pem", engine=self.engine,
            engine_options=cls.describe_options(self.options),
            method_options={"keep_psd": self.keep_psd, "psd_channels": psd_spec, "grid_error": grid_error,
                            **({"grid_estimate": estimate} if grid_error and estimate != "midpoints" else {}),
                            "grid": grid.f.tolist(), "reduction": REDUCTION_FORMAT},
            spectra=scenario.track.irregularities)
        plan = model_plan(setup.model)  # the workers' engines have the same outputs and derived channels
        rows_kept = psd_rows(plan.names, psd_spec) if self.keep_psd else []
        if self.keep_psd:
            check_psd_channels(plan.names, psd_spec, execution.where)
        z_kept = psd_z_rows(plan, rows_kept)
        psd_z = tuple(int(z) for z in z_kept) if self.keep_psd and z_kept is not None else None
        ptasks = pem_tasks(scenario, grid)
        tasks = self._tasks(cls, execution, ptasks, [(prefix, pem_tasks(scenario, g)) for prefix, g in mid_grids],
                            psd_z, nodes)
        sizing = PemSizing(
            n_freq=int(grid.f.size), n_types=len(spectra), keep_psd=self.keep_psd,
            workers=execution.worker_processes(len(tasks)),
            task_freqs=max((len({p.freq_index for p in t.data.columns}) for t in tasks[1:]), default=0),
            output_step=scenario.analysis.output_step, limit=execution.worker_limit(), where=scenario_where(scenario),
            psd_channels=len(rows_kept), psd_task_rows=None if psd_z is None else len(psd_z))
        state = PemState(setup=setup, plan=plan, spectra=spectra, grid_error=grid_error, rows_kept=rows_kept,
                         ptasks=len(ptasks), t0=t0, scenario=scenario, estimate=estimate, cells=cells)
        system = (None if cls.full_model else  # a linear engine's system, built once here for every worker
                  linear_model(setup.model, wheel_forces=False, mean=cls.linear_mean(self.options)))
        return RunPlan(files=RunFiles("pem", "checkpoint"), tasks=tasks, identity=identity, state=state,
                       worker=PemWorker(self.engine, scenario, self.options, sizing, system), desc=f"PEM ({self.engine})")

    def _tasks(self, cls: Any, execution: Execution, ptasks: Sequence[PemTask],
               mid_tasks: Sequence[tuple[str, Sequence[PemTask]]], psd_z: tuple[int, ...] | None,
               nodes: dict[int, float]) -> list[Task]:
        """The mean task first, then the columns: one task per column on an engine that runs them
        separately, else slices (the package docstring); the grid error's sweeps after them (``mid_tasks``:
        (key prefix, columns), "pemm" the midpoints). ``nodes``: the local estimate's node factors per
        frequency index (:func:`~..grid.local_node_factors`), summed by the grid's tasks."""
        keep_psd = self.keep_psd
        tasks = [Task("pem-mean", MeanTask())]
        if cls.single_columns:
            tasks += [Task(f"pem-{p.type_index}-{p.freq_index:05d}",
                           ColumnTask((p,), keep_psd, psd_z=psd_z,
                                      nodes=((p.freq_index, nodes[p.freq_index]),) if p.freq_index in nodes else ()))
                      for p in ptasks]
            tasks += [Task(f"{prefix}-{p.type_index}-{p.freq_index:05d}", ColumnTask((p,), False, True))
                      for prefix, sweep in mid_tasks for p in sweep]
            return tasks
        weights = (slice_weights(cls, self.options, execution.cores, len(ptasks)) if execution.slices is None
                   else execution.slices)
        tasks += column_slices(ptasks, weights, keep_psd, psd_z=psd_z, nodes=nodes)
        mid_weights = [1.0] * max(1, execution.cores) if execution.slices is None else execution.slices
        for prefix, sweep in mid_tasks:  # after the loads are level: equal slices
            if sweep:
                tasks += column_slices(sweep, mid_weights, False, prefix, True)
        return tasks

    # ------------------------------------------------------------------ in this process, task by task
    def reduce(self, state: PemState, i: int, task: Task, result: dict[str, np.ndarray]) -> None:
        if isinstance(task.data, MeanTask):
            _reduce_mean(state, task, result, self.keep_psd)
            return
        if "var_nodes_z" in result:
            _add_node_sums(state, result)
        result = {**result, **finish_pem_task(result, state.plan, state.coef,
                                              None if task.data.midpoints else state.rows_kept)}
        var_t = result["var_t"]
        assert state.var is not None
        if task.data.midpoints:  # the grid error's midpoint sweep: sigma^2 only
            if state.var_mid is None:
                state.var_mid = np.zeros_like(state.var)
            state.var_mid += var_t.transpose(1, 2, 0)
            return
        for key, total in state.sums.items():
            total += result[key]
        var, n_types = state.var, len(state.spectra)
        if var_t.shape != (var.shape[2], n_types, var.shape[1]):
            raise RuntimeError(f"task {task.key}: result shape {var_t.shape} does not fit the mean's {var.shape[1:]}")
        var += var_t.transpose(1, 2, 0)
        state.describe = json.loads(str(result["describe"]))
        if state.psd is not None:
            _add_psd(state.psd, result["freq_index"], result["psd"],
                     len({p.type_index for p in task.data.columns}) == n_types)

    # ------------------------------------------------------------------ after the run
    def finish(self, state: PemState, stats: dict[str, Any]) -> RandomResponse:
        scenario, setup, plan = state.scenario, state.setup, state.plan
        grid, model = setup.grid, setup.model
        extra = {
            "method": "pem",
            "derivatives": plan.derivative_sources(),
            "derived_channels": derived_provenance(model.derived_catalogue, model.derived),
            "linearization": scenario.analysis.linearization,
            "seconds": _time.perf_counter() - state.t0,
            "n_frequencies": int(grid.f.size),
            "n_frequencies_in_band": int(band_mask(grid, scenario).sum()),
            "quadrature": grid.rule,
            "columns": state.ptasks,
            "grid_spacing": scenario.analysis.freq_spacing,
            **setup.provenance(),
            **stats,
        }
        return _result(scenario, state, extra, self.engine, [plan.names[i] for i in state.rows_kept])

    def save(self, result: RandomResponse, out: Path) -> None:
        result.save(out / "pem")


@dataclass(frozen=True)
class PemWorker:
    """What a PEM worker gets (:class:`~tb_exudyn.methods.driver.Worker`): the engine to build, the
    sweep's sizing for the memory check and a linear engine's system (built once in the parent)."""

    engine: str
    scenario: Scenario
    options: Any
    sizing: PemSizing | None = None
    system: LinearModel | None = field(default=None, repr=False)  # determined by the fields above

    def setup(self) -> Any:
        """The engine (the Exudyn engine's model; a linear engine on the parent's ``system``), once per
        worker; the sweep's memory estimate checked against its limit (ResourceError) before any
        task allocates."""
        built = make_engine(self.engine, self.scenario, self.options, system=self.system)
        s = self.sizing
        if s is not None:
            check_memory(pem_memory(s, built), s.limit or memory_limit(None, s.where), s.where)
        return built

    def work(self, engine: Any, task: Task) -> dict[str, np.ndarray]:
        """A column task: its columns, its reducer, the integration."""
        data: ColumnTask = task.data
        columns = harmonic_columns(data.columns, engine.scenario)
        n_types = len(engine.scenario.track.irregularities)
        reducer = PsdReducer(columns, engine_plan(engine), column_frequencies(data.columns, columns),
                             engine.steps.n_outputs, n_types, 1.0 / engine.fs, data.keep_psd, data.psd_z,
                             data.midpoints, nodes=data.nodes)
        result = (engine.integrate_estimate if data.midpoints else engine.integrate)(columns, reducer)
        result["describe"] = np.array(json.dumps(engine.describe()))
        return result


def _reduce_mean(state: PemState, task: Task, result: dict[str, np.ndarray], keep_psd: bool) -> None:
    """The mean task's result: the mean rows, the ratios' coefficients and the zeroed sums."""
    plan = state.plan
    state.mean = result
    n_ch, n_t = result["mean"].shape
    if tuple(str(c) for c in result["names"]) != plan.names:
        raise RuntimeError(f"task {task.key}: the mean's channels are not the plan's")
    state.rows = rows = mean_rows(plan, result["outputs"], result["time"])
    state.coef = ratio_coefficients(plan, rows) if plan.ratios else None
    state.var = np.zeros((len(state.spectra), n_ch, n_t))
    state.sums = {k: np.zeros(shape) for k, shape in (
        ("dvar", (n_t, n_ch)), ("dcov", (n_t, n_ch)), ("lam", (n_t, 2, n_ch)),
        ("sperling_power", (n_t, len(plan.sperling))))}
    # zero pages: touched once, by _add_psd
    state.psd = (np.zeros((len(state.rows_kept), state.setup.grid.f.size, n_t), dtype=PSD_STORAGE)
                 if keep_psd else None)
    for message in result["warnings"]:
        warnings.warn(str(message), stacklevel=5)


def _add_psd(psd: np.ndarray, k: np.ndarray, part: np.ndarray, whole: bool) -> None:
    """A task's PSD rows (the kept rows, :func:`finish_pem_task`) at frequencies ``k`` into ``psd``;
    ``whole``: the task holds every type of its frequencies (its frequencies' only task: 0 + x, bitwise)."""
    if k.size and np.array_equal(k, np.arange(k[0], k[0] + k.size)):
        view = psd[:, k[0]:k[0] + k.size, :]  # into a view: no temporary
        if whole:
            view[...] = part
        else:
            view += part
    else:
        psd[:, k, :] += part


def _add_node_sums(state: PemState, raw: dict[str, np.ndarray]) -> None:
    """A grid task's node sums of the local grid-error estimate (``var_nodes_z``, ``nd_nodes``: its
    columns' |y|^2 and the ratios' cross sums by type, weighted by the node factors) as sigma^2 by
    type per channel, the ratios by their first-order coefficients (:func:`finish_pem_task` on those
    sums), into ``state.var_nodes``: the sum T of :func:`~..grid.locally_refined_variance`."""
    assert state.var is not None
    sub = {k: v for k, v in raw.items() if k not in ("psd_z", "psd_z_rows", "nd_psd")}
    sub.update(var_z=raw["var_nodes_z"], nd_type=raw["nd_nodes"])
    var_t = finish_pem_task(sub, state.plan, state.coef, None)["var_t"]
    if state.var_nodes is None:
        state.var_nodes = np.zeros_like(state.var)
    state.var_nodes += var_t.transpose(1, 2, 0)


def _grid_error(state: PemState, channels: tuple[str, ...]) -> GridError | None:
    """The grid error from the midpoint sweep (None: not estimated), warned about above the tolerance."""
    if not state.grid_error:
        return None
    assert state.var is not None and state.mean is not None
    var = state.var.sum(axis=0)
    plain = np.sqrt(var)
    if state.estimate == "local":
        mid, nodes = (np.zeros_like(var) if v is None else v.sum(axis=0) for v in (state.var_mid, state.var_nodes))
        refined, method = np.sqrt(locally_refined_variance(var, mid, nodes)), local_method(*state.cells)
    else:
        assert state.var_mid is not None
        refined, method = np.sqrt(refined_variance(var, state.var_mid.sum(axis=0))), GridError.method
    precision = (state.describe or {}).get("grid_error_precision")
    method += f" (the midpoints in {precision})" if precision else ""
    error = grid_error_from_sigma(state.mean["time"], channels, plain, refined, method)
    for message in grid_error_messages(error):
        warnings.warn(message, GridErrorWarning, stacklevel=6)
    return error


def _result(scenario: Scenario, state: PemState, extra: dict[str, Any], engine: str,
            psd_names: list[str]) -> RandomResponse:
    """The sweep's RandomResponse from the reduced state (``extra``: the method's provenance)."""
    mean, grid, plan = state.mean, state.setup.grid, state.plan
    assert mean is not None and state.var is not None
    channels = tuple(str(c) for c in mean["names"])
    var_by_type = state.var
    stats_ = finish_pem(plan, mean["mean"], mean["time"], state.rows, state.coef, var_by_type.sum(axis=0),
                        **state.sums)
    error = _grid_error(state, channels)
    provenance = merge_provenance(mean, state.describe if state.describe is not None else {"engine": engine}, {
        **extra,
        "grid_error": error.as_dict() if error is not None else
        "not estimated (an engine that runs columns separately: the midpoint sweep would double the runs)",
    })
    provenance["warnings"] = list(provenance.get("warnings", [])) + state.setup.messages() + (
        grid_error_messages(error) if error is not None else [])
    return RandomResponse(
        method="pem", time=mean["time"], channels=channels,
        units=tuple(str(u) for u in mean["units"]), mean=stats_.mean, std=stats_.std,
        band=grid.band, scenario=scenario, freq=grid.f, df=grid.df, psd=state.psd, var_by_type=var_by_type,
        psd_channels=None if state.psd is None else tuple(psd_names),
        types=tuple(state.spectra), provenance=provenance, mean_rate=stats_.mean_rate, std_rate=stats_.std_rate,
        rho=stats_.rho, bandwidth=stats_.bandwidth,
    )


def _estimate(value: Any, cls: Any, where: str) -> tuple[str, bool]:
    """The grid-error estimate asked for by ``grid_error`` (None: on with the engines that integrate all
    columns at once, where it is cheap; True: the default estimate; or an estimate's name) and whether
    it is made. SettingError naming ``grid_error`` for anything else."""
    if value is None:
        return DEFAULT_GRID_ESTIMATE, not cls.single_columns
    if isinstance(value, (bool, np.bool_)):
        return DEFAULT_GRID_ESTIMATE, bool(value)
    if isinstance(value, str) and value in GRID_ESTIMATES:
        return value, True
    raise SettingError(where, "grid_error", value, "true, false or one of " + ", ".join(f"'{e}'" for e in GRID_ESTIMATES))


def run(scenario: Scenario, engine: str, execution: Execution, *, options: Any = None, keep_psd: bool = True,
        psd_channels: str | Sequence[str] = "key", grid_error: bool | str | None = None,
        least_count: bool = False) -> RandomResponse:
    """The PEM sweep of ``scenario`` on ``engine`` (:class:`PemMethod` through the driver)."""
    return drive(PemMethod(scenario, engine, options, keep_psd, psd_channels, grid_error, least_count), execution)


__all__ = ["PemMethod", "PemState", "PemWorker", "run"]
