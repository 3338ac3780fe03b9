"""Time-integration settings as data, and their translation into Exudyn simulation settings.

The time step, the output step and the generalized-alpha spectral radius are scenario data
(``Analysis.time_step``, ``output_step``, ``spectral_radius``); :class:`SolverSettings` holds the
rest (Newton tolerances, modified Newton, linear solver).

Measured convergence (ICE motor car over a 32 m span at 250 km/h, scenario ``quick``, and the
reference study's train, gravity and a 1 mm irregularity of 7-13 m wavelength):

- Newton tolerances: tightening the defaults (relative 1e-8, absolute 1e-6 N per coordinate) to
  1e-10 / 1e-8 changes no channel by more than 1e-6 of its dynamic range (deterministic run) and
  the small cross-plane channels of a pseudo-excitation run (0.1 mm) by at most 1e-3; the looser
  1e-6 / 1e-4 saves 20 % of the run time but moves those small channels by up to 5 %. An
  absolute tolerance of 1e-10 N per coordinate cannot be met (round-off of contact forces of 1e5 N
  on a 2e9 N/m contact): Newton then fails, which :func:`~tb_exudyn.solvers.engine.integrate`
  reports as an error.
- Time step 1 ms against 0.25 ms (with the default contact damping, see ``BuildOptions``): bridge
  displacement 2e-4, bridge and car-body accelerations 0.5 % and 0.1 %, bogie accelerations 1.5 %,
  wheel-rail forces 0.8 % of their dynamic range. Without irregularity the dynamic part of the
  wheel forces is small (a few hundred N on 80 kN) and dominated by the kinks of the rail at the
  span ends, which a stiff contact resolves only with smaller steps (20 % of that small part).
- Spectral radius 0.9 against 1.0 (no numerical damping): at most 0.8 % (wheel forces).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

import exudyn as exu


@dataclass(frozen=True)
class SolverSettings:
    """Settings of the implicit generalized-alpha integration.

    Attributes
    ----------
    spectral_radius : generalized-alpha spectral radius at infinite frequency (None: the
        scenario's ``analysis.spectral_radius``)
    newton_relative_tolerance : Newton's relative residual tolerance
    newton_absolute_tolerance : Newton's absolute residual tolerance
    modified_newton : keep the Jacobian over steps while Newton contracts (much faster; the
        model is linear, so Newton converges either way)
    max_newton_iterations : Newton iterations per step before the step fails
    sparse : sparse linear solver (Eigen SparseLU) instead of dense
    """

    spectral_radius: Optional[float] = None
    newton_relative_tolerance: float = 1e-8
    newton_absolute_tolerance: float = 1e-6
    modified_newton: bool = True
    max_newton_iterations: int = 25
    sparse: bool = True

    def __post_init__(self) -> None:
        if self.spectral_radius is not None and not 0.0 <= self.spectral_radius <= 1.0:
            raise ValueError(f"spectral_radius must be in [0, 1], got {self.spectral_radius!r}")
        for name in ("newton_relative_tolerance", "newton_absolute_tolerance"):
            if not getattr(self, name) > 0.0:
                raise ValueError(f"{name} must be > 0, got {getattr(self, name)!r}")
        if self.max_newton_iterations < 1:
            raise ValueError(f"max_newton_iterations must be >= 1, got {self.max_newton_iterations!r}")


def number_of_steps(duration: float, time_step: float) -> int:
    """Steps covering ``duration`` (rounded up; a duration within 1e-9 of whole steps is not)."""
    n = duration / time_step
    return max(1, int(round(n)) if abs(n - round(n)) < 1e-9 * max(1.0, n) else int(n) + 1)


def simulation_settings(
    settings: SolverSettings, *, time_step: float, n_steps: int, output_step: float, spectral_radius: float
) -> exu.SimulationSettings:
    """Exudyn settings of a run of ``n_steps`` constant steps of ``time_step``.

    Exudyn's step is endTime / numberOfSteps: the end time is set to exactly n_steps * time_step.
    No automatic step size or step-size adaptation (a failing step raises instead), no files.
    """
    ss = exu.SimulationSettings()
    ti = ss.timeIntegration
    ti.numberOfSteps = int(n_steps)
    ti.endTime = n_steps * time_step
    ti.startTime = 0.0
    ti.verboseMode = 0
    ti.automaticStepSize = False
    ti.adaptiveStep = False
    ti.generalizedAlpha.spectralRadius = float(
        settings.spectral_radius if settings.spectral_radius is not None else spectral_radius
    )
    ti.generalizedAlpha.computeInitialAccelerations = True
    ti.newton.useModifiedNewton = bool(settings.modified_newton)
    ti.newton.relativeTolerance = float(settings.newton_relative_tolerance)
    ti.newton.absoluteTolerance = float(settings.newton_absolute_tolerance)
    ti.newton.maxIterations = int(settings.max_newton_iterations)
    ss.linearSolver.solverType = exu.LinearSolverType.EigenSparse if settings.sparse else exu.LinearSolverType.EXUdense
    ss.solution.file.write = False
    ss.solution.sensors.active = True
    ss.solution.sensors.writePeriod = float(output_step)
    ss.show.statistics = False
    ss.show.computationTime = False
    ss.parallel.numberOfThreads = 1
    return ss
