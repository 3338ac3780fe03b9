"""The deterministic run: gravity on, the train starting in static equilibrium on the approach.

Without an excitation this is the mean response of the pseudo-excitation method; with a sampled
profile it is one Monte Carlo sample. The vehicles start from their exact static equilibrium on
the rigid approach track (nothing bounces at t = 0), the bridge at rest and unloaded.
"""

from __future__ import annotations

import platform
import time as _time
from collections import defaultdict
from typing import Any

import numpy as np

from ..system.excitation import Excitation, HarmonicExcitation, NoExcitation, ProfileExcitation, as_excitation
from ..builder.model import TrainBridgeModel, build_model
from ..results.time_history import TimeHistory
from ..scenario import Scenario
from .engine import RunInfo, integrate
from .settings import SolverSettings


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
    import exudyn
    import scipy

    from .. import __version__

    return {
        "tb_exudyn": __version__, "exudyn": exudyn.__version__, "numpy": np.__version__,
        "scipy": scipy.__version__, "python": platform.python_version(),
    }


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
    model.set_excitation(excitation)
    model.set_gravity(gravity)
    model.reset(initial)  # type: ignore[arg-type]
    rec, info = integrate(model, settings, duration)
    values = model.channel_values(rec)
    units = model.channel_units()
    provenance: dict[str, Any] = {
        "engine": "exudyn",
        "versions": versions(),
        "run_time_s": info.wall_time,
        "steps": info.n_steps,
        "time_step_s": info.time_step,
        "end_time_s": info.end_time,
        "newton_iterations": info.newton_iterations,
        "jacobian_updates": info.jacobian_updates,
        "solver_settings": _settings_dict(settings or SolverSettings(), model),
        "excitation": describe_excitation(excitation),
        "gravity": gravity,
        "initial_state": initial,
        "bridge_modes": model.bridge.n_modes,
        "bridge_model": model.bridge.description,
        "contact_damping_ratio": model.options.contact_damping_ratio,
        "warnings": list(model.warnings),
    }
    th = TimeHistory(time=rec.times, channels=values, units={n: units[n] for n in values},
                     scenario=model.scenario, provenance=provenance)
    return th, info


def _settings_dict(settings: SolverSettings, model: TrainBridgeModel) -> dict[str, Any]:
    rho = settings.spectral_radius if settings.spectral_radius is not None else model.scenario.analysis.spectral_radius
    return {
        "spectral_radius": rho,
        "newton_relative_tolerance": settings.newton_relative_tolerance,
        "newton_absolute_tolerance": settings.newton_absolute_tolerance,
        "modified_newton": settings.modified_newton,
        "max_newton_iterations": settings.max_newton_iterations,
        "sparse": settings.sparse,
    }


def run_deterministic(
    scenario: Scenario,
    excitation: Excitation | None = None,
    *,
    settings: SolverSettings | None = None,
    model: TrainBridgeModel | None = None,
) -> TimeHistory:
    """The train crossing the bridge under gravity, starting in static equilibrium.

    Parameters
    ----------
    scenario : the scenario
    excitation : None (smooth track: the mean response) or a deterministic profile / harmonic
    settings : solver settings (defaults measured to be converged)
    model : a model already built from this scenario, to re-run without rebuilding

    Returns
    -------
    TimeHistory with the channels of ``scenario.analysis.channels`` at ``analysis.output_step``.

    Raises
    ------
    SimulationIncomplete if the integration does not reach its end time.
    """
    start = _time.perf_counter()
    if model is None:
        model = build_model(scenario)
    elif model.scenario != scenario:
        raise ValueError("the given model was built from a different scenario")
    build = _time.perf_counter() - start
    th, _ = run_model(model, excitation, gravity=True, initial="static", settings=settings)
    th.provenance["build_time_s"] = build
    th.provenance["total_time_s"] = _time.perf_counter() - start
    return th


def _group(name: str) -> str:
    """'bridge.span1.mid.acc_z' -> 'bridge.span1.mid'; 'car1.axle1.left.force_z' -> 'car1.axle1'."""
    parts = name.split(".")
    if parts[0] == "bridge":
        return ".".join(parts[:3])
    return ".".join(parts[:2])


def summarize(th: TimeHistory) -> str:
    """Peaks per channel group: for every channel its largest magnitude (signed), time and unit."""
    groups: dict[str, list[str]] = defaultdict(list)
    for name in th.channels:
        groups[_group(name)].append(name)
    title = th.scenario.name if th.scenario is not None else "time history"
    lines = [
        f"{title}: {len(th.channels)} channels, t = {th.time[0]:.3g} ... {th.time[-1]:.4g} s "
        f"({th.time.size} samples)"
    ]
    steps, run = th.provenance.get("steps"), th.provenance.get("run_time_s")
    if steps and run:
        lines.append(f"run: {steps} steps in {run:.3g} s ({1e6 * run / steps:.0f} us/step)")
    width = max((len(n) for n in th.channels), default=10)
    for group, names in groups.items():
        lines.append(f"{group}:")
        for name in names:
            value, t = th.peak(name)
            lines.append(f"  {name:<{width}}  peak {value: .4e} {th.unit(name):<8} at t = {t:.3f} s")
    return "\n".join(lines)
