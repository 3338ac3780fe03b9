"""The pseudo-excitation method (PEM): the frequency sweep, on any engine.

For each irregularity spectrum S (one-sided, rad/m) and grid frequency f_k [Hz] with width df_k, the
pseudo-irregularity at wheel j is r~_j(t) = a_k exp(i Omega_k (v t - a_j)), Omega_k = 2 pi f_k / v,
a_k = sqrt(S(Omega_k) dOmega_k) = sqrt(S_hz(f_k) df_k): one complex column of
:class:`~tb_exudyn.system.columns.HarmonicColumns`. The system is linear in the irregularity, so the
engine integrates each column's response y~ (the Exudyn engine as two real runs, the linear engines
all columns at once), and with independent spectra adding

    S_y(f_k, t) = sum over spectra |y~_k(t)|^2 / df_k         (one-sided PSD per Hz)
    sigma_y^2(t) = sum_k S_y(f_k, t) df_k                      (over the analysed band)

(:class:`PsdReducer`); the mean is the deterministic run (gravity, no irregularity), Exudyn's, as a
task of its own. Frequencies whose wavelength v / f lies outside the track's wavelength band carry no
irregularity (PSD zero there).

Tasks: an engine that runs columns separately (``single_columns``) gets one task per column; the
others get slices of contiguous frequencies (every type of a frequency in the same slice), one per
core and a half one (:func:`default_slices`): on as many workers as cores, the worker that runs the
mean takes a full slice after it and another the half slice. A result never depends on the number of
workers, the executor or a resume (bitwise), and on the slicing only at round-off.
"""

from __future__ import annotations

import json
import math
import time as _time
import warnings
from dataclasses import dataclass
from typing import Any, Sequence

import numpy as np
from numpy.typing import NDArray

from ..engines import check_engine, make_engine
from ..errors import ScenarioError
from ..execution import Execution, Task
from ..results.random_response import RandomResponse
from ..scenario import Scenario, scenario_to_toml
from ..system.columns import HarmonicColumns
from ..system.conventions import cross_level_scale, spatial_frequency
from ..system.excitation import KINDS
from ..track import get_spectrum
from .common import MeanTask, fingerprint_identity, mean_of, merge_provenance
from .grid import FrequencyGrid, band_mask, check_grid_against_spectra, scenario_grid

#: precision in which a task's PSD map travels to the parent (sigma^2 is float64 throughout):
#: float32's relative rounding of 6e-8 is far below the engines' agreement of 1e-6 and halves the
#: largest messages (the reference study's map is 420 MB in float64)
PSD_TRANSPORT = np.float32
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
    """A set of columns (every type of a set of frequencies, or one column) integrated together."""

    columns: tuple[PemTask, ...]
    keep_psd: bool


def kind_and_unit(spectrum_name: str) -> tuple[str, str]:
    """The coupling's input kind for a spectrum and, for cross-level, whether it is an angle or a height."""
    s = get_spectrum(spectrum_name)
    if s.kind not in KINDS:
        raise ScenarioError(
            None, "track.irregularities", spectrum_name,
            "vertical, alignment or cross-level spectra (gauge irregularity does not excite this model)",
            "irregularity kind not modelled",
        )
    return s.kind, ("height" if s.unit == "m" else "angle")


def pem_tasks(scenario: Scenario, grid: FrequencyGrid) -> list[PemTask]:
    """One column per (spectrum, frequency inside the wavelength band), in a fixed order (type-major)."""
    mask = band_mask(grid, scenario)
    out = []
    for ti, name in enumerate(scenario.track.irregularities):
        s = get_spectrum(name)
        for k in np.flatnonzero(mask):
            omega, d_omega = grid.omega_spatial[k], grid.d_omega_spatial[k]
            amp = math.sqrt(float(s.psd(omega)) * d_omega)
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


class PsdReducer:
    """PEM's reduction at an output time: |y~|^2 summed per type (sigma^2) and, with ``keep_psd``,
    summed over types and divided by df (the PSD map, gathered in blocks of output times)."""

    def __init__(self, columns: HarmonicColumns, n_ch: int, n_t: int, n_types: int, keep_psd: bool) -> None:
        m, n_f = columns.width, columns.freq_index.size
        self.columns = columns
        self.var = np.zeros((n_t, n_types, n_ch))
        self.psd = np.zeros((n_ch, n_f, n_t), dtype=PSD_TRANSPORT) if keep_psd else None
        self.per_freq = np.zeros((n_ch, n_f))
        self.block = np.zeros((n_ch, n_f, PSD_BLOCK), dtype=PSD_TRANSPORT)  # output times gathered before a write
        self.P2, self.power = np.zeros((n_ch, 2 * m)), np.zeros((n_ch, m))
        self.type_sum = np.zeros((m, n_types))  # (m, n_types): which type each column is
        self.type_sum[np.arange(m), columns.type_index] = 1.0
        self.by_type = np.zeros((n_ch, n_types))
        self.inv_df = 1.0 / columns.df
        self.n_t = n_t

    def record(self, i: int, Y: ComplexArray, ext: IntArray) -> None:
        """Reduce the columns' outputs Y (internal channel order; ``ext``: internal row of each channel)."""
        P2, power, nty = self.P2, self.power, self.columns.n_types
        np.multiply(Y.view(np.float64), Y.view(np.float64), out=P2)
        np.add(P2[:, 0::2], P2[:, 1::2], out=power)  # |y~|^2 (no reductions over short axes: slow)
        np.matmul(power, self.type_sum, out=self.by_type)
        self.var[i] = self.by_type[ext].T
        if self.psd is not None:
            per_freq = self.per_freq
            p3 = power.reshape(power.shape[0], -1, nty)
            per_freq[:] = p3[:, :, 0]
            for ti in range(1, nty):
                np.add(per_freq, p3[:, :, ti], out=per_freq)
            np.multiply(per_freq, self.inv_df, out=per_freq)
            self.block[:, :, i % PSD_BLOCK] = per_freq[ext]
            if i % PSD_BLOCK == PSD_BLOCK - 1 or i == self.n_t - 1:  # a strided write per time: 3x slower
                i0 = i - i % PSD_BLOCK
                self.psd[:, :, i0:i + 1] = self.block[:, :, : i + 1 - i0]

    def result(self) -> dict[str, np.ndarray]:
        out = {"var_t": self.var, "freq_index": self.columns.freq_index}
        if self.psd is not None:
            out["psd"] = self.psd
        return out


# ---------------------------------------------------------------------------------- tasks
def default_slices(cores: int) -> list[float]:
    """Slice weights: one per core and a half one (see the module docstring: the mean costs about half
    a slice's share, one Exudyn run against the batched columns)."""
    return [1.0] * max(1, cores) + [0.5]


def column_slices(ptasks: Sequence[PemTask], weights: Sequence[float], keep_psd: bool) -> list[Task]:
    """The sweep's (type, frequency) pairs cut into tasks of contiguous frequencies (all types of a
    frequency in the same task) with numbers of frequencies in proportion to ``weights``."""
    freqs = np.array(sorted({p.freq_index for p in ptasks}))
    w = np.asarray(weights, dtype=float)[: freqs.size]
    edges = np.unique(np.round(np.concatenate(([0.0], np.cumsum(w) / w.sum())) * freqs.size).astype(int))
    out = []
    for a, b in zip(edges[:-1], edges[1:]):
        chosen = set(freqs[a:b].tolist())
        cols = tuple(p for p in ptasks if p.freq_index in chosen)
        out.append(Task(f"pemb-{freqs[a]:05d}-{freqs[b - 1]:05d}", ColumnTask(cols, keep_psd)))
    return out


def _setup(engine: str, scenario: Scenario, options: Any) -> Any:
    """Build the engine (and its model) once per worker."""
    return make_engine(engine, scenario, options)


def _work(engine: Any, task: Task) -> dict[str, np.ndarray]:
    if isinstance(task.data, MeanTask):
        return engine.mean()
    data: ColumnTask = task.data
    columns = harmonic_columns(data.columns, engine.scenario)
    n_types = len(engine.scenario.track.irregularities)
    reducer = PsdReducer(columns, len(engine.outputs.names), engine.steps.n_outputs, n_types, data.keep_psd)
    result = engine.integrate(columns, reducer)
    result["describe"] = np.array(json.dumps(engine.describe()))
    return result


# ---------------------------------------------------------------------------------- the sweep
def prepare_sweep(scenario: Scenario) -> tuple[FrequencyGrid, dict[str, Any]]:
    """Checks before any run: irregularities present and modelled, the grid inside every spectrum's
    validity and the wavelength band. Returns the grid and the spectra."""
    if not scenario.track.irregularities:
        raise ScenarioError(None, "track.irregularities", [], "at least one spectrum name", "no irregularity to analyse")
    grid = scenario_grid(scenario)
    spectra = {n: get_spectrum(n) for n in scenario.track.irregularities}
    for n in spectra:
        kind_and_unit(n)
    check_grid_against_spectra(grid, scenario, spectra)
    return grid, spectra


def run(scenario: Scenario, engine: str, execution: Execution, *, options: Any = None, keep_psd: bool = True
        ) -> RandomResponse:
    """The PEM sweep of ``scenario`` on ``engine``; see :func:`tb_exudyn.run_pem`."""
    t0 = _time.perf_counter()
    cls = check_engine(engine, scenario, options)
    grid, spectra = prepare_sweep(scenario)
    checkpoint = execution.checkpoint("checkpoint", fingerprint_identity(
        scenario_to_toml(scenario), method="pem", engine=engine, engine_options=cls.describe_options(options),
        method_options={"keep_psd": keep_psd}))
    ptasks = pem_tasks(scenario, grid)
    tasks = [Task("pem-mean", MeanTask())]
    if cls.single_columns:
        tasks += [Task(f"pem-{p.type_index}-{p.freq_index:05d}", ColumnTask((p,), keep_psd)) for p in ptasks]
    else:
        weights = default_slices(execution.cores) if execution.slices is None else execution.slices
        tasks += column_slices(ptasks, weights, keep_psd)
    n_types = len(spectra)
    state: dict[str, Any] = {}

    def reduce(i: int, task: Task, result: dict[str, np.ndarray]) -> None:
        if isinstance(task.data, MeanTask):
            state["mean"] = result
            n_ch, n_t = result["mean"].shape
            state["var"] = np.zeros((n_types, n_ch, n_t))
            state["psd"] = np.zeros((n_ch, grid.f.size, n_t)) if keep_psd else None  # zero pages: touched once, below
            for message in result["warnings"]:
                warnings.warn(str(message), stacklevel=4)
            return
        var_t = result["var_t"]
        var = state["var"]
        if var_t.shape != (var.shape[2], n_types, var.shape[1]):
            raise RuntimeError(f"task {task.key}: result shape {var_t.shape} does not fit the mean's {var.shape[1:]}")
        var += var_t.transpose(1, 2, 0)
        state["describe"] = json.loads(str(result["describe"]))
        if state["psd"] is not None:
            k = result["freq_index"]
            whole = len({p.type_index for p in task.data.columns}) == n_types  # every type of its frequencies
            if k.size and np.array_equal(k, np.arange(k[0], k[0] + k.size)):
                view = state["psd"][:, k[0]:k[0] + k.size, :]  # into a view: no temporary
                if whole:
                    view[...] = result["psd"]  # the only task of these frequencies: 0 + x, bitwise
                else:
                    view += result["psd"]
            else:
                state["psd"][:, k, :] += result["psd"]

    stats = execution.run(tasks, setup=_setup, setup_args=(engine, scenario, options), work=_work, reduce=reduce,
                          checkpoint=checkpoint, desc=f"PEM ({engine})")
    mean = state["mean"]
    provenance = merge_provenance(mean, state.get("describe", {"engine": engine}), {
        "method": "pem",
        "linearization": scenario.analysis.linearization,
        "seconds": _time.perf_counter() - t0,
        "n_frequencies": int(grid.f.size),
        "n_frequencies_in_band": int(band_mask(grid, scenario).sum()),
        "quadrature": grid.rule,
        "columns": len(ptasks),
        **stats,
    })
    var_by_type = state["var"]
    result = RandomResponse(
        method="pem", time=mean["time"], channels=tuple(str(c) for c in mean["names"]),
        units=tuple(str(u) for u in mean["units"]), mean=mean_of(mean), std=np.sqrt(var_by_type.sum(axis=0)),
        band=grid.band, scenario=scenario, freq=grid.f, df=grid.df, psd=state["psd"], var_by_type=var_by_type,
        types=tuple(spectra), provenance=provenance,
    )
    out = execution.output_folder()
    if out is not None:
        result.save(out / "pem")
    return result


__all__ = ["ColumnTask", "PemTask", "PsdReducer", "column_slices", "default_slices", "harmonic_columns",
           "kind_and_unit", "pem_tasks", "prepare_sweep", "run"]
