"""The pseudo-excitation method (PEM): the frequency sweep, on any engine.

For each irregularity spectrum S (one-sided, rad/m) and grid frequency f_k [Hz] with width df_k, the
pseudo-irregularity at wheel j is r~_j(t) = a_k exp(i Omega_k (v t - a_j)), Omega_k = 2 pi f_k / v,
a_k = sqrt(S(Omega_k) dOmega_k) = sqrt(S_hz(f_k) df_k): one complex column of
:class:`~tb_exudyn.system.columns.HarmonicColumns`. The system is linear in the irregularity, so the
engine integrates each column's response y~ (the Exudyn engine as two real runs, the linear engines
all columns at once), and with independent spectra adding

    S_y(f_k, t) = sum over spectra |y~_k(t)|^2 / df_k         (one-sided PSD per Hz)
    sigma_y^2(t) = sum_k S_y(f_k, t) df_k                      (over the analysed band)

(:class:`PsdReducer`); the mean is the deterministic run (gravity, no irregularity) as a task of its
own, by the engine: the batched engine's is the linear model's under the dead loads (Exudyn's
nonlinear run with ``BatchedOptions(mean="exudyn")``), the Exudyn engine's Exudyn's; the provenance's
``mean_engine`` says which. Frequencies whose wavelength v / f lies outside the track's wavelength band carry no
irregularity (PSD zero there).

Tasks: an engine that runs columns separately (``single_columns``) gets one task per column; the
others get slices of contiguous frequencies (every type of a frequency in the same slice), one per
core (:func:`default_slices`), the last one shorter by the mean's cost (the engine's hint; a half
slice where it is not known): on as many workers as cores, the worker that runs the mean takes the
last slice after it and every worker's load is about equal. A result never depends on the number of
workers, the executor or a resume (bitwise), and on the slicing only at round-off.
"""

from __future__ import annotations

import fnmatch
import json
import math
import time as _time
import warnings
from dataclasses import dataclass
from typing import Any, Sequence

import numpy as np
from numpy.typing import NDArray

from ..system.derived import derived_provenance
from ..engines import check_engine, make_engine
from ..errors import ScenarioError, SettingError
from ..execution import Execution, RunFiles, Task
from ..execution.resources import (PROCESS_BYTES, MemoryEstimate, MemoryLimit, Part, check_memory,
                                   check_run_length, column_bytes, describe_counts, memory_limit, model_bytes,
                                   scenario_where)
from ..results.checks import GRID_ERROR_TOLERANCE  # grid errors above it are warned about and reported
from ..results.random_response import RandomResponse
from ..scenario import Scenario, scenario_to_toml
from ..system.columns import HarmonicColumns
from ..system.conventions import cross_level_scale, spatial_frequency
from ..system.excitation import KINDS
from ..system.labels import default_patterns
from ..track import get_spectrum
from .common import MeanTask, analysis_setup, fingerprint_identity, merge_provenance
from .grid import FrequencyGrid, band_mask, check_grid_against_spectra, midpoint_grid, refined_variance
from .grid_error import GridError, grid_error_from_sigma



class GridErrorWarning(UserWarning):
    """The frequency grid changes a channel's max sigma by more than GRID_ERROR_TOLERANCE."""


def grid_error_messages(error: GridError, tolerance: float = GRID_ERROR_TOLERANCE) -> list[str]:
    """One line on the channels whose estimated grid error exceeds ``tolerance`` (empty if none)."""
    bad = error.exceeding(tolerance)
    if not bad:
        return []
    i = int(np.argmax(np.abs(error.rel_error_max_sigma)))
    return [f"the frequency grid is too coarse for {len(bad)} of {len(error.channels)} channels: their max sigma "
            f"changes by more than {100 * tolerance:g} % when the grid is refined (largest "
            f"{100 * error.rel_error_max_sigma[i]:+.2g} % on {error.channels[i]}; e.g. {', '.join(bad[:3])}); "
            "use analysis.freq_spacing = 'adaptive' or more frequencies (analysis.n_freq)"]
from .pseudo_reduction import reducer_column_bytes
from .reduction import (REDUCTION_FORMAT, PseudoReduction, ReductionPlan, engine_plan, finish_pem, finish_pem_task,
                        mean_rows, model_plan, ratio_coefficients)

#: precision in which a task's PSD map travels to the parent (sigma^2 is float64 throughout):
#: float32's relative rounding of 6e-8 is far below the engines' agreement of 1e-6 and halves the
#: largest messages (the reference study's map is 420 MB in float64)
PSD_TRANSPORT = np.float32
#: precision in which a result keeps its PSD maps (sigma^2 is float64 throughout): float32's relative
#: rounding of 6e-8 is far below every stated tolerance, and halves the files
PSD_STORAGE = np.float32
#: output times written to a task's PSD map at once (contiguous runs of the time axis)
PSD_BLOCK = 16

ComplexArray = NDArray[np.complex128]
IntArray = NDArray[np.int64]


@dataclass(frozen=True)
class PemTask:
    """One (spectrum, frequency) pair: one complex column."""

    type_index: int
    spectrum: str
    freq_index: int
    f: float
    df: float
    amplitude: float  # a_k = sqrt(S_hz(f) df): the true pseudo-amplitude, in the spectrum's unit


@dataclass(frozen=True)
class ColumnTask:
    """A set of columns (every type of a set of frequencies, or one column) integrated together;
    ``midpoints``: columns of the grid error's midpoint sweep (sigma^2 only)."""

    columns: tuple[PemTask, ...]
    keep_psd: bool
    midpoints: bool = False
    psd_z: tuple[int, ...] | None = None  # the z rows whose PSD maps the task keeps (None: all)


def kind_and_unit(spectrum_name: str, where: str | None = None) -> tuple[str, str]:
    """The coupling's input kind for a spectrum and, for cross-level, whether it is an angle or a height
    (``where``: the scenario's file, for the error of a kind the model does not take)."""
    s = get_spectrum(spectrum_name)
    if s.kind not in KINDS:
        raise ScenarioError(
            where, "track.irregularities", spectrum_name,
            "vertical, alignment or cross-level spectra (gauge irregularity does not excite this model)",
            "irregularity kind not modelled",
        )
    return s.kind, ("height" if s.unit == "m" else "angle")


def pem_tasks(scenario: Scenario, grid: FrequencyGrid) -> list[PemTask]:
    """One column per (spectrum, frequency inside the wavelength band), in a fixed order (type-major)."""
    mask = band_mask(grid, scenario)
    omegas, d_omegas = grid.omega_spatial, grid.d_omega_spatial  # properties: computed once, not per k
    out = []
    for ti, name in enumerate(scenario.track.irregularities):
        s = get_spectrum(name)
        for k in np.flatnonzero(mask):
            omega, d_omega = omegas[k], d_omegas[k]
            amp = math.sqrt(float(s.psd(omega)) * d_omega)  # one by one: bitwise as before (not vectorised)
            out.append(PemTask(ti, name, int(k), float(grid.f[k]), float(grid.df[k]), amp))
    return out


def harmonic_columns(ptasks: Sequence[PemTask], scenario: Scenario) -> HarmonicColumns:
    """The columns of a task, frequency-major; every frequency must carry the same types in the same order."""
    freqs = sorted({p.freq_index for p in ptasks})
    types = sorted({p.type_index for p in ptasks})
    by = {(p.freq_index, p.type_index): p for p in ptasks}
    if len(by) != len(ptasks) or len(by) != len(freqs) * len(types):
        raise ValueError("a PEM task must hold the same irregularity types at each of its frequencies, once")
    order = [by[(k, ti)] for k in freqs for ti in types]
    kinds, units, scale = [], [], []
    for p in order:
        kind, unit = kind_and_unit(p.spectrum)
        kinds.append(KINDS.index(kind))
        units.append(unit)
        scale.append(p.amplitude * (cross_level_scale(unit, scenario.track.half_gauge) if kind == "cross_level" else 1.0))
    return HarmonicColumns(
        kinds=np.array(kinds, dtype=np.int64), omega=spatial_frequency(np.array([p.f for p in order]), scenario.speed),
        amplitude=np.array([p.amplitude for p in order]), units=tuple(units), scale=np.array(scale),
        type_index=np.array([p.type_index for p in order], dtype=np.int64), freq_index=np.array(freqs, dtype=np.int64),
        df=np.array([by[(k, types[0])].df for k in freqs]), n_types=len(types),
    )


class PsdReducer(PseudoReduction):
    """PEM's reduction at an output time (:class:`~tb_exudyn.methods.reduction.PseudoReduction`): per
    result channel (the scenario's channels and its derived channels) |y~|^2 summed per type (sigma^2),
    the PSD map with ``keep_psd`` (summed over types, divided by df; ``psd_z``: only of those z rows,
    :func:`psd_z_rows`), the time derivative's sums for
    the Rice rate, the ratios' cross sums and the Sperling inputs' weighted power.

    columns : the task's columns; f_col : (m,) excitation frequency of each column [Hz]."""

    def __init__(self, columns: HarmonicColumns, plan: ReductionPlan, f_col: NDArray[np.float64], n_t: int,
                 n_types: int, dt: float, keep_psd: bool, psd_z: Sequence[int] | None = None,
                 variance_only: bool = False) -> None:
        self.columns = columns
        super().__init__(plan, f_col, columns.type_index, n_types, columns.freq_index.size, columns.df, n_t, dt,
                         keep_psd, None if psd_z is None else np.asarray(psd_z, dtype=np.int64), variance_only)

    def result(self) -> dict[str, np.ndarray]:
        return {**super().result(), "freq_index": self.columns.freq_index}


def column_frequencies(ptasks: Sequence[PemTask], columns: HarmonicColumns) -> NDArray[np.float64]:
    """(m,) the excitation frequency [Hz] of each of ``columns`` (built from ``ptasks``)."""
    by = {p.freq_index: p.f for p in ptasks}
    return np.repeat(np.array([by[int(k)] for k in columns.freq_index]), columns.n_types)


# ---------------------------------------------------------------------------------- tasks
def default_slices(cores: int, mean_share: float | None = None) -> list[float]:
    """Slice weights for ``cores`` workers that take the tasks in order, the mean first: the mean's
    worker takes the last slice after it, so that slice is shorter by the mean, ``mean_share`` (the
    mean's cost as a share of a full slice; None: not known, a half slice, the cost of an Exudyn run).
    With a known share: ``cores`` slices, the last one 1 - share (every worker's load equal); without:
    ``cores`` full slices and a half one (module docstring)."""
    n = max(1, cores)
    if mean_share is None:
        return [1.0] * n + [0.5]
    if n == 1:
        return [1.0]
    return [1.0] * (n - 1) + [min(1.0, max(0.1, 1.0 - mean_share))]


def slice_weights(cls: Any, options: Any, cores: int, n_columns: int) -> list[float]:
    """:func:`default_slices` with the mean's share from the engine's cost hint
    (``cls.mean_cost_columns``, in columns) and a sweep of ``n_columns`` columns: a full slice is then
    (n_columns + cost) / cores columns and the mean's worker takes the last slice, shorter by the mean."""
    cost = cls.mean_cost_columns(options) if hasattr(cls, "mean_cost_columns") else None
    if cost is None or n_columns <= 0:
        return default_slices(cores)
    return default_slices(cores, float(cost) / ((n_columns + float(cost)) / max(1, cores)))


def column_slices(ptasks: Sequence[PemTask], weights: Sequence[float], keep_psd: bool, prefix: str = "pemb",
                  midpoints: bool = False, psd_z: tuple[int, ...] | None = None) -> list[Task]:
    """The sweep's (type, frequency) pairs cut into tasks of contiguous frequencies (all types of a
    frequency in the same task) with numbers of frequencies in proportion to ``weights``."""
    freqs = np.array(sorted({p.freq_index for p in ptasks}))
    w = np.asarray(weights, dtype=float)[: freqs.size]
    edges = np.unique(np.round(np.concatenate(([0.0], np.cumsum(w) / w.sum())) * freqs.size).astype(int))
    out = []
    for a, b in zip(edges[:-1], edges[1:]):
        chosen = set(freqs[a:b].tolist())
        cols = tuple(p for p in ptasks if p.freq_index in chosen)
        out.append(Task(f"{prefix}-{freqs[a]:05d}-{freqs[b - 1]:05d}", ColumnTask(cols, keep_psd, midpoints, psd_z)))
    return out


@dataclass(frozen=True)
class PemSizing:
    """What the memory estimate of a sweep needs besides the built model (:func:`pem_memory`)."""

    n_freq: int
    n_types: int
    task_freqs: int  # frequencies of the largest task
    keep_psd: bool
    workers: int  # worker processes (0: in the main process)
    output_step: float
    limit: MemoryLimit | None  # None: what the machine running the setup has available
    where: str
    psd_channels: int | None = None  # channels whose PSD map is kept (None: all)
    psd_task_rows: int | None = None  # rows of a task's PSD map (psd_z_rows; None: one per output channel)
    where_option: str = ""  # the caller of the options ("command line": name them as flags)


def pem_memory(s: PemSizing, engine: Any) -> MemoryEstimate:
    """The memory of a sweep on a built ``engine`` [bytes]: in the main process the kept PSD map (float32)
    and the task results waiting or arriving (a pool: one waiting and one arriving, which is briefly
    there twice, as the received message and the array); in each worker the largest task's PSD map
    (float32; a pool sends a copy), its columns' state, the model, the interpreter."""
    n_ch, n_t = len(engine.outputs.names), engine.steps.n_outputs
    pool = s.workers > 0
    n_f = ("analysis.n_freq", s.n_freq)
    psd = "--psd-channels" if s.where_option == "command line" else "psd_channels"
    remedy = ("a smaller analysis.n_freq, fewer analysis.channels or a larger analysis.output_step"
              + (f", fewer PSD maps ({psd}), or keep_psd=False" if s.keep_psd else ""))
    n_task = n_ch if s.psd_task_rows is None else s.psd_task_rows
    task_map = 4 * n_task * s.task_freqs * n_t if s.keep_psd else 0
    task_var = 8 * n_t * s.n_types * n_ch
    m = s.task_freqs * s.n_types
    n_kept = n_ch if s.psd_channels is None else s.psd_channels
    parent = (
        Part(f"the PSD map ({describe_counts(channels=n_kept, frequencies=s.n_freq, output_times=n_t)}, float32)",
             4 * n_kept * s.n_freq * n_t if s.keep_psd else 0, *n_f, remedy),
        Part("the task results waiting or arriving", 3 * (task_map + task_var) if pool else 0, *n_f, remedy),
        Part("sigma, mean and the variances per type", 8 * n_ch * n_t * (s.n_types + 6), "analysis.output_step",
             s.output_step, "a larger analysis.output_step, or fewer analysis.channels"),
        Part("the interpreter and its libraries", PROCESS_BYTES),
    )
    worker = (
        Part(f"a task's PSD map ({describe_counts(channels=n_task, frequencies=s.task_freqs, output_times=n_t)}, "
             "float32" + (", and its copy sent back" if pool else "") + ")",
             (2 if pool else 1) * task_map + task_map // max(1, n_t) * PSD_BLOCK, *n_f, remedy),
        Part(f"the state of a task's {m} columns", m * column_bytes(engine) + task_var, *n_f, remedy),
        Part(f"the reduction's buffers of a task's {m} columns", m * reducer_column_bytes(engine_plan(engine), n_ch),
             *n_f, remedy),
        Part("the model", model_bytes(engine)),
        Part("the interpreter and its libraries", PROCESS_BYTES),
    )
    return MemoryEstimate(parent, worker, s.workers)


def _setup(engine: str, scenario: Scenario, options: Any, sizing: PemSizing | None = None) -> Any:
    """Build the engine (and its model) once per worker; with ``sizing``, refuse (ResourceError) a
    sweep whose memory estimate exceeds its limit, before any task allocates."""
    built = make_engine(engine, scenario, options)
    if sizing is not None:
        check_memory(pem_memory(sizing, built), sizing.limit or memory_limit(None, sizing.where), sizing.where)
    return built


def _work(engine: Any, task: Task) -> dict[str, np.ndarray]:
    if isinstance(task.data, MeanTask):
        return engine.mean()
    data: ColumnTask = task.data
    columns = harmonic_columns(data.columns, engine.scenario)
    n_types = len(engine.scenario.track.irregularities)
    reducer = PsdReducer(columns, engine_plan(engine), column_frequencies(data.columns, columns),
                         engine.steps.n_outputs, n_types, 1.0 / engine.fs, data.keep_psd, data.psd_z, data.midpoints)
    result = (engine.integrate_estimate if data.midpoints else engine.integrate)(columns, reducer)
    result["describe"] = np.array(json.dumps(engine.describe()))
    return result


# ---------------------------------------------------------------------------------- the sweep
def prepare_sweep(scenario: Scenario) -> dict[str, Any]:
    """Checks before any run: irregularities present and modelled. Returns the spectra."""
    if not scenario.track.irregularities:
        raise ScenarioError(scenario.where, "track.irregularities", [], "at least one spectrum name", "no irregularity to analyse")
    spectra = {n: get_spectrum(n) for n in scenario.track.irregularities}
    for n in spectra:
        kind_and_unit(n, scenario.where)
    return spectra


def psd_rows(names: Sequence[str], psd_channels: str | Sequence[str]) -> list[int]:
    """Rows of ``names`` whose PSD map a result keeps: "key" (the key channels,
    :func:`tb_exudyn.system.labels.default_patterns`: those with checks and those of the reference
    study's figures), "all", or glob patterns."""
    if psd_channels == "all":
        return list(range(len(names)))
    pats = [p for _, group in default_patterns(names) for p in group] if psd_channels == "key" else (
        [psd_channels] if isinstance(psd_channels, str) else list(psd_channels))
    return [i for i, n in enumerate(names) if any(fnmatch.fnmatchcase(n, p) for p in pats)]


def psd_z_rows(plan: ReductionPlan, psd_rows: Sequence[int] | None) -> IntArray | None:
    """The z rows a task must keep PSD maps of for the result rows ``psd_rows`` (None: all rows, all
    z): a linear row's own z, a ratio's numerator and denominator (its cross term is kept for every
    ratio); Sperling rows have none. What :func:`~tb_exudyn.methods.reduction.finish_pem_task` reads, so a worker builds and
    sends only these maps."""
    if psd_rows is None:
        return None
    ratio_at = {int(r[0]): (int(r[1]), int(r[2])) for r in plan.ratios}
    z: set[int] = set()
    for r in psd_rows:
        if plan.result_z[int(r)] >= 0:
            z.add(int(plan.result_z[int(r)]))
        elif int(r) in ratio_at:
            z.update(ratio_at[int(r)])
    return np.array(sorted(z), dtype=np.int64)


def check_psd_channels(names: Sequence[str] | None, psd_channels: Any, where: str) -> None:
    """SettingError for a ``psd_channels`` that is not "key", "all" or glob patterns each matching one
    of the result channels ``names`` (None: the form only); ``where``: the caller (the command line
    names --psd-channels)."""
    key = "--psd-channels" if where == "command line" else "psd_channels"
    allowed = "'key', 'all', or glob patterns of result channels (e.g. 'car1.body.*'; channels.txt lists them)"
    if psd_channels in ("key", "all"):
        return
    pats = [psd_channels] if isinstance(psd_channels, str) else psd_channels
    if not isinstance(pats, (list, tuple)) or not pats or not all(isinstance(p, str) and p.strip() for p in pats):
        raise SettingError(where, key, psd_channels, allowed)
    for p in pats if names is not None else ():
        if not any(fnmatch.fnmatchcase(n, p) for n in names):
            raise SettingError(where, key, p, allowed, "matches no channel of this scenario")


def run(scenario: Scenario, engine: str, execution: Execution, *, options: Any = None, keep_psd: bool = True,
        psd_channels: str | Sequence[str] = "key",
        grid_error: bool | None = None, least_count: bool = False) -> RandomResponse:
    """The PEM sweep of ``scenario`` on ``engine``; see :func:`tb_exudyn.run_pem`. ``least_count``:
    an adaptive grid gets at least the count its rules need (:func:`.common.analysis_setup`; the
    result's scenario then has that ``analysis.n_freq``)."""
    t0 = _time.perf_counter()
    check_run_length(scenario)
    cls = check_engine(engine, scenario, options)
    spectra = prepare_sweep(scenario)
    setup = analysis_setup(scenario, least_count=least_count)
    scenario = setup.scenario
    grid = setup.grid
    check_grid_against_spectra(grid, scenario, spectra)
    if grid_error is None:  # cheap where the columns are integrated together
        grid_error = not cls.single_columns
    grid_error = bool(grid_error) and grid.rule == "trapezoid" and grid.f.size > 1
    psd_spec = tuple(psd_channels) if isinstance(psd_channels, (list, tuple)) else psd_channels
    check_psd_channels(None, psd_spec, execution.where)  # the form, before anything is built
    identity = fingerprint_identity(
        scenario_to_toml(scenario), method="pem", engine=engine, engine_options=cls.describe_options(options),
        method_options={"keep_psd": keep_psd, "psd_channels": psd_spec, "grid_error": grid_error, "grid": grid.f.tolist(),
                        "reduction": REDUCTION_FORMAT}, spectra=scenario.track.irregularities)
    n_types = len(spectra)
    model = setup.model
    plan = model_plan(model)  # the workers' engines have the same outputs and derived channels
    rows_kept = psd_rows(plan.names, psd_spec) if keep_psd else []
    if keep_psd:
        check_psd_channels(plan.names, psd_spec, execution.where)
    z_kept = psd_z_rows(plan, rows_kept)
    psd_z = tuple(int(z) for z in z_kept) if keep_psd and z_kept is not None else None  # a task keeps only these maps
    ptasks = pem_tasks(scenario, grid)
    mid = midpoint_grid(grid) if grid_error else None
    mid_tasks = pem_tasks(scenario, mid) if mid is not None else []
    tasks = [Task("pem-mean", MeanTask())]
    if cls.single_columns:
        tasks += [Task(f"pem-{p.type_index}-{p.freq_index:05d}", ColumnTask((p,), keep_psd, psd_z=psd_z)) for p in ptasks]
        tasks += [Task(f"pemm-{p.type_index}-{p.freq_index:05d}", ColumnTask((p,), False, True)) for p in mid_tasks]
    else:
        weights = slice_weights(cls, options, execution.cores, len(ptasks)) if execution.slices is None else execution.slices
        tasks += column_slices(ptasks, weights, keep_psd, psd_z=psd_z)
        if mid_tasks:  # after the loads are level: equal slices
            mid_weights = [1.0] * max(1, execution.cores) if execution.slices is None else execution.slices
            tasks += column_slices(mid_tasks, mid_weights, False, "pemm", True)
    sizing = PemSizing(
        n_freq=int(grid.f.size), n_types=n_types, keep_psd=keep_psd, workers=execution.worker_processes(len(tasks)),
        task_freqs=max((len({p.freq_index for p in t.data.columns}) for t in tasks[1:]), default=0),
        output_step=scenario.analysis.output_step, limit=execution.worker_limit(), where=scenario_where(scenario),
        psd_channels=len(rows_kept), psd_task_rows=None if psd_z is None else len(psd_z), where_option=execution.where)
    state: dict[str, Any] = {}

    def reduce(i: int, task: Task, result: dict[str, np.ndarray]) -> None:
        if isinstance(task.data, MeanTask):
            state["mean"] = result
            n_ch, n_t = result["mean"].shape
            if tuple(str(c) for c in result["names"]) != plan.names:
                raise RuntimeError(f"task {task.key}: the mean's channels are not the plan's")
            state["rows"] = rows = mean_rows(plan, result["outputs"], result["time"])
            state["coef"] = ratio_coefficients(plan, rows) if plan.ratios else None
            state["var"] = np.zeros((n_types, n_ch, n_t))
            state["sums"] = {k: np.zeros(shape) for k, shape in (
                ("dvar", (n_t, n_ch)), ("dcov", (n_t, n_ch)), ("lam", (n_t, 2, n_ch)),
                ("sperling_power", (n_t, len(plan.sperling))))}
            # zero pages: touched once, below
            state["psd"] = np.zeros((len(rows_kept), grid.f.size, n_t), dtype=PSD_STORAGE) if keep_psd else None
            for message in result["warnings"]:
                warnings.warn(str(message), stacklevel=4)
            return
        result = {**result, **finish_pem_task(result, plan, state["coef"], None if task.data.midpoints else rows_kept)}
        var_t = result["var_t"]
        if task.data.midpoints:  # the grid error's sweep: sigma^2 only
            state.setdefault("var_mid", np.zeros_like(state["var"]))
            state["var_mid"] += var_t.transpose(1, 2, 0)
            return
        for key, total in state["sums"].items():
            total += result[key]
        var = state["var"]
        if var_t.shape != (var.shape[2], n_types, var.shape[1]):
            raise RuntimeError(f"task {task.key}: result shape {var_t.shape} does not fit the mean's {var.shape[1:]}")
        var += var_t.transpose(1, 2, 0)
        state["describe"] = json.loads(str(result["describe"]))
        if state["psd"] is not None:
            k, part = result["freq_index"], result["psd"]  # the kept rows (finish_pem_task)
            whole = len({p.type_index for p in task.data.columns}) == n_types  # every type of its frequencies
            if k.size and np.array_equal(k, np.arange(k[0], k[0] + k.size)):
                view = state["psd"][:, k[0]:k[0] + k.size, :]  # into a view: no temporary
                if whole:
                    view[...] = part  # the only task of these frequencies: 0 + x, bitwise
                else:
                    view += part
            else:
                state["psd"][:, k, :] += part

    with execution.claim(RunFiles("pem", "checkpoint")) as out:
        checkpoint = execution.checkpoint("checkpoint", identity)
        stats = execution.run(tasks, setup=_setup, setup_args=(engine, scenario, options, sizing), work=_work,
                              reduce=reduce, checkpoint=checkpoint, desc=f"PEM ({engine})")
        extra = {
            "method": "pem",
            "derivatives": plan.derivative_sources(),
            "derived_channels": derived_provenance(model.derived_catalogue, model.derived),
            "linearization": scenario.analysis.linearization,
            "seconds": _time.perf_counter() - t0,
            "n_frequencies": int(grid.f.size),
            "n_frequencies_in_band": int(band_mask(grid, scenario).sum()),
            "quadrature": grid.rule,
            "columns": len(ptasks),
            "grid_spacing": scenario.analysis.freq_spacing,
            **setup.provenance(),
            **stats,
        }
        result = _result(scenario, grid, spectra, plan, state, extra, setup.messages(), grid_error, engine,
                         [plan.names[i] for i in rows_kept])
        if out is not None:
            result.save(out / "pem")
    return result


def _result(scenario: Scenario, grid: FrequencyGrid, spectra: dict[str, Any], plan: ReductionPlan,
            state: dict[str, Any], extra: dict[str, Any], messages: list[str], grid_error: bool, engine: str,
            psd_names: list[str]) -> RandomResponse:
    """The sweep's RandomResponse from the reduced state (``extra``: the method's provenance,
    ``messages``: the set-up's warnings)."""
    mean = state["mean"]
    channels = tuple(str(c) for c in mean["names"])
    var_by_type = state["var"]
    stats_ = finish_pem(plan, mean["mean"], mean["time"], state["rows"], state["coef"], var_by_type.sum(axis=0),
                        **state["sums"])
    error = None
    if grid_error:
        plain = np.sqrt(var_by_type.sum(axis=0))
        refined = np.sqrt(refined_variance(var_by_type.sum(axis=0), state["var_mid"].sum(axis=0)))
        precision = state.get("describe", {}).get("grid_error_precision")
        method = GridError.method + (f" (the midpoints in {precision})" if precision else "")
        error = grid_error_from_sigma(mean["time"], channels, plain, refined, method)
        for message in grid_error_messages(error):
            warnings.warn(message, GridErrorWarning, stacklevel=4)
    provenance = merge_provenance(mean, state.get("describe", {"engine": engine}), {
        **extra,
        "grid_error": error.as_dict() if error is not None else
        "not estimated (an engine that runs columns separately: the midpoint sweep would double the runs)",
    })
    provenance["warnings"] = list(provenance.get("warnings", [])) + messages + (
        grid_error_messages(error) if error is not None else [])
    return RandomResponse(
        method="pem", time=mean["time"], channels=channels,
        units=tuple(str(u) for u in mean["units"]), mean=stats_.mean, std=stats_.std,
        band=grid.band, scenario=scenario, freq=grid.f, df=grid.df, psd=state["psd"], var_by_type=var_by_type,
        psd_channels=None if state["psd"] is None else tuple(psd_names),
        types=tuple(spectra), provenance=provenance, mean_rate=stats_.mean_rate, std_rate=stats_.std_rate,
        rho=stats_.rho, bandwidth=stats_.bandwidth,
    )


__all__ = ["ColumnTask", "PemSizing", "PemTask", "PsdReducer", "column_frequencies", "column_slices", "default_slices", "slice_weights",
           "harmonic_columns", "kind_and_unit", "pem_memory", "pem_tasks", "prepare_sweep", "psd_rows", "psd_z_rows", "reducer_column_bytes", "run"]
