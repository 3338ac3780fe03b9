"""The EN 1991-2 check's arguments checked and its work planned, before any work (:func:`plan_check`).

:func:`plan_check` takes the arguments of :func:`tb_exudyn.codes.check.check` and returns a
:class:`CheckSetup`: the bridge on the check's mesh, the mass cases and their modes up to the cut-off, the
trains (HSLM-B for HSLM-A under 7 m), the damping, the speed series of each train, the stochastic rows'
scenarios at their speeds and the interaction trains, every integration's size checked. Errors name the
library's keys (the arguments: ``trains``, ``stochastic_speeds`` ...) and the caller ``where``; the command
line respells them as its flags. Nothing is computed beyond the modes: the work is the check's method
(:mod:`tb_exudyn.methods.check`: one task per mass case and train, one per stochastic speed).
"""

from __future__ import annotations

import importlib
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from ..errors import ResourceError, ScenarioError, SettingError, UserError, one_of
from ..scenario.code_data import MASS_CASES, with_mass_case
from ..scenario.io import load_bridge
from ..scenario.model import Continuous, Frame, SimpleBeam
from ..scenario.registry import model_files
from ..scenario.schema import source_file
from . import en1991 as code
from . import interaction as vbi
from . import stochastic as stoch
from .a2_verdicts import check_alpha
from .check_modes import modes_for_check
from .hslm_b import HSLM_B_SPANS, hslm_b
from .moving_force import MAX_STEPS, integration_steps
from .trains import ForceTrain, TrainSource, distinct_trains, train_sources

#: the check's checkpoint folder in its output folder (tb_exudyn.methods.check)
CHECKPOINT = "checkpoint-check"
#: the mass case of a bridge without ballast (EN 1991-2 6.4.6.3.2: its only case)
NOMINAL_CASE = "nominal"
#: HSLM-A applies to spans from this length; HSLM-B below (EN 1991-2 Annex E, Table E.4) [m] [check]
HSLM_A_MIN_SPAN = 7.0
#: the check's finite-element mesh: at least this many beam elements per span. The shipped bridges' 16
#: place single_span_32m's third torsion mode at 43.84 Hz against the closed form's 43.22 Hz, and the
#: deck accelerations at speeds off resonance follow it (up to 32 % apart under HSLM-A1); 64 give 43.26
#: Hz and every speed's mid-span acceleration within 0.83 % of the closed form (tests/codes/test_check.py)
CHECK_ELEMENTS_PER_SPAN = 64
#: the lowest line speed a check takes [km/h]: its series is rounded to 1e-6 km/h (1e-300 km/h would round to
#: a speed of 0) and its time steps grow as 1 / v (HSLM-A1 over single_span_32m at 1.2 km/h needs 1.2 million,
#: refused by MAX_STEPS with its own message); a railway line speed is tens to hundreds of km/h, so a value
#: below 1 km/h can only be a mistake (a unit, a typo)
MIN_LINE_SPEED_KMH = 1.0


@dataclass(frozen=True)
class CaseModes:
    """A mass case's modes for the check (:func:`tb_exudyn.codes.check_modes.modes_for_check`)."""

    modal: Any = field(repr=False)
    used: np.ndarray = field(repr=False)
    f1: float = 0.0
    f3: float | None = None
    cutoff: float = 0.0
    basis: str = ""


@dataclass(frozen=True)
class CheckSetup:
    """Everything :func:`plan_check` checked and planned (see the module docstring)."""

    where: str = field(repr=False)
    bridge: Any = field(repr=False)
    label: str
    mesh_basis: str
    construction: str
    construction_basis: str
    line_speed_kmh: float
    track: str
    maintenance: str
    speed_step_kmh: float
    additional_damping: bool
    cases: tuple[str, ...]
    trains: tuple[ForceTrain, ...] = field(repr=False)
    spans: tuple[float, ...]
    zeta: float
    zeta_vehicles: float
    damping_basis: str
    limit: float
    k_irr: float
    alpha: float
    alpha_given: bool
    modes: dict[str, CaseModes] = field(repr=False)
    ref_case: str
    series: dict[str, tuple[float, ...]] = field(repr=False)
    #: the trains with stochastic rows, their scenarios (stochastic.base_scenario) and speeds
    stochastic_trains: tuple[ForceTrain, ...] = field(default=(), repr=False)
    stochastic_source: Any = field(default=None, repr=False)
    bases: dict[str, Any] = field(default_factory=dict, repr=False)
    run_speeds: dict[str, tuple[float, ...]] = field(default_factory=dict, repr=False)
    interaction_trains: tuple[ForceTrain, ...] = field(default=(), repr=False)

    @property
    def span(self) -> float:
        """The longest span: Table 6.6's ratio and L_Phi of Annex C."""
        return max(self.spans)

    def err(self, key: str, value: Any, allowed: str, reason: str = "") -> SettingError:
        return SettingError(self.where, key, value, allowed, reason)

    def stochastic_prefix(self, train: str) -> str:
        """How an error of a stochastic row's PEM (e.g. a run this machine cannot hold) says which option's runs."""
        given = self.stochastic_source.source_file or self.stochastic_source.name
        return f"{self.where}: key 'stochastic_scenario' = {given!r}, the stochastic rows of {train}"


def prefixed(exc: UserError, prefix: str) -> UserError:
    """The same error (class and attributes) with ``prefix: `` before its one line."""
    out = type(exc).__new__(type(exc))
    Exception.__init__(out, f"{prefix}: {exc}")
    out.__dict__.update(exc.__dict__)
    out.message = f"{prefix}: {exc}"
    return out


def _scalars(where: str, line_speed_kmh: Any, track: str, maintenance: str, speed_step_kmh: Any,
             damping_ratio: Any) -> None:
    def err(key: str, value: Any, allowed: str, reason: str = "") -> SettingError:
        return SettingError(where, key, value, allowed, reason)

    number = isinstance(line_speed_kmh, (int, float)) and not isinstance(line_speed_kmh, bool)
    if not (number and math.isfinite(line_speed_kmh) and MIN_LINE_SPEED_KMH <= line_speed_kmh <= code.MAX_LINE_SPEED_KMH):
        raise err("line_speed_kmh", line_speed_kmh, f"a speed in [{MIN_LINE_SPEED_KMH:g}, {code.MAX_LINE_SPEED_KMH:g}] km/h",
                  "out of range" if number and math.isfinite(line_speed_kmh) else "")
    if track not in code.DECK_ACCELERATION_LIMITS:
        raise err("track", track, " or ".join(code.DECK_ACCELERATION_LIMITS))
    if maintenance not in code.IRREGULARITY_FACTOR:
        raise err("maintenance", maintenance, " or ".join(code.IRREGULARITY_FACTOR))
    if not (isinstance(speed_step_kmh, (int, float)) and 0 < speed_step_kmh <= code.MAX_SPEED_STEP_KMH):
        raise err("speed_step_kmh", speed_step_kmh, f"0 < step <= {code.MAX_SPEED_STEP_KMH:g} km/h")
    if damping_ratio is not None and not (isinstance(damping_ratio, (int, float)) and 0.0 <= damping_ratio < 1.0):
        raise err("damping_ratio", damping_ratio, "a ratio in [0, 1), or none for Table 6.6")


def _bridge(where: str, bridge: Any, construction: str | None) -> tuple[Any, str, str, str, str]:
    """(bridge on the check's mesh, its label as the user gave it, mesh basis, construction, its basis)."""
    def err(key: str, value: Any, allowed: str, reason: str = "") -> SettingError:
        return SettingError(where, key, value, allowed, reason)

    label = str(bridge) if isinstance(bridge, (str, Path)) else (
        source_file(bridge) or getattr(bridge, "name", type(bridge).__name__))  # the bridge as the user gave it
    if isinstance(bridge, (str, Path)):
        text = str(bridge)
        known = model_files("bridges")
        if not (text.endswith(".toml") or Path(text).exists()) and text not in known:
            raise err("bridge", text, one_of(known, text, tail=" or a .toml file"), "unknown bridge name")
        bridge = load_bridge(bridge)
    if not isinstance(bridge, (SimpleBeam, Frame, Continuous)):  # e.g. a modal_table: no section data
        raise err("bridge", label, "a bridge with sections (SimpleBeam, Frame, Continuous)",
                  f"a {getattr(bridge, 'kind', 'bridge')} bridge has no section data"
                  if hasattr(bridge, "kind") else "")
    mesh_basis = f"{bridge.elements_per_span} beam elements per span (the bridge's)"
    if bridge.elements_per_span < CHECK_ELEMENTS_PER_SPAN:
        mesh_basis = (f"{CHECK_ELEMENTS_PER_SPAN} beam elements per span (the bridge's {bridge.elements_per_span} "
                      "refined: the torsion modes up to the cut-off converge)")
        bridge = bridge.replace(elements_per_span=CHECK_ELEMENTS_PER_SPAN)
    if construction is None:
        if bridge.code is None:
            raise err("bridge", label, "a bridge whose file declares its construction type ([code] table, "
                      f"code.construction: {', '.join(code.CONSTRUCTION_TYPES)}), or a construction type given",
                      "no construction type")
        construction, construction_basis = bridge.code.construction, "the bridge's data (code.construction)"
    else:
        construction_basis = "given"
    if construction not in code.CONSTRUCTION_TYPES:
        raise err("construction", construction, ", ".join(code.CONSTRUCTION_TYPES))
    return bridge, label, mesh_basis, construction, construction_basis


def _cases(where: str, bridge: Any, cases: Sequence[str] | None) -> tuple[str, ...]:
    ballast = bridge.code is not None and bridge.code.ballast_mass_per_length > 0.0
    if cases is None:
        cases = ("lower", NOMINAL_CASE, "upper") if ballast else (NOMINAL_CASE,)
    cases = tuple(cases)
    bad = [c for c in cases if c not in MASS_CASES] or ([] if ballast or cases == (NOMINAL_CASE,) else
                                                         [c for c in cases if c != NOMINAL_CASE])
    if bad or not cases:
        raise SettingError(where, "cases", list(cases), "mass cases of " + ", ".join(MASS_CASES) + (
            "" if ballast else " (only nominal: the bridge declares no ballast, code.ballast_mass_per_length)"))
    return cases


def _trains(where: str, trains: Any, spans: Sequence[float], continuous: bool) -> list[ForceTrain]:
    """The trains, each once; HSLM-B for HSLM-A on a simply supported span under 7 m (EN 1991-2 6.4.6.1.1)."""
    given = [trains] if isinstance(trains, (str, ForceTrain)) else list(trains)
    if not given:
        raise SettingError(where, "trains", given, "hslm_a, HSLM-A1 ... HSLM-A10 or a train of models/trains",
                           "no train")
    pairs = [pair for t in given for pair in ([(t, TrainSource(t.name, f"the ForceTrain object {t.name!r}", id(t)))]
                                              if isinstance(t, ForceTrain) else train_sources(t, where, "trains"))]
    train_list = distinct_trains(pairs, where, "trains")  # two trains with one name: refused, naming both
    hslm_a = any(t.name.startswith("HSLM-A") for t in train_list)
    if hslm_a and min(spans) < HSLM_A_MIN_SPAN and not continuous and min(spans) >= HSLM_B_SPANS[0]:
        b = hslm_b(min(spans))
        train_list = distinct_trains([p for p in pairs if not p[0].name.startswith("HSLM-A")] + [
            (b, TrainSource("hslm_a", f"EN 1991-2's {b.name} (HSLM-A's stand-in under 7 m)", "hslm_b"))],
            where, "trains")
    if any(t.name.startswith("HSLM-A") for t in train_list) and min(spans) < HSLM_A_MIN_SPAN:
        raise SettingError(where, "trains", [t.name for t in train_list], f"spans >= {HSLM_A_MIN_SPAN:g} m for HSLM-A",
                           f"a continuous girder's {min(spans):g} m span (HSLM-B: simple spans < 7 m)")
    return train_list


def _stochastic_speeds(where: str, stochastic_speeds: Any, line_speed_kmh: float) -> list[float]:
    """The stochastic rows' own speeds (none: every speed of the series), checked against the series' range."""
    if stochastic_speeds is None:
        return []
    top_speed = code.DESIGN_SPEED_FACTOR * float(line_speed_kmh)
    low_speed = min(code.SPEED_SERIES_START_KMH, top_speed)

    def err(value: Any, allowed: str, reason: str = "") -> SettingError:
        return SettingError(where, "stochastic_speeds", value, allowed, reason)

    if isinstance(stochastic_speeds, (str, bytes)):
        raise err(stochastic_speeds, "speeds [km/h] as numbers, or none for every speed")
    values = [stochastic_speeds] if isinstance(stochastic_speeds, (int, float)) else stochastic_speeds
    try:
        values = [v for v in values]
    except TypeError:
        raise err(stochastic_speeds, "speeds [km/h], or none for every speed") from None
    allowed = (f"speeds from {low_speed:g} to {top_speed:g} km/h (the check's series: 40 m/s to 1.2 x the "
               "line speed), each once")
    if not values:
        raise err(list(values), allowed, "no speed")
    for v in values:
        if isinstance(v, bool) or not isinstance(v, (int, float, np.floating, np.integer)) or not (
                math.isfinite(v) and low_speed - 1e-6 <= v <= top_speed + 1e-6):
            raise err(v, allowed, "outside the series' range")
    keys = [round(float(v), 6) for v in values]
    if len(set(keys)) != len(keys):
        raise err(list(values), allowed, "a speed given twice")
    return [min(max(k, low_speed), top_speed) for k in keys]


def _stochastic(where: str, train_list: Sequence[ForceTrain], cases: Sequence[str], track: str, stochastic: Any,
                stochastic_speeds: Any, stochastic_scenario: Any, line_speed_kmh: float) -> tuple[list, list, Any]:
    """(the trains with stochastic rows, their own speeds, the source scenario)."""
    if not isinstance(stochastic, bool):
        raise SettingError(where, "stochastic", stochastic, "True or False")
    if not stochastic and (stochastic_speeds is not None or stochastic_scenario is not None):
        key = "stochastic_speeds" if stochastic_speeds is not None else "stochastic_scenario"
        raise SettingError(where, key, stochastic_speeds if stochastic_speeds is not None else str(stochastic_scenario),
                           "with stochastic=True only", "no stochastic rows asked for")
    if not stochastic:
        return [], [], None
    chosen = [t for t in train_list if stoch.eligible(t)]
    if not chosen:
        raise SettingError(where, "stochastic", [t.name for t in train_list], "vehicle models (ice_mttm, "
                           "ave_s103, a .toml)", "no train for the stochastic rows (HSLM-A: moving forces)")
    if NOMINAL_CASE not in cases:
        raise SettingError(where, "cases", list(cases), f"mass cases including {NOMINAL_CASE!r} (the stochastic rows' case)")
    extra = _stochastic_speeds(where, stochastic_speeds, line_speed_kmh)
    return chosen, extra, stoch.scenario_source(stochastic_scenario, where, "stochastic_scenario")


def _damping(construction: str, span: float, damping_ratio: float | None, additional: bool) -> tuple[float, float, str]:
    """(zeta of the moving-force rows, zeta of the vehicle models' rows, its basis)."""
    if damping_ratio is not None:
        zeta = float(damping_ratio)
        basis = f"damping ratio {100 * zeta:.3g} % (given)"
    else:
        zeta = code.damping_ratio_table_6_6(construction, span)
        basis = f"damping {100 * zeta:.3g} % (Table 6.6, {construction.replace('_', ' ')}, L = {span:g} m)"
    zeta_vehicles = zeta  # eq. 6.13 is for moving-force models: the vehicle model's rows leave it out
    if additional:
        dz = code.additional_damping_eq_6_13(span)
        zeta += dz
        basis += f" + {100 * dz:.3g} % (eq. 6.13)"
    return zeta, zeta_vehicles, basis


def _series(train_list: Sequence[ForceTrain], modes: dict[str, CaseModes], line_speed_kmh: float, step_kmh: float,
            stochastic_names: set[str], extra: Sequence[float]) -> dict[str, tuple[float, ...]]:
    """Each train's speed series (6.4.6.2), refined near every case's v_i = n0 D / i; a stochastic train's own
    speeds added."""
    out = {}
    for train in train_list:
        v_res = sorted({float(v) for m in modes.values() for v in code.resonant_speeds_kmh(m.f1, train.regular_length)})
        speeds = code.speed_series(line_speed_kmh, v_res, step_kmh=step_kmh)
        if train.name in stochastic_names and extra:
            speeds = np.unique(np.round(np.concatenate([speeds, extra]), 6))
        out[train.name] = tuple(float(v) for v in speeds)
    return out


def _stochastic_runs(where: str, bridge: Any, trains: Sequence[ForceTrain], source: Any, series: dict, extra: list,
                     zeta_vehicles: float, cutoff: float) -> tuple[dict[str, Any], dict[str, tuple[float, ...]]]:
    """The stochastic rows' scenarios and speeds, every speed's scenario checked before any run."""
    bases, run_speeds = {}, {}
    for train in trains:
        bases[train.name] = stoch.base_scenario(source, bridge, train, zeta_vehicles, cutoff, where,
                                                "stochastic_scenario")
        chosen = {stoch.speed_key(c) for c in (series[train.name] if not extra else extra)}
        run_speeds[train.name] = tuple(v for v in series[train.name] if stoch.speed_key(v) in chosen)
        for v in run_speeds[train.name]:
            try:
                sc = stoch.scenario_at(bases[train.name], v)
            except ScenarioError as exc:
                raise SettingError(where, "stochastic_scenario", source.source_file or source.name, exc.allowed,
                                   f"analysis.{exc.key} at {v:g} km/h: {exc.reason}") from None
            _track_size(where, source, train, sc, v)
    return bases, run_speeds


def _track_size(where: str, source: Any, train: ForceTrain, sc: Any, v: float) -> None:
    """A stochastic row's track (``track.structure`` of the source) within the dense eigen-solution's size at its
    speed (tb_exudyn.system.track_bridge.scenario_extent), before any work: SettingError naming the option."""
    if not sc.track.structure:
        return
    try:  # the track's module on first use (scipy's sparse matrices: only with a track)
        importlib.import_module("tb_exudyn.system.track_bridge").scenario_extent(sc)
    except ScenarioError as exc:  # one line within 200 characters
        raise SettingError(where, "stochastic_scenario", source.source_file or source.name,
                           "a track.structure_approach", f"{train.name} at {v:g} km/h: {exc.reason}") from None


def too_many_steps(where: str, line_speed_kmh: float, train: ForceTrain, lowest_kmh: float, steps: Any) -> ResourceError:
    return ResourceError.from_parts(
        where, "line_speed_kmh", line_speed_kmh, "a higher line speed: the lowest speed of the series sets the step",
        f"{train.name} at {lowest_kmh:g} km/h needs {steps} steps, more than {MAX_STEPS}")


def plan_check(bridge: Any, line_speed_kmh: float, trains: Any = ("hslm_a",), track: str = "ballasted",
               construction: str | None = None, additional_damping: bool = False, damping_ratio: float | None = None,
               maintenance: str = "careful", speed_step_kmh: float = code.MAX_SPEED_STEP_KMH,
               cases: Sequence[str] | None = None, where: str = "check", stochastic: bool = False,
               stochastic_speeds: Any = None, stochastic_scenario: Any = None, interaction: bool = False,
               alpha: float | None = None) -> CheckSetup:
    """The arguments of :func:`tb_exudyn.codes.check.check` checked and the work planned (the module
    docstring); SettingError (or ResourceError) naming ``where`` and the argument otherwise."""
    _scalars(where, line_speed_kmh, track, maintenance, speed_step_kmh, damping_ratio)
    bridge, label, mesh_basis, construction, construction_basis = _bridge(where, bridge, construction)
    cases = _cases(where, bridge, cases)
    spans = tuple(float(s) for s in bridge.spans)
    train_list = _trains(where, trains, spans, isinstance(bridge, Continuous))
    chosen, extra, source = _stochastic(where, train_list, cases, track, stochastic, stochastic_speeds,
                                        stochastic_scenario, line_speed_kmh)

    def err(key: str, value: Any, allowed: str, reason: str = "") -> SettingError:
        return SettingError(where, key, value, allowed, reason)

    interaction_trains = vbi.check_trains(train_list, interaction, err)
    alpha_value = check_alpha(alpha, where, "alpha")
    zeta, zeta_vehicles, basis = _damping(construction, max(spans), damping_ratio, additional_damping)
    # each mass case its own bridge and modes; the nominal case's (or the first's) describe the result
    modes = {case: CaseModes(*modes_for_check(with_mass_case(bridge, case) if bridge.code is not None else bridge,
                                              err, label)) for case in cases}
    ref_case = NOMINAL_CASE if NOMINAL_CASE in modes else cases[0]
    series = _series(train_list, modes, line_speed_kmh, speed_step_kmh, {t.name for t in chosen}, extra)
    bases, run_speeds = _stochastic_runs(where, bridge, chosen, source, series, extra, zeta_vehicles,
                                         modes[NOMINAL_CASE].cutoff) if chosen else ({}, {})
    for case, train in ((c, t) for c in cases for t in train_list):  # every integration's size, before any work
        m = modes[case]
        steps = integration_steps(m.modal.length, m.modal.frequencies[m.used], train, np.array(series[train.name]),
                                  spans).n_steps
        if steps > MAX_STEPS:
            raise too_many_steps(where, line_speed_kmh, train, series[train.name][0], steps)
    return CheckSetup(
        where=where, bridge=bridge, label=label, mesh_basis=mesh_basis, construction=construction,
        construction_basis=construction_basis, line_speed_kmh=float(line_speed_kmh), track=track,
        maintenance=maintenance, speed_step_kmh=float(speed_step_kmh), additional_damping=bool(additional_damping),
        cases=cases, trains=tuple(train_list), spans=spans, zeta=zeta, zeta_vehicles=zeta_vehicles,
        damping_basis=basis, limit=code.deck_acceleration_limit(track), k_irr=code.IRREGULARITY_FACTOR[maintenance],
        alpha=alpha_value, alpha_given=alpha is not None, modes=modes, ref_case=ref_case, series=series,
        stochastic_trains=tuple(chosen), stochastic_source=source, bases=bases, run_speeds=run_speeds,
        interaction_trains=tuple(interaction_trains))


__all__ = ["CHECKPOINT", "CHECK_ELEMENTS_PER_SPAN", "CaseModes", "CheckSetup", "HSLM_A_MIN_SPAN", "MIN_LINE_SPEED_KMH",
           "NOMINAL_CASE", "plan_check", "prefixed", "too_many_steps"]
