"""A real train with vehicle-bridge interaction beside the same train as moving forces (EN 1991-2 6.4.6.3.1(3)).

EN 1991-2 checks a train as constant moving forces; with its vehicles' own dynamics (springs, dampers, the
bodies' inertia) the train takes energy out of a resonating short span, and eq. 6.13's additional damping
Delta zeta stands in for that effect in a moving-force model. :func:`interaction_comparison` computes both
on the same bridge at one speed, for a train given as vehicle models (``ForceTrain.vehicles``, the real
trains of models/trains):

- **moving forces**: :func:`tb_exudyn.codes.moving_force.moving_force_response` of the train's axle loads
  on the bridge's modes up to ``max_frequency`` at the bridge's damping ratio (and again at zeta + Delta
  zeta of eq. 6.13 for the longest span, :func:`tb_exudyn.codes.en1991.additional_damping_eq_6_13`);
- **interaction**: the project's deterministic run (:func:`tb_exudyn.methods.deterministic.run_deterministic`:
  the Exudyn model of the vehicles on the same modes, gravity on, the vehicles starting in static
  equilibrium on the approach, the bridge at rest, no irregularity: the mean response), on a scenario
  (:func:`interaction_scenario`) whose run-out lets the bridge ring for as long as the moving-force run's
  tail, its output step the time step.

Both read the peak |vertical acceleration| at each span's mid-span on the track line (the moving-force
station ``span<i>.x4/8``, the run's channel ``bridge.span<i>.mid.acc_z``): the same modes, the same
damping, the same loads (the axle loads of models/trains are the vehicles' weights per axle). The
methods layer (which builds Exudyn models) is loaded by name on first use, as codes/stochastic.py does.
"""

from __future__ import annotations

import importlib
import math
import time
import warnings
from dataclasses import dataclass, field
from typing import Any, Callable, Sequence

import numpy as np

from ..errors import SettingError
from ..scenario import Scenario
from ..scenario.code_data import with_mass_case
from ..scenario.model import Analysis, Track, Train
from ..structure import modal_bridge
from . import en1991 as code
from .moving_force import moving_force_response
from .trains import ForceTrain

#: the bridge's modes up to this frequency by default [Hz] (EN 1991-2 6.4.6.2's cut-off is at least 30 Hz)
DEFAULT_MAX_FREQUENCY = 60.0
#: the interaction run's time step (also its output step) [s]: 1 ms resolves the wheel-rail contact of
#: the shipped vehicles and gives 167 samples per period of a 6 Hz span (a sampled peak within 2e-4)
DEFAULT_TIME_STEP = 1e-3
#: the approach before the bridge [m]: the vehicles start in static equilibrium and the track is smooth,
#: so nothing moves before the first axle reaches the bridge
DEFAULT_LEAD_IN = 10.0
#: the moving-force runs' samples per period of the highest mode (``moving_force_response``): its loads vary
#: linearly between steps, an O(dx^2) error in the peak; on the 15 m span of tests/codes/test_interaction.py
#: (ice_mttm at 283 km/h) 20 samples (the check's default, at its lowest speed) give 4.9550 m/s^2, 40 4.9580,
#: 80 4.9588 and 160 4.9589: 80 is within 3e-5 of the converged peak, for one speed a few ms
MF_SAMPLES_PER_PERIOD = 80.0
#: the builder's warning on a short approach concerns runs that start at rest (PEM, Monte Carlo); the
#: deterministic run starts in static equilibrium (its module docstring), so it does not apply here
_LEAD_IN_WARNING = r"track\.lead_in = .*start at rest"


@dataclass(frozen=True)
class InteractionComparison:
    """One train at one speed, as moving forces and with interaction, on the same bridge.

    ``spans`` the span lengths along the track [m]; per span (n_spans,) the peak |vertical acceleration|
    at mid-span [m/s^2]: ``moving_force_acc`` (damping ratio ``damping_ratio``), ``moving_force_dz_acc``
    (zeta + ``additional_damping``, eq. 6.13 for the longest span), ``interaction_acc`` (the deterministic
    run of the vehicle model); ``frequencies`` the bridge's modes used [Hz]; ``end_time_s`` the time the
    interaction run reached (its last output time) and ``planned_end_time_s`` the scenario's duration
    (from the first axle ``lead_in`` before the bridge to the last one ``run_out`` past it); ``scenario`` the
    interaction run's scenario (``run_deterministic`` of it gives ``interaction_acc``)."""

    train: str
    bridge: str
    speed_kmh: float
    spans: tuple[float, ...]
    damping_ratio: float
    additional_damping: float
    moving_force_acc: np.ndarray = field(repr=False)
    moving_force_dz_acc: np.ndarray = field(repr=False)
    interaction_acc: np.ndarray = field(repr=False)
    frequencies: np.ndarray = field(repr=False)
    end_time_s: float = 0.0
    planned_end_time_s: float = 0.0
    scenario: Scenario | None = field(default=None, repr=False)
    seconds: float = 0.0
    case: str = "nominal"

    @property
    def difference(self) -> float:
        """Interaction minus moving forces (largest mid-span peaks) [m/s^2]: < 0 where interaction lowers it."""
        return self.max_interaction - self.max_moving_force

    @property
    def max_moving_force(self) -> float:
        """The largest mid-span peak of the moving forces [m/s^2]."""
        return float(np.max(self.moving_force_acc))

    @property
    def max_interaction(self) -> float:
        """The largest mid-span peak with interaction [m/s^2]."""
        return float(np.max(self.interaction_acc))

    @property
    def max_moving_force_dz(self) -> float:
        """The largest mid-span peak of the moving forces at zeta + Delta zeta [m/s^2]."""
        return float(np.max(self.moving_force_dz_acc))

    @property
    def reduction(self) -> float:
        """1 - interaction / moving forces (largest mid-span peaks): > 0 where interaction lowers the peak."""
        return 1.0 - self.max_interaction / self.max_moving_force

    @property
    def reduction_dz(self) -> float:
        """1 - (zeta + Delta zeta) / zeta moving-force peaks: what eq. 6.13 takes off."""
        return 1.0 - self.max_moving_force_dz / self.max_moving_force


def _methods() -> Any:
    """tb_exudyn.methods.deterministic, loaded on first use (it builds Exudyn models)."""
    return importlib.import_module("tb_exudyn.methods.deterministic")


def _check_train(train: ForceTrain) -> None:
    if not train.vehicles:
        raise SettingError("interaction_comparison", "train", train.name,
                           "a train given as vehicle models (models/trains)", "moving forces only")


def interaction_scenario(bridge: Any, train: ForceTrain, speed_kmh: float, *, max_frequency: float,
                         run_out: float, time_step: float = DEFAULT_TIME_STEP,
                         lead_in: float = DEFAULT_LEAD_IN) -> Scenario:
    """The interaction run's scenario: ``train``'s vehicles over ``bridge`` at ``speed_kmh``, smooth track,
    the bridge's modes up to ``max_frequency``, the mid-span accelerations as channels."""
    _check_train(train)
    return Scenario(
        name=f"interaction_{train.name}_{bridge.name}", speed_kmh=float(speed_kmh),
        train=Train(vehicles=tuple(train.vehicles)), bridge=bridge,
        track=Track(lead_in=float(lead_in), run_out=float(run_out)),
        analysis=Analysis(time_step=float(time_step), output_step=float(time_step),
                          mode_max_frequency=float(max_frequency), channels=("bridge.span*.mid.acc_z",)),
        description=f"{train.name} with vehicle-bridge interaction over {bridge.name} (smooth track)",
        source="tb_exudyn.codes.interaction")


def interaction_comparison(bridge: Any, train: ForceTrain, speed_kmh: float, *,
                           max_frequency: float = DEFAULT_MAX_FREQUENCY, time_step: float = DEFAULT_TIME_STEP,
                           lead_in: float = DEFAULT_LEAD_IN, case: str = "nominal") -> InteractionComparison:
    """``train`` crossing ``bridge`` (a bridge of the scenario, its own damping ratio on every mode) at
    ``speed_kmh`` as moving forces and with interaction (the module docstring). SettingError for a train
    without vehicle models or a speed <= 0; SimulationIncomplete (from the run) if the interaction run
    stops before its end time. ``case``: the bridge's mass case, a label recorded in the result."""
    start = time.perf_counter()
    v_kmh = float(speed_kmh)
    if not (math.isfinite(v_kmh) and v_kmh > 0):
        raise SettingError("interaction_comparison", "speed_kmh", speed_kmh, "a speed > 0 km/h")
    _check_train(train)
    spans = tuple(float(s) for s in bridge.spans)
    mb = modal_bridge(bridge, max_frequency)
    zeta = float(bridge.damping_ratio)
    dz = code.additional_damping_eq_6_13(max(spans))
    mf = moving_force_response(mb, train, [v_kmh], spans, samples_per_period=MF_SAMPLES_PER_PERIOD)
    mf_dz = moving_force_response(mb, train, [v_kmh], spans, damping_ratio=zeta + dz,
                                  samples_per_period=MF_SAMPLES_PER_PERIOD)
    sc = interaction_scenario(bridge, train, v_kmh, max_frequency=max_frequency, time_step=time_step,
                              lead_in=lead_in, run_out=mf.tail_s * v_kmh / 3.6 + 1.0)
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message=_LEAD_IN_WARNING)
        th = _methods().run_deterministic(sc)
    n_modes = int(th.provenance.get("bridge_modes", mb.n_modes))
    if n_modes != mb.n_modes:  # both from the same FE modes: a difference is a defect, not a setting
        raise RuntimeError(f"interaction run on {n_modes} bridge modes, moving forces on {mb.n_modes}")
    inter = np.array([abs(th.peak(f"bridge.span{i + 1}.mid.acc_z")[0]) for i in range(len(spans))])
    return InteractionComparison(
        train=train.name, bridge=bridge.name, speed_kmh=v_kmh, spans=spans, damping_ratio=zeta,
        additional_damping=dz, moving_force_acc=mf.max_acc[mf.mid_stations, 0].copy(),
        moving_force_dz_acc=mf_dz.max_acc[mf_dz.mid_stations, 0].copy(), interaction_acc=inter,
        frequencies=mb.frequencies.copy(), end_time_s=float(th.time[-1]),
        planned_end_time_s=float(sc.duration), scenario=sc,
        seconds=time.perf_counter() - start, case=case)


# ------------------------------------------------------------------ the check's rows (codes/check.py)
def check_trains(trains: Sequence[ForceTrain], asked: Any, err: Callable[..., Exception]) -> list[ForceTrain]:
    """The trains of the check's interaction rows (``check(..., interaction=True)``): those given as vehicle
    models; none when not asked. ``err(key, value, allowed, reason)`` makes the check's error: raised for
    ``asked`` not a bool, or asked with no such train."""
    if not isinstance(asked, bool):
        raise err("interaction", asked, "True or False")
    if not asked:
        return []
    chosen = [t for t in trains if t.vehicles]
    if not chosen:
        raise err("interaction", [t.name for t in trains], "a train of vehicle models (ice_mttm, ave_s103, a train "
                  ".toml of vehicles): HSLM trains are moving forces",
                  "no train for the interaction rows")
    return chosen


def check_bridge(bridge: Any, damping_ratio: float, case: str) -> Any:
    """The check's interaction bridge: ``bridge`` (the check's mesh) in mass case ``case`` at ``damping_ratio``
    (the check's without eq. 6.13's Delta zeta, which is for moving-force models)."""
    return (with_mass_case(bridge, case) if bridge.code is not None else bridge).replace(damping_ratio=float(damping_ratio))


def check_comparison(bridge: Any, train: ForceTrain, speed_kmh: float, damping_ratio: float, cutoff_hz: float,
                     case: str) -> InteractionComparison:
    """The check's comparison of ``train`` at ``speed_kmh``: on :func:`check_bridge`, the modes up to ``cutoff_hz``."""
    return interaction_comparison(check_bridge(bridge, damping_ratio, case), train, speed_kmh,
                                  max_frequency=cutoff_hz * (1.0 + 1e-9), case=case)


def comparison_arrays(c: InteractionComparison) -> dict[str, np.ndarray]:
    """A comparison as plain arrays (a check task's result, checkpointable): its numbers and its run's run_out,
    from which :func:`comparison_of` rebuilds the scenario."""
    out = {name: np.asarray(getattr(c, name), dtype=float) for name in (
        "speed_kmh", "damping_ratio", "additional_damping", "moving_force_acc", "moving_force_dz_acc",
        "interaction_acc", "frequencies", "end_time_s", "planned_end_time_s", "seconds")}
    out["run_out"] = np.asarray(c.scenario.track.run_out if c.scenario is not None else math.nan, dtype=float)
    return out


def comparison_of(arrays: dict[str, np.ndarray], bridge: Any, train: ForceTrain, damping_ratio: float,
                  cutoff_hz: float, case: str) -> InteractionComparison:
    """The comparison of :func:`comparison_arrays`' arrays for :func:`check_comparison`'s arguments (its scenario
    rebuilt: :func:`interaction_scenario` of the same inputs)."""
    b = check_bridge(bridge, damping_ratio, case)
    v = float(arrays["speed_kmh"])
    sc = interaction_scenario(b, train, v, max_frequency=cutoff_hz * (1.0 + 1e-9), run_out=float(arrays["run_out"]))
    return InteractionComparison(
        train=train.name, bridge=b.name, speed_kmh=v, spans=tuple(float(x) for x in b.spans),
        damping_ratio=float(arrays["damping_ratio"]), additional_damping=float(arrays["additional_damping"]),
        moving_force_acc=np.array(arrays["moving_force_acc"]), moving_force_dz_acc=np.array(arrays["moving_force_dz_acc"]),
        interaction_acc=np.array(arrays["interaction_acc"]), frequencies=np.array(arrays["frequencies"]),
        end_time_s=float(arrays["end_time_s"]), planned_end_time_s=float(arrays["planned_end_time_s"]), scenario=sc,
        seconds=float(arrays["seconds"]), case=case)


def summary_lines(comparisons: Sequence[InteractionComparison]) -> list[str]:
    """The check summary's lines of its interaction rows (none without them)."""
    if not comparisons:
        return []
    lines = ["interaction (vehicle models, deterministic run, smooth track) against moving forces, largest "
             "mid-span peak at the train's deciding speed:",
             f"  {'train':<10} {'km/h':>7} {'case':<8} {'moving F':>9} {'interact.':>9} {'difference':>11} "
             f"{'+dzeta 6.13':>11}"]
    for c in comparisons:
        lines.append(f"  {c.train:<10} {c.speed_kmh:>7.1f} {c.case:<8} {c.max_moving_force:>9.3f} "
                     f"{c.max_interaction:>9.3f} {c.difference:>+7.3f} ({-100 * c.reduction:+.0f} %) "
                     f"{c.max_moving_force_dz:>7.3f}")
    return lines


__all__ = ["DEFAULT_LEAD_IN", "DEFAULT_MAX_FREQUENCY", "DEFAULT_TIME_STEP", "InteractionComparison", "MF_SAMPLES_PER_PERIOD", "check_bridge",
           "check_comparison", "check_trains", "comparison_arrays", "comparison_of", "interaction_comparison", "interaction_scenario", "summary_lines"]
