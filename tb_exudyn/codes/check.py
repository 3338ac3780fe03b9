"""The EN 1991-2 dynamic check of a bridge under trains of moving forces: one table of every train at
every speed, and its verdict.

:func:`check` builds the bridge's modes (finite elements, no Exudyn), takes the damping of Table 6.6
(optionally with eq. 6.13's additional damping), the modes up to the cut-off max(30 Hz, 1.5 f1, f3)
and the speed series of 6.4.6.2 for each train, runs :func:`moving_force_response` (all speeds of a
train in one integration) and returns a :class:`CheckResult`: the rows, the limit and what decided
the values. Figures: :func:`tb_exudyn.plotting.plot_check` (``CheckResult.plot()``). Clause by clause: docs/en1991.md.

With ``stochastic=True`` the trains given as vehicle models (the real trains of models/trains) also get,
at their speeds of the nominal mass case (all, or ``stochastic_speeds``), the PEM of the random track
irregularity on top of the mean (:mod:`tb_exudyn.codes.stochastic`): the probability of exceeding the
deck limit in one passage and the level exceeded with the target probability, beside the deterministic
value x (1 + k phi'') of every row.
"""

from __future__ import annotations

import importlib
import math
import time
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any, Callable, Sequence

import numpy as np

from ..atomic import write_text_atomic
from ..errors import SettingError
from ..execution import Execution
from ..execution.threads import single_threaded_blas
from ..results.check_records import CheckRecord, check_dataset, record_columns, records_csv
from ..results.checks import DEFAULT_TARGET_PROBABILITY
from ..scenario.io import load_bridge  # noqa: F401 - the check's bridges (tests read them here)
from . import en1991 as code
from .check_modes import FIRST_MODE_LIMIT_HZ, MODE_LIMIT_CAP_HZ  # noqa: F401 - the check's, named here too
from .check_modes import vertical as _vertical
from .check_plan import (CHECK_ELEMENTS_PER_SPAN, HSLM_A_MIN_SPAN, MIN_LINE_SPEED_KMH, NOMINAL_CASE,  # noqa: F401
                         CheckSetup, plan_check)
from .moving_force import MovingForceResponse, integration_steps
from . import stochastic as stoch
from .trains import ForceTrain
from .a2_verdicts import a2_verdicts, place_words
from .criteria import deck_criterion, moving_force_load_model
from . import interaction as vbi

#: the table's file in an output folder
CHECK_CSV = "check.csv"
CHECK_FIGURE = "check.png"
#: the check's HTML page (tb_exudyn.report.check)
CHECK_PAGE = "check.html"
#: the check's typed records as NetCDF (``CheckResult.to_xarray()``; ``tb-exudyn check --netcdf``)
CHECK_DATA = "check.nc"
#: every file a check writes into its output folder, in the order they are written
CHECK_FILES = (CHECK_CSV, CHECK_DATA, CHECK_FIGURE, CHECK_PAGE)

VERDICT_OK, VERDICT_EXCEEDS = "ok", "exceeds"


@dataclass(frozen=True)
class CheckResult:
    """The table of a check and what it was computed with.

    ``columns`` the table's column names; ``rows`` one :class:`~tb_exudyn.results.check_records.CheckRecord`
    per (train, speed, case), read by attribute or by column (``row["max_deck_acc_z"]``). Columns: train,
    speed_kmh, case, damping_ratio (fraction), cutoff_hz, acc_z_mid_span<i> (peak |vertical acceleration|
    at mid-span of span i along the track [m/s^2], one per span), max_deck_acc_z (largest over the deck
    stations), max_deck_acc_z_location (its station, e.g. 'span1.x4/8 (16 m)'), disp_z_mid (largest peak
    |displacement| at a mid-span [m]), phi_dyn (phi'_dyn = max |y_dyn / y_stat| - 1, largest over the
    spans' mid-spans), phi_irregularity (phi'' of Annex C), enhancement (1 + phi_dyn + k phi''), limit
    (m/s^2), verdict ('ok' or 'exceeds': max_deck_acc_z against limit), max_deck_acc_z_with_phi2
    (max_deck_acc_z x (1 + k phi''): the code's allowance for the irregularity on the deterministic value,
    k = 1/2 careful maintenance, 1 standard), and the stochastic columns (None, empty in the CSV, where not
    computed: :data:`tb_exudyn.codes.stochastic.COLUMNS`): p_exceed (probability of exceeding ``limit`` in
    one passage), level_at_target (the level exceeded with ``target_probability`` per passage) [m/s^2],
    stochastic_location (the deck channel deciding them), stochastic_mean_acc (the largest |mean| there:
    the vehicle model's deterministic run), stochastic_verdict, stochastic_caveats, stochastic_n_freq (the
    PEM frequencies used).

    ``stochastic_scenarios``: per train with stochastic rows its scenario
    (:func:`tb_exudyn.codes.stochastic.base_scenario`; the row at a speed: :meth:`stochastic_scenario`);
    ``warnings``: the PEM runs' warnings (lightly damped modes, grid error), each naming its speed.
    """

    bridge: str
    line_speed_kmh: float
    track: str
    limit: float
    construction: str
    damping_ratio: float
    damping_basis: str
    cutoff_hz: float
    cutoff_basis: str
    mode_frequencies: tuple[float, ...]
    dynamic_analysis: tuple[bool, str]
    resonant_speeds_kmh: dict[str, tuple[float, ...]]
    columns: tuple[str, ...]
    rows: tuple[CheckRecord, ...] = field(repr=False)
    responses: tuple[MovingForceResponse, ...] = field(default=(), repr=False)
    seconds: float = 0.0
    vertical_frequencies: tuple[float, ...] = ()
    cases: tuple[str, ...] = (NOMINAL_CASE,)
    construction_basis: str = ""
    mesh_basis: str = ""
    stochastic_scenarios: dict[str, Any] = field(default_factory=dict, repr=False)
    stochastic_basis: str = ""
    #: per train of vehicle models, with ``check(..., interaction=True)``: interaction against moving forces
    interaction: tuple = ()
    target_probability: float | None = None
    warnings: tuple[str, ...] = ()
    #: one verdict per EN 1990 A2.4.4 criterion (tb_exudyn.codes.a2_verdicts), deck acceleration first
    criteria: tuple = ()
    #: the bridge's file as the user gave it, where it is not the shipped bridge of that name ('' if so)
    bridge_file: str = ""
    #: how the check's tasks ran (tb_exudyn.methods.check on the driver): tasks, tasks_run,
    #: tasks_from_checkpoint, executor
    run: dict = field(default_factory=dict, repr=False)

    def __len__(self) -> int:
        return len(self.rows)

    def column(self, name: str) -> list[Any]:
        """One column of the table, in row order."""
        if name not in self.columns:
            raise SettingError("CheckResult.column", "name", name, ", ".join(self.columns))
        return [r[name] for r in self.rows]

    def stochastic_rows(self) -> list[dict[str, Any]]:
        """The rows with the stochastic columns computed."""
        return [r for r in self.rows if r.get("p_exceed") is not None]

    def stochastic_scenario(self, train: str, speed_kmh: float):  # noqa: ANN201
        """The scenario of ``train``'s stochastic row at ``speed_kmh``: ``run_pem`` of it with
        ``stochastic.engine_options("batched")`` gives the row's numbers (``tb-exudyn run`` of its TOML,
        ``scenario_to_toml``: within float32's error, docs/en1991.md)."""
        if train not in self.stochastic_scenarios:
            raise SettingError("CheckResult.stochastic_scenario", "train", train,
                               ", ".join(self.stochastic_scenarios) or "none: the check has no stochastic rows")
        row = next((r for r in self.stochastic_rows() if r["train"] == train and
                    stoch.speed_key(r["speed_kmh"]) == stoch.speed_key(speed_kmh)), None)
        return stoch.scenario_at(self.stochastic_scenarios[train], speed_kmh,
                                 None if row is None else row["stochastic_n_freq"])

    def trains(self) -> list[str]:
        return list(dict.fromkeys(r["train"] for r in self.rows))

    def deciding_row(self) -> dict[str, Any]:
        """The row with the largest max_deck_acc_z / limit (the first such, in row order)."""
        return max(self.rows, key=lambda r: r["max_deck_acc_z"])

    @property
    def verdict(self) -> str:
        return VERDICT_EXCEEDS if any(r["verdict"] == VERDICT_EXCEEDS for r in self.rows) else VERDICT_OK

    def verdict_line(self) -> str:
        """One line: the verdict, the deciding train, speed, case, location and margin."""
        r = self.deciding_row()
        margin = self.limit - r["max_deck_acc_z"]
        state = "EXCEEDED" if self.verdict == VERDICT_EXCEEDS else "met"
        share = f"{abs(margin):.2f} m/s^2 ({abs(100 * margin / self.limit):.0f} %)"
        return (f"deck acceleration limit {self.limit:g} m/s^2 ({self.track} track) {state}: peak "
                f"{r['max_deck_acc_z']:.3f} m/s^2, {r['train']} at {r['speed_kmh']:.1f} km/h ({r['case']} case), "
                f"{place_words(r['max_deck_acc_z_location'])}; " + (f"margin {share}" if margin >= 0 else f"over by {share}"))

    def summary(self) -> str:
        """A one-screen summary: the verdict, the settings, the largest values per train."""
        lines = [*(["criteria (EN 1990 A2.4.4):"] + ["  " + c.line() for c in self.criteria] if self.criteria else []),
                 self.verdict_line(),
                 f"bridge {self.bridge}{f' ({self.bridge_file})' if self.bridge_file else ''}: "
                 f"{self.construction.replace('_', ' ')} ({self.construction_basis}), "
                 f"{self.damping_basis}; mass cases {', '.join(self.cases)}",
                 f"{len(self.mode_frequencies)} modes up to {self.cutoff_hz:.3g} Hz ({self.cutoff_basis}), at the track "
                 f"line (torsion included), {self.mesh_basis}, nominal case: " + ", ".join(f"{f:.3g}" for f in self.mode_frequencies) + " Hz",
                 f"dynamic analysis {'required' if self.dynamic_analysis[0] else 'not required'} by Figure 6.9: "
                 f"{self.dynamic_analysis[1]}",
                 f"{'train':<10} {'speeds':>6} {'max acc':>9} {'at km/h':>8} {'phi_dyn':>8} {'v_i = n0 D / i [km/h]'}"]
        for name in self.trains():
            rows = [r for r in self.rows if r["train"] == name]
            top = max(rows, key=lambda r: r["max_deck_acc_z"])
            res = ", ".join(f"{v:.0f}" for v in self.resonant_speeds_kmh.get(name, ()))
            lines.append(f"{name:<10} {len(rows):>6} {top['max_deck_acc_z']:>9.3f} {top['speed_kmh']:>8.1f} "
                         f"{max(r['phi_dyn'] for r in rows):>8.3f} {res}")
        srows = self.stochastic_rows()
        if srows or self.stochastic_basis:
            lines.append(f"stochastic rows ({self.stochastic_basis}):")
            lines.append(f"  {'train':<10} {'speeds':>6} {'max P(exceed)':>14} {'at km/h':>8} {'level at P*':>12} "
                         f"{'det x(1+k phi2)':>16}")
            for name in dict.fromkeys(r["train"] for r in srows):
                rows = [r for r in srows if r["train"] == name]
                top = max(rows, key=lambda r: (r["p_exceed"] if math.isfinite(r["p_exceed"]) else -1.0,
                                               r["level_at_target"]))
                lines.append(f"  {name:<10} {len(rows):>6} {top['p_exceed']:>14.3g} {top['speed_kmh']:>8.1f} "
                             f"{top['level_at_target']:>12.3f} {top['max_deck_acc_z_with_phi2']:>16.3f}")
            if self.warnings:
                lines.append(f"  {len(self.warnings)} warning(s) of the PEM runs (CheckResult.warnings), e.g. "
                             f"{self.warnings[0][:160]}")
        return "\n".join(lines + vbi.summary_lines(self.interaction))

    def csv_text(self) -> str:
        """check.csv's text, from the records (:func:`tb_exudyn.results.check_records.records_csv`)."""
        return records_csv(self.rows)

    def to_xarray(self):  # noqa: ANN201
        """The check as an :class:`xarray.Dataset` (:func:`tb_exudyn.results.check_records.check_dataset`;
        NetCDF: :func:`tb_exudyn.results.export.export_netcdf`)."""
        return check_dataset(self)

    def to_csv(self, path: str | Path) -> Path:
        """Write the table as CSV (atomically: the file is the old one or the whole new one)."""
        return write_text_atomic(path, self.csv_text())

    def plot(self):  # noqa: ANN201
        """The figure of :func:`tb_exudyn.plotting.plot_check` (matplotlib, loaded on first use)."""
        return importlib.import_module("tb_exudyn.plotting").plot_check(self)


def _case_rows(setup: CheckSetup, case: str, train: str, resp: MovingForceResponse) -> list[CheckRecord]:
    """The rows of one mass case and train: one per speed of its response."""
    m = setup.modes[case]
    phi_dyn = resp.phi_dyn.max(axis=0)
    mids = resp.mid_stations
    where_max = resp.max_acc.argmax(axis=0)
    limit, k_irr = setup.limit, setup.k_irr
    rows = []
    for j, v in enumerate(resp.speeds_kmh):
        s = int(where_max[j])
        peak = float(resp.max_acc[s, j])
        phi2 = code.phi_irregularity_annex_c(m.f1, setup.span, v / 3.6)  # L_Phi: the longest span [check]
        rows.append(CheckRecord(
            criterion=deck_criterion(setup.track), load_model=moving_force_load_model(train), train=train,
            speed_kmh=float(v), case=case, track=setup.track,
            location=f"{resp.station_names[s]} ({resp.station_x[s]:g} m)", value=peak, limit=limit,
            damping_ratio=setup.zeta, cutoff_hz=float(m.cutoff),
            acc_z_mid_span=tuple(float(resp.max_acc[mid, j]) for mid in mids),
            disp_z_mid=float(resp.max_disp[mids, j].max()), phi_dyn=float(phi_dyn[j]), phi_irregularity=phi2,
            enhancement=float(1.0 + phi_dyn[j] + k_irr * phi2),
            value_with_phi2=float(peak * (1.0 + k_irr * phi2))))
    return rows


def _stochastic_basis(setup: CheckSetup, runs: Sequence[stoch.StochasticRun]) -> str:
    if not setup.stochastic_trains:
        return ""
    source = setup.stochastic_source
    n_runs = sum(len(v) for v in setup.run_speeds.values())
    return (f"PEM of {', '.join(source.track.irregularities)} (track and analysis of {source.name}) on the vehicle "
            f"models of {', '.join(t.name for t in setup.stochastic_trains)}, nominal case, damping "
            f"{100 * setup.zeta_vehicles:.3g} %; {n_runs} runs in {sum(r.seconds for r in runs):.1f} s; target "
            f"probability {DEFAULT_TARGET_PROBABILITY:.3g} per passage; criterion {deck_criterion(setup.track)}"
            + "".join(f"; {r.train}: {r.grid_error}" for r in runs if r.grid_error))


def _assemble(setup: CheckSetup, responses: dict[tuple[str, str], MovingForceResponse],
              stochastic: dict[str, list[tuple[float, dict[str, Any]]]], stats: dict[str, Any], t0: float,
              static: dict | None = None, interaction: dict | None = None) -> CheckResult:
    """The CheckResult of the check's tasks (tb_exudyn.methods.check): the rows of every (case, train) in that
    order, the stochastic values in the nominal case's rows, the A2.4.4 verdicts, the interaction runs."""
    rows, ordered = [], []
    for case in setup.cases:
        for train in setup.trains:
            ordered.append(responses[(case, train.name)])
            rows += _case_rows(setup, case, train.name, ordered[-1])
    runs = [stoch.stochastic_run(setup.bases[t.name], stochastic[t.name], setup.track, t.name)
            for t in setup.stochastic_trains]
    for run in runs:
        rows = [replace(r, stochastic=run.values.get(stoch.speed_key(r.speed_kmh))) if r.train == run.train and
                r.case == NOMINAL_CASE else r for r in rows]
    messages = [m for run in runs for m in run.warnings]
    m = setup.modes[setup.ref_case]
    mb, used, cutoff = m.modal, m.used, m.cutoff
    inter = tuple(vbi.comparison_of((interaction or {})[t.name], setup.bridge, t, setup.zeta_vehicles, cutoff,
                                    setup.ref_case) for t in setup.interaction_trains)  # the driver's tasks
    verdicts = a2_verdicts(setup.bridge, setup.line_speed_kmh, setup.track, setup.maintenance, mb, rows, ordered,
                           setup.cases, [t.name for t in setup.trains], setup.limit, setup.alpha, setup.alpha_given,
                           static=static)
    bridge = setup.bridge
    return CheckResult(
        criteria=verdicts, bridge=bridge.name, bridge_file="" if setup.label == bridge.name else setup.label,
        line_speed_kmh=setup.line_speed_kmh, track=setup.track, limit=setup.limit, construction=setup.construction,
        damping_ratio=setup.zeta, damping_basis=setup.damping_basis, cutoff_hz=float(cutoff), cutoff_basis=m.basis,
        mode_frequencies=tuple(float(f) for f in mb.frequencies[used]),
        vertical_frequencies=tuple(float(f) for f in mb.frequencies[_vertical(mb)] if f <= cutoff * (1.0 + 1e-9)),
        cases=setup.cases, construction_basis=setup.construction_basis, mesh_basis=setup.mesh_basis,
        dynamic_analysis=code.dynamic_analysis_required(setup.line_speed_kmh, setup.span, m.f1),
        resonant_speeds_kmh={t.name: tuple(float(v) for v in code.resonant_speeds_kmh(m.f1, t.regular_length))
                             for t in setup.trains},
        columns=record_columns(len(setup.spans)), rows=tuple(rows), responses=tuple(ordered),
        seconds=time.perf_counter() - t0, stochastic_scenarios=dict(setup.bases),
        stochastic_basis=_stochastic_basis(setup, runs),
        target_probability=float(DEFAULT_TARGET_PROBABILITY) if setup.stochastic_trains else None,
        warnings=tuple(dict.fromkeys(messages)), interaction=inter, run=dict(stats))


def table_files(result: CheckResult) -> dict[str, bytes]:
    """What a check writes into its output folder unless told otherwise: its table (check.csv)."""
    return {CHECK_CSV: result.csv_text().encode()}


#: a check whose moving-force integrations add up to less than this (steps x modes x speeds) runs in this
#: process when no worker count is given: a worker process's start (importing the methods, 1-2 s each, in
#: parallel) would cost more than it saves. About 8e-8 CPU-s per unit: li_zhu_2011_bridge under HSLM-A at
#: 250 km/h is 4.2e8 (33 CPU-s: a pool of 2), single_span_32m under HSLM-A1 at 120 km/h 2.5e5 (in this process)
IN_PROCESS_WORK = 5e7


def _work(setup: CheckSetup) -> float:
    """The moving-force integrations' size, steps x modes x speeds summed (the stochastic rows: infinite)."""
    if setup.stochastic_trains:
        return math.inf
    total = 0.0
    for case in setup.cases:
        m = setup.modes[case]
        f = m.modal.frequencies[m.used]
        for t in setup.trains:
            speeds = np.array(setup.series[t.name])
            total += integration_steps(m.modal.length, f, t, speeds, setup.spans).n_steps * f.size * speeds.size
    return total


def check(
    bridge,  # noqa: ANN001
    line_speed_kmh: float,
    trains: Sequence[str | ForceTrain] | str = ("hslm_a",),
    track: str = "ballasted",
    construction: str | None = None,
    additional_damping: bool = False,
    damping_ratio: float | None = None,
    maintenance: str = "careful",
    speed_step_kmh: float = code.MAX_SPEED_STEP_KMH,
    cases: Sequence[str] | None = None,
    where: str = "check",
    stochastic: bool = False,
    stochastic_speeds: Sequence[float] | None = None,
    stochastic_scenario: Any = None,
    interaction: bool = False,
    workers: int | None = None,
    executor: Any = None,
    progress: bool = False,
    alpha: float | None = None,
    out: str | Path | None = None,
    resume: bool = False,
    overwrite: bool = False,
    keep_checkpoint: bool = False,
    render: Callable[[CheckResult], dict[str, bytes]] | None = None,
) -> CheckResult:
    """The EN 1991-2 dynamic check of ``bridge`` under ``trains`` (deterministic moving forces).

    Parameters
    ----------
    bridge : a bridge name of models/bridges, a .toml path, or a ``SimpleBeam`` / ``Frame``
    line_speed_kmh : the maximum line speed at the site, in [1, 600] km/h (MIN_LINE_SPEED_KMH); speeds up to 1.2 x it
    trains : 'hslm_a' (HSLM-A1 ... A10), 'HSLM-A3', a real train of models/trains, or ForceTrain objects
    track : 'ballasted' (limit 3.5 m/s^2) or 'direct' (5.0 m/s^2)
    construction : the Table 6.6 type: steel_composite, prestressed_concrete, reinforced_concrete,
        filler_beam; None (default): the bridge's own (``code.construction`` of its file; the shipped
        bridges are prestressed concrete box girders), refused when the bridge has none
    additional_damping : add eq. 6.13's Delta zeta (moving-force models, spans below 30 m)
    damping_ratio : a given ratio instead of Table 6.6 (recorded as such)
    maintenance : 'careful' or 'standard', the factor on phi'' (Annex C)
    speed_step_kmh : the step of the speed series (at most 5 km/h)
    cases : the mass cases (EN 1991-2 6.4.6.3.2, :data:`tb_exudyn.scenario.MASS_CASES`) each of whose
        bridge gets its own modes and rows; None (default): lower, nominal and upper where the bridge
        declares ballast, else nominal
    where : how error messages name the caller (errors name the arguments as their keys)
    stochastic : also the stochastic rows (:mod:`tb_exudyn.codes.stochastic`): for every train given as
        vehicle models, the PEM of the track irregularity at its speeds of the nominal mass case (one PEM
        run per speed: about 4 CPU-s each for the reference study's ICE over li_zhu_2011_bridge)
    stochastic_speeds : those speeds only [km/h] (None: every speed of the series); a speed not in the
        series is added to it (for the trains with stochastic rows), within the series' range
    stochastic_scenario : the scenario whose track and analysis the PEM runs take (a name, a .toml path
        or a Scenario; default li_zhu_2011: german_low vertical, alignment, cross-level)
    interaction : per train given as vehicle models, its vehicle-bridge interaction run beside its moving forces
        at its deciding speed (:func:`tb_exudyn.codes.interaction.check_comparison`; one Exudyn run per train, a
        task of the check's method: :class:`tb_exudyn.methods.check.InteractionTask`)
    workers, executor, progress : how the check's tasks run (:class:`tb_exudyn.execution.Execution`: one task
        per mass case and train, one per stochastic speed; :mod:`tb_exudyn.methods.check`); workers None: all
        cores, or this process for a check whose integrations are small (:data:`IN_PROCESS_WORK`). The
        result is bitwise the same for any of them
    alpha : the classified-load factor alpha of EN 1991-2 6.3.2(3) on LM71 and SW/0 in the static criteria
        (None: 1.0, which the verdicts say was not given)
    out, resume, overwrite, keep_checkpoint : the output folder (None: nothing written) and what may be done
        to it (:class:`~tb_exudyn.execution.Execution`): the check's checkpoint ``out/checkpoint-check`` (one
        file per finished task: an interrupted check resumes with ``resume=True``, to the same bits), then
        the files of ``render`` written as one group (all or none); earlier check files are refused unless
        ``overwrite``
    render : the files written into ``out`` from the result ({name: bytes}; default :func:`table_files`, the
        table alone); names among :data:`CHECK_FILES` (one left out is removed with the write)

    Raises SettingError naming ``where`` and the argument for any value outside what is allowed, before any
    work and before ``out`` is touched.
    """
    started = time.perf_counter()
    execution_args = dict(executor=executor, out=out, resume=resume, progress=progress, where=where,
                          overwrite=overwrite, keep_checkpoint=keep_checkpoint)
    Execution(workers=workers, **execution_args)  # its arguments checked first (nothing is touched)
    # one BLAS thread here too, as in every worker: the plan's eigenproblems (the mass cases' modes, the PEM
    # model's) are small, and a multi-threaded OpenBLAS let its threads spin on them: li_zhu_2011_bridge with
    # ice_mttm's stochastic column planned in 16 CPU-s instead of 0.8 (2 cores, measured under load 15)
    with single_threaded_blas():
        setup = plan_check(bridge, line_speed_kmh, trains=trains, track=track, construction=construction,
                           additional_damping=additional_damping, damping_ratio=damping_ratio, maintenance=maintenance,
                           speed_step_kmh=speed_step_kmh, cases=cases, where=where, stochastic=stochastic,
                           stochastic_speeds=stochastic_speeds, stochastic_scenario=stochastic_scenario,
                           interaction=interaction, alpha=alpha)
        if workers is None and executor is None and _work(setup) < IN_PROCESS_WORK:
            workers = 1
        method = importlib.import_module("tb_exudyn.methods.check").CheckMethod(
            setup, assemble=_assemble, render=render or table_files, group=CHECK_FILES, started=started)
        return importlib.import_module("tb_exudyn.methods.driver").drive(method, Execution(workers=workers,
                                                                                           **execution_args))


__all__ = ["CHECK_CSV", "CHECK_DATA", "CHECK_FIGURE", "CHECK_FILES", "CHECK_PAGE", "CheckResult", "NOMINAL_CASE", "check",
           "table_files"]
