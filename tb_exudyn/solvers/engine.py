"""Run a built train-bridge model through time with Exudyn and collect its recording.

The same built system is re-run: only its initial state and the excitation data change between
runs (``TrainBridgeModel.reset`` / ``set_excitation``); nothing is rebuilt.
"""

from __future__ import annotations

import time as _time
from dataclasses import dataclass

import exudyn as exu
import numpy as np

from ..system.channels import Recording
from ..builder.model import TrainBridgeModel
from .settings import SolverSettings, number_of_steps, simulation_settings
from .threads import single_threaded_blas


class SimulationIncomplete(RuntimeError):
    """The integration stopped before its end time (Newton failed, or the solver gave up)."""


@dataclass(frozen=True)
class RunInfo:
    """What a run did: steps, end time, wall-clock time [s], Newton statistics."""

    n_steps: int
    time_step: float
    end_time: float
    wall_time: float
    newton_iterations: int
    jacobian_updates: int


def integrate(
    model: TrainBridgeModel, settings: SolverSettings | None = None, duration: float | None = None
) -> tuple[Recording, RunInfo]:
    """Integrate the model from its initial state (set by ``reset``) over ``duration``
    (default: the scenario's crossing time, rounded up to whole output steps) and return the
    recording at the output step.

    Raises
    ------
    SimulationIncomplete
        When the run did not reach its end time (Exudyn may stop early without an error).
    """
    settings = settings or SolverSettings()
    an = model.scenario.analysis
    dt = an.time_step
    # whole output steps, so that the last sample lies on the output grid
    ratio = int(round(an.output_step / dt))
    n_steps = ratio * number_of_steps(model.scenario.duration if duration is None else duration, an.output_step)
    end_time = n_steps * dt
    ss = simulation_settings(settings, time_step=dt, n_steps=n_steps, output_step=an.output_step,
                             spectral_radius=an.spectral_radius)
    solver = exu.MainSolverImplicitSecondOrder()
    start = _time.perf_counter()
    try:
        with single_threaded_blas():
            ok = solver.SolveSystem(model.mbs, ss)
    except Exception as err:  # Exudyn raises plain RuntimeErrors from C++
        raise SimulationIncomplete(
            f"the Exudyn run failed at t = {model.mbs.systemData.GetTime():.6g} s of {end_time:.6g} s: {err}"
        ) from err
    wall = _time.perf_counter() - start
    t_reached = model.mbs.systemData.GetTime()
    if not ok or abs(t_reached - end_time) > 0.5 * dt:
        raise SimulationIncomplete(
            f"the Exudyn run stopped at t = {t_reached:.6g} s before its end time {end_time:.6g} s "
            f"({n_steps} steps of {dt:g} s): {solver.GetErrorString() or 'Newton did not converge'}; "
            "try a smaller time step or looser Newton tolerances (SolverSettings)"
        )
    rec = model.recording()
    _check_output_times(rec.times, an.output_step, end_time)
    info = RunInfo(
        n_steps=n_steps, time_step=dt, end_time=end_time, wall_time=wall,
        newton_iterations=int(solver.it.newtonStepsCount), jacobian_updates=int(solver.it.newtonJacobiCount),
    )
    return rec, info


def _check_output_times(times: np.ndarray, output_step: float, end_time: float) -> None:
    expected = np.arange(times.size) * output_step
    n_expected = int(round(end_time / output_step)) + 1
    if times.size != n_expected or not np.allclose(times, expected, rtol=0.0, atol=1e-9 * max(1.0, end_time)):
        raise SimulationIncomplete(
            f"recorded output times do not follow the output step {output_step:g} s "
            f"({times.size} samples from {times[:1]} to {times[-1:]}, expected {n_expected})"
        )
