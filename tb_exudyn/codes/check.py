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
from ..errors import ResourceError, ScenarioError, SettingError, UserError
from ..results.check_records import CheckRecord, check_dataset, record_columns, records_csv
from ..results.checks import DEFAULT_TARGET_PROBABILITY
from ..scenario.io import load_bridge
from ..scenario.code_data import MASS_CASES, with_mass_case
from ..scenario.model import Continuous, Frame, SimpleBeam
from ..scenario.registry import model_files
from ..scenario.schema import source_file
from . import en1991 as code
from .check_modes import FIRST_MODE_LIMIT_HZ, MODE_LIMIT_CAP_HZ  # noqa: F401 - the check's, named here too
from .check_modes import modes_for_check as _modes_for_check, vertical as _vertical
from .moving_force import MAX_STEPS, MovingForceResponse, integration_steps, moving_force_response
from . import stochastic as stoch
from .trains import ForceTrain, TrainSource, distinct_trains, train_sources
from .a2_verdicts import a2_verdicts, check_alpha, place_words
from .criteria import deck_criterion, moving_force_load_model
from .hslm_b import HSLM_B_SPANS, hslm_b
from . import interaction as vbi

#: the table's file in an output folder
CHECK_CSV = "check.csv"
CHECK_FIGURE = "check.png"
#: the check's HTML page (tb_exudyn.report.check)
CHECK_PAGE = "check.html"
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
        """The scenario of ``train``'s stochastic row at ``speed_kmh``: ``run_pem`` of it, or ``tb-exudyn
        run`` of its TOML (``scenario_to_toml``), gives the row's numbers."""
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


def _prefixed(exc: UserError, prefix: str) -> UserError:
    """The same error (class and attributes) with ``prefix: `` before its one line."""
    out = type(exc).__new__(type(exc))
    Exception.__init__(out, f"{prefix}: {exc}")
    out.__dict__.update(exc.__dict__)
    out.message = f"{prefix}: {exc}"
    return out


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
    option_names: dict[str, str] | None = None,
    stochastic: bool = False,
    stochastic_speeds: Sequence[float] | None = None,
    stochastic_scenario: Any = None,
    interaction: bool = False,
    workers: int | None = None,
    executor: Any = None,
    progress: bool = False,
    alpha: float | None = None,
    before_work: Callable[[], None] | None = None,
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
    where : how error messages name the caller (the CLI passes 'command line')
    option_names : argument -> name in error messages (the CLI's options, e.g. {'trains': '--trains'})
    stochastic : also the stochastic rows (:mod:`tb_exudyn.codes.stochastic`): for every train given as
        vehicle models, the PEM of the track irregularity at its speeds of the nominal mass case (one PEM
        run per speed: about 12-20 s each for the reference study's ICE over li_zhu_2011_bridge)
    stochastic_speeds : those speeds only [km/h] (None: every speed of the series); a speed not in the
        series is added to it (for the trains with stochastic rows), within the series' range
    stochastic_scenario : the scenario whose track and analysis the PEM runs take (a name, a .toml path
        or a Scenario; default li_zhu_2011: german_low vertical, alignment, cross-level)
    interaction : per train given as vehicle models, its vehicle-bridge interaction run beside its moving forces
        at its deciding speed (:func:`tb_exudyn.codes.interaction.check_rows`; one Exudyn run per train)
    workers, executor, progress : how the PEM runs execute (as :func:`tb_exudyn.methods.sweep.run_sweep`)
    alpha : the classified-load factor alpha of EN 1991-2 6.3.2(3) on LM71 and SW/0 in the static criteria
        (None: 1.0, which the verdicts say was not given)
    before_work : called once, after every argument is checked and the work planned (modes, speed series,
        the integrations' sizes, the stochastic rows' scenarios), before the first integration: the command
        line takes its output folder there, so that a refused argument leaves it untouched

    Raises SettingError naming ``where`` and the argument for any value outside what is allowed.
    """
    t0 = time.perf_counter()
    names = dict(option_names or {})

    def err(key: str, value: Any, allowed: str, reason: str = "") -> SettingError:
        return SettingError(where, names.get(key, key), value, allowed, reason)

    ok = isinstance(line_speed_kmh, (int, float)) and not isinstance(line_speed_kmh, bool) and math.isfinite(
        line_speed_kmh) and MIN_LINE_SPEED_KMH <= line_speed_kmh <= code.MAX_LINE_SPEED_KMH
    if not ok:
        raise err("line_speed_kmh", line_speed_kmh,
                  f"a speed in [{MIN_LINE_SPEED_KMH:g}, {code.MAX_LINE_SPEED_KMH:g}] km/h",
                  "out of range" if isinstance(line_speed_kmh, (int, float)) and not isinstance(line_speed_kmh, bool)
                  and math.isfinite(line_speed_kmh) else "")
    if track not in code.DECK_ACCELERATION_LIMITS:
        raise err("track", track, " or ".join(code.DECK_ACCELERATION_LIMITS))
    if maintenance not in code.IRREGULARITY_FACTOR:
        raise err("maintenance", maintenance, " or ".join(code.IRREGULARITY_FACTOR))
    if not (isinstance(speed_step_kmh, (int, float)) and 0 < speed_step_kmh <= code.MAX_SPEED_STEP_KMH):
        raise err("speed_step_kmh", speed_step_kmh, f"0 < step <= {code.MAX_SPEED_STEP_KMH:g} km/h")
    if damping_ratio is not None and not (isinstance(damping_ratio, (int, float)) and 0.0 <= damping_ratio < 1.0):
        raise err("damping_ratio", damping_ratio, "a ratio in [0, 1), or none for Table 6.6")
    label = str(bridge) if isinstance(bridge, (str, Path)) else (
        source_file(bridge) or getattr(bridge, "name", type(bridge).__name__))  # the bridge as the user gave it
    if isinstance(bridge, (str, Path)):
        text = str(bridge)
        known = model_files("bridges")
        if not (text.endswith(".toml") or Path(text).exists()) and text not in known:
            raise err("bridge", text, f"one of {', '.join(known)} or a path to a .toml file", "unknown bridge name")
        bridge = load_bridge(bridge)
    if not isinstance(bridge, (SimpleBeam, Frame, Continuous)):  # e.g. a modal_table: no section data
        raise err("bridge", label, "a bridge name, a .toml path, SimpleBeam, Frame or Continuous",
                  f"a {getattr(bridge, 'kind', 'bridge')} bridge has no section data for the code's mass cases"
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
    ballast = bridge.code is not None and bridge.code.ballast_mass_per_length > 0.0
    if cases is None:
        cases = ("lower", NOMINAL_CASE, "upper") if ballast else (NOMINAL_CASE,)
    cases = tuple(cases)
    bad = [c for c in cases if c not in MASS_CASES] or ([] if ballast or cases == (NOMINAL_CASE,) else
                                                         [c for c in cases if c != NOMINAL_CASE])
    if bad or not cases:
        raise err("cases", list(cases), "mass cases of " + ", ".join(MASS_CASES) + (
            "" if ballast else " (only nominal: the bridge declares no ballast, code.ballast_mass_per_length)"))
    given = [trains] if isinstance(trains, (str, ForceTrain)) else list(trains)
    if not given:
        raise err("trains", given, "hslm_a, HSLM-A1 ... HSLM-A10 or a train of models/trains", "no train")
    key_trains = names.get("trains", "trains")
    pairs = [pair for t in given for pair in ([(t, TrainSource(t.name, f"the ForceTrain object {t.name!r}", id(t)))]
                                              if isinstance(t, ForceTrain) else train_sources(t, where, key_trains))]
    train_list = distinct_trains(pairs, where, key_trains)  # two trains with one name: refused, naming both
    spans = [float(s) for s in bridge.spans]
    if any(t.name.startswith("HSLM-A") for t in train_list) and min(spans) < HSLM_A_MIN_SPAN and not isinstance(
            bridge, Continuous) and min(spans) >= HSLM_B_SPANS[0]:  # HSLM-B instead (EN 1991-2 6.4.6.1.1)
        b = hslm_b(min(spans))
        train_list = distinct_trains([p for p in pairs if not p[0].name.startswith("HSLM-A")] + [
            (b, TrainSource("hslm_a", f"EN 1991-2's {b.name} (HSLM-A's stand-in under 7 m)", "hslm_b"))],
            where, key_trains)
    if any(t.name.startswith("HSLM-A") for t in train_list) and min(spans) < HSLM_A_MIN_SPAN:
        raise err("trains", [t.name for t in train_list], f"spans >= {HSLM_A_MIN_SPAN:g} m for HSLM-A",
                  f"span {min(spans):g} m of a continuous girder: HSLM-B is for simply supported spans under 7 m "
                  "(EN 1991-2 Table E.4)")

    stochastic_trains: list[ForceTrain] = []
    extra_speeds: list[float] = []
    if not isinstance(stochastic, bool):
        raise err("stochastic", stochastic, "True or False")
    if not stochastic and (stochastic_speeds is not None or stochastic_scenario is not None):
        given_key = "stochastic_speeds" if stochastic_speeds is not None else "stochastic_scenario"
        raise err(given_key, stochastic_speeds if stochastic_speeds is not None else str(stochastic_scenario),
                  f"with {names.get('stochastic', 'stochastic=True')} only", "no stochastic rows asked for")
    if stochastic:
        stochastic_trains = [t for t in train_list if stoch.eligible(t)]
        if not stochastic_trains:
            raise err("stochastic", [t.name for t in train_list], "trains given as vehicle models among the trains "
                      "(ice_mttm, ave_s103 or a train .toml file of vehicles): HSLM-A trains are moving forces",
                      "no train for the stochastic rows")
        if NOMINAL_CASE not in cases:
            raise err("cases", list(cases), f"mass cases including {NOMINAL_CASE!r} (the stochastic rows' case)")
        top_speed = code.DESIGN_SPEED_FACTOR * float(line_speed_kmh)
        low_speed = min(code.SPEED_SERIES_START_KMH, top_speed)
        if stochastic_speeds is not None:
            if isinstance(stochastic_speeds, (str, bytes)):
                raise err("stochastic_speeds", stochastic_speeds, "speeds [km/h] as numbers, or none for every speed")
            values = [stochastic_speeds] if isinstance(stochastic_speeds, (int, float)) else stochastic_speeds
            try:
                values = [v for v in values]
            except TypeError:
                raise err("stochastic_speeds", stochastic_speeds, "speeds [km/h], or none for every speed") from None
            allowed = (f"speeds from {low_speed:g} to {top_speed:g} km/h (the check's series: 40 m/s to 1.2 x the "
                       "line speed), each once")
            if not values:
                raise err("stochastic_speeds", list(values), allowed, "no speed")
            for v in values:
                if isinstance(v, bool) or not isinstance(v, (int, float, np.floating, np.integer)) or not (
                        math.isfinite(v) and low_speed - 1e-6 <= v <= top_speed + 1e-6):
                    raise err("stochastic_speeds", v, allowed, "outside the series' range")
            keys = [round(float(v), 6) for v in values]
            if len(set(keys)) != len(keys):
                raise err("stochastic_speeds", list(values), allowed, "a speed given twice")
            extra_speeds = [min(max(k, low_speed), top_speed) for k in keys]
        source_scenario = stoch.scenario_source(stochastic_scenario, where,
                                                names.get("stochastic_scenario", "stochastic_scenario"))

    interaction_trains = vbi.check_trains(train_list, interaction, err)
    alpha_value = check_alpha(alpha, where, names.get("alpha", "alpha"))
    span = max(spans)  # the longest span: the smallest Table 6.6 ratio (the lower limit for every span)
    if damping_ratio is not None:
        zeta = float(damping_ratio)
        basis = f"damping ratio {100 * zeta:.3g} % (given)"
    else:
        zeta = code.damping_ratio_table_6_6(construction, span)
        basis = f"damping {100 * zeta:.3g} % (Table 6.6, {construction.replace('_', ' ')}, L = {span:g} m)"
    zeta_vehicles = zeta  # eq. 6.13 is for moving-force models: the vehicle model's rows leave it out
    if additional_damping:
        dz = code.additional_damping_eq_6_13(span)
        zeta += dz
        basis += f" + {100 * dz:.3g} % (eq. 6.13)"

    limit = code.deck_acceleration_limit(track)
    k_irr = code.IRREGULARITY_FACTOR[maintenance]
    # each mass case its own bridge and modes; the nominal case's (or the first's) describe the result
    modes_of = {case: _modes_for_check(with_mass_case(bridge, case) if bridge.code is not None else bridge, err,
                                       label) for case in cases}
    ref_case = NOMINAL_CASE if NOMINAL_CASE in modes_of else cases[0]
    mb, used, f1, _f3, cutoff, cutoff_basis = modes_of[ref_case]
    dyn_required = code.dynamic_analysis_required(line_speed_kmh, span, f1)

    columns = record_columns(len(spans))
    stochastic_names = {t.name for t in stochastic_trains}
    series: dict[str, np.ndarray] = {}
    for train in train_list:
        # the resonances of every case: the series is refined near each case's v_i = n0 D / i
        v_res = sorted({float(v) for c in cases for v in code.resonant_speeds_kmh(modes_of[c][2], train.regular_length)})
        speeds = code.speed_series(line_speed_kmh, v_res, step_kmh=speed_step_kmh)
        if train.name in stochastic_names and extra_speeds:
            speeds = np.unique(np.round(np.concatenate([speeds, extra_speeds]), 6))
        series[train.name] = speeds
    # the stochastic rows' scenarios, built (and every speed's scenario checked) before any run
    bases: dict[str, Any] = {}
    run_speeds: dict[str, list[float]] = {}
    if stochastic_trains:
        _, _, _, _, cutoff_n, _ = modes_of[NOMINAL_CASE]
        key_sc = names.get("stochastic_scenario", "stochastic_scenario")
        for train in stochastic_trains:
            bases[train.name] = stoch.base_scenario(source_scenario, bridge, train, zeta_vehicles, cutoff_n,
                                                    where, key_sc)
            chosen = series[train.name] if not extra_speeds else np.array(extra_speeds)
            run_speeds[train.name] = [float(v) for v in series[train.name] if stoch.speed_key(v) in
                                      {stoch.speed_key(c) for c in chosen}]
            for v in run_speeds[train.name]:
                try:
                    stoch.scenario_at(bases[train.name], v)
                except ScenarioError as exc:
                    given = source_scenario.source_file or source_scenario.name
                    raise err("stochastic_scenario", given, exc.allowed,
                              f"its analysis at {v:g} km/h (the speed rule: its band x v / v0, at most "
                              f"0.1 / analysis.time_step): analysis.{exc.key}: {exc.reason}"
                              ) from None
    def too_many_steps(train: ForceTrain, steps: Any) -> ResourceError:
        return ResourceError.from_parts(
            where, names.get("line_speed_kmh", "line_speed_kmh"), line_speed_kmh,
            "a higher line speed: the lowest speed of the series sets the step",
            f"{train.name} at {series[train.name][0]:g} km/h needs {steps} steps, more than {MAX_STEPS}")

    for case, train in ((c, t) for c in cases for t in train_list):  # every integration's size, before any
        mb_c, used_c = modes_of[case][:2]
        steps = integration_steps(mb_c.length, mb_c.frequencies[used_c], train, series[train.name], spans).n_steps
        if steps > MAX_STEPS:
            raise too_many_steps(train, steps)
    if before_work is not None:  # every argument checked and the work planned: the caller's turn (its --out)
        before_work()
    rows, responses, resonant = [], [], {}
    for case, train in ((c, t) for c in cases for t in train_list):
        mb_c, used_c, f1_c, _, cutoff_c, _ = modes_of[case]
        resonant[train.name] = tuple(float(v) for v in code.resonant_speeds_kmh(f1, train.regular_length))
        speeds = series[train.name]
        try:
            resp = moving_force_response(mb_c, train, speeds, spans, damping_ratio=zeta, modes=used_c)
        except ResourceError as exc:
            raise too_many_steps(train, getattr(exc, "steps", "?")) from None
        responses.append(resp)
        phi_dyn = resp.phi_dyn.max(axis=0)
        mids = resp.mid_stations
        where_max = resp.max_acc.argmax(axis=0)
        for j, v in enumerate(resp.speeds_kmh):
            s = int(where_max[j])
            peak = float(resp.max_acc[s, j])
            phi2 = code.phi_irregularity_annex_c(f1_c, span, v / 3.6)  # L_Phi: the longest span [check]
            rows.append(CheckRecord(
                criterion=deck_criterion(track), load_model=moving_force_load_model(train.name), train=train.name,
                speed_kmh=float(v), case=case, track=track,
                location=f"{resp.station_names[s]} ({resp.station_x[s]:g} m)", value=peak, limit=limit,
                damping_ratio=zeta, cutoff_hz=float(cutoff_c),
                acc_z_mid_span=tuple(float(resp.max_acc[m, j]) for m in mids),
                disp_z_mid=float(resp.max_disp[mids, j].max()), phi_dyn=float(phi_dyn[j]), phi_irregularity=phi2,
                enhancement=float(1.0 + phi_dyn[j] + k_irr * phi2),
                value_with_phi2=float(peak * (1.0 + k_irr * phi2))))
    # the stochastic rows: one PEM sweep per train over its chosen speeds, into the nominal case's rows
    runs, messages = [], []
    for train in stochastic_trains:
        try:
            run = stoch.run_stochastic(bases[train.name], run_speeds[train.name], track, workers=workers,
                                       executor=executor, progress=progress, name=train.name)
        except UserError as exc:  # e.g. a run this machine cannot hold: say which option's runs
            given = source_scenario.source_file or source_scenario.name
            raise _prefixed(exc, f"{where}: key '{names.get('stochastic_scenario', 'stochastic_scenario')}' = "
                                 f"{given!r}, the stochastic rows of {train.name}") from None
        runs.append(run)
        messages += run.warnings
        rows = [replace(r, stochastic=run.values.get(stoch.speed_key(r.speed_kmh))) if r.train == train.name and
                r.case == NOMINAL_CASE else r for r in rows]
    stochastic_basis = ""
    if stochastic_trains:
        n_runs = sum(len(v) for v in run_speeds.values())
        stochastic_basis = (
            f"PEM of {', '.join(source_scenario.track.irregularities)} (track and analysis of {source_scenario.name}) "
            f"on the vehicle models of {', '.join(t.name for t in stochastic_trains)}, nominal case, damping "
            f"{100 * zeta_vehicles:.3g} %; {n_runs} runs in {sum(r.seconds for r in runs):.1f} s; target probability "
            f"{DEFAULT_TARGET_PROBABILITY:.3g} per passage; criterion {deck_criterion(track)}")
    inter = vbi.check_rows(bridge, interaction_trains, rows, zeta_vehicles, cutoff, ref_case) if interaction_trains else ()
    verdicts = a2_verdicts(bridge, float(line_speed_kmh), track, maintenance, mb, rows, responses, cases,
                           [t.name for t in train_list], limit, alpha_value, alpha is not None)
    return CheckResult(
        criteria=verdicts, bridge=bridge.name, bridge_file="" if label == bridge.name else label,
        line_speed_kmh=float(line_speed_kmh), track=track, limit=limit, construction=construction,
        damping_ratio=zeta, damping_basis=basis, cutoff_hz=float(cutoff), cutoff_basis=cutoff_basis,
        mode_frequencies=tuple(float(f) for f in mb.frequencies[used]),
        vertical_frequencies=tuple(float(f) for f in mb.frequencies[_vertical(mb)] if f <= cutoff * (1.0 + 1e-9)),
        cases=cases, construction_basis=construction_basis, mesh_basis=mesh_basis, dynamic_analysis=dyn_required,
        resonant_speeds_kmh=resonant, columns=columns, rows=tuple(rows), responses=tuple(responses),
        seconds=time.perf_counter() - t0, stochastic_scenarios=bases, stochastic_basis=stochastic_basis,
        target_probability=float(DEFAULT_TARGET_PROBABILITY) if stochastic_trains else None, warnings=tuple(dict.fromkeys(messages)),
        interaction=inter,
    )



__all__ = ["CHECK_CSV", "CHECK_FIGURE", "CHECK_PAGE", "CheckResult", "NOMINAL_CASE", "check"]
