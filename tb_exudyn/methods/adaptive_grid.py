"""An adaptive PEM frequency grid: fine where the system's modes and the run's length need it.

The PEM variance is a quadrature over frequency, sigma^2(t) = sum_k S_y(f_k, t) df_k (trapezoid rule,
docs/theory.md section 5). Its integrand has two kinds of narrow features:

- a mode of frequency f_m and damping ratio zeta: a resonance of half-power half-width b = zeta f_m
  [Hz] (half-power band 2 zeta f_m);
- the start-up of the run: a pseudo-response that started at t = 0 is, near a lightly damped mode, a
  Fejer-like kernel sin^2(pi (f - f_m) t) / (pi (f - f_m))^2 of width 1/t, which keeps sharpening
  until the run ends at t = T (the mode's response to a harmonic lasting T has a spectral width of
  about 1/T).

Seen from the lag (the Fourier variable of f), the integrand of a mode decays like
exp(-2 pi b |tau|) and, the response starting at t = 0, has no lag longer than the run (plus the
train's length / v for responses summed over axles). The trapezoid rule with spacing h sums the
integrand's aliases at lags 1/h, 2/h, ...: its relative error on a resonance is about
2 exp(-2 pi b / h) (Poisson summation), and it vanishes once 1/h exceeds the longest lag. So either
criterion is enough near a mode:

    h_m = max(b / halfwidth_points, 1 / (run_factor * T))            (spacing at the mode) [Hz]

with halfwidth_points = 1 (error about 2e-3 on a resonance) and run_factor = 2 (lags up to 2 T; the
study's train adds its spread, 1.5 s, to a 5.6 s run). Away from the mode, the spacing grows in
proportion to the distance, h = |f - f_m| / grade (a graded mesh: the resonance's tails
1/(f - f_m)^2 vary on the scale of the distance). Between modes, the background (the track spectra
fall like f^-2...-4) gets at most a relative spacing ``background_relative`` (h <= 0.05 f) and at most

    h_bg = 1 / (spread + 1 / background_max)                             [Hz]

where spread = train length (first to last axle) / v [s] is the longest delay between two wheels'
inputs: a bridge response sums the axles' contributions, whose cross terms oscillate in f with
periods down to 1 / spread, and the bridge modes' memory (5 % damping: 1/(2 pi zeta f) = 0.16 s at
20 Hz) adds to it; 1 / background_max = 0.5 s stands for that memory (a single axle's lag).

The needed spacing h(f) is the smallest of all these (:func:`required_spacing` of a
:class:`GridProblem`). The nodes equidistribute its inverse, the point density
(:func:`adaptive_nodes`): successive nodes lie at most one unit of integral(df / h) apart. The
weights are the trapezoid rule on the non-uniform nodes (:func:`tb_exudyn.track.quadrature_weights`),
so the band is exactly [f_min, f_max] and the weights sum to f_max - f_min; on a smooth density
the rule converges at second order. The values of :class:`GridResolution` come from the
measurements in docs/adaptive_grid.md.

The modes are plain data: a sequence of (frequency [Hz], damping ratio) pairs (e.g. the damped
eigenvalues of the linearised train-bridge system at one or more train positions); modes with a
damping ratio of 1 or more (no resonance) or a frequency <= 0 are ignored.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ..scenario import Scenario

#: a mode as plain data: (frequency [Hz], damping ratio [-])
Mode = tuple[float, float]


@dataclass(frozen=True)
class GridResolution:
    """What the adaptive grid must resolve (module docstring; values measured in docs/adaptive_grid.md).

    Attributes
    ----------
    run_factor : near a lightly damped mode, spacing <= 1 / (run_factor * duration) [-]
    halfwidth_points : near a damped mode, spacing <= zeta f / halfwidth_points (points per
        half-power half-width) [-]
    grade : away from a mode the spacing grows as |f - f_m| / grade [-]
    background_relative : background spacing <= background_relative * f [-]
    background_max : background spacing <= 1 / (spread + 1 / background_max) [Hz]: background_max
        for a single axle (spread 0)
    """

    run_factor: float = 2.0
    halfwidth_points: float = 1.0
    grade: float = 10.0
    background_relative: float = 0.05
    background_max: float = 2.0

    def __post_init__(self) -> None:
        for name in ("run_factor", "halfwidth_points", "grade", "background_relative", "background_max"):
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
                raise ValueError(f"GridResolution.{name} must be a positive number, got {value!r}")


def resonant_modes(modes: Sequence[Mode]) -> NDArray[np.float64]:
    """The modes as an (n, 2) array [frequency Hz, damping ratio], without those that have no resonance
    (damping ratio >= 1 or frequency <= 0); ValueError for a negative or non-finite damping ratio."""
    m = np.asarray(list(modes), dtype=float).reshape(-1, 2)
    if not np.all(np.isfinite(m)) or np.any(m[:, 1] < 0):
        raise ValueError("modes must be finite (frequency [Hz], damping ratio >= 0) pairs")
    return m[(m[:, 0] > 0) & (m[:, 1] < 1)]


@dataclass(frozen=True, eq=False)
class GridProblem:
    """What a grid must resolve.

    Attributes
    ----------
    f_min, f_max : the band [Hz], 0 < f_min < f_max
    modes : (n, 2) [frequency Hz, damping ratio] of the resonant modes (:func:`resonant_modes`)
    duration : the run's length T [s] (first axle at -lead_in until the last is run_out past the bridge)
    spread : the time between the first and the last axle passing a point, train length / v [s]
    """

    f_min: float
    f_max: float
    modes: NDArray[np.float64]
    duration: float
    spread: float = 0.0

    def __post_init__(self) -> None:
        if not (0 < self.f_min < self.f_max and math.isfinite(self.f_max)):
            raise ValueError(f"need 0 < f_min < f_max, got {self.f_min!r}, {self.f_max!r}")
        if not (self.duration > 0 and math.isfinite(self.duration)):
            raise ValueError(f"duration must be positive [s], got {self.duration!r}")
        if not (self.spread >= 0 and math.isfinite(self.spread)):
            raise ValueError(f"spread must be >= 0 [s], got {self.spread!r}")
        object.__setattr__(self, "modes", resonant_modes(self.modes))


def grid_problem(f_min: float, f_max: float, modes: Sequence[Mode], duration: float,
                 spread: float = 0.0) -> GridProblem:
    """A :class:`GridProblem` from plain values (modes: (frequency [Hz], damping ratio) pairs)."""
    return GridProblem(float(f_min), float(f_max), resonant_modes(modes), float(duration), float(spread))


def mode_spacing(problem: GridProblem, resolution: GridResolution = GridResolution()) -> NDArray[np.float64]:
    """h_m = max(zeta f / halfwidth_points, 1 / (run_factor * duration)) [Hz] at every resonant mode."""
    f, zeta = problem.modes[:, 0], problem.modes[:, 1]
    return np.maximum(zeta * f / resolution.halfwidth_points, 1.0 / (resolution.run_factor * problem.duration))


def background_spacing(problem: GridProblem, resolution: GridResolution = GridResolution()) -> float:
    """The background's largest spacing 1 / (spread + 1 / background_max) [Hz] (module docstring)."""
    return 1.0 / (problem.spread + 1.0 / resolution.background_max)


def required_spacing(problem: GridProblem, f: NDArray[np.float64],
                     resolution: GridResolution = GridResolution()) -> NDArray[np.float64]:
    """The largest grid spacing [Hz] allowed at frequencies f [Hz] (module docstring):

        h(f) = min( background_relative f, 1 / (spread + 1 / background_max),
                    min over modes sqrt(h_m^2 + ((f - f_m) / grade)^2) ).
    """
    f = np.asarray(f, dtype=float)
    bg = background_spacing(problem, resolution)
    ff = f.reshape(-1)
    flat = np.minimum(resolution.background_relative * ff, bg)
    # a mode lowers h only where |f - f_m| / grade < h <= h_bg: each mode is evaluated on the sorted
    # frequencies within 1.01 grade h_bg of it (the same values as over all f; a sweep's grid has
    # hundreds of modes and tens of thousands of auxiliary points: 0.08 s per call before)
    order = np.argsort(ff, kind="stable")
    fs = ff[order]
    reach = 1.01 * resolution.grade * bg
    for fm, hm in zip(problem.modes[:, 0], mode_spacing(problem, resolution)):
        i0, i1 = np.searchsorted(fs, (fm - reach, fm + reach), side="left")
        at = order[i0:i1]
        flat[at] = np.minimum(flat[at], np.hypot(hm, (fs[i0:i1] - fm) / resolution.grade))
    return flat.reshape(f.shape)


def _auxiliary_points(problem: GridProblem, resolution: GridResolution) -> NDArray[np.float64]:
    """Points at which to integrate the density 1/h: every part of the band at an eighth of the
    spacing that governs it (the background's geometric and uniform parts, and each mode's graded
    mesh f_m + g h_m sinh(u / g), on which a step of u is one spacing)."""
    lo, hi, r, g = problem.f_min, problem.f_max, resolution.background_relative, resolution.grade
    parts = [np.geomspace(lo, hi, int(math.ceil(8 * math.log(hi / lo) / r)) + 2),
             np.linspace(lo, hi, int(math.ceil(8 * (hi - lo) / background_spacing(problem, resolution))) + 2)]
    for fm, hm in zip(problem.modes[:, 0], mode_spacing(problem, resolution)):
        u_max = g * math.asinh(max(abs(hi - fm), abs(fm - lo)) / (g * hm))
        u = np.linspace(-u_max, u_max, int(math.ceil(16 * u_max)) + 2)
        parts.append(fm + g * hm * np.sinh(u / g))
    return np.unique(np.clip(np.concatenate(parts), lo, hi))


def grid_density(problem: GridProblem, resolution: GridResolution = GridResolution()
                 ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Auxiliary frequencies [Hz] and the cumulative point count U(f) = integral_{f_min}^f df / h(f)
    on them (trapezoid rule; U(f_max) + 1 is the least number of nodes the resolution needs)."""
    aux = _auxiliary_points(problem, resolution)
    rho = 1.0 / required_spacing(problem, aux, resolution)
    counts = np.concatenate(([0.0], np.cumsum(np.diff(aux) * (rho[1:] + rho[:-1]) / 2)))
    return aux, counts


def points_needed(problem: GridProblem, resolution: GridResolution = GridResolution()) -> int:
    """The least number of grid nodes (both ends included) that meets the resolution."""
    _, counts = grid_density(problem, resolution)
    return int(math.ceil(counts[-1] - 1e-9)) + 1


def adaptive_nodes(problem: GridProblem, n: int, resolution: GridResolution = GridResolution()) -> NDArray[np.float64]:
    """n nodes [Hz] from f_min to f_max (both included) that equidistribute the point density 1/h:
    every spacing is at most (points_needed - 1) / (n - 1) times the required one, so n >=
    :func:`points_needed` meets the resolution and extra points refine the whole grid evenly.
    ValueError if n < 2."""
    if n < 2:
        raise ValueError(f"an adaptive grid needs at least 2 nodes, got {n}")
    aux, counts = grid_density(problem, resolution)
    nodes = np.interp(np.linspace(0.0, counts[-1], n), counts, aux)
    nodes[0], nodes[-1] = problem.f_min, problem.f_max
    return nodes


def scenario_grid_problem(scenario: Scenario, modes: Sequence[Mode]) -> GridProblem:
    """The scenario's grid problem: its band (analysis.freq_min, freq_max), the modes (frequency [Hz],
    damping ratio; e.g. those of the linearised system with the train on the approach and on the
    bridge), the run's duration and the train's spread (train length / speed)."""
    a = scenario.analysis
    return grid_problem(a.freq_min, a.freq_max, modes, scenario.duration, scenario.train.length / scenario.speed)
