"""The PEM frequency grid and its quadrature weights.

The grid is temporal frequency f [Hz] (what users see). A run at speed v excites spatial frequency
Omega = 2 pi f / v [rad/m], i.e. wavelength v / f. Each grid point carries a width df (its quadrature
weight) so that the band variance of a spectrum S is sum_k S_hz(f_k) df_k: the trapezoid rule, so the
band is exactly [freq_min, freq_max] (the two end nodes carry half a spacing). The irregularity is
taken as zero outside the track's wavelength band [wavelength_min, wavelength_max], which is stated
with every sigma.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Sequence

import numpy as np
from numpy.typing import NDArray

from ..errors import SettingError
from ..scenario import Scenario, ScenarioError
from ..system.conventions import spatial_frequency
from ..track import quadrature_weights
from .adaptive_grid import (GridProblem, GridResolution, Mode, adaptive_nodes, points_needed, required_spacing,
                            scenario_grid_problem)


@dataclass(frozen=True)
class FrequencyGrid:
    """Frequencies [Hz], their quadrature widths [Hz], and the spatial equivalents at speed v."""

    f: np.ndarray
    df: np.ndarray
    speed: float
    rule: str = "trapezoid"

    @property
    def omega_spatial(self) -> np.ndarray:
        """Spatial circular frequencies [rad/m]."""
        return spatial_frequency(self.f, self.speed)

    @property
    def d_omega_spatial(self) -> np.ndarray:
        """Spatial quadrature widths [rad/m]."""
        return spatial_frequency(self.df, self.speed)

    @property
    def band(self) -> tuple[float, float]:
        """The band the quadrature covers [Hz]."""
        if self.rule == "trapezoid" and self.f.size > 1:
            return float(self.f[0]), float(self.f[-1])
        return float(self.f[0] - self.df[0] / 2), float(self.f[-1] + self.df[-1] / 2)


def frequency_grid(
    f_min: float, f_max: float, n: int, speed: float, spacing: str = "linear", given: np.ndarray | None = None
) -> FrequencyGrid:
    """A grid of n frequencies from f_min to f_max (nodes include both ends), or the ``given`` one.

    'linear': equally spaced; 'log': equally spaced in log f. Widths: trapezoid rule.
    A single frequency lies at the band's middle with the width f_max - f_min (or f_min if they are
    equal) as a mid-point cell, so that the cell is the band (at f_min it reached below 0 Hz).
    """
    if given is not None and len(given):
        f = np.asarray(given, dtype=float)
    elif n == 1:
        f = np.array([0.5 * (f_min + f_max)])  # the middle of the band: its cell spans [f_min, f_max]
    elif spacing == "linear":
        f = np.linspace(f_min, f_max, n)
    elif spacing == "log":
        f = np.geomspace(f_min, f_max, n)
    else:
        raise SettingError("frequency_grid", "spacing", spacing, "'linear' or 'log'")
    if f.size == 1:
        return FrequencyGrid(f=f, df=np.array([f_max - f_min if f_max > f_min else f_min]), speed=float(speed),
                             rule="midpoint")
    return FrequencyGrid(f=f, df=quadrature_weights(f, "trapezoid"), speed=float(speed), rule="trapezoid")


def scenario_grid(scenario: Scenario, modes: Sequence[Mode] | None = None) -> FrequencyGrid:
    """The scenario's PEM grid (Analysis.freq_min, freq_max, n_freq, freq_spacing); an adaptive grid
    needs the system's ``modes`` ((frequency [Hz], damping ratio) pairs: :mod:`.adaptive_grid`)."""
    a = scenario.analysis
    if a.freq_spacing == "adaptive":
        if modes is None:
            raise ValueError("an adaptive grid needs the system's modes (frequency, damping ratio)")
        return scenario_adaptive_grid(scenario, modes)
    return frequency_grid(a.freq_min, a.freq_max, a.n_freq, scenario.speed, a.freq_spacing)


def adaptive_grid(problem: GridProblem, speed: float, n_max: int,
                  resolution: GridResolution = GridResolution()) -> FrequencyGrid:
    """The adaptive grid with n_max nodes and its trapezoid weights (band exactly [f_min, f_max]) at
    train speed ``speed`` [m/s]. ValueError (giving the count needed) when n_max is below
    :func:`points_needed`."""
    needed = points_needed(problem, resolution)
    if n_max < needed:
        raise ValueError(f"the adaptive grid needs at least {needed} frequencies, {n_max} allowed")
    f = adaptive_nodes(problem, n_max, resolution)
    return FrequencyGrid(f=f, df=quadrature_weights(f, "trapezoid"), speed=float(speed), rule="trapezoid")


def scenario_adaptive_grid(scenario: Scenario, modes: Sequence[Mode],
                           resolution: GridResolution = GridResolution()) -> FrequencyGrid:
    """The scenario's PEM grid for ``analysis.freq_spacing = "adaptive"``: analysis.n_freq nodes placed
    for :func:`scenario_grid_problem`.

    ScenarioError naming ``analysis.n_freq`` when n_freq is below what the modes and the run need.
    """
    a = scenario.analysis
    problem = scenario_grid_problem(scenario, modes)
    needed = points_needed(problem, resolution)
    if a.n_freq < needed:
        T, m = problem.duration, problem.modes
        inside = m[(m[:, 0] >= a.freq_min) & (m[:, 0] <= a.freq_max)]
        light = inside[2 * math.pi * inside[:, 1] * inside[:, 0] * T < 1.0]  # decay time 1/(zeta w) > T
        detail = f"{len(inside)} modes"
        if len(light):
            f_l = light[np.argmin(light[:, 0] * light[:, 1]), 0]
            detail += f", {len(light)} outlasting the {T:.3g} s run (e.g. {f_l:.4g} Hz)"
        raise ScenarioError(
            scenario.where, "analysis.n_freq", a.n_freq,
            f"at least {needed}, or a shorter run or band",
            f"too few for {detail}",
        )
    return adaptive_grid(problem, scenario.speed, a.n_freq, resolution)


def midpoint_grid(grid: FrequencyGrid) -> FrequencyGrid:
    """The midpoints of a trapezoid grid's cells, each with its cell's width (the mid-point rule).

    A sweep on it refines the grid's trapezoid sum without recomputing a column: the trapezoid rule on
    the nodes and midpoints together is (trapezoid + midpoint) / 2 cell by cell, so its variance is
    (var(grid) + var(midpoint_grid(grid))) / 2 (:func:`refined_variance`).
    """
    if grid.rule != "trapezoid" or grid.f.size < 2:
        raise ValueError("midpoint_grid needs a trapezoid grid of at least 2 nodes")
    f = np.asarray(grid.f, dtype=float)
    return FrequencyGrid(f=(f[1:] + f[:-1]) / 2, df=np.diff(f), speed=grid.speed, rule="midpoint")


def refined_variance(var_trapezoid: NDArray[np.float64], var_midpoint: NDArray[np.float64]) -> NDArray[np.float64]:
    """Variance on the grid with its midpoints added (trapezoid rule on the union of nodes) from the
    grid's variance and the variance of the sweep on :func:`midpoint_grid` (any matching shapes)."""
    a, b = np.asarray(var_trapezoid, dtype=float), np.asarray(var_midpoint, dtype=float)
    if a.shape != b.shape:
        raise ValueError(f"variance shapes differ: {a.shape} and {b.shape}")
    return (a + b) / 2


#: the local estimate refines the cells wider than LOCAL_RATIO times the spacing the adaptive grid's
#: rules require there (:func:`estimate_cells`; measured in docs/speed.md, "The grid-error estimate at
#: a fraction of its cost")
LOCAL_RATIO = 1.5


def estimate_cells(grid: FrequencyGrid, problem: GridProblem, ratio: float = LOCAL_RATIO,
                   resolution: GridResolution = GridResolution()) -> NDArray[np.bool_]:
    """(n - 1,) True for the cells of a trapezoid grid that the local estimate refines: those wider than
    ``ratio`` times :func:`~.adaptive_grid.required_spacing` at their midpoint, i.e. where the grid is
    coarser than the rules of docs/adaptive_grid.md ask for (a damped mode's peak, the run's length near
    a lightly damped one: the aliasing regime). A cell that meets the rules is taken as converged."""
    if grid.rule != "trapezoid" or grid.f.size < 2:
        raise ValueError("estimate_cells needs a trapezoid grid of at least 2 nodes")
    f = np.asarray(grid.f, dtype=float)
    return np.diff(f) > ratio * required_spacing(problem, (f[1:] + f[:-1]) / 2, resolution)


def local_grids(grid: FrequencyGrid, cells: NDArray[np.bool_]) -> tuple[FrequencyGrid, FrequencyGrid]:
    """The midpoints of the chosen ``cells`` (each with its cell's width) and the nodes of those cells
    with the trapezoid weights of the chosen cells alone (half of each chosen neighbour cell): a sweep
    on each gives the chosen cells' midpoint and trapezoid sums, M and T, and the grid refined on those
    cells only has the variance var(grid) + (M - T) / 2 (:func:`locally_refined_variance`)."""
    f, cells, w = _local_weights(grid, cells)
    h, nodes = np.diff(f), w > 0
    return (FrequencyGrid(f=(f[1:] + f[:-1])[cells] / 2, df=h[cells], speed=grid.speed, rule="midpoint"),
            FrequencyGrid(f=f[nodes], df=w[nodes], speed=grid.speed, rule="trapezoid"))


def _local_weights(grid: FrequencyGrid, cells: NDArray[np.bool_]) -> tuple[NDArray[np.float64], NDArray[np.bool_], NDArray[np.float64]]:
    """The grid's nodes, the cell flags and each node's trapezoid weight over the chosen cells alone."""
    f = np.asarray(grid.f, dtype=float)
    cells = np.asarray(cells, dtype=bool)
    if grid.rule != "trapezoid" or cells.shape != (f.size - 1,):
        raise ValueError("local_grids needs a trapezoid grid and one flag per cell")
    half = np.where(cells, np.diff(f) / 2, 0.0)
    w = np.zeros(f.size)
    w[:-1] += half
    w[1:] += half
    return f, cells, w


def local_node_factors(grid: FrequencyGrid, cells: NDArray[np.bool_]) -> dict[int, float]:
    """Grid index -> the factor of the local estimate's node sum T at that node: its trapezoid weight
    over the chosen cells alone (the node grid of :func:`local_grids`) divided by the grid's own
    weight. A PEM column's |y|^2 is proportional to its quadrature width (its amplitude is
    sqrt(S(f) d_omega)), so T is the grid's own columns' |y|^2 summed with these factors: the node
    sweep of :func:`local_grids` without integrating its columns again."""
    _, _, w = _local_weights(grid, cells)
    df = np.asarray(grid.df, dtype=float)
    return {int(k): float(w[k] / df[k]) for k in np.flatnonzero(w > 0)}


def locally_refined_variance(var_grid: NDArray[np.float64], var_mid: NDArray[np.float64],
                             var_nodes: NDArray[np.float64]) -> NDArray[np.float64]:
    """Variance on the grid with the midpoints of some cells added, from the grid's variance and the
    sweeps on :func:`local_grids` (any matching shapes): var_grid + (M - T) / 2, at least 0 (M and T
    may come in a lower precision than the grid's own columns). With every cell chosen, T is the grid's
    own sum and this is :func:`refined_variance`."""
    a, m, t = (np.asarray(x, dtype=float) for x in (var_grid, var_mid, var_nodes))
    if not a.shape == m.shape == t.shape:
        raise ValueError(f"variance shapes differ: {a.shape}, {m.shape} and {t.shape}")
    return np.maximum(a + (m - t) / 2, 0.0)


def refined_grid(grid: FrequencyGrid) -> FrequencyGrid:
    """The grid's nodes and midpoints together, with their trapezoid weights."""
    f = np.sort(np.concatenate((grid.f, midpoint_grid(grid).f)))
    return FrequencyGrid(f=f, df=quadrature_weights(f, "trapezoid"), speed=grid.speed, rule="trapezoid")


def band_mask(grid: FrequencyGrid, scenario: Scenario) -> np.ndarray:
    """True where the grid's wavelength v / f lies in the track's wavelength band."""
    wavelength = grid.speed / grid.f
    t = scenario.track
    return (wavelength >= t.wavelength_min * (1 - 1e-12)) & (wavelength <= t.wavelength_max * (1 + 1e-12))


def check_grid_against_spectra(grid: FrequencyGrid, scenario: Scenario, spectra: dict) -> None:
    """Every spectrum must be valid over the part of the grid inside the wavelength band.

    Raises ScenarioError naming the scenario key, before any run starts.
    """
    mask = band_mask(grid, scenario)
    if not mask.any():
        raise ScenarioError(
            scenario.where, "analysis.freq_min", scenario.analysis.freq_min,
            f"a band overlapping the track's {scenario.speed / scenario.track.wavelength_max:.4g}-"
            f"{scenario.speed / scenario.track.wavelength_min:.4g} Hz (its wavelengths at {scenario.speed:.4g} m/s)",
            "no PEM frequency in the wavelength band",
        )
    omega = grid.omega_spatial[mask]
    for name, spectrum in spectra.items():
        lo, hi = spectrum.validity
        if omega.min() < lo * (1 - 1e-9) or omega.max() > hi * (1 + 1e-9):
            raise ScenarioError(
                scenario.where, "track.wavelength_min", scenario.track.wavelength_min,
                f"wavelengths within the validity of {name}: {2 * math.pi / hi:.4g}-{2 * math.pi / lo:.4g} m",
                "frequency band outside the spectrum's validity",
            )
