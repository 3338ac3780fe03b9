"""The stochastic column of the EN 1991-2 check: the PEM of the random track irregularity on top of the mean,
for trains given as vehicle models, at the check's speeds.

EN 1991-2 covers the track's irregularity by a factor on the moving-force result (Annex C: 1 + phi''/2 for
a carefully maintained track); the pseudo-excitation method computes what that factor approximates. For a
train whose cars are vehicle models (the real trains of models/trains: ``ForceTrain.vehicles``) the check
builds one scenario (:func:`base_scenario`):

- the bridge: the check's own (its nominal mass case, the check's mesh of at least 64 elements per span)
  with the check's damping ratio on every mode (Table 6.6 or the one given; eq. 6.13's additional damping
  is for moving-force models and is left out of the vehicle model);
- the train: the train's vehicles in running order (a car's ``body_mass`` applied);
- the track and the analysis: those of a scenario (default :data:`DEFAULT_SCENARIO`, the reference study:
  german_low vertical, alignment and cross-level), with ``analysis.mode_max_frequency`` raised, where it is
  lower, to :data:`MODE_MARGIN` x the check's cut-off so that the channel along the track has every mode
  up to the cut-off;

and runs it at the chosen speeds with :func:`tb_exudyn.methods.sweep.run_sweep` (one rule for a run at a
speed: :func:`scenario_at` is ``sweep_scenario``, i.e. :func:`tb_exudyn.scenario.speed_rule.at_speed`: the
scenario's band and approach scaled by v / v0, its grid kept), on the channels :data:`CHANNELS`. Each
speed's row takes from the verdicts' exceedance machinery (``RandomResponse.checks()``, the default limits
and target probability: :func:`tb_exudyn.methods.sweep.check_values`) the deck acceleration criterion of
the check's track (:func:`tb_exudyn.codes.criteria.deck_criterion`: the criterion of models/limits/en1990_deck.toml
whose value is the moving-force rows' limit too, :func:`~tb_exudyn.codes.criteria.deck_acceleration_limit`) at its
deciding location: ``p_exceed``, the probability of exceeding
the limit at least once in one passage (Rice's rate, Poisson's first passage), and ``level_at_target``,
the level exceeded with the target probability per passage. The row at a speed is that of ``run_pem`` of
:func:`scenario_at` at that speed with :func:`engine_options` (the columns in float32: :data:`PRECISION`), to
round-off; ``tb-exudyn run`` of it (float64) within float32's error (sigma within 1e-5 of its largest value).

A scenario with a track structure (``track.structure``) gives rows on the track (docs/track.md section 8): its
structure, reach (``track.structure_approach``) and cut-off (``analysis.track_mode_max_frequency``) go with its
track and analysis; a train whose cars the track does not carry (the creep cars) is refused naming ``trains``
(:func:`check_on_track`), a speed whose track would exceed the dense eigen-solution's size naming the scenario,
before any work; the defaults of the two settings the rows take are said in the rows' warnings (:func:`track_note`).
"""

from __future__ import annotations

import dataclasses
import importlib
import math
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Sequence

from ..errors import ScenarioError, SettingError, one_of
from ..results.caveats import can_turn
from ..results.check_records import StochasticValues
from ..results.schema import CHECK_RECORD
from ..results.sweep import read_checks
from ..scenario import Scenario, load_scenario
from ..scenario.model import Analysis, Track, Train
from ..scenario.track_structure import TRACK_VEHICLE_KINDS
from ..scenario.registry import model_files
from .criteria import deck_criterion
from .trains import ForceTrain

#: the scenario whose track and analysis the stochastic rows take by default: the reference study
DEFAULT_SCENARIO = "li_zhu_2011"
#: the PEM runs' channels: the deck's vertical accelerations at the stations (a sweep's key quantity must
#: match a channel of the model: the plain ``acc_z``) and with them the derived ``acc_z_en1990`` along the
#: track, modes up to the cut-off, which the deck criterion reads
CHANNELS: tuple[str, ...] = ("bridge.span*.acc_z*",)
#: the bridge modes of the PEM model reach at least this factor times the check's cut-off frequency
MODE_MARGIN = 1.05
#: the precision of the PEM runs' columns (the batched engine's ``BatchedOptions.precision``): float32, as its grid
#: error's midpoint columns already are. On ice_mttm over li_zhu_2011_bridge (144 and 300 km/h) a speed's CPU
#: time falls by 14-26 % and every channel's max sigma stays within 7e-7 of the largest sigma of the float64 run,
#: the level at the target within 1e-7 relative (the engine's stated error: 1e-5 of a channel's largest sigma,
#: docs/speed.md section 1); tests/codes/test_stochastic.py compares the row with the float64 run
PRECISION = "float32"
#: the frequency grid's error (PEM's grid-error sweep: about a fifth of a speed's work, 1.5 CPU-s of ice_mttm's
#: 4.5 over li_zhu_2011_bridge) is estimated at every GRID_ERROR_EVERY-th speed of a train, its last speed included
#: (30 speeds: 4 of them) (:func:`grid_error_sampled`: the column's
#: measure of its grid), and at every other speed whose row a grid error of GRID_ERROR_TURN of sigma could turn
#: (:func:`grid_error_needed`: its PEM is run again with the estimate). The grid error enters a row only as a
#: caveat that could turn its verdict (``results.caveats.can_turn``: the relative error at least the margin
#: between the level and the limit), so a row whose margin exceeds GRID_ERROR_TURN is the same with and without
#: the estimate as long as the grid's error stays below GRID_ERROR_TURN there; the sampled speeds measure it
#: (li_zhu_2011's 200 linear frequencies, ice_mttm at 30 speeds from 144 to 300 km/h, every speed estimated:
#: the deciding channel's error at most 1.3 %, any deck channel's 2.6 %, both at 300 km/h, a sampled speed:
#: the error grows with the speed at the top of the range, the grid's spacing growing as v against the modes'
#: fixed peaks), and :func:`stochastic_run` warns when they reach half of GRID_ERROR_TURN (the error varies
#: from speed to speed as the peaks move across the grid's cells: a factor 2 of room)
GRID_ERROR_EVERY = 10
GRID_ERROR_TURN = 0.25
#: the table's stochastic columns (None where not computed): those of the check's schema that read a record's
#: StochasticValues
COLUMNS: tuple[str, ...] = tuple(v.name for v in CHECK_RECORD if v.attribute.startswith("stochastic."))


def engine_options(engine: str) -> Any:
    """The options of the PEM runs on ``engine``: the batched engine's in :data:`PRECISION` (None: another
    engine's defaults). ``run_pem(scenario_at(...), options=engine_options("batched"))`` gives a row's numbers."""
    if engine != "batched":
        return None
    # the engines: imported on first use (as _sweep)
    return importlib.import_module("tb_exudyn.engines.batched").BatchedOptions(precision=PRECISION)


def grid_error_sampled(i: int, n: int) -> bool:
    """Whether the ``i``-th of a train's ``n`` speeds estimates its grid error whatever its margin
    (:data:`GRID_ERROR_EVERY`; the last speed too)."""
    return i % GRID_ERROR_EVERY == 0 or i == n - 1


def grid_error_needed(summary: Any, criterion: str) -> bool:
    """Whether a grid error of :data:`GRID_ERROR_TURN` could turn the criterion's verdict in a speed's summary
    (run without the estimate): its level within that fraction of the limit, or not finite."""
    found = read_checks(summary).get(criterion)
    if found is None:
        return True
    return can_turn(found.estimate, found.limit, GRID_ERROR_TURN) is not False


def _sweep() -> Any:
    """tb_exudyn.methods.sweep, imported on first use: the methods build Exudyn models, which the check's
    moving-force rows (and ``tb-exudyn list``) do not need (as SweepResult.plot loads the plotting)."""
    return importlib.import_module("tb_exudyn.methods.sweep")


def eligible(train: ForceTrain) -> bool:
    """Whether the train is given as vehicle models (its stochastic rows can be computed)."""
    return bool(train.vehicles)


def scenario_source(scenario: str | Path | Scenario | None, where: str, key: str) -> Scenario:
    """The scenario whose track and analysis the rows take (None: :data:`DEFAULT_SCENARIO`); an unknown
    name, one without track irregularities or one with a track structure raises SettingError naming ``key``."""
    if scenario is None:
        scenario = DEFAULT_SCENARIO
    if isinstance(scenario, Scenario):
        sc = scenario
    elif isinstance(scenario, (str, Path)):
        text = str(scenario)
        known = model_files("scenarios")
        if not text.strip() or (text not in known and not text.endswith(".toml") and not Path(text).exists()):
            raise SettingError(where, key, text, one_of(known, text, tail=" or a scenario .toml file"),
                               "unknown scenario")
        sc = load_scenario(text)  # a bad file: its ScenarioError names the file and the key
    else:
        raise SettingError(where, key, type(scenario).__name__, "a scenario name, a .toml path or a Scenario")
    if not sc.track.irregularities:
        raise SettingError(where, key, sc.name, "a scenario with track irregularities (track.irregularities)",
                           "no irregularity: nothing random to analyse")
    return sc


def check_on_track(source: Scenario, train: ForceTrain, where: str = "check") -> None:
    """A train whose cars the track layer does not carry (the creep cars: ``TRACK_VEHICLE_KINDS``) on a
    ``source`` naming a track structure: SettingError naming ``trains``, before any work."""
    if not source.track.structure:
        return
    kinds = sorted({v.kind for v in train.vehicles} - set(TRACK_VEHICLE_KINDS))
    if kinds:  # one line within 200 characters
        raise SettingError(where, "trains", train.name, "cars of kind car15 or articulated on a track.structure",
                           f"{', '.join(kinds)}: the track layer carries no creep rows yet")


def track_note(base: Scenario) -> str:
    """What the rows of ``base`` (a check's stochastic scenario) take of the track at its defaults, the user's
    scenario not setting them (docs/track.md 8): the track modes' cut-off ``analysis.track_mode_max_frequency``
    and the track's reach ``track.structure_approach``; "" without a track structure or with both set."""
    if not base.track.structure:
        return ""
    left = []
    if base.analysis.track_mode_max_frequency == _default(Analysis, "track_mode_max_frequency"):
        left.append(f"the track's modes up to {base.analysis.track_mode_max_frequency:g} Hz "
                    "(analysis.track_mode_max_frequency; 300 Hz keeps the band within 2 % at a fraction of the cost)")
    if base.track.structure_approach == _default(Track, "structure_approach"):
        left.append("the rails under each speed's whole run (track.structure_approach = 0; a speed's lead-in, "
                    "scaled by the speed rule, lengthens its track, solved anew per speed)")
    if not left:
        return ""
    return (f"the stochastic rows on the track {base.track.structure} take the defaults: {'; '.join(left)}: set them "
            f"in the stochastic scenario (docs/track.md 8)")


def _default(cls: Any, name: str) -> Any:
    return next(f.default for f in dataclasses.fields(cls) if f.name == name)


def base_scenario(source: Scenario, bridge: Any, train: ForceTrain, damping_ratio: float, cutoff_hz: float,
                  where: str = "check", key: str = "stochastic_scenario") -> Scenario:
    """The scenario of ``train``'s stochastic rows (the module docstring): ``bridge`` (the check's, in its
    nominal case) at ``damping_ratio``, the train's vehicles, the track and analysis of ``source`` with
    the bridge modes up to at least MODE_MARGIN x ``cutoff_hz``; its speed is the source's (the approach
    rule of the sweep scales the lead-in from it). A combination the schema refuses (e.g. a vehicle
    longer than the track) raises SettingError naming ``key``."""
    if not eligible(train):
        raise SettingError(where, "trains", train.name, "a train given as vehicle models (models/trains)",
                           "moving forces only")
    check_on_track(source, train, where)
    an = source.analysis
    modes = max(an.mode_max_frequency, MODE_MARGIN * float(cutoff_hz))
    try:
        return Scenario(
            name=f"check_{train.name}_{bridge.name}", speed_kmh=source.speed_kmh,
            train=Train(vehicles=tuple(train.vehicles)),
            bridge=bridge.replace(damping_ratio=float(damping_ratio)),
            track=source.track, analysis=an.replace(mode_max_frequency=modes),
            description=f"EN 1991-2 check, stochastic rows: {train.name} over {bridge.name} (nominal mass case), "
                        f"track and analysis of {source.name}",
            source=f"tb_exudyn.codes.check (stochastic), from scenario {source.name}",
            notes=f"bridge damping ratio {damping_ratio:g} on every mode (the check's); bridge modes up to "
                  f"{modes:.4g} Hz (the check's cut-off {cutoff_hz:.4g} Hz)")
    except ScenarioError as exc:
        raise SettingError(where, key, source.name, exc.allowed or "a scenario whose track fits the train",
                           f"the check's scenario for {train.name}: {exc.key} {exc.reason}".strip()) from None


def scenario_at(base: Scenario, speed_kmh: float, n_freq: int | None = None) -> Scenario:
    """The scenario of the row at ``speed_kmh``: what :func:`run_sweep` runs there (its grid and approach
    rules, the channels :data:`CHANNELS`); ``n_freq``: the count the run used (an adaptive grid is raised
    at each speed to what its rules need: the row's ``stochastic_n_freq``). ``run_pem`` of it with
    :func:`engine_options` gives the row's numbers (``tb-exudyn run`` of its TOML, ``scenario_to_toml``: within
    float32's error)."""
    sc = _sweep().sweep_scenario(base, float(speed_kmh), CHANNELS)
    if n_freq is not None and int(n_freq) != sc.analysis.n_freq:
        sc = sc.replace(analysis=sc.analysis.replace(n_freq=int(n_freq)))
    return sc


@dataclass(frozen=True)
class StochasticRun:
    """The stochastic rows of one train: per speed (km/h, rounded to 1e-6) its values (the columns of
    :data:`COLUMNS`), the warnings of the runs and their time."""

    train: str
    base: Scenario = field(repr=False)
    values: dict[float, StochasticValues] = field(repr=False)
    warnings: tuple[str, ...] = ()
    seconds: float = 0.0
    #: what the speeds' grid-error estimates measured ("" when none was made)
    grid_error: str = ""


def speed_key(speed_kmh: float) -> float:
    return round(float(speed_kmh), 6)


def run_stochastic(base: Scenario, speeds_kmh: Sequence[float], track: str, *, workers: int | None = None,
                   executor: Any = None, progress: bool = False, name: str = "") -> StochasticRun:
    """The PEM of ``base`` at each speed (:func:`tb_exudyn.methods.sweep.run_sweep` with the channels
    :data:`CHANNELS`; nothing written) and per speed the columns: p_exceed and level_at_target of the
    track's deck criterion at its deciding location, that location, the largest |mean| there (the
    vehicle model's deterministic run), the criterion's verdict and its caveats that could turn it."""
    engine = importlib.import_module("tb_exudyn.engines").DEFAULT_ENGINE  # on first use (as _sweep)
    t0 = time.perf_counter()
    methods = _sweep()
    # a sweep names its tasks by speed_label (6 significant digits): speeds sharing a label run in
    # separate sweeps (e.g. 250 and 250.0001 km/h)
    batches: list[list[float]] = []
    for v in speeds_kmh:
        batch = next((b for b in batches if methods.speed_label(v) not in {methods.speed_label(x) for x in b}), None)
        if batch is None:
            batches.append(batch := [])
        batch.append(float(v))
    done: list[tuple[float, dict[str, Any]]] = []
    for batch in batches:
        sweep = methods.run_sweep(base, batch, channels=CHANNELS, workers=workers, executor=executor,
                                  progress=progress, options=engine_options(engine))
        done += list(zip(sweep.speeds, sweep.summaries))
    return stochastic_run(base, done, track, name, time.perf_counter() - t0)


def stochastic_run(base: Scenario, done: Sequence[tuple[float, Any]], track: str, name: str = "",
                   seconds: float | None = None) -> StochasticRun:
    """The stochastic rows of one train from its speeds' sweep summaries (``done``: (speed, summary) as
    :func:`tb_exudyn.methods.sweep.speed_summary` makes them, one per PEM run; the EN 1991-2 check's
    method runs them as its tasks); ``seconds``: the runs' time (default: the summaries' own)."""
    crit = deck_criterion(track)
    values: dict[float, StochasticValues] = {}
    messages: list[str] = []
    estimated: list[tuple[float, float]] = []  # (speed, the deciding channel's grid error) where estimated
    for v, s in done:
        found = read_checks(s).get(crit)
        if found is None:  # the channels are the model's (its limit file was read before the work)
            raise SettingError("check", "stochastic", name or base.name, f"a model with the channels {CHANNELS[0]}",
                               f"no {crit} row at {v:g} km/h")
        names = [str(c) for c in s["channels"]]
        mean = float(s["max_abs_mean"][names.index(found.channel)]) if found.channel in names else math.nan
        ge = s.get("grid_error")
        if ge is not None and found.channel in names and math.isfinite(float(ge[names.index(found.channel)])):
            estimated.append((float(v), float(ge[names.index(found.channel)])))
        values[speed_key(v)] = StochasticValues(
            p_exceed=found.probability, level_at_target=found.estimate, location=found.channel, mean_acc=mean,
            verdict=found.verdict + (f" ({found.reason})" if found.reason else ""), caveats=found.caveats,
            n_freq=int(s["n_freq"]))
        messages += [str(m) for m in s.get("warnings", ())]
    if seconds is None:
        seconds = sum(float(s["seconds"]) for _, s in done if math.isfinite(float(s["seconds"])))
    grid, note = _grid_error_note(estimated, len(done))
    notes = [n for n in (note, track_note(base)) if n]
    return StochasticRun(train=name or base.name, base=base, values=values,
                         warnings=tuple(dict.fromkeys(messages + notes)), seconds=seconds,
                         grid_error=grid)


def _grid_error_note(estimated: Sequence[tuple[float, float]], n: int) -> tuple[str, str]:
    """(what the rows' grid-error estimates measured, a warning when they reach GRID_ERROR_TURN / 2: the speeds
    without an estimate were judged against GRID_ERROR_TURN)."""
    if not estimated:
        return "", ""
    v, top = max(estimated, key=lambda e: abs(e[1]))
    text = (f"grid error of the deciding channel estimated at {len(estimated)} of {n} speeds: at most "
            f"{100 * abs(top):.2g} % (at {v:g} km/h)")
    if len(estimated) == n or abs(top) < GRID_ERROR_TURN / 2:
        return text, ""
    return text, (f"the frequency grid's error reaches {100 * abs(top):.2g} % at {v:g} km/h, more than half of the "
                  f"{100 * GRID_ERROR_TURN:g} % the speeds without an estimate were judged against (their rows may "
                  f"miss a grid-error caveat): refine the grid (analysis.n_freq, analysis.freq_spacing = 'adaptive')")


__all__ = ["CHANNELS", "COLUMNS", "DEFAULT_SCENARIO", "GRID_ERROR_EVERY", "GRID_ERROR_TURN", "MODE_MARGIN", "PRECISION",
           "StochasticRun", "base_scenario", "check_on_track", "eligible", "engine_options", "grid_error_needed", "grid_error_sampled", "run_stochastic", "scenario_at", "scenario_source", "speed_key",
           "stochastic_run", "track_note"]
