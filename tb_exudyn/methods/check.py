"""The EN 1991-2 check as a :class:`~tb_exudyn.methods.driver.Method`: its cases are the driver's tasks.

:func:`tb_exudyn.codes.check.check` plans the check (:func:`tb_exudyn.codes.check_plan.plan_check`: the
arguments, the modes of each mass case, the speed series, the stochastic rows' scenarios) and runs this
method with :func:`~tb_exudyn.methods.driver.drive`, so that the check's work goes where every method's
does: in this process, a local process pool (``workers``) or an executor (Dask), with a checkpoint in the
output folder and ``resume``. The tasks, in reduction order:

- one :class:`InteractionTask` per train of the interaction runs (``interaction=True``): its moving forces in
  the reference mass case again (the speed of their largest mid-span peak) and its Exudyn run with
  interaction there (:func:`tb_exudyn.codes.interaction.check_comparison`); the longest tasks, first;
- one :class:`StochasticTask` per train given as vehicle models and speed of its stochastic rows: the
  speed's whole PEM, as a speed sweep's :class:`~tb_exudyn.methods.sweep.SpeedTask` (its summary; the columns
  in float32 and the grid error estimated at every GRID_ERROR_EVERY-th speed, elsewhere only where it could
  turn the row: :mod:`tb_exudyn.codes.stochastic`); the heaviest tasks, first, so that the pool's last tasks
  are short ones;
- one :class:`StaticTask` per set of static load models (LM71, SW/0 on a continuous girder; LM71 alone for
  the comfort criterion there): :func:`~tb_exudyn.codes.deformation.static_deformations` (EN 1990 A2.4.4's
  deformation criteria);
- one :class:`MovingForceTask` per mass case and train: :func:`~tb_exudyn.codes.moving_force.moving_force_response`
  at every speed of the train's series on that case's modes (sent with the task: every worker integrates
  on the modes the plan computed), its :class:`~tb_exudyn.codes.moving_force.MovingForceResponse` as
  plain arrays (:func:`response_arrays`, checkpointable).

The results are reduced in task order, so that the check is bitwise the same for any number of workers,
any executor and after a resume. ``finish`` hands the responses and the stochastic summaries to the
check's ``assemble`` (codes/check.py: the rows, the verdicts of EN 1990 A2.4.4, the interaction runs, the
:class:`~tb_exudyn.codes.check.CheckResult`); ``save`` writes what ``render`` makes of the result (the table;
the command line adds the figure and the page) into the output folder as one group, all files or none.
"""

from __future__ import annotations

import dataclasses
import time as _time
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from types import SimpleNamespace
from typing import Any, Callable

import numpy as np

from ..codes.check_plan import CHECKPOINT, CheckSetup, prefixed
from ..codes.deformation import LM71, SW0, StaticDeformations, static_deformations
from ..codes.moving_force import MovingForceResponse, moving_force_response
from ..codes.criteria import deck_criterion
from ..codes.stochastic import CHANNELS, engine_options, grid_error_needed, grid_error_sampled, track_note
from ..codes.trains import ForceTrain
from ..codes import interaction as vbi
from ..engines import DEFAULT_ENGINE
from ..errors import UserError
from ..execution import Execution, RunFiles, Task
from ..execution.threads import single_threaded_blas
from ..files import write_output
from ..results.sweep import grouped_warnings
from ..scenario.model import Continuous
from ..scenario.speed_rule import capped
from .common import fingerprint_identity
from .driver import RunPlan
from . import sweep, warm_up

@dataclass(frozen=True)
class MovingForceTask:
    """One mass case and train at every speed of its series. Its repr (the case, the axles, the speeds, the
    damping, the modes' frequencies) is its checkpoint digest; the modes themselves travel unprinted."""

    case: str
    train: str
    axles: tuple[tuple[float, float], ...]
    regular_length: float
    speeds_kmh: tuple[float, ...]
    damping_ratio: float
    frequencies: tuple[float, ...]
    spans: tuple[float, ...]
    force_train: ForceTrain = field(repr=False, compare=False)
    modal: Any = field(repr=False, compare=False)
    used: tuple[int, ...] = field(repr=False, compare=False, default=())


@dataclass(frozen=True)
class StaticTask:
    """The static load models on the bridge (EN 1990 A2.4.4.2.2-4, A2.4.4.3.2): LM71 (and SW/0 on a continuous
    girder), or ``loads`` alone (('LM71',): the comfort criterion's). Its repr (the bridge's data) is its digest."""

    bridge: Any
    loads: tuple[str, ...] = ()


@dataclass(frozen=True)
class StochasticTask:
    """One speed of a train's stochastic rows: a speed sweep's task (the speed's whole PEM)."""

    train: str
    speed_kmh: float
    speed: sweep.SpeedTask
    #: how an error of its PEM (e.g. a run this machine cannot hold) says which option's runs
    prefix: str = field(repr=False, default="")
    #: the deck criterion whose verdict decides whether a speed not sampled estimates its grid error
    #: (``speed.grid_error`` False: only where :func:`~tb_exudyn.codes.stochastic.grid_error_needed`)
    criterion: str = ""


@dataclass(frozen=True)
class InteractionTask:
    """One train's interaction run (``interaction=True``): its moving forces in the reference mass case (``moving``:
    that case's and train's moving-force task, integrated again here to the same bits) decide the speed, the
    largest mid-span peak (as the check's rows of that case would: the first of equal ones), where the train as
    vehicle models crosses with interaction (:func:`tb_exudyn.codes.interaction.check_comparison`: one Exudyn
    run). Its repr (the moving-force task's, the bridge's, the damping and the cut-off) is its digest."""

    moving: MovingForceTask
    bridge: Any
    damping_ratio: float
    cutoff_hz: float


def deciding_speed(resp: MovingForceResponse) -> float:
    """The speed of a response's largest mid-span peak (the first of equal ones): the rows' ``max(acc_z_mid_span)``."""
    peaks = resp.max_acc[list(resp.mid_stations), :].max(axis=0)
    return float(resp.speeds_kmh[int(np.argmax(peaks))])


def interaction_task(task: InteractionTask) -> dict[str, np.ndarray]:
    m = task.moving
    with single_threaded_blas():
        resp = moving_force_response(m.modal, m.force_train, np.array(m.speeds_kmh), m.spans,
                                     damping_ratio=m.damping_ratio, modes=np.array(m.used, dtype=int))
    comparison = vbi.check_comparison(task.bridge, m.force_train, deciding_speed(resp), task.damping_ratio,
                                      task.cutoff_hz, m.case)
    return vbi.comparison_arrays(comparison)


def response_arrays(resp: MovingForceResponse) -> dict[str, np.ndarray]:
    """A response as plain arrays (checkpointable): each field, strings as string arrays."""
    out = {}
    for f in dataclasses.fields(MovingForceResponse):
        value = getattr(resp, f.name)
        out[f.name] = np.array(value, dtype=str) if isinstance(value, (str, tuple)) else np.asarray(value)
    return out


def response_of(arrays: dict[str, np.ndarray]) -> MovingForceResponse:
    """The response of :func:`response_arrays`' arrays."""
    kw: dict[str, Any] = {}
    for f in dataclasses.fields(MovingForceResponse):
        a = arrays[f.name]
        if f.name == "train":
            kw[f.name] = str(a)
        elif f.name == "station_names":
            kw[f.name] = tuple(str(x) for x in a)
        elif f.name in ("step_m", "tail_s"):
            kw[f.name] = float(a)
        else:
            kw[f.name] = np.array(a)
    return MovingForceResponse(**kw)


def static_arrays(sd: StaticDeformations) -> dict[str, np.ndarray]:
    """Static deformations as plain arrays (checkpointable): each per-track field as '<field>.<track>'."""
    out: dict[str, np.ndarray] = {"spans": np.array(sd.spans, dtype=float), "loads": np.array(sd.loads, dtype=str)}
    for f in dataclasses.fields(StaticDeformations):
        if f.name not in out:
            out.update({f"{f.name}.{t}": np.asarray(v, dtype=float) for t, v in enumerate(getattr(sd, f.name))})
    return out


def static_of(arrays: dict[str, np.ndarray]) -> StaticDeformations:
    """The static deformations of :func:`static_arrays`' arrays."""
    kw: dict[str, Any] = {"spans": tuple(float(x) for x in arrays["spans"]),
                          "loads": tuple(str(x) for x in arrays["loads"])}
    for f in dataclasses.fields(StaticDeformations):
        if f.name not in kw:
            per = [arrays[f"{f.name}.{t}"] for t in range(sum(1 for k in arrays if k.startswith(f.name + ".")))]
            kw[f.name] = tuple(float(a) if a.ndim == 0 else np.array(a) for a in per)
    return StaticDeformations(**kw)


def static_task(task: StaticTask) -> dict[str, np.ndarray]:
    loads = tuple(m for m in (LM71, SW0) if m.name in task.loads) or None
    with single_threaded_blas():
        return static_arrays(static_deformations(task.bridge, loads))


def moving_force_task(task: MovingForceTask) -> dict[str, np.ndarray]:
    """A moving-force task's response (one thread of BLAS, as in any worker: the same bits everywhere)."""
    with single_threaded_blas():
        resp = moving_force_response(task.modal, task.force_train, np.array(task.speeds_kmh), task.spans,
                                     damping_ratio=task.damping_ratio, modes=np.array(task.used, dtype=int))
    return response_arrays(resp)


@dataclass(frozen=True)
class CheckWorker:
    """The check's worker (:class:`~tb_exudyn.methods.driver.Worker`): nothing to set up (the modes come
    with each task; a PEM speed builds its own model) but the track-and-deck bodies the plan solved for the
    stochastic rows (``tracks``: :func:`tb_exudyn.methods.sweep.shared_tracks`, kept as a sweep's workers keep
    them; not in its repr); a stochastic row's error says which option's runs."""

    tracks: tuple = field(default=(), repr=False, compare=False)

    def setup(self) -> None:
        sweep.keep_tracks(self.tracks)
        return None

    def work(self, _: Any, task: Task) -> dict[str, np.ndarray]:
        data = task.data
        if isinstance(data, MovingForceTask):
            return moving_force_task(data)
        if isinstance(data, StaticTask):
            return static_task(data)
        if isinstance(data, InteractionTask):
            return interaction_task(data)
        try:
            summary = sweep.SpeedWorker().work(None, Task(task.key, data.speed))
            if data.speed.grid_error is False and grid_error_needed(summary, data.criterion):
                summary = sweep.SpeedWorker().work(None, Task(task.key, dataclasses.replace(data.speed, grid_error=None)))
            return summary
        except UserError as exc:
            raise prefixed(exc, data.prefix) from None


@dataclass
class CheckState:
    """The responses of each (case, train) in task order and each stochastic train's (speed, summary)."""

    responses: dict[tuple[str, str], MovingForceResponse]
    stochastic: dict[str, list[tuple[float, dict[str, np.ndarray]]]]
    t0: float
    #: the static deformations by their load models' names (() the default set)
    static: dict[tuple[str, ...], StaticDeformations] = field(default_factory=dict)
    #: each stochastic train's speeds whose band the speed rule capped (as a sweep's provenance says)
    capped: dict[str, list[float]] = field(default_factory=dict)
    #: each interaction train's comparison (:func:`tb_exudyn.codes.interaction.comparison_arrays`)
    interaction: dict[str, dict[str, np.ndarray]] = field(default_factory=dict)


def _stochastic_tasks(setup: CheckSetup) -> tuple[list[Task], Any, tuple]:
    """The stochastic rows' tasks (each speed's scenario checked, as a sweep's plan checks them), the
    engine class (None without them) and the tracks the plan solved that the speeds share (a train's whole
    series on one track: :func:`tb_exudyn.methods.sweep.shared_tracks`; the last train's kept)."""
    tasks, cls, options, tracks = [], None, engine_options(DEFAULT_ENGINE), ()
    for t, train in enumerate(setup.stochastic_trains):
        speeds = setup.run_speeds[train.name]
        cls, scenarios = sweep.speed_scenarios(setup.bases[train.name], speeds, DEFAULT_ENGINE, CHANNELS, options)
        tracks = sweep.shared_tracks(setup.bases[train.name], scenarios) or tracks
        for i, (v, sc) in enumerate(zip(speeds, scenarios)):
            st = sweep.SpeedTask(sc, DEFAULT_ENGINE, options, None, False, sweep.SWEEP_SLICES,
                                 grid_error=None if grid_error_sampled(i, len(speeds)) else False)
            tasks.append(Task(f"pem-{t:02d}-{v:.6f}", StochasticTask(train.name, float(v), st, setup.stochastic_prefix(
                train.name), deck_criterion(setup.track))))
    return tasks, cls, tracks


def _moving_force_tasks(setup: CheckSetup) -> list[Task]:
    tasks = []
    for case in setup.cases:
        m = setup.modes[case]
        for t, train in enumerate(setup.trains):
            data = MovingForceTask(
                case=case, train=train.name,
                axles=tuple((float(x), float(p)) for x, p in zip(train.positions, train.loads)),
                regular_length=float(train.regular_length), speeds_kmh=setup.series[train.name],
                damping_ratio=float(setup.zeta), frequencies=tuple(float(f) for f in m.modal.frequencies[m.used]),
                spans=setup.spans, force_train=train, modal=m.modal, used=tuple(int(i) for i in m.used))
            tasks.append(Task(f"moving-{case}-{t:02d}", data))
    return tasks


def _interaction_tasks(setup: CheckSetup, moving: list[Task]) -> list[Task]:
    """One per interaction train, on the reference mass case's moving-force task of that train."""
    m = setup.modes[setup.ref_case]
    by = {(t.data.case, t.data.train): t.data for t in moving}
    return [Task(f"interaction-{i:02d}", InteractionTask(by[(setup.ref_case, train.name)], setup.bridge,
                                                         float(setup.zeta_vehicles), float(m.cutoff)))
            for i, train in enumerate(setup.interaction_trains)]


def _static_tasks(setup: CheckSetup) -> list[Task]:
    """The static load models: the default set, and LM71 alone where the default adds SW/0 (a continuous
    girder: the comfort criterion loads LM71 only)."""
    sets = [()] + ([(LM71.name,)] if isinstance(setup.bridge, Continuous) else [])
    return [Task(f"static-{i}", StaticTask(setup.bridge, loads)) for i, loads in enumerate(sets)]


def _identity(setup: CheckSetup) -> dict[str, Any]:
    """The checkpoint's fingerprint: the bridge, the trains, the settings that change a number and the
    stochastic rows' scenarios (with the package versions and tb_exudyn's source)."""
    return fingerprint_identity(
        repr(setup.bridge), method="en1991_check", engine="moving_force" + ("+" + DEFAULT_ENGINE if setup.bases else ""),
        engine_options={"stochastic": repr(engine_options(DEFAULT_ENGINE))} if setup.bases else {},
        method_options={"setup": repr(setup), "trains": [repr(t) for t in setup.trains],
                        "series": {k: list(v) for k, v in setup.series.items()},
                        "stochastic": {k: repr(v) for k, v in setup.bases.items()},
                        "stochastic_speeds": {k: list(v) for k, v in setup.run_speeds.items()}},
        spectra=setup.stochastic_source.track.irregularities if setup.bases else ())


@dataclass(frozen=True)
class CheckMethod:
    """The check on the driver (the module docstring). ``setup``: the plan of
    :func:`tb_exudyn.codes.check_plan.plan_check`; ``assemble(setup, responses, stochastic, stats, seconds)``:
    the CheckResult (codes/check.py); ``render(result)``: the files written into the output folder
    ({name: bytes}); ``group``: every file name a check writes there (those ``render`` leaves out are
    removed with the write: ``--no-figures`` after a check with figures)."""

    setup: CheckSetup
    assemble: Callable[..., Any] = field(repr=False)
    render: Callable[[Any], dict[str, bytes]] = field(repr=False)
    group: tuple[str, ...] = ()
    #: when the check began (time.perf_counter(); 0: at this plan), for the result's seconds
    started: float = field(default=0.0, repr=False)

    def plan(self, execution: Execution) -> RunPlan:
        t0 = self.started or _time.perf_counter()
        stochastic, cls, tracks = _stochastic_tasks(self.setup)
        if cls is not None:
            warm_up.start(cls, engine_options(DEFAULT_ENGINE), execution.announce)  # a first run's compile, not in every worker
        moving = _moving_force_tasks(self.setup)  # an interaction run first: one Exudyn run, the longest task
        tasks = _interaction_tasks(self.setup, moving) + stochastic + moving + _static_tasks(self.setup)
        state = CheckState(responses={}, stochastic={t.name: [] for t in self.setup.stochastic_trains}, t0=t0)
        return RunPlan(files=RunFiles("check", CHECKPOINT, group=self.group), tasks=tasks,
                       identity=_identity(self.setup), state=state,
                       worker=CheckWorker(tracks), desc="EN 1991-2 check")

    def reduce(self, state: CheckState, i: int, task: Task, result: dict[str, np.ndarray]) -> None:
        data = task.data
        if isinstance(data, MovingForceTask):
            state.responses[(data.case, data.train)] = response_of(result)
        elif isinstance(data, StaticTask):
            state.static[data.loads] = static_of(result)
        elif isinstance(data, InteractionTask):
            state.interaction[data.moving.train] = result
        else:
            state.stochastic[data.train].append((data.speed_kmh, result))
            if capped(self.setup.bases[data.train], data.speed.scenario):
                state.capped.setdefault(data.train, []).append(data.speed_kmh)

    def finish(self, state: CheckState, stats: dict[str, Any]) -> Any:
        for train, done in state.stochastic.items():  # the PEM runs' warnings once per kind, as a sweep's
            view = SimpleNamespace(speeds=tuple(v for v, _ in done), summaries=tuple(s for _, s in done),
                                   provenance={"band_capped_kmh": state.capped.get(train, [])},
                                   base=self.setup.bases[train])
            for category, message in grouped_warnings(view):
                warnings.warn(message, category, stacklevel=3)
            if note := track_note(self.setup.bases[train]):  # the track's defaults the rows took (in the result too)
                warnings.warn(note, UserWarning, stacklevel=3)
        return self.assemble(self.setup, state.responses, state.stochastic, stats, state.t0, state.static,
                             state.interaction)

    def save(self, result: Any, out: Path) -> None:
        files = self.render(result)
        stale = [out / n for n in self.group if n not in files and (out / n).is_file()]
        write_output([(out / name, data) for name, data in files.items()], named=out, overwrite=True,
                     where=self.setup.where, key="out", remove=stale)


__all__ = ["CHECKPOINT", "CheckMethod", "CheckState", "CheckWorker", "InteractionTask", "MovingForceTask", "StaticTask",
           "StochasticTask", "deciding_speed",
           "response_arrays", "response_of", "static_arrays", "static_of"]
