"""Speed sweeps: PEM at a series of train speeds, the frequency grid following the speed.

At each speed v the scenario is :func:`sweep_scenario` of the base: the one rule for a run at a
speed (:func:`tb_exudyn.scenario.speed_rule.at_speed`, also that of ``run --speed-kmh`` and of the EN
check's stochastic rows):

- the base's band scaled by v / v0 (the same wavelengths; freq_max at most 0.1 / time_step, the
  highest frequency the time step resolves, as ``Analysis`` requires), the base's number of
  frequencies and spacing (pass ``n_freq`` to refine, ``freq_spacing="adaptive"`` for converged
  grids: the study's 200 linear points are not converged for every channel, docs/findings.md). With
  the adaptive spacing each speed's grid has at least ``n_freq`` nodes and at least what the grid's
  rules need at that speed (its band, run length and train spread follow the speed:
  :func:`tb_exudyn.methods.adaptive_grid.points_needed`); the count used is in the speed's result
  (``result.scenario.analysis.n_freq``) and in the table;
- the base's approach kept in seconds above v0 and in metres below it (a faster train gets a longer
  lead-in, so that the runs, started at rest, have settled as well as at the base speed);
- the output channels of the key quantities (:data:`KEY_QUANTITIES`, or those given: each given
  pattern must match a channel of the model, derived channels such as ``acc_z_en1990`` included,
  else the sweep is refused naming it; a default quantity the model lacks is left out and listed in
  ``provenance["quantities_left_out"]``). The default ones include the deck acceleration along the
  track ``bridge.*.acc_z_en1990``, so that every sweep checks the deck acceleration criterion (the
  code checks of each speed are those whose channels the sweep computes).

The warnings of the speeds are issued once per kind after the sweep (:func:`grouped_warnings`: the
first message of that kind and the speeds it was raised at); each speed's own are in its summary
(and in the report).

Each speed is one task on the sweep's executor (the local process pool, a Dask executor: the
same :class:`~tb_exudyn.execution.Execution` as a sweep over frequencies), running the whole PEM of
that speed in its worker in one column slice (:data:`SWEEP_SLICES`), so that a sweep's result at
a speed is bitwise that of ``run_pem(sweep_scenario(base, v), ..., slices=SWEEP_SLICES)`` (with an
adaptive grid: of ``run_pem`` on the speed's result's scenario, whose n_freq is the count used). With an
output folder each speed's result and checkpoint go to ``DIR/<speed>/`` (``pem/`` and
``checkpoint/``) and the sweep's per-speed summaries to ``DIR/checkpoint-sweep/``: an interrupted
sweep resumes speed by speed, and a speed half done resumes within its own checkpoint.

A scenario with a track structure (``track.structure``, docs/track.md section 8) sweeps as any other: each speed
a PEM on the track-and-deck body. Its modes and the static correction of the left-out ones are a costly part of a
speed's set-up and do not depend on the speed when the rails are cut short of the run
(``track.structure_approach``: placed by the bridge, not by the lead-in the speed rule scales), so the parent's
(its model built for the channel list) is sent with the workers' set-up (:func:`shared_tracks`,
:class:`SpeedWorker`) and every speed takes it instead of solving it again; with the rails under the whole run each
speed has its own (longer at higher speeds: each speed's size is checked before any run).

The table (:func:`sweep_rows`, ``speed_sweep.csv``, written with the output folder; the figure is
:func:`tb_exudyn.plotting.plot_speed_sweep`, the page :func:`tb_exudyn.report.write_sweep_report`,
``speed_sweep.html``, both written by ``tb-exudyn sweep``): one row per speed with, per key quantity, the
largest |mean|, sigma and |mean| + 3 sigma over its channels and time, and the channel; the code
checks' estimates and exceedance probabilities enter through :func:`check_values` (the hook for
``RandomResponse.checks()``, issue 16). :func:`resonance_speeds` gives v = f_n d / i for the
bridge's first modes, d the car length and the bogie spacing, i = 1, 2, 3.

EN 1991-2 (6.4.6.2) analyses a series of speeds up to 1.2 x the maximum line speed:
:func:`en1991_speeds`.
"""

from __future__ import annotations

import fnmatch
import importlib
import itertools
import math
import time as _time
import typing
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Iterable, Sequence

import numpy as np

from ..builder.model import build_model
from ..engines import DEFAULT_ENGINE, check_engine
from ..errors import ResourceError, ScenarioError, SettingError
from ..execution import Execution, RunFiles, Task
from ..execution.output import SWEEP_FIGURE, SWEEP_PAGE
from ..execution.resources import MAX_STEPS, check_run_length
from ..results.checks import default_limits, grid_error_of
from ..results.random_response import RandomResponse
from ..results.sweep import (SWEEP_TABLE, CriterionValues, Resonance, SweepResult, checks_text, criterion_values,
                             grouped_warnings, write_sweep)
from ..scenario import Scenario, scenario_to_toml
from ..scenario.io import as_scenario
from ..scenario.model import KMH, Analysis
from ..scenario.speed_rule import RULE, at_speed, capped
from ..structure import modal_bridge
from ..system.modes import DIRECTIONS, nth_frequency
from .common import analysis_high, analysis_setup, fingerprint_identity, whole_number
from .driver import RunPlan, drive
from . import warm_up
from .speed_series import (EN1991_SPEED_FACTOR, MAX_SPEEDS, SPEED_CHECK, check_speeds, en1991_speeds, parse_speeds,
                           range_count, speed_label, speed_range)
from .pem import GRID_ERROR_TOLERANCE, prepare_sweep
from . import pem

#: the key quantities of a sweep: (column name, channel pattern, what it is); those that match no
#: channel of the model are left out (and listed in the sweep's provenance, ``quantities_left_out``)
KEY_QUANTITIES: tuple[tuple[str, str, str], ...] = (
    ("deck_acc_z", "bridge.*.mid.acc_z", "bridge deck vertical acceleration at mid-span [m/s^2]"),
    ("deck_acc_z_en1990", "bridge.*.acc_z_en1990",
     "deck vertical acceleration along the track, modes up to the EN 1990 cut-off (the deck criterion) [m/s^2]"),
    ("deck_acc_y", "bridge.*.mid.acc_y", "bridge deck lateral acceleration at mid-span [m/s^2]"),
    ("body_acc_z", "car*.body.acc_z", "car body vertical acceleration [m/s^2]"),
    ("body_acc_y", "car*.body.acc_y", "car body lateral acceleration [m/s^2]"),
    ("wheel_force_z", "car*.axle*force_z", "vertical wheel-rail force [N]"),
    ("wheel_force_y", "car*.axle*force_y", "lateral wheel-rail force [N]"),
)
#: sigma multiple of the design value max |mean| + K sigma in the table
K_SIGMA = 3.0
#: the grid spacings a sweep may ask for: those of ``Analysis.freq_spacing`` (read from the schema)
FREQ_SPACINGS: tuple[str, ...] = typing.get_args(typing.get_type_hints(Analysis)["freq_spacing"])


# ------------------------------------------------------------------------------------- scenario
def model_channel_names(scenario: Scenario) -> list[str]:
    """Every channel a run of the scenario can output: the model's channels and its derived ones
    (``acc_z_en1990``, ``twist_3m``, the ratios and weighted accelerations; tb_exudyn.system.derived)."""
    model = build_model(scenario, warn=False)
    return [c.name for c in model.channels] + list(model.derived_catalogue.names())


def key_patterns(scenario: Scenario, channels: Sequence[str] | None = None,
                 names: Sequence[str] | None = None) -> tuple[tuple[str, str, str], ...]:
    """The key quantities (name, pattern, description) that match channels of the scenario's model,
    derived ones included (``names``: those channels, default :func:`model_channel_names`).
    ``channels``: patterns instead of :data:`KEY_QUANTITIES`, each its own quantity; a given pattern
    that matches no channel is refused (SettingError naming ``channels``), never dropped."""
    names = list(model_channel_names(scenario) if names is None else names)
    known = {q[1]: q for q in KEY_QUANTITIES}  # a given pattern that is a key quantity keeps its name
    if channels is not None:
        items = tuple(known.get(p, (p, p, p)) for p in channels)
        for p in channels:
            if not fnmatch.filter(names, p):
                raise SettingError("run_sweep", "channels", p, "patterns matching channels", f"{p!r} matches no channel")
        return items
    keep = tuple(q for q in KEY_QUANTITIES if fnmatch.filter(names, q[1]))
    if not keep:
        raise SettingError("run_sweep", "channels", [q[1] for q in KEY_QUANTITIES],
                           "patterns matching channels of the model, e.g. 'bridge.*.mid.acc_z'", "no key quantity")
    return keep


def sweep_scenario(base: Scenario, speed_kmh: float, patterns: Sequence[str] | None = None,
                   n_freq: int | None = None, freq_spacing: str | None = None) -> Scenario:
    """The scenario of a sweep at ``speed_kmh`` (the module docstring): the one rule for a run at a
    speed (:func:`tb_exudyn.scenario.speed_rule.at_speed`: band and approach scaled by v / v0, the grid
    kept), then ``n_freq`` nodes spaced ``freq_spacing`` (default the base's), the channels
    ``patterns`` (default: those of :func:`key_patterns`), as ``run --speed-kmh v --n-freq N
    --freq-spacing S --channels ...`` makes it."""
    sc = at_speed(base, speed_kmh)
    an = sc.analysis
    patterns = tuple(patterns) if patterns is not None else tuple(q[1] for q in key_patterns(base))
    return sc.replace(analysis=an.replace(n_freq=int(n_freq or an.n_freq), freq_spacing=freq_spacing or an.freq_spacing,
                                          channels=patterns))


def with_least_count(scenario: Scenario) -> Scenario:
    """``scenario`` with an adaptive grid's ``analysis.n_freq`` raised to what its rules need (what a
    sweep's speed runs with: :func:`tb_exudyn.methods.common.analysis_setup` with ``least_count``; one
    model build and two modal analyses); any other grid as it is. ``run --speed-kmh`` calls it, so
    that a run at a speed and the sweep's row there use the same grid."""
    if scenario.analysis.freq_spacing != "adaptive":
        return scenario
    return analysis_setup(scenario, warn=False, least_count=True).scenario


def _speed_scenario(base: Scenario, speed_kmh: float, patterns: Sequence[str], n_freq: int | None,
                    freq_spacing: str | None) -> Scenario:
    """:func:`sweep_scenario` with its run length checked (:func:`check_run_length`, as the speed's PEM
    will), a speed at which either fails refused naming the speed (not the key of the derived scenario
    that failed, nor the base's file for a speed it does not hold)."""
    label = speed_label(speed_kmh)
    try:
        sc = sweep_scenario(base, speed_kmh, patterns, n_freq, freq_spacing)
    except ScenarioError as exc:
        raise SettingError("run_sweep", "speeds_kmh", speed_kmh, f"valid speeds ({exc.allowed})", f"at {label} km/h {exc.key} = {exc.value!r}: {exc.reason}"
                           ) from None
    try:
        check_run_length(sc)
        if sc.track.structure:  # the track's size at this speed (its lead-in scaled): before any run
            importlib.import_module("tb_exudyn.system.track_bridge").scenario_extent(sc)
    except ScenarioError as exc:
        raise SettingError("run_sweep", "speeds_kmh", speed_kmh, "lower speeds, or a track.structure_approach",
                           f"at {label} km/h {exc.reason}") from None
    except ResourceError as exc:
        dt, distance = sc.analysis.time_step, sc.duration * sc.speed
        if not sc.duration / dt > MAX_STEPS:
            raise SettingError("run_sweep", "speeds_kmh", speed_kmh, "speeds whose run the scenario's analysis "
                               "allows", f"at {label} km/h: {exc}") from None
        raise SettingError("run_sweep", "speeds_kmh", speed_kmh, f"here from {distance / (dt * MAX_STEPS) / KMH:.3g} km/h "
                           f"(at most {MAX_STEPS:.0e} steps of {dt:g} s)", f"at {label} km/h the "
                           f"crossing of {distance:.4g} m takes {sc.duration / dt:.4g} steps") from None
    return sc


# ------------------------------------------------------------------------------------- resonances
def train_distances(scenario: Scenario) -> dict[str, float]:
    """The train's characteristic load spacings [m]: the (first) car length and bogie spacing."""
    out = {}
    v = scenario.train.vehicles[0]
    if getattr(v, "length", 0.0):
        out["car length"] = float(v.length)
    geometry = getattr(v, "geometry", None)
    if geometry is not None and getattr(geometry, "half_bogie_spacing", 0.0):
        out["bogie spacing"] = 2.0 * float(geometry.half_bogie_spacing)
    return out


def resonance_speeds(scenario: Scenario, orders: Sequence[int] = (1, 2, 3)) -> list[Resonance]:
    """v = f_n d / i for the first vertical, lateral and torsion modes of the bridge alone (its FE
    modes up to analysis.mode_max_frequency), d the car length and the bogie spacing, i in ``orders``."""
    an = scenario.analysis
    mb = modal_bridge(scenario.bridge, an.mode_max_frequency, an.max_modes)
    out = []
    for d in DIRECTIONS:
        f = nth_frequency(mb.frequencies, mb.mode_types, d, 1)
        if math.isnan(f):
            continue
        for name, dist in train_distances(scenario).items():
            out += [Resonance(d, f, name, dist, i, f * dist / i / KMH) for i in orders]
    return out


# ------------------------------------------------------------------------------------- the sweep
def keep_tracks(tracks: tuple) -> None:
    """A worker's set-up: keep the parent's tracks (:func:`shared_tracks`) for this process's builds."""
    if tracks:
        importlib.import_module("tb_exudyn.system.track_bridge").keep_tracks(tracks)


def shared_tracks(base: Scenario, scenarios: Sequence[Scenario]) -> tuple:
    """The track the parent solved for ``base`` (its model built by :func:`key_patterns`) when a speed's scenario
    has that track (the same structure and extent: the rails cut short of the run, ``track.structure_approach``,
    are placed by the bridge, not by the speed's lead-in; under the whole run, the speeds up to the base's, whose
    lead-in the speed rule keeps), for the workers to keep (:class:`SpeedWorker`); () otherwise (no track, or
    every speed its own)."""
    if not base.track.structure:
        return ()
    tb = importlib.import_module("tb_exudyn.system.track_bridge")
    extent = tb.scenario_extent(base)[1:]
    if all(tb.scenario_extent(sc)[1:] != extent for sc in scenarios):
        return ()
    return tb.solved_tracks()


@dataclass(frozen=True)
class SpeedTask:
    """The PEM of one speed (run in a worker). The fields that say only how it runs (its folder,
    resume, overwrite, keep_checkpoint) are left out of its repr, and so of the checkpoint's task
    digest: a resumed sweep reuses the speeds the first run finished."""

    scenario: Scenario
    engine: str
    options: Any
    out: str | None = field(repr=False)
    resume: bool = field(repr=False)
    slices: tuple[float, ...] = ()
    keep_psd: bool = False
    overwrite: bool = field(default=False, repr=False)
    keep_checkpoint: bool = field(default=False, repr=False)
    #: PEM's ``grid_error`` (None: the engine's default; False: not estimated, as the EN 1991-2 check's speeds
    #: whose verdict it cannot turn)
    grid_error: bool | None = None


#: the column slices of a speed's PEM in a sweep: one. A speed is one worker's task, so slices there
#: would not spread its work over cores; each would repeat the per-task set-up (the time-only block
#: data and the per-block operators of the whole crossing; li_zhu_2011: 5.9 -> 5.7 CPU-s per speed at
#: 300 km/h, 12.1 -> 10.3 s at 160 km/h against run_pem's 2-core slices, sigma within 1.3e-15 of its largest)
SWEEP_SLICES = (1.0,)


@dataclass(frozen=True)
class SpeedWorker:
    """A sweep's worker (:class:`~tb_exudyn.methods.driver.Worker`): each task a speed's whole PEM. ``tracks``: the
    track-and-deck bodies the parent solved (:func:`shared_tracks`), kept by each worker's set-up so that its
    speeds' builds take them instead of solving them again (not in its repr: the set-up cache's key)."""

    tracks: tuple = field(default=(), repr=False, compare=False)

    def setup(self) -> None:
        keep_tracks(self.tracks)
        return None

    def work(self, _: Any, task: Task) -> dict[str, np.ndarray]:
        """The PEM of the task's speed (its own driver run, in this worker) and its summary."""
        st: SpeedTask = task.data
        execution = Execution(workers=1, out=st.out, resume=st.resume, progress=False, slices=st.slices, where="run_sweep",
                              overwrite=st.overwrite and not st.resume, keep_checkpoint=st.keep_checkpoint)
        with warnings.catch_warnings(record=True) as caught:  # handed to the parent, which shows them once
            warnings.simplefilter("always")
            result = pem.run(st.scenario, st.engine, execution, options=st.options, keep_psd=st.keep_psd,
                             least_count=st.scenario.analysis.freq_spacing == "adaptive", grid_error=st.grid_error)
        summary = speed_summary(result)
        seen = dict.fromkeys((f"{w.message} (at {speed_label(st.scenario.speed_kmh)} km/h)",
                              f"{w.category.__module__}:{w.category.__qualname__}") for w in caught)
        summary["warnings"] = np.array([m for m, _ in seen], dtype=str).reshape(-1)
        summary["warning_kinds"] = np.array([k for _, k in seen], dtype=str).reshape(-1)
        return summary


def speed_summary(result: RandomResponse) -> dict[str, np.ndarray]:
    """What the table needs of one speed's result, as plain arrays (checkpointable)."""
    peak = np.abs(result.mean).max(axis=1)
    return {
        "grid_error": grid_errors(result),
        "channels": np.array(result.channels, dtype=str), "units": np.array(result.units, dtype=str),
        "max_abs_mean": peak, "max_sigma": result.std.max(axis=1),
        "max_design": (np.abs(result.mean) + K_SIGMA * result.std).max(axis=1),
        "band": np.array(result.band, dtype=float), "n_freq": np.array(result.freq.size),
        "lead_in": np.array(float(result.scenario.track.lead_in) if result.scenario is not None else math.nan),
        "freq_spacing": np.array(result.scenario.analysis.freq_spacing if result.scenario is not None else ""),
        "seconds": np.array(float(result.provenance.get("seconds", math.nan))),
        "checks": np.array(checks_text(check_values(result))),
    }


def grid_errors(result: RandomResponse) -> np.ndarray:
    """Per channel the estimated grid error of the result (the larger of |relative error of max sigma|
    and the largest relative deviation over time: :func:`tb_exudyn.results.checks.grid_error_of`, the
    checks' own hook); NaN where it was not estimated."""
    values = (grid_error_of(result.provenance, c) for c in result.channels)
    return np.array([np.nan if v is None else v for v in values], dtype=float)


def check_values(result: RandomResponse) -> dict[str, CriterionValues]:
    """One speed's code checks (:meth:`RandomResponse.checks`, the default limits and target probability) per
    criterion that applies, at its deciding location: :func:`tb_exudyn.results.sweep.criterion_values`. The one
    place that turns checks into a sweep's values (rows, CSV, figure and report)."""
    return criterion_values(result.checks())


def check_sweep(scenario: Scenario, speeds_kmh: Iterable[float], *, engine: str = DEFAULT_ENGINE,
                channels: Sequence[str] | None = None, n_freq: int | None = None, options: Any = None,
                freq_spacing: str | None = None) -> tuple[float, ...]:
    """What :func:`run_sweep` checks before it creates its output folder, with the same arguments and
    the same errors (SettingError or ScenarioError naming ``run_sweep`` and the argument): the speeds
    (:func:`check_speeds`), the spacing, the key quantities, the engine and options, every speed's
    scenario, grid and spectra. Returns the speeds as checked (floats). Cheap (no model is built): a
    caller that creates the output folder itself calls it first, so that a refused sweep writes nothing."""
    return _plan(scenario, speeds_kmh, engine, channels, n_freq, options, freq_spacing)[0]


def _plan(scenario: Scenario, speeds_kmh: Iterable[float], engine: str, channels: Sequence[str] | None,
          n_freq: int | None, options: Any, freq_spacing: str | None) -> tuple[Any, ...]:
    """The checks of :func:`check_sweep`; (speeds, key quantities, engine class, each speed's scenario,
    the default key quantities the model lacks)."""
    if hasattr(speeds_kmh, "__len__") and len(speeds_kmh) > MAX_SPEEDS:  # type: ignore[arg-type]
        raise SettingError("run_sweep", "speeds_kmh", speeds_kmh, f"at most {MAX_SPEEDS} speeds",
                           f"{len(speeds_kmh)} speeds")  # type: ignore[arg-type]
    items = tuple(itertools.islice(speeds_kmh, MAX_SPEEDS + 1))  # an iterator of any length: the bound's worth
    if len(items) > MAX_SPEEDS:
        raise SettingError("run_sweep", "speeds_kmh", speeds_kmh, f"at most {MAX_SPEEDS} speeds",
                           f"more than {MAX_SPEEDS} speeds")
    speeds = check_speeds(items, "run_sweep", "speeds_kmh")
    n_freq = None if n_freq is None else whole_number(n_freq, "run_sweep", "n_freq", 1, analysis_high("n_freq"))
    if freq_spacing is not None and freq_spacing not in FREQ_SPACINGS:
        raise SettingError("run_sweep", "freq_spacing", freq_spacing, " or ".join(map(repr, FREQ_SPACINGS)))
    if scenario.track.structure:  # each speed's track size, before the base's model (its track) is built
        for v in speeds:
            _speed_scenario(scenario, v, ("*",), n_freq, freq_spacing)
    quantities = key_patterns(scenario, channels)
    left_out = tuple(q for q in KEY_QUANTITIES if q not in quantities) if channels is None else ()
    cls = check_engine(engine, scenario, options)
    patterns = tuple(dict.fromkeys(q[1] for q in quantities))
    scenarios = [_speed_scenario(scenario, v, patterns, n_freq, freq_spacing) for v in speeds]
    for sc in scenarios:  # every speed's grid and spectra checked before any run
        prepare_sweep(sc)
    return speeds, quantities, cls, scenarios, left_out


def speed_scenarios(scenario: Scenario, speeds_kmh: Sequence[float], engine: str = DEFAULT_ENGINE,
                    channels: Sequence[str] | None = None, options: Any = None) -> tuple[Any, list[Scenario]]:
    """The engine class and each speed's scenario, checked as :func:`check_sweep` checks them (``options``: the
    engine's): for a method whose tasks include a sweep's speeds (the EN 1991-2 check's stochastic rows)."""
    _, _, cls, scenarios, _ = _plan(scenario, speeds_kmh, engine, channels, None, options, None)
    return cls, scenarios


@dataclass
class SweepState:
    """What the sweep's plan checked (speeds, quantities, scenarios, left out) and each speed's summary."""

    speeds: tuple[float, ...]
    quantities: Any
    scenarios: list[Scenario]
    left_out: tuple[Any, ...]
    summaries: list[dict[str, np.ndarray]]
    t0: float


@dataclass(frozen=True)
class SweepMethod:
    """The speed sweep as a :class:`~tb_exudyn.methods.driver.Method`; see :func:`run_sweep` (the
    same arguments)."""

    scenario: Scenario
    speeds_kmh: Any
    engine: str = DEFAULT_ENGINE
    channels: Sequence[str] | None = None
    n_freq: int | None = None
    options: Any = None
    keep_psd: bool = False
    slices: Sequence[float] | None = None
    freq_spacing: str | None = None

    def plan(self, execution: Execution) -> RunPlan:
        t0 = _time.perf_counter()
        default_limits()  # the limit files of check_values, read and checked before any speed runs
        scenario = self.scenario
        speeds, quantities, cls, scenarios, left_out = _plan(scenario, self.speeds_kmh, self.engine, self.channels,
                                                             self.n_freq, self.options, self.freq_spacing)
        warm_up.start(cls, self.options, execution.announce)  # a first run's compile, not in every worker
        root = execution.output_folder()
        cuts = tuple(self.slices) if self.slices is not None else SWEEP_SLICES
        tasks = [Task(f"speed-{speed_label(v)}", SpeedTask(
            sc, self.engine, self.options, None if root is None else str(root / speed_label(v)), execution.resume,
            cuts, self.keep_psd, execution.overwrite, execution.keep_checkpoint)) for v, sc in zip(speeds, scenarios)]
        identity = fingerprint_identity(
            scenario_to_toml(scenario), method="pem_sweep", engine=self.engine,
            engine_options=cls.describe_options(self.options),
            method_options={"keep_psd": self.keep_psd, "channels": [q[1] for q in quantities], "n_freq": self.n_freq,
                            "freq_spacing": self.freq_spacing, "slices": list(cuts), "speeds_kmh": list(speeds)},
            spectra=scenario.track.irregularities)
        state = SweepState(speeds=speeds, quantities=quantities, scenarios=scenarios, left_out=left_out,
                           summaries=[{} for _ in tasks], t0=t0)
        return RunPlan(files=RunFiles(SWEEP_TABLE, "checkpoint-sweep", drawn=(SWEEP_FIGURE, SWEEP_PAGE)), tasks=tasks,
                       identity=identity, state=state, worker=SpeedWorker(shared_tracks(scenario, scenarios)),
                       desc=f"speed sweep ({self.engine})")

    def reduce(self, state: SweepState, i: int, task: Task, result: dict[str, np.ndarray]) -> None:
        state.summaries[i] = result  # its warnings: grouped by kind once every speed is in

    def finish(self, state: SweepState, stats: dict[str, Any]) -> SweepResult:
        scenario, speeds = self.scenario, state.speeds
        cut = [v for v, sc in zip(speeds, state.scenarios) if capped(scenario, sc)]
        result = SweepResult(base=scenario, speeds=speeds, summaries=tuple(state.summaries),
                             quantities=state.quantities,
                             resonances=tuple(resonance_speeds(scenario)),
                             provenance={"seconds": _time.perf_counter() - state.t0, "engine": self.engine,
                                         "speed_rule": RULE, "base_speed_kmh": scenario.speed_kmh,
                                         "band_capped_kmh": cut, "quantities_left_out": [q[1] for q in state.left_out],
                                         **stats})
        for category, message in grouped_warnings(result):
            warnings.warn(message, category, stacklevel=2)
        return result

    def save(self, result: SweepResult, out: Path) -> None:
        write_sweep(result, out)


def run_sweep(scenario: Scenario | str | Path, speeds_kmh: Sequence[float], *, engine: str = DEFAULT_ENGINE,
              workers: int | None = None, executor: Any = None, out: str | Path | None = None, resume: bool = False,
              progress: bool = True, channels: Sequence[str] | None = None, n_freq: int | None = None,
              options: Any = None, keep_psd: bool = False, slices: Sequence[float] | None = None,
              overwrite: bool = False, keep_checkpoint: bool = False, freq_spacing: str | None = None) -> SweepResult:
    """PEM of ``scenario`` at each of ``speeds_kmh`` (see the module docstring).

    Parameters
    ----------
    scenario : the base scenario (its speed only sets the approach's duration kept at other speeds), or
        its name or TOML file (loaded)
    speeds_kmh : the speeds [km/h] (e.g. :func:`parse_speeds`, :func:`en1991_speeds`)
    engine, options : the PEM engine and its options (default the batched engine)
    workers, executor, progress : as :func:`tb_exudyn.run_pem`; the speeds are the tasks
    out : folder: ``out/<speed>/`` (each speed's PEM result and checkpoint), ``out/checkpoint-sweep``
    resume : reuse finished speeds and tasks
    channels : patterns of the key quantities (default :data:`KEY_QUANTITIES`)
    n_freq : frequencies per speed (default the base's analysis.n_freq; with the adaptive spacing the
        least, raised at each speed to what the grid's rules need there)
    freq_spacing : "linear", "log" or "adaptive" (default the base's analysis.freq_spacing)
    keep_psd : keep each speed's PSD map (default False: sigma only)
    slices : the column slices of every speed's PEM (default :data:`SWEEP_SLICES`: one)
    overwrite : replace an earlier sweep's table, checkpoint and speeds in ``out`` (without it or
        ``resume`` a folder holding them is refused)
    keep_checkpoint : keep ``out/checkpoint-sweep`` (and each speed's checkpoint) after the results are
        written (default: removed)
    """
    scenario = as_scenario(scenario, "run_sweep")
    execution = Execution(workers=workers, executor=executor, out=out, resume=resume, progress=progress,
                          where="run_sweep", overwrite=overwrite, keep_checkpoint=keep_checkpoint)
    return drive(SweepMethod(scenario, speeds_kmh, engine, channels, n_freq, options, keep_psd, slices, freq_spacing),
                 execution)


__all__ = ["EN1991_SPEED_FACTOR", "FREQ_SPACINGS", "KEY_QUANTITIES", "MAX_SPEEDS", "SPEED_CHECK",
           "SWEEP_SLICES", "SpeedTask", "SpeedWorker", "check_values", "check_speeds", "check_sweep", "en1991_speeds",
           "grid_errors", "key_patterns", "model_channel_names", "parse_speeds", "range_count", "resonance_speeds", "run_sweep",
           "shared_tracks", "speed_label", "speed_range", "speed_scenarios", "speed_summary", "with_least_count", "sweep_scenario", "train_distances"]
