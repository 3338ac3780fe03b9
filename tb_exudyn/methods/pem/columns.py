"""PEM's columns and tasks: one (spectrum, frequency) pair per complex column, the columns of a task,
the reducer of a task's outputs (:class:`PsdReducer`) and the slices of contiguous frequencies the
sweep is cut into (the package docstring)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Sequence

import numpy as np
from numpy.typing import NDArray

from ...errors import ScenarioError
from ...execution import Task
from ...scenario import Scenario
from ...system.columns import HarmonicColumns
from ...system.conventions import cross_level_scale, spatial_frequency
from ...system.excitation import KINDS
from ...track import get_spectrum, track_spectrum
from ..grid import FrequencyGrid, band_mask
from ..pseudo_reduction import PseudoReduction
from ..reduction import ReductionPlan

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
    ``midpoints``: columns of the grid error's midpoint sweep (sigma^2 only); ``nodes``: (frequency
    index, factor) of the local grid-error estimate's nodes among the columns (their trapezoid weight
    over the grid's: the reducer's node sums, :class:`PsdReducer`)."""

    columns: tuple[PemTask, ...]
    keep_psd: bool
    midpoints: bool = False
    psd_z: tuple[int, ...] | None = None  # the z rows whose PSD maps the task keeps (None: all)
    nodes: tuple[tuple[int, float], ...] = ()


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
        s = track_spectrum(name, scenario.track.irregularity_level)
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
    """PEM's reduction at an output time (:class:`~tb_exudyn.methods.pseudo_reduction.PseudoReduction`, a
    :class:`~tb_exudyn.engines.protocols.Reducer`): per
    result channel (the scenario's channels and its derived channels) |y~|^2 summed per type (sigma^2),
    the PSD map with ``keep_psd`` (summed over types, divided by df; ``psd_z``: only of those z rows,
    :func:`psd_z_rows`), the time derivative's sums for
    the Rice rate, the ratios' cross sums and the Sperling inputs' weighted power.

    columns : the task's columns; f_col : (m,) excitation frequency of each column [Hz]; nodes:
    (frequency index, factor) of the local grid-error estimate's nodes (:class:`ColumnTask`)."""

    def __init__(self, columns: HarmonicColumns, plan: ReductionPlan, f_col: NDArray[np.float64], n_t: int,
                 n_types: int, dt: float, keep_psd: bool, psd_z: Sequence[int] | None = None,
                 variance_only: bool = False, compiled: bool = True,
                 nodes: Sequence[tuple[int, float]] = ()) -> None:
        self.columns = columns
        at = dict(nodes)
        weight = np.repeat([at.get(int(k), 0.0) for k in columns.freq_index], columns.n_types) if at else None
        super().__init__(plan, f_col, columns.type_index, n_types, columns.freq_index.size, columns.df, n_t, dt,
                         keep_psd, None if psd_z is None else np.asarray(psd_z, dtype=np.int64), variance_only,
                         compiled, weight)

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
                  midpoints: bool = False, psd_z: tuple[int, ...] | None = None,
                  nodes: dict[int, float] | None = None) -> list[Task]:
    """The sweep's (type, frequency) pairs cut into tasks of contiguous frequencies (all types of a
    frequency in the same task) with numbers of frequencies in proportion to ``weights``; ``nodes``:
    the local grid-error estimate's factor per frequency index (each task gets its own)."""
    freqs = np.array(sorted({p.freq_index for p in ptasks}))
    w = np.asarray(weights, dtype=float)[: freqs.size]
    edges = np.unique(np.round(np.concatenate(([0.0], np.cumsum(w) / w.sum())) * freqs.size).astype(int))
    out = []
    for a, b in zip(edges[:-1], edges[1:]):
        chosen = set(freqs[a:b].tolist())
        cols = tuple(p for p in ptasks if p.freq_index in chosen)
        mine = tuple((k, f) for k, f in sorted((nodes or {}).items()) if k in chosen)
        out.append(Task(f"{prefix}-{freqs[a]:05d}-{freqs[b - 1]:05d}", ColumnTask(cols, keep_psd, midpoints, psd_z, mine)))
    return out


__all__ = ["ColumnTask", "PemTask", "PsdReducer", "column_frequencies", "column_slices", "default_slices",
           "harmonic_columns", "kind_and_unit", "pem_tasks", "slice_weights"]
