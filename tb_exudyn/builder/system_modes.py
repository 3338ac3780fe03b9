"""Modes of a built train-bridge model: what each global coordinate is, and the mode table.

:func:`system_modes` builds the scenario (:func:`~tb_exudyn.builder.model.build_model`), takes M, K,
D from :meth:`TrainBridgeModel.linearized_system` at the time the train's first axle stands at
the requested position, and returns the :class:`~tb_exudyn.system.modes.ModeTable`.

The linearisation (Exudyn's ComputeLinearizedSystem) is about the unloaded reference configuration
with the coupling FROZEN at that time: the train stands still at those positions, so the table has
no convective term (the v d(phi)/dx damping and stiffness a moving wheel adds to the bridge modes)
and no geometric stiffness of the gravity preload (PEM's linear model, "rest").

- "vehicles on rigid track": position None, i.e. t = 0, when every axle is on the rigid approach
  track; the bridge is then free of the train, so the table holds the bridge's own modes and each
  vehicle's modes on rigid track, uncoupled.
- "coupled system at a train position": the first axle at x [m] along the track (x = 0 at the
  bridge start; negative on the approach), or a time t [s] of the run.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from ..errors import SettingError
from ..execution.resources import check_run_length
from ..scenario.model import Scenario
from ..system.components import find_components
from ..system.conventions import scenario_steps
from ..system.excitation import KINDS
from ..system.damping_guard import DampingWarning, RunTimes, damping_warnings
from ..system.modes import Dof, ModeTable, mode_table
from ..track import get_spectrum
from .linear import linear_system
from .model import TrainBridgeModel, build_model

#: names of a rigid-body node's coordinates x, y, z, rx, ry, rz in words, for bodies and wheelsets
BODY_WORDS = ("longitudinal", "lateral", "bounce", "roll", "pitch", "yaw")
WHEELSET_WORDS = ("longitudinal", "lateral", "vertical", "roll", "spin", "yaw")


def _part_name(channel_part: str) -> str:
    """'body' -> 'body', 'bogie1' -> 'leading bogie', 'bogie2' -> 'trailing bogie', 'axle3' -> 'axle 3'."""
    if channel_part == "bogie1":
        return "leading bogie"
    if channel_part == "bogie2":
        return "trailing bogie"
    if channel_part.startswith("axle"):
        return f"axle {channel_part[4:]}"
    return channel_part


def model_dofs(model: TrainBridgeModel) -> tuple[Dof, ...]:
    """A :class:`Dof` for every global ODE2 coordinate of a built model, in global order.

    Bridge: one per modal coordinate, part "<type> <number within the type>" with the finite-element
    modal report's type (vertical, lateral, torsion, longitudinal, pier, mixed). Vehicles: every
    coordinate of every body node, group "car k (<vehicle name>)"; wheelsets (and sprung-mass
    wheel masses: the ``axle`` channels) have role "wheelset"; the coordinates held only by the builder's weak springs are
    ``decoupled``."""
    n = model.n_ode2
    dofs: list[Dof | None] = [None] * n
    counts: dict[str, int] = {}
    for k, idx in enumerate(model.node_indices(model.bridge_node)):
        kind = model.bridge.mode_types[k]
        counts[kind] = counts.get(kind, 0) + 1
        dofs[int(idx)] = Dof("bridge", f"{kind} {counts[kind]}", kind, "bridge", "bridge")
    vehicles = model.scenario.train.vehicles
    decoupled = set(model.parts.decoupled)
    for body in model.parts.bodies:
        car, part = body.name.split(".", 1)
        veh = vehicles[int(car[3:]) - 1]
        group = f"car {car[3:]} ({veh.name})"
        indices = model.node_indices(body.node)
        wheelset = part.startswith("axle")  # a sprung mass without wheel mass is a body on the rail
        if indices.size == 6:
            words = WHEELSET_WORDS if wheelset else BODY_WORDS
        else:  # a one-coordinate vertical mass (sprung mass, its wheel)
            words = ("bounce",) if not wheelset else ("vertical",)
        for c, idx in enumerate(indices):
            dofs[int(idx)] = Dof(group, _part_name(part), words[c], body.name, "wheelset" if wheelset else "vehicle",
                                 (body.node, c) in decoupled)
    missing = [i for i, d in enumerate(dofs) if d is None]
    if missing:  # pragma: no cover - every coordinate belongs to the bridge or a vehicle body
        raise RuntimeError(f"global coordinates {missing} belong to no described node")
    return tuple(dofs)  # type: ignore[arg-type]


def position_time(scenario: Scenario, position: float) -> float:
    """The time [s] at which the train's first axle is at ``position`` [m] along the track
    (x = 0 at the bridge start; the run starts with it at -lead_in)."""
    return (float(position) + scenario.track.lead_in) / scenario.speed


def system_modes(
    scenario: Scenario,
    position: float | None = None,
    *,
    time: float | None = None,
    model: TrainBridgeModel | None = None,
) -> ModeTable:
    """The damped modes of the linearised train-bridge system with the train standing still.

    Parameters
    ----------
    scenario : the scenario
    position : where the train's first axle stands [m] (x = 0 at the bridge start); None (and no
        ``time``): t = 0, every axle on the rigid approach track (vehicles on rigid track, bridge
        alone)
    time : instead of ``position``, the time of the run [s] at whose axle positions the train stands
    model : an already built model of the scenario (else it is built)

    The coupling is frozen at that time: no convective terms (module docstring).
    """
    if position is not None and time is not None:
        raise SettingError("system_modes", "time", time, "either position or time, not both")
    for key, value in (("position", position), ("time", time)):
        if value is not None and not math.isfinite(float(value)):
            raise SettingError("system_modes", key, value, "a finite number")
    t = 0.0 if position is None and time is None else (float(time) if time is not None
                                                      else position_time(scenario, position))  # type: ignore[arg-type]
    if model is None:
        model = build_model(scenario, warn=False)
    M, K, D = model.linearized_system(t)
    inputs = input_forces(model, t)
    x0 = -scenario.track.lead_in + scenario.speed * t
    on = sum(0.0 <= x0 - a <= scenario.bridge.length for a in scenario.train.axle_positions)
    ground = "rigid track" if model.track is None else f"the track {scenario.track.structure}"
    where = (f"vehicles on {ground}, bridge free" if on == 0 and t == 0.0
             else f"first axle at x = {x0:.4g} m (t = {t:.4g} s), {on} of {len(scenario.train.axle_positions)} axles on the bridge")
    on_track = model.bridge.track_text()
    where += f"; {on_track}" if on_track else ""
    text = f"modes of '{scenario.name}': {where}; coupling frozen (no convective terms), linearised about rest"
    return mode_table(M, K, D, model_dofs(model), text, inputs)


def input_forces(model: TrainBridgeModel, t: float) -> dict[str, NDArray[np.float64]]:
    """Irregularity kind -> (n_ode2, 2 n_axles) generalised forces of a unit input value and a unit
    slope at each axle, the train at its positions of time t (:meth:`WheelRailCoupling.unit_input_forces`
    in global coordinates): what gives each mode its reach (:meth:`ModeTable.reached`)."""
    local = model.coupling.unit_input_forces(t)
    ci = model.coupling_indices()
    out = {}
    for k, kind in enumerate(KINDS):
        F = np.zeros((model.n_ode2, local.shape[2]))
        F[ci] = local[k]
        out[kind] = F
    return out


# ============================================================================================
# the damping guard of a scenario


def run_times(scenario: Scenario) -> RunTimes:
    """Duration of the scenario's run and the times its first axle reaches and its last axle
    leaves the bridge [s] (t = 0: first axle at -lead_in)."""
    v, tr = scenario.speed, scenario.track
    return RunTimes(
        duration=scenario.duration,
        bridge_entry=tr.lead_in / v,
        bridge_exit=(tr.lead_in + scenario.bridge.length + scenario.train.length) / v,
    )


def analysed_band(scenario: Scenario) -> tuple[float, float]:
    """The band the random runs excite [Hz]: analysis.freq_min-freq_max, narrowed to the
    frequencies v / wavelength of the track's wavelength band (outside it the irregularity is zero)."""
    an, tr, v = scenario.analysis, scenario.track, scenario.speed
    return max(an.freq_min, v / tr.wavelength_max), min(an.freq_max, v / tr.wavelength_min)


def excited_coordinates(scenario: Scenario, model: TrainBridgeModel) -> NDArray[np.bool_]:
    """(n,) whether the scenario's irregularity kinds reach each global coordinate during the run:
    the coordinates of the independent parts of the system (M, K, D and the coupling over the
    run's output times) that an input of a kind among ``track.irregularities`` drives, as the
    batched engine finds them (``find_components``); e.g. no lateral bridge mode under a vertical
    sprung mass on a vertical profile, no weak-spring coordinate ever. Switches the model to no
    excitation, no gravity, rest (the pseudo-runs' state)."""
    kinds = {KINDS.index(k) for k in scenario_kinds(scenario)}
    out = np.zeros(model.n_ode2, dtype=bool)
    for comp in find_components(linear_system(model), scenario_steps(scenario).output_times):
        if kinds & set(comp.kinds):
            out[comp.coords] = True
    return out


def damping_guard(
    scenario: Scenario,
    *,
    table: ModeTable | None = None,
    model: TrainBridgeModel | None = None,
    band: tuple[float, float] | None = None,
) -> list[DampingWarning]:
    """The damping warnings of a scenario's random runs (:func:`~tb_exudyn.system.modes.damping_warnings`):
    the modes of the vehicles on rigid track and of the free bridge (``system_modes`` at t = 0, or
    ``table`` of the same model) inside ``band`` (default :func:`analysed_band`) that the scenario's
    irregularities excite (:func:`excited_coordinates`, and that an input of their kinds reaches:
    :meth:`ModeTable.reached`) and whose decay time exceeds the run. Empty
    for a scenario without irregularities (nothing random excites any mode). Each warning carries
    the channel patterns it affects ("car2.*", "bridge.*"). A run too long to make is refused as
    the run is (:func:`~tb_exudyn.execution.resources.check_run_length`: ResourceError naming the key).

    The modes at t = 0 suffice: the damping ratios of the vehicle modes are the same with the train
    on the approach and on the bridge (docs/findings.md section 4), and the bridge's own modes keep
    their modal damping. ``model`` (built from ``scenario``) is switched to the pseudo-runs' state
    (no excitation, no gravity, rest)."""
    if not scenario.track.irregularities:
        return []
    check_run_length(scenario)  # the guard follows the run's output times: refused as the run is
    if model is None:
        model = build_model(scenario, warn=False)
    if table is None:
        table = system_modes(scenario, model=model)
    excited = excited_coordinates(scenario, model)
    return damping_warnings(table, analysed_band(scenario) if band is None else band, run_times(scenario),
                            excited=excited, inputs=scenario_kinds(scenario))


def scenario_kinds(scenario: Scenario) -> tuple[str, ...]:
    """The irregularity kinds (:data:`~tb_exudyn.system.excitation.KINDS`) of the scenario's spectra."""
    kinds = {get_spectrum(s).kind for s in scenario.track.irregularities}
    return tuple(k for k in KINDS if k in kinds)
