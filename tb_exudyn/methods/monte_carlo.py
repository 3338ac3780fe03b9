"""Monte Carlo: sample mean and standard deviation over sampled irregularity profiles, on any engine.

Sample k is the profile ``sample_rng(seed, k)`` draws (:mod:`.sampling`), whatever engine and worker
runs it. On an engine of the full model (``full_model``: the Exudyn engine) every sample is one run
with gravity from static equilibrium on the sampled track (method ``"monte_carlo"``); on a linear
engine (batched, dense) every sample is the engine's deterministic run (the mean task: the batched
engine's linear mean by default, ``mean_engine`` in the provenance) plus the linear model's response
to the sample's profiles from rest (method ``"monte_carlo_linear"``). What the linear
method leaves out is exactly what the Exudyn model has beyond the linear one (the rigid bodies'
large-rotation terms, and with ``analysis.linearization = "rest"`` the suspensions' preload
stiffness), which PEM leaves out too: it checks PEM's statistics (time-domain superposition of sampled
profiles instead of pseudo-excitations), not the linearisation; the full-model Monte Carlo checks that.

Start: every input is tapered in over ``track.taper_length`` after the first axle's start, so a
sample starts in static equilibrium with zero input, exactly as PEM's runs start at rest: both
analyse the same process from t = 0.

Reduction: a task (a block of samples: one sample per task on an engine that runs columns
separately, else blocks of at most ``TASK_PROFILE_BYTES`` of profiles in proportion to the slices)
reduces its samples to their mean and sum of squared deviations at every output time (exact two-pass
within the task); the parent merges tasks in task order (Chan, Golub & LeVeque's pairwise update),
so a result is bitwise the same for any number of workers, any executor and after a resume.

Linearity guard: every sample reports its minimum vertical wheel-rail force (every ``*.force_z``,
selected or not; compressive wheel load, positive = pressing) over the output times. A value <= 0 is
a loss of contact, which the linear contact model turns into tension: such samples are counted in the
provenance, listed in ``min_wheel_force``, and a :class:`LossOfContactWarning` is issued, because PEM
assumes a linear system and the comparison no longer holds.
"""

from __future__ import annotations

import json
import math
import time as _time
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Sequence

import numpy as np
from numpy.typing import NDArray

from ..system.derived import derived_provenance
from ..engines import check_engine, engine_class, make_engine
from ..engines.exudyn_runs import linear_model
from ..engines.linear_model import LinearModel
from ..execution import Execution, RunFiles, Task
from ..execution.resources import (PROCESS_BYTES, MemoryEstimate, MemoryLimit, Part, check_memory,
                                   check_run_length, check_task_count, column_bytes, describe_counts, memory_limit,
                                   model_bytes, scenario_where)
from ..results.random_response import RandomResponse
from ..scenario import Scenario, scenario_to_toml
from ..system.columns import ProfileColumns
from .common import (AnalysisSetup, MeanTask, analysis_high, analysis_setup, fingerprint_identity, merge_provenance,
                     whole_number)
from .driver import RunPlan, drive
from . import warm_up
from .pem import default_slices
from .reduction import (REDUCTION_FORMAT, ReductionPlan, SampleReduction, engine_plan, mean_rows, model_plan,
                        sample_offsets)
from .sampling import POINTS_PER_WAVELENGTH, TRIG_TABLE_MAX, Discretisation, ProfileSampler

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]
#: largest profile storage (values and knot slopes of every kind) of one task's samples
TASK_PROFILE_BYTES = 192 * 2**20
#: two-sided 95 % normal quantile
Z95 = 1.959963984540054
STATISTICS_PROVENANCE = {
    "std_estimator": "sample standard deviation (ddof = 1)",
    "confidence": "95 %: mean +- 1.96 s/sqrt(N); std: chi-square interval",
}
LINEARIZED_ABOUT = {"rest": "rest (unloaded, as PEM)",
                    "static": "the static equilibrium under gravity (with the suspension preload's stiffness)"}


class LossOfContactWarning(UserWarning):
    """Some Monte Carlo samples lost wheel-rail contact (the linear model no longer holds)."""


@dataclass(frozen=True)
class SampleTask:
    """Samples [start, stop) of a run seeded with ``seed``."""

    seed: int
    start: int
    stop: int
    keep_samples: bool


class SampleReducer(SampleReduction):
    """At every output time: the mean and the sum of squared deviations of the task's samples over the
    result channels (the scenario's channels and its derived channels, :class:`~.reduction.SampleReduction`, a
    :class:`~tb_exudyn.engines.protocols.Reducer`),
    every sample's minimum and maximum of every channel, the samples' vertical wheel forces and, if
    asked, the samples."""


@dataclass(frozen=True)
class McSizing:
    """What the memory estimate of a Monte Carlo run needs besides the built model (:func:`mc_memory`)."""

    n_samples: int
    task_samples: int  # samples of the largest task
    keep_samples: bool
    profile_bytes: int  # profile storage of one sample
    table_bytes: int  # the sampler's trigonometric table (shared by a worker's tasks)
    workers: int  # worker processes (0: in the main process)
    limit: MemoryLimit | None  # None: what the machine running the setup has available
    where: str


def mc_memory(s: McSizing, engine: Any) -> MemoryEstimate:
    """The memory of a Monte Carlo run on a built ``engine`` [bytes]: in the main process the kept
    samples, the per-sample minimum forces and extremes and the task results waiting or arriving (a pool: one
    waiting and one arriving, briefly there twice); in each worker the largest task's profiles (the
    sampled grids, half the columns' values and slopes built from them, while they are built), its
    reduction (every wheel force at every output
    time, the samples if kept; a pool sends a copy), its columns' state, the model, the compiled code
    of the mean task (:meth:`~tb_exudyn.engines.base.Engine.code_bytes`), the interpreter."""
    n_sel = len(engine_plan(engine).names)  # the result channels: the scenario's and the derived ones
    n_t, n_force = engine.steps.n_outputs, int(engine.force_rows.size)
    pool = s.workers > 0
    nb = s.task_samples
    key = ("n_samples", s.n_samples)
    remedy = ("fewer samples (n_samples or analysis.n_samples)"
              + (", or not keeping them (keep_samples=False)" if s.keep_samples else ""))
    kept = 8 * n_sel * n_t if s.keep_samples else 0
    task_result = nb * (8 * n_force * n_t + kept + 16 * n_sel) + 16 * n_sel * n_t
    parent = (
        Part(f"the kept samples ({describe_counts(samples=s.n_samples, channels=n_sel, output_times=n_t)}, float64)",
             s.n_samples * kept, "keep_samples" if s.keep_samples else "n_samples",
             s.keep_samples if s.keep_samples else s.n_samples, remedy),
        Part("the minimum wheel force and every channel's extremes per sample", 8 * s.n_samples * (1 + 2 * n_sel),
             *key, remedy),
        Part("the task results waiting or arriving", 3 * task_result if pool else 0, *key, remedy),
        Part("the statistics", 8 * 8 * n_sel * n_t, "analysis.output_step", engine.scenario.analysis.output_step,
             "a larger analysis.output_step, or fewer analysis.channels"),
        Part("the interpreter and its libraries", PROCESS_BYTES),
    )
    worker = (
        Part(f"a task's profiles ({nb} samples)", 3 * nb * s.profile_bytes // 2 + s.table_bytes, *key, remedy),
        Part(f"a task's reduction ({describe_counts(samples=nb, wheel_forces=n_force, output_times=n_t)})"
             + (", and its copy sent back" if pool else ""), (2 if pool else 1) * task_result, *key, remedy),
        Part(f"the state of a task's {(nb + 1) // 2} columns", ((nb + 1) // 2) * column_bytes(engine), *key, remedy),
        Part("the model", model_bytes(engine)),
        Part("the engine's compiled code (the mean task's)", engine.code_bytes(False)),
        Part("the interpreter and its libraries", PROCESS_BYTES),
    )
    return MemoryEstimate(parent, worker, s.workers)


@dataclass(frozen=True)
class MonteCarloWorker:
    """What a Monte Carlo worker gets (:class:`~tb_exudyn.methods.driver.Worker`): the engine to build
    (every wheel force as an output), the sampler's discretisation and grid, the run's sizing."""

    engine: str
    scenario: Scenario
    options: Any
    discretisation: Discretisation
    grid: Any
    sizing: McSizing | None = None
    system: LinearModel | None = field(default=None, repr=False)  # determined by the fields above

    def setup(self) -> tuple[Any, ProfileSampler]:
        """The engine (the Exudyn engine's model; a linear engine on the parent's ``system``) and the
        sampler, once per worker; with ``sizing``, refuse (ResourceError) a run whose memory estimate
        exceeds its limit, before any task allocates."""
        built = make_engine(self.engine, self.scenario, self.options, wheel_forces=True, system=self.system)
        s = self.sizing
        if s is not None:
            check_memory(mc_memory(s, built), s.limit or memory_limit(None, s.where), s.where)
        return built, ProfileSampler(self.scenario, self.discretisation, self.grid)

    def work(self, state: tuple[Any, ProfileSampler], task: Task) -> dict[str, np.ndarray]:
        """A block of samples: their profiles, their reducer, the integration."""
        engine, sampler = state
        st: SampleTask = task.data
        result = integrate_samples(engine, sampler, st.seed, range(st.start, st.stop), st.keep_samples)
        plan = engine_plan(engine)
        return {**result, "names": np.array(plan.names, dtype=str), "units": np.array(plan.units, dtype=str),
                "warnings": np.array(engine.warnings, dtype=str).reshape(-1),
                "describe": np.array(json.dumps(engine.describe()))}


def integrate_samples(engine: Any, sampler: ProfileSampler, seed: int, indices: Sequence[int],
                      keep_samples: bool = False) -> dict[str, np.ndarray]:
    """Samples ``indices`` of a run seeded with ``seed`` on ``engine`` (built with ``wheel_forces``),
    reduced at every output time by :class:`SampleReducer` (a linear engine: the responses from rest
    without gravity about the engine's mean run, :meth:`~tb_exudyn.engines.base.Engine.mean`; the full
    model: the samples themselves)."""
    plan = engine_plan(engine)
    offsets = zmean = force_mean = None
    if not engine.full_model:  # responses about the mean: the mean run gives the totals
        det = engine.mean()
        offsets = sample_offsets(plan, det["mean"])
        zmean = mean_rows(plan, det["outputs"], det["time"]).value
        force_mean = det["outputs"][engine.force_rows]
    reducer = SampleReducer(plan, engine.force_rows, engine.steps.n_outputs, len(indices), keep_samples, offsets,
                            zmean, engine.fs, force_mean)
    return engine.integrate(sampler.columns(seed, indices), reducer)


# ---------------------------------------------------------------------------------- statistics
def sample_statistics(mean: FloatArray, m2: FloatArray, n: int) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Sample standard deviation (ddof = 1) from the sum of squared deviations ``m2`` of ``n``
    samples, and the 95 % confidence intervals (2, ...) of the mean (normal) and of the std
    (chi-square)."""
    std = np.sqrt(m2 / (n - 1))
    half = Z95 * std / math.sqrt(n)
    mean_ci = np.stack([mean - half, mean + half])
    from scipy.stats import chi2  # on first use: keeps 0.3 s out of every import

    q_hi, q_lo = chi2.ppf([0.975, 0.025], n - 1)
    std_ci = np.stack([std * math.sqrt((n - 1) / q_hi), std * math.sqrt((n - 1) / q_lo)])
    return std, mean_ci, std_ci


def warn_loss_of_contact(min_force: FloatArray) -> IntArray:
    """Indices of the samples whose minimum vertical wheel force is <= 0, with a
    :class:`LossOfContactWarning` when there are any."""
    lost = np.flatnonzero(min_force <= 0.0)
    if lost.size:
        warnings.warn(
            f"{lost.size} of {min_force.size} Monte Carlo samples lost wheel-rail contact (minimum vertical wheel "
            f"force {np.nanmin(min_force):.4g} N <= 0; first samples {lost[:5].tolist()}): the linear contact pulls "
            "the wheel back, so these samples, and a comparison with PEM (which assumes a linear system), "
            "are not reliable", LossOfContactWarning, stacklevel=3,
        )
    return lost


def contact_provenance(min_force: FloatArray, lost: IntArray) -> dict[str, Any]:
    return {
        "samples_with_loss_of_contact": int(lost.size),
        "min_wheel_force_N": float(np.nanmin(min_force)) if np.isfinite(min_force).any() else None,
    }


def sample_blocks(n: int, weights: Sequence[float], largest: int) -> list[tuple[int, int]]:
    """Samples 0..n-1 cut into contiguous blocks in proportion to ``weights``, none above ``largest``."""
    w = np.asarray(weights, dtype=float)
    edges = np.unique(np.round(np.concatenate(([0.0], np.cumsum(w) / w.sum())) * n).astype(int))
    blocks = []
    for a, b in zip(edges[:-1], edges[1:]):
        pieces = -(-(b - a) // largest)
        cuts = np.round(np.linspace(a, b, pieces + 1)).astype(int)
        blocks += [(int(p), int(q)) for p, q in zip(cuts[:-1], cuts[1:]) if q > p]
    return blocks


# ---------------------------------------------------------------------------------- the method
@dataclass
class McState:
    """What Monte Carlo's reduce accumulates (in this process) and its finish reads: the running
    mean and sum of squared deviations (``mean``, ``m2`` over ``n`` samples, Chan's update in task
    order), the mean task's result (``det``, a linear engine) and its ``offsets``, the samples'
    minimum wheel forces, extremes and (``keep_samples``) values, and the first task's names, units,
    warnings and time."""

    setup: AnalysisSetup
    sampler: ProfileSampler
    plan: ReductionPlan
    n_samples: int
    seed: int
    linear: bool
    blocks: list[tuple[int, int]]
    t0: float
    min_force: FloatArray
    extremes: tuple[FloatArray, FloatArray]
    n: int = 0
    mean: FloatArray | None = None
    m2: FloatArray | None = None
    det: dict[str, np.ndarray] | None = None
    offsets: FloatArray | None = None
    samples: FloatArray | None = None
    first: dict[str, Any] | None = None
    describe: dict[str, Any] = field(default_factory=dict)
    run_times: list[float] = field(default_factory=list)


@dataclass(frozen=True)
class MonteCarloMethod:
    """Monte Carlo of ``scenario`` on ``engine`` (see :func:`tb_exudyn.run_monte_carlo`);
    ``n_samples`` and ``seed`` override ``analysis.n_samples`` and ``analysis.seed`` (None: the
    scenario's), ``where`` names the caller in messages."""

    scenario: Scenario
    engine: str
    n_samples: int | None = None
    seed: int | None = None
    keep_samples: bool = False
    discretisation: Discretisation = "pem_grid"
    options: Any = None
    where: str = "run_monte_carlo"

    @property
    def files(self) -> RunFiles:
        linear = not engine_class(self.engine, self.where).full_model
        return RunFiles("mc_linear" if linear else "mc", "checkpoint-mc-linear" if linear else "checkpoint-mc")

    def plan(self, execution: Execution) -> RunPlan:
        t0 = _time.perf_counter()
        scenario, where = self.scenario, self.where
        check_run_length(scenario)
        cls = check_engine(self.engine, scenario, self.options, linearized=False)
        warm_up.start(cls, self.options, execution.announce, harmonic=False)  # a first run's compile, beside the set-up
        n = whole_number(scenario.analysis.n_samples if self.n_samples is None else self.n_samples, where,
                         "n_samples", 2, analysis_high("n_samples"))
        seed = whole_number(scenario.analysis.seed if self.seed is None else self.seed, where, "seed", 0,
                            analysis_high("seed"))
        setup = analysis_setup(scenario)
        sampler = ProfileSampler(scenario, self.discretisation, setup.grid)  # every check on spectra and band
        linear = not cls.full_model
        # the checkpoint does not depend on N: a larger N with resume reuses the samples run
        key_scenario = scenario.replace(analysis=scenario.analysis.replace(n_samples=1, seed=seed))
        identity = fingerprint_identity(
            scenario_to_toml(key_scenario), method="monte_carlo_linear" if linear else "monte_carlo",
            engine=self.engine, engine_options=cls.describe_options(self.options),
            method_options={"seed": seed, "discretisation": self.discretisation, "keep_samples": self.keep_samples,
                            "grid": setup.grid.f.tolist(), "reduction": REDUCTION_FORMAT,
                            "points_per_wavelength": POINTS_PER_WAVELENGTH}, spectra=scenario.track.irregularities)
        blocks, tasks = self._tasks(cls, execution, sampler, n, seed)
        sizing = self._sizing(sampler, n, blocks, execution.worker_processes(len(tasks)), execution)
        plan = model_plan(setup.model, wheel_forces=True)  # the workers' engines have the same outputs
        shape = (n, len(plan.names))
        state = McState(setup=setup, sampler=sampler, plan=plan, n_samples=n, seed=seed, linear=linear, blocks=blocks,
                        t0=t0, min_force=np.full(n, math.nan), extremes=(np.full(shape, np.nan), np.full(shape, np.nan)))
        system = (None if cls.full_model else  # a linear engine's system, built once here for every worker
                  linear_model(setup.model, wheel_forces=True, mean=cls.linear_mean(self.options)))
        worker = MonteCarloWorker(self.engine, scenario, self.options, self.discretisation, setup.grid, sizing, system)
        return RunPlan(files=self.files, tasks=tasks, identity=identity, state=state, worker=worker,
                       desc=f"Monte Carlo ({self.engine})")

    def _tasks(self, cls: Any, execution: Execution, sampler: ProfileSampler, n: int, seed: int
               ) -> tuple[list[tuple[int, int]], list[Task]]:
        """The sample blocks and their tasks: one sample per task on an engine that runs columns
        separately, else the mean task and blocks in proportion to the slices (the module docstring)."""
        if cls.single_columns:
            check_task_count(n, self.where, "n_samples", n, "fewer samples, or a linear engine ('batched')")
            blocks = [(k, k + 1) for k in range(n)]
            return blocks, [Task(f"mc-{a:07d}", SampleTask(seed, a, b, self.keep_samples)) for a, b in blocks]
        n_kinds = len({kind for kind, _ in sampler.kinds})
        largest = max(2, TASK_PROFILE_BYTES // ProfileColumns.profile_bytes(sampler.n_points, n_kinds))
        weights = default_slices(execution.cores) if execution.slices is None else execution.slices
        blocks = sample_blocks(n, weights, largest)
        tasks = [Task("mcl-mean", MeanTask())]
        tasks += [Task(f"mcl-{a:07d}-{b - 1:07d}", SampleTask(seed, a, b, self.keep_samples)) for a, b in blocks]
        return blocks, tasks

    def _sizing(self, sampler: ProfileSampler, n: int, blocks: list[tuple[int, int]], workers: int,
                execution: Execution) -> McSizing:
        n_kinds = len({kind for kind, _ in sampler.kinds})
        table = 2 * sampler.n_points * sampler.n_frequencies
        return McSizing(
            n_samples=n, task_samples=max(b - a for a, b in blocks), keep_samples=self.keep_samples,
            profile_bytes=ProfileColumns.profile_bytes(sampler.n_points, n_kinds),
            table_bytes=8 * table if self.discretisation == "pem_grid" and table <= TRIG_TABLE_MAX else 0,
            workers=workers, limit=execution.worker_limit(), where=scenario_where(self.scenario))

    def reduce(self, state: McState, i: int, task: Task, result: dict[str, np.ndarray]) -> None:
        if isinstance(task.data, MeanTask):
            state.det = result
            state.offsets = sample_offsets(state.plan, result["mean"])
            for message in result["warnings"]:
                warnings.warn(str(message), stacklevel=5)
            return
        st: SampleTask = task.data
        nb, mean_b, m2_b = int(result["n"]), result["mean"], result["m2"]
        if state.first is None:
            state.first = {"names": result["names"], "units": result["units"], "time": result.get("time"),
                           "warnings": [str(w) for w in result["warnings"]]}
            if not state.linear:
                for message in state.first["warnings"]:
                    warnings.warn(message, stacklevel=5)
        det = state.det
        state.extremes[0][st.start:st.stop] = result["sample_min"]
        state.extremes[1][st.start:st.stop] = result["sample_max"]
        if nb != st.stop - st.start or (det is not None and mean_b.shape != det["mean"].shape):
            raise RuntimeError(f"task {task.key}: {nb} samples of shape {mean_b.shape}, expected {st.stop - st.start}")
        _merge(state, nb, mean_b, m2_b)
        state.min_force[st.start:st.stop] = result["min_force"]  # NaN: a model without vertical wheel forces
        if self.keep_samples:
            if state.samples is None:
                state.samples = np.empty((state.n_samples,) + mean_b.shape)
            state.samples[st.start:st.stop] = (result["samples"] if det is None
                                               else state.offsets[None] + result["samples"])  # type: ignore[index]
        state.describe = json.loads(str(result["describe"]))
        if "run_times" in result:
            state.run_times += result["run_times"].tolist()

    def finish(self, state: McState, stats: dict[str, Any]) -> RandomResponse:
        scenario, det, n = self.scenario, state.det, state.n_samples
        assert state.mean is not None and state.m2 is not None and state.first is not None
        mean = state.mean if det is None else state.offsets + state.mean
        std, mean_ci, std_ci = sample_statistics(mean, state.m2, n)
        lost = warn_loss_of_contact(state.min_force)
        provenance = self._provenance(state, lost, stats)
        return RandomResponse(
            method="monte_carlo_linear" if state.linear else "monte_carlo",
            time=state.first["time"] if det is None else det["time"],
            channels=tuple(str(c) for c in state.first["names"]), units=tuple(str(u) for u in state.first["units"]),
            mean=mean, std=std, band=tuple(float(b) for b in state.sampler.band),  # type: ignore[arg-type]
            scenario=scenario.replace(analysis=scenario.analysis.replace(n_samples=n, seed=state.seed)),
            types=tuple(scenario.track.irregularities), std_ci=std_ci, mean_ci=mean_ci, n_samples=n,
            min_wheel_force=state.min_force, samples=state.samples, provenance=provenance,
            sample_min=state.extremes[0], sample_max=state.extremes[1],
        )

    def _provenance(self, state: McState, lost: IntArray, stats: dict[str, Any]) -> dict[str, Any]:
        model, n, linear = state.setup.model, state.n_samples, state.linear
        extra: dict[str, Any] = {
            "method": "monte_carlo_linear" if linear else "monte_carlo",
            "seconds": _time.perf_counter() - state.t0,
            "seed": state.seed,
            "n_samples": n,
            "gravity": True,
            "initial_state": "static",
            "sample_blocks": [list(b) for b in state.blocks] if linear else f"{n} tasks of one sample",
            **contact_provenance(state.min_force, lost),
            **state.setup.provenance(),
            "derived_channels": derived_provenance(model.derived_catalogue, model.derived),
            "extremes": "every sample's minimum and maximum of every channel over the whole record (sample_min, sample_max)",
            **STATISTICS_PROVENANCE,
            **state.sampler.describe(),
            **stats,
        }
        if linear:
            lin = self.scenario.analysis.linearization
            extra["linearization"] = lin
            extra["model"] = ("linear: each sample is the engine's mean run (gravity, static start; mean_engine says "
                              "whose) plus the response of the model linearised about " + LINEARIZED_ABOUT[lin] +
                              " (M, K, D from Exudyn, the linear wheel-rail contact) to the sample's profiles, integrated "
                              f"by the {self.engine} engine; the samples are those of the Exudyn Monte Carlo")
            provenance = merge_provenance(state.det, state.describe, extra)  # type: ignore[arg-type]
        else:
            provenance = {**state.describe, **extra, "warnings": state.first["warnings"],  # type: ignore[index]
                          "sample_run_time_median_s": float(np.median(state.run_times))}
        provenance["warnings"] = list(provenance.get("warnings", [])) + state.setup.messages()
        return provenance

    def save(self, result: RandomResponse, out: Path) -> None:
        result.save(out / self.files.result)


def _merge(state: McState, nb: int, mean_b: FloatArray, m2_b: FloatArray) -> None:
    """A block's mean and sum of squared deviations into the state's (Chan, Golub & LeVeque's pairwise
    update, in task order)."""
    na = state.n
    if na == 0:
        state.mean, state.m2 = mean_b.copy(), m2_b.copy()
    else:
        assert state.mean is not None and state.m2 is not None
        delta = mean_b - state.mean
        state.mean += delta * (nb / (na + nb))
        state.m2 += m2_b + delta * delta * (na * nb / (na + nb))
    state.n = na + nb


def run(scenario: Scenario, engine: str, execution: Execution, *, n_samples: int | None = None,
        seed: int | None = None, keep_samples: bool = False, discretisation: Discretisation = "pem_grid",
        options: Any = None, where: str = "run_monte_carlo") -> RandomResponse:
    """Monte Carlo of ``scenario`` on ``engine`` (:class:`MonteCarloMethod` through the driver); see
    :func:`tb_exudyn.run_monte_carlo`."""
    return drive(MonteCarloMethod(scenario, engine, n_samples, seed, keep_samples, discretisation, options, where),
                 execution)


__all__ = ["LossOfContactWarning", "McSizing", "McState", "MonteCarloMethod", "MonteCarloWorker", "SampleReducer",
           "integrate_samples", "mc_memory", "run",
           "sample_blocks", "sample_statistics", "warn_loss_of_contact"]
