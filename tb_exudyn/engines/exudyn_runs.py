"""Runs of a built model through time with Exudyn: its settings, the run, its provenance.

The same built system is re-run: only its initial state and the excitation data change between
runs (``TrainBridgeModel.reset`` / ``set_excitation``); nothing is rebuilt. The time step, the output
step and the generalized-alpha spectral radius are scenario data (``analysis.time_step``,
``output_step``, ``spectral_radius``); :class:`SolverSettings` holds Newton's settings and the
linear solver, which change numbers only to within the tolerances measured below.

Measured convergence (ICE motor car over a 32 m span at 250 km/h, scenario ``quick``, and the
reference study's train, gravity and a 1 mm irregularity of 7-13 m wavelength):

- Newton tolerances: tightening the defaults (relative 1e-8, absolute 1e-6 N per coordinate) to
  1e-10 / 1e-8 changes no channel by more than 1e-6 of its dynamic range (deterministic run) and
  the small cross-plane channels of a pseudo-excitation run (0.1 mm) by at most 1e-3; the looser
  1e-6 / 1e-4 saves 20 % of the run time but moves those small channels by up to 5 %. An
  absolute tolerance of 1e-10 N per coordinate cannot be met (round-off of contact forces of 1e5 N
  on a 2e9 N/m contact): Newton then fails, which :func:`integrate` reports as an error.
- Time step 1 ms against 0.25 ms (with the default contact damping, ``analysis.contact_damping_ratio``):
  bridge displacement 2e-4, bridge and car-body accelerations 0.5 % and 0.1 %, bogie accelerations
  1.5 %, wheel-rail forces 0.8 % of their dynamic range. Without irregularity the dynamic part of the
  wheel forces is small (a few hundred N on 80 kN) and dominated by the kinks of the rail at the
  span ends, which a stiff contact resolves only with smaller steps (20 % of that small part).
- Spectral radius 0.9 against 1.0 (no numerical damping): at most 0.8 % (wheel forces).
"""

from __future__ import annotations

import json
import platform
import time as _time
from dataclasses import asdict, dataclass
from typing import Any

import exudyn as exu
import numpy as np
import scipy

from .._version import __version__
from ..builder.linear import linear_system
from ..builder.model import TrainBridgeModel
from ..builder.model import build_model as _build_model
from ..errors import SettingError, SimulationIncomplete
from ..execution.threads import single_threaded_blas
from ..system.derived_values import derived_values
from ..storage import json_default
from ..results.time_history import TimeHistory
from ..system.channels import Recording, evaluate, output_map
from ..system.conventions import run_steps
from ..system.excitation import Excitation, HarmonicExcitation, NoExcitation, ProfileExcitation, as_excitation
from .linear_model import LinearMeanInputs, LinearModel


@dataclass(frozen=True)
class SolverSettings:
    """Newton's settings and the linear solver of the Exudyn engine's implicit integration.

    Attributes
    ----------
    newton_relative_tolerance : Newton's relative residual tolerance
    newton_absolute_tolerance : Newton's absolute residual tolerance
    modified_newton : keep the Jacobian over steps while Newton contracts (much faster; the
        model is linear, so Newton converges either way)
    max_newton_iterations : Newton iterations per step before the step fails
    sparse : sparse linear solver (Eigen SparseLU) instead of dense
    """

    newton_relative_tolerance: float = 1e-8
    newton_absolute_tolerance: float = 1e-6
    modified_newton: bool = True
    max_newton_iterations: int = 25
    sparse: bool = True

    def __post_init__(self) -> None:
        for name in ("newton_relative_tolerance", "newton_absolute_tolerance"):
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and value > 0.0 and np.isfinite(value)):
                raise SettingError("SolverSettings", name, value, "a finite number > 0")
        if isinstance(self.max_newton_iterations, bool) or not isinstance(self.max_newton_iterations, int) \
                or self.max_newton_iterations < 1:
            raise SettingError("SolverSettings", "max_newton_iterations", self.max_newton_iterations,
                               "a whole number >= 1")

    def describe(self) -> dict[str, Any]:
        return asdict(self)


def simulation_settings(settings: SolverSettings, *, time_step: float, n_steps: int, output_step: float,
                        spectral_radius: float) -> exu.SimulationSettings:
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
    ti.generalizedAlpha.spectralRadius = float(spectral_radius)
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


@dataclass(frozen=True)
class RunInfo:
    """What a run did: steps, end time, wall-clock time [s], Newton statistics."""

    n_steps: int
    time_step: float
    end_time: float
    wall_time: float
    newton_iterations: int
    jacobian_updates: int


def integrate(model: TrainBridgeModel, settings: SolverSettings | None = None, duration: float | None = None
              ) -> tuple[Recording, RunInfo]:
    """Integrate the model from its initial state (set by ``reset``) over ``duration`` (default: the
    scenario's crossing time, rounded up to whole output steps: :func:`~tb_exudyn.system.conventions.run_steps`)
    and return the recording at the output step.

    Raises
    ------
    SimulationIncomplete
        When the run did not reach its end time (Exudyn may stop early without an error).
    """
    settings = settings or SolverSettings()
    an = model.scenario.analysis
    dt = an.time_step
    steps = run_steps(model.scenario.duration if duration is None else duration, dt, an.output_step)
    n_steps, end_time = steps.n_steps, steps.n_steps * dt
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
            f"the Exudyn run stopped at t = {t_reached:.6g} s before its end time {end_time:.6g} s ({n_steps} steps of "
            f"{dt:g} s): {solver.GetErrorString() or 'Newton did not converge'}; try a smaller time step"
        )
    rec = model.recording()
    _check_output_times(rec.times, an.output_step, end_time)
    info = RunInfo(n_steps=n_steps, time_step=dt, end_time=end_time, wall_time=wall,
                   newton_iterations=int(solver.it.newtonStepsCount), jacobian_updates=int(solver.it.newtonJacobiCount))
    return rec, info


def _check_output_times(times: np.ndarray, output_step: float, end_time: float) -> None:
    expected = np.arange(times.size) * output_step
    n_expected = int(round(end_time / output_step)) + 1
    if times.size != n_expected or not np.allclose(times, expected, rtol=0.0, atol=1e-9 * max(1.0, end_time)):
        raise SimulationIncomplete(
            f"recorded output times do not follow the output step {output_step:g} s "
            f"({times.size} samples from {times[:1]} to {times[-1:]}, expected {n_expected})"
        )


def describe_excitation(excitation: Excitation | None) -> str:
    """A one-line description of an excitation for provenance."""
    exc = as_excitation(excitation)
    if isinstance(exc, NoExcitation):
        return "none"
    if isinstance(exc, HarmonicExcitation):
        return (f"harmonic {exc.kind} ({exc.part} part): amplitude {exc.amplitude:g}, "
                f"Omega {exc.spatial_frequency:g} rad/m")
    assert isinstance(exc, ProfileExcitation)
    kinds = [k for k in ("vertical", "alignment", "cross_level") if getattr(exc, k) is not None]
    return "profile: " + (", ".join(kinds) or "none") + f" (cross-level as {exc.cross_level_unit})"


def versions() -> dict[str, str]:
    """Versions of the packages a result depends on."""
    return {
        "tb_exudyn": __version__, "exudyn": exu.__version__, "numpy": np.__version__,
        "scipy": scipy.__version__, "python": platform.python_version(),
    }


def model_values(model: TrainBridgeModel, rec: Any) -> tuple[dict[str, np.ndarray], dict[str, str]]:
    """(values, units) of the model's selected channels, then its selected derived channels
    (:mod:`tb_exudyn.system.derived`; real time histories: :mod:`tb_exudyn.system.derived_values`), from
    a recording of a run."""
    outputs = model.output_channels()
    raw = evaluate(outputs, rec, model.output_shapes, model.rail_rows)
    values = {c.name: raw[c.name] for c in model.selected}
    units = {c.name: c.unit for c in model.selected}
    if model.derived:
        fs = 1.0 / model.scenario.analysis.output_step
        values.update(derived_values(model.derived, raw, fs))
        units.update({d.name: d.unit for d in model.derived})
    return values, units


def run_model(
    model: TrainBridgeModel,
    excitation: Excitation | None = None,
    *,
    gravity: bool = True,
    initial: str = "static",
    settings: SolverSettings | None = None,
    duration: float | None = None,
) -> tuple[TimeHistory, RunInfo]:
    """One run of a built model (no rebuild): set excitation and loads, reset, integrate.

    Parameters
    ----------
    model : a built model (see :func:`tb_exudyn.builder.build_model`)
    excitation : irregularity input of this run (None: smooth track)
    gravity : dead loads on (the mean response) or off (a pure irregularity response)
    initial : "static" (static equilibrium on the approach) or "rest"
    settings : solver settings (default :class:`SolverSettings`)
    duration : simulated time [s] (default: the crossing, see ``Scenario.duration``)
    """
    settings = settings or SolverSettings()
    model.set_excitation(excitation)
    model.set_gravity(gravity)
    model.reset(initial)  # type: ignore[arg-type]
    rec, info = integrate(model, settings, duration)
    values, units = model_values(model, rec)
    provenance: dict[str, Any] = {
        "engine": "exudyn",
        "versions": versions(),
        "run_time_s": info.wall_time,
        "steps": info.n_steps,
        "time_step_s": info.time_step,
        "end_time_s": info.end_time,
        "newton_iterations": info.newton_iterations,
        "jacobian_updates": info.jacobian_updates,
        "solver_settings": {"spectral_radius": model.scenario.analysis.spectral_radius, **settings.describe()},
        "excitation": describe_excitation(excitation),
        "gravity": gravity,
        "initial_state": initial,
        "bridge_modes": model.bridge.n_modes,
        "bridge_model": model.bridge.description,
        "contact_damping_ratio": model.scenario.analysis.contact_damping_ratio,
        "warnings": list(model.warnings),
    }
    th = TimeHistory(time=rec.times, channels=values, units={n: units[n] for n in values},
                     scenario=model.scenario, provenance=provenance)
    return th, info



# ------------------------------------------------------------------ the Exudyn side of the engines
def exudyn_mean(engine: Any) -> dict[str, np.ndarray]:
    """The mean as Exudyn's deterministic run (gravity, static start, no irregularity) on
    ``engine``'s model, in the form of :meth:`tb_exudyn.engines.base.Engine.mean` (the Exudyn engine's
    mean, and a linear engine's with ``mean="exudyn"``)."""
    start = _time.perf_counter()
    model = engine.model
    th, _ = run_model(model, None, gravity=True, initial="static")
    rec = model.recording()
    forces = [c for c in model.channels if c.name.endswith(".force_z")] if engine.wheel_forces else []
    if forces:
        values = evaluate(forces, rec, model.bridge.station_shapes)
        force_mean = np.stack([values[c.name] for c in forces])
    else:
        force_mean = np.zeros((0, th.time.size))
    outputs = engine.channel_values(rec)
    model.set_gravity(False)  # back to the sweep's state
    model.set_excitation(None)
    return {
        "force_mean": force_mean, "outputs": outputs,
        "mean": np.stack([th.channels[c] for c in th.names]), "time": th.time,
        "names": np.array(th.names, dtype=str), "units": np.array([th.units[c] for c in th.names], dtype=str),
        "provenance": np.array(json.dumps(th.provenance, default=json_default)),
        "warnings": np.array(model.warnings, dtype=str).reshape(-1),
        "seconds": np.array(_time.perf_counter() - start),
    }


def build_model(scenario: Any) -> TrainBridgeModel:
    """The scenario's Exudyn model (for an engine: built without issuing the scenario's warnings)."""
    return _build_model(scenario, warn=False)


def linear_model(model: TrainBridgeModel, wheel_forces: bool = False, mean: bool = False) -> LinearModel:
    """What a linear engine needs of ``model`` (:class:`~tb_exudyn.engines.linear_model.LinearModel`),
    built here once and sent to the workers; with ``mean`` the linear mean's inputs too (the static
    state under the dead loads and the linear system about it)."""
    channels = model.output_channels(wheel_forces)
    outputs = output_map(channels, model.node_indices, model.output_shapes)
    lin = linear_system(model, model.scenario.analysis.linearization)
    inputs = None
    if mean:
        model.set_excitation(None)
        model.set_gravity(True)
        try:
            static = model.static_state(0.0)
        finally:
            model.set_gravity(False)
        inputs = LinearMeanInputs(static=static, lin_static=None if lin.linearization == "static" else
                                  linear_system(model, "static"), bridge_modes=model.bridge.n_modes,
                                  bridge_description=model.bridge.description)
    return LinearModel(lin=lin, outputs=outputs, selected=tuple((c.name, c.unit) for c in model.selected),
                       derived=tuple(model.derived),
                       force_channels=tuple(c.name for c in model.channels if c.name.endswith(".force_z")),
                       warnings=tuple(model.warnings), n_coordinates=int(model.n_ode2), mean=inputs)


__all__ = ["RunInfo", "SimulationIncomplete", "SolverSettings", "build_model", "describe_excitation", "exudyn_mean",
           "integrate", "linear_model", "linear_system", "run_model", "simulation_settings", "versions"]
