"""The physical and numerical conventions every engine and method shares: each in ONE function.

- Train position: axle j is at x_j(t) = x0_j + v t along the track (x = 0 at the bridge start, x0_j
  = -lead_in - a_j, a_j the axle's distance behind the first axle): :func:`axle_positions`.
- Spatial frequency: a temporal frequency f [Hz] at speed v [m/s] excites the spatial circular
  frequency Omega = 2 pi f / v [rad/m] (wavelength v / f): :func:`spatial_frequency`.
- Harmonic input phase: a pseudo-excitation of spatial frequency Omega reaches the axle at x with the
  phase Omega (x - x_ref), x_ref the first axle's position at t = 0: :func:`harmonic_phase`; its
  complex input is exp(i phase) (real part: the cosine run, imaginary part: the sine run).
- Cross-level: the model's input is the cross-level angle theta_c [rad]; a cross-level given as a
  rail height difference h = z_left - z_right [m] is the angle h / (2 b), b = ``track.half_gauge``
  (the rails sit at z_v +- b theta_c): :func:`cross_level_scale`. The track spectra's formulas carry
  their own published constant b (``tb_exudyn.track.SPECTRUM_HALF_GAUGE``), which defines the
  spectra, not the model.
- Steps: a run covers the crossing in whole output steps of whole time steps; Exudyn's step is
  end_time / n_steps, so end_time = n_steps * time_step exactly: :func:`number_of_steps`,
  :func:`run_steps`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

FloatArray = NDArray[np.float64]


def axle_positions(axle_start: ArrayLike, speed: float, t: float) -> FloatArray:
    """Axle positions x_j(t) = x0_j + v t [m] along the track."""
    return np.asarray(axle_start, dtype=float) + speed * t


def spatial_frequency(f: ArrayLike, speed: float) -> FloatArray:
    """Spatial circular frequency Omega = 2 pi f / v [rad/m] of temporal frequency f [Hz] at speed v."""
    return 2.0 * math.pi * np.asarray(f, dtype=float) / speed


def harmonic_phase(omega: ArrayLike, x: ArrayLike, x_ref: float) -> FloatArray:
    """The phase Omega (x - x_ref) [rad] of a harmonic input at positions x (an outer product when
    both are arrays: shape x.shape + omega.shape)."""
    return np.multiply.outer(np.asarray(x, dtype=float) - x_ref, np.asarray(omega, dtype=float))


def cross_level_scale(unit: str, half_gauge: float) -> float:
    """Factor from a cross-level value in ``unit`` to the model's angle [rad]: 1 for an angle
    ("angle" or "rad"), 1 / (2 b) for a rail height difference ("height" or "m")."""
    if unit in ("angle", "rad"):
        return 1.0
    if unit in ("height", "m"):
        return 1.0 / (2.0 * half_gauge)
    raise ValueError(f"cross-level unit must be an angle ('angle', 'rad') or a height ('height', 'm'), got {unit!r}")


def number_of_steps(duration: float, time_step: float) -> int:
    """Steps covering ``duration`` (rounded up; a duration within 1e-9 of whole steps is not)."""
    n = duration / time_step
    return max(1, int(round(n)) if abs(n - round(n)) < 1e-9 * max(1.0, n) else int(n) + 1)


@dataclass(frozen=True)
class RunSteps:
    """The time grid of a run: ``n_steps`` steps of ``h`` [s], an output every ``ratio`` steps."""

    n_steps: int
    ratio: int
    h: float

    @property
    def end_time(self) -> float:
        return self.n_steps * self.h

    @property
    def n_outputs(self) -> int:
        """Output times, t = 0 included."""
        return self.n_steps // self.ratio + 1

    @property
    def output_times(self) -> FloatArray:
        return np.arange(self.n_outputs) * (self.h * self.ratio)


def run_steps(duration: float, time_step: float, output_step: float) -> RunSteps:
    """Whole output steps covering ``duration``; the step is end_time / n_steps, as Exudyn takes it
    (end_time = n_steps * time_step exactly)."""
    ratio = int(round(output_step / time_step))
    n_steps = ratio * number_of_steps(duration, output_step)
    end_time = n_steps * time_step
    return RunSteps(n_steps=n_steps, ratio=ratio, h=end_time / n_steps)


def scenario_steps(scenario) -> RunSteps:  # noqa: ANN001 - a Scenario (no import: system does not need scenario)
    """The run steps of a scenario's crossing (``analysis.time_step``, ``output_step``, ``duration``)."""
    an = scenario.analysis
    return run_steps(scenario.duration, an.time_step, an.output_step)


__all__ = [
    "RunSteps", "axle_positions", "cross_level_scale", "harmonic_phase", "number_of_steps", "run_steps",
    "scenario_steps", "spatial_frequency",
]
