"""Speed sweeps: PEM at a series of train speeds, the frequency grid following the speed.

At each speed v the scenario is :func:`sweep_scenario` of the base: the same train, bridge, track
and analysis, with

- the PEM band over the track's wavelength band at that speed: freq_min = v / wavelength_max,
  freq_max = min(v / wavelength_min, 0.1 / time_step) (the highest frequency the time step resolves,
  as ``Analysis`` requires), the base's number of frequencies and spacing (pass ``n_freq`` to refine,
  ``freq_spacing="adaptive"`` for converged grids: the study's 200 linear points are not converged
  for every channel, docs/findings.md). With the adaptive spacing each speed's grid has at least
  ``n_freq`` nodes and at least what the grid's rules need at that speed (its band, run length and
  train spread follow the speed: :func:`tb_exudyn.methods.adaptive_grid.points_needed`); the count
  used is in the speed's result (``result.scenario.analysis.n_freq``) and in the table;
- an approach at least the base's in metres and in seconds (a faster train gets a longer lead-in,
  so that the runs, started at rest, have settled as well as at the base speed);
- the output channels of the key quantities (:data:`KEY_QUANTITIES`, or those given).

Each speed is one task on the sweep's executor (the local process pool, a Dask executor: the
same :class:`~tb_exudyn.execution.Execution` as a sweep over frequencies), running the whole PEM of
that speed in its worker with the column slices of a separate run on this machine, so that a
sweep's result at a speed is bitwise that of ``run_pem(sweep_scenario(base, v), ...)`` (with an
adaptive grid: of ``run_pem`` on the speed's result's scenario, whose n_freq is the count used). With an
output folder each speed's result and checkpoint go to ``DIR/<speed>/`` (``pem/`` and
``checkpoint/``) and the sweep's per-speed summaries to ``DIR/checkpoint-sweep/``: an interrupted
sweep resumes speed by speed, and a speed half done resumes within its own checkpoint.

The table (:func:`sweep_rows`, ``speed_sweep.csv``, written with the output folder; the figure is
:func:`tb_exudyn.plotting.plot_speed_sweep`, the page :func:`tb_exudyn.report.write_sweep_report`,
``speed_sweep.html``, both written by ``tb-exudyn sweep``): one row per speed with, per key quantity, the
largest |mean|, sigma and |mean| + 3 sigma over its channels and time, and the channel; the code
checks' estimates and exceedance probabilities enter through :func:`check_columns` (the hook for
``RandomResponse.checks()``, issue 16). :func:`resonance_speeds` gives v = f_n d / i for the
bridge's first modes, d the car length and the bogie spacing, i = 1, 2, 3.

EN 1991-2 (6.4.6.2) analyses a series of speeds up to 1.2 x the maximum line speed:
:func:`en1991_speeds`.
"""

from __future__ import annotations

import dataclasses
import fnmatch
import importlib
import itertools
import json
import math
import re
import time as _time
import typing
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Iterable, Sequence

import numpy as np

from ..builder.model import channel_list
from ..engines import check_engine
from ..errors import ResourceError, ScenarioError, SettingError
from ..execution import Execution, RunFiles, Task
from ..execution.output import SWEEP_FIGURE, SWEEP_PAGE
from ..execution.resources import MAX_STEPS, check_run_length
from ..results.checks import default_limits, grid_error_of
from ..results.export import write_table_csv
from ..results.random_response import RandomResponse
from ..scenario import Scenario, scenario_to_toml
from ..scenario.model import KMH, Analysis
from ..structure import modal_bridge
from ..system.modes import DIRECTIONS, nth_frequency
from .common import fingerprint_identity
from .pem import GRID_ERROR_TOLERANCE, default_slices, prepare_sweep
from . import pem

#: the key quantities of a sweep: (column name, channel pattern, what it is); those that match no
#: channel of the model are left out
KEY_QUANTITIES: tuple[tuple[str, str, str], ...] = (
    ("deck_acc_z", "bridge.*.mid.acc_z", "bridge deck vertical acceleration at mid-span [m/s^2]"),
    ("deck_acc_y", "bridge.*.mid.acc_y", "bridge deck lateral acceleration at mid-span [m/s^2]"),
    ("body_acc_z", "car*.body.acc_z", "car body vertical acceleration [m/s^2]"),
    ("body_acc_y", "car*.body.acc_y", "car body lateral acceleration [m/s^2]"),
    ("wheel_force_z", "car*.axle*force_z", "vertical wheel-rail force [N]"),
    ("wheel_force_y", "car*.axle*force_y", "lateral wheel-rail force [N]"),
)
#: EN 1991-2, 6.4.6.2: speeds up to this factor times the maximum line speed
EN1991_SPEED_FACTOR = 1.2
#: sigma multiple of the design value max |mean| + K sigma in the table
K_SIGMA = 3.0
#: the grid spacings a sweep may ask for: those of ``Analysis.freq_spacing`` (read from the schema)
FREQ_SPACINGS: tuple[str, ...] = typing.get_args(typing.get_type_hints(Analysis)["freq_spacing"])
#: the sweep's table in its output folder
SWEEP_TABLE = "speed_sweep.csv"


# ------------------------------------------------------------------------------------- speeds
#: a sweep's speeds follow the scenario's rule for speed_kmh (the schema's check: what a scenario file
#: and ``run --speed-kmh`` accept, finite, > 0 and <= 1000 km/h)
SPEED_CHECK = next(f.metadata["check"] for f in dataclasses.fields(Scenario) if f.name == "speed_kmh")
#: at most this many speeds in one sweep: each speed is a whole PEM run (13.6-25.5 s of a worker for
#: the reference study, docs/speed.md) and its own folder, so 1000 speeds are already 4-7 hours on
#: one core, a 0.6 km/h step over the whole range of speeds, and 18 times EN 1991-2's series at 5 km/h
#: steps up to 1.2 x 350 km/h (56 speeds); more is a slip (a step in m/s, a missing digit)
MAX_SPEEDS = 1000


def _keys(where: str) -> dict[str, str]:
    """How to name the speeds' arguments in a message: command-line options, or function arguments."""
    if where == "command line":
        return {"speeds": "--speeds-kmh", "line": "--line-speed-kmh", "step": "--speed-step-kmh",
                "start": "start_kmh"}  # (no option sets the start)
    return {"speeds": "speeds_kmh", "line": "line_speed_kmh", "step": "step_kmh", "start": "start_kmh"}


def check_speeds(speeds: Sequence[float], where: str = "run_sweep", key: str | None = None,
                 shown: Any = None) -> tuple[float, ...]:
    """The speeds of a sweep [km/h] as floats, checked before any work (SettingError naming ``where``
    and ``key``, showing ``shown``, default the speeds): at most :data:`MAX_SPEEDS`, each within
    :data:`SPEED_CHECK`, no two with the same :func:`speed_label` (the folder and task key of a speed)."""
    key = key or _keys(where)["speeds"]
    shown = list(speeds) if shown is None else shown
    allowed = f"1 to {MAX_SPEEDS} distinct speeds, each {SPEED_CHECK.describe()} km/h"
    if len(speeds) > MAX_SPEEDS:
        raise SettingError(where, key, shown, allowed, f"{len(speeds)} speeds")
    if not speeds:
        raise SettingError(where, key, shown, allowed, "no speed")
    seen: dict[str, float] = {}  # label -> speed
    for v in speeds:
        if not (_is_number(v) and SPEED_CHECK.ok(float(v))):
            raise SettingError(where, key, shown, allowed, f"speed {v!r} out of range")
        label = speed_label(float(v))
        if label in seen:
            raise SettingError(where, key, shown, allowed + " (different in the 6 significant digits of a speed's "
                               "folder and task key)", f"{seen[label]!r} and {float(v)!r} are the same speed {label!r}")
        seen[label] = float(v)
    return tuple(seen.values())


def _is_number(x: Any) -> bool:
    return isinstance(x, (int, float, np.integer, np.floating)) and not isinstance(x, (bool, np.bool_))


def parse_speeds(text: str, where: str = "command line") -> tuple[float, ...]:
    """'START:STOP:STEP' (km/h, STOP included) or a comma list '160,220,300', checked by
    :func:`check_speeds` (the count before the list is made)."""
    key = _keys(where)["speeds"]
    allowed = (f"START:STOP:STEP with 0 < START <= STOP <= {SPEED_CHECK.high:g} and STEP > 0, or speeds separated "
               f"by commas, each {SPEED_CHECK.describe()} km/h; at most {MAX_SPEEDS} speeds")
    try:
        if ":" in text:
            start, stop, step = (float(x) for x in text.split(":"))
        else:
            speeds = tuple(float(x) for x in text.split(",") if x.strip())
    except ValueError:
        raise SettingError(where, key, text, allowed, "not numbers") from None
    if ":" not in text:
        return check_speeds(speeds, where, key, text)
    if not (SPEED_CHECK.ok(start) and SPEED_CHECK.ok(stop) and start <= stop):
        raise SettingError(where, key, text, allowed, "START or STOP out of range")
    count = range_count(start, stop, step)
    if count is None:
        raise SettingError(where, key, text, allowed, "STEP not finite and > 0")
    if count > MAX_SPEEDS:
        raise SettingError(where, key, text, allowed, f"{count:.4g} speeds")
    return check_speeds(speed_range(start, stop, step), where, key, text)


def range_count(start: float, stop: float, step: float) -> float | None:
    """How many speeds :func:`speed_range` gives (a float: inf or 1e12 are counted, not made), or None
    when the step is not finite and > 0."""
    if not (math.isfinite(step) and step > 0):
        return None
    return math.floor((stop - start) / step + 1e-9) + 1.0 if stop >= start else 0.0


def speed_range(start: float, stop: float, step: float) -> tuple[float, ...]:
    """start, start + step, ... up to stop (included within 1e-9 of a step) [km/h]."""
    n = int(math.floor((stop - start) / step + 1e-9)) + 1
    return tuple(round(start + i * step, 9) for i in range(n))


def en1991_speeds(line_speed_kmh: float, step_kmh: float = 10.0, start_kmh: float | None = None,
                  where: str = "en1991_speeds") -> tuple[float, ...]:
    """EN 1991-2 (6.4.6.2): a series of speeds up to 1.2 x the maximum line speed, in steps of
    ``step_kmh`` from ``start_kmh`` (default: half the line speed, rounded to a step) [km/h]; the
    last speed is 1.2 x the line speed itself. Checked before the series is made (SettingError naming
    ``where`` and the argument, or the option with ``where="command line"``): the top speed within
    :data:`SPEED_CHECK`, the step finite and > 0, at most :data:`MAX_SPEEDS` speeds."""
    keys = _keys(where)
    top_high = SPEED_CHECK.high / EN1991_SPEED_FACTOR
    line_allowed = f"a line speed V > 0 and <= {top_high:g} km/h (so that {EN1991_SPEED_FACTOR:g} V is " \
                   f"{SPEED_CHECK.describe()} km/h)"
    if not (_is_number(line_speed_kmh) and SPEED_CHECK.ok(EN1991_SPEED_FACTOR * float(line_speed_kmh))):
        raise SettingError(where, keys["line"], line_speed_kmh, line_allowed, "out of range")
    top = EN1991_SPEED_FACTOR * line_speed_kmh
    if not (_is_number(step_kmh) and math.isfinite(step_kmh) and step_kmh > 0):
        raise SettingError(where, keys["step"], step_kmh, f"a finite step > 0 km/h (at most {MAX_SPEEDS} speeds)",
                           "out of range")
    if start_kmh is not None and not (_is_number(start_kmh) and SPEED_CHECK.ok(float(start_kmh)) and start_kmh <= top):
        raise SettingError(where, keys["start"], start_kmh, f"a speed > 0 and <= {EN1991_SPEED_FACTOR:g} x the line "
                           f"speed ({top:g} km/h)", "out of range")
    start = start_kmh if start_kmh is not None else max(step_kmh, step_kmh * round(0.5 * line_speed_kmh / step_kmh))
    if start > top:  # a step above the top speed: the top speed alone
        return check_speeds((round(top, 9),), where, keys["line"], line_speed_kmh)
    count = range_count(start, top, step_kmh) or 0.0
    if count > MAX_SPEEDS:  # (one more, 1.2 V itself, refused by check_speeds)
        raise SettingError(where, keys["step"], step_kmh, f"a step giving at most {MAX_SPEEDS} speeds from {start:g} "
                           f"to {top:g} km/h (at least {(top - start) / (MAX_SPEEDS - 1):.3g} km/h)",
                           f"{count:.4g} speeds")
    speeds = [v for v in speed_range(start, top, step_kmh)]
    if abs(speeds[-1] - top) > 1e-9:
        speeds.append(round(top, 9))
    return check_speeds(speeds, where, keys["step"], step_kmh)


def speed_label(speed_kmh: float) -> str:
    """The folder (and task) name of a speed: '220', '222.5'."""
    return f"{speed_kmh:g}"


# ------------------------------------------------------------------------------------- scenario
def key_patterns(scenario: Scenario, channels: Sequence[str] | None = None) -> tuple[tuple[str, str, str], ...]:
    """The key quantities (name, pattern, description) that match channels of the scenario's model
    (``channels``: patterns instead of :data:`KEY_QUANTITIES`, each its own quantity)."""
    names = [n for n, _ in channel_list(scenario)]
    known = {q[1]: q for q in KEY_QUANTITIES}  # a given pattern that is a key quantity keeps its name
    items = KEY_QUANTITIES if channels is None else tuple(known.get(p, (p, p, p)) for p in channels)
    keep = tuple(q for q in items if fnmatch.filter(names, q[1]))
    if not keep:
        raise SettingError("run_sweep", "channels", list(channels or [q[1] for q in items]),
                           "patterns matching channels of the model, e.g. 'bridge.*.mid.acc_z'", "no key quantity")
    return keep


def sweep_scenario(base: Scenario, speed_kmh: float, patterns: Sequence[str] | None = None,
                   n_freq: int | None = None, freq_spacing: str | None = None) -> Scenario:
    """The scenario of a sweep at ``speed_kmh`` (the module docstring): the grid over the track's
    wavelength band at that speed (``n_freq`` nodes spaced ``freq_spacing``, default the base's),
    an approach at least the base's in metres and in seconds, the channels ``patterns`` (default:
    those of :func:`key_patterns`)."""
    lead_in = max(base.track.lead_in, base.track.lead_in * speed_kmh / base.speed_kmh)
    sc = base.replace(speed_kmh=float(speed_kmh), track=base.track.replace(lead_in=lead_in))
    v, tr, an = sc.speed, sc.track, sc.analysis
    patterns = tuple(patterns) if patterns is not None else tuple(q[1] for q in key_patterns(base))
    return sc.replace(analysis=an.replace(
        freq_min=v / tr.wavelength_max, freq_max=min(v / tr.wavelength_min, 0.1 / an.time_step),
        n_freq=int(n_freq or an.n_freq), freq_spacing=freq_spacing or an.freq_spacing, channels=patterns))


def _speed_scenario(base: Scenario, speed_kmh: float, patterns: Sequence[str], n_freq: int | None,
                    freq_spacing: str | None) -> Scenario:
    """:func:`sweep_scenario` with its run length checked (:func:`check_run_length`, as the speed's PEM
    will), a speed at which either fails refused naming the speed (not the key of the derived scenario
    that failed, nor the base's file for a speed it does not hold)."""
    label = speed_label(speed_kmh)
    try:
        sc = sweep_scenario(base, speed_kmh, patterns, n_freq, freq_spacing)
    except ScenarioError as exc:
        raise SettingError("run_sweep", "speeds_kmh", speed_kmh, f"speeds at which the sweep's scenario is valid "
                           f"({exc.key} {exc.allowed})", f"at {label} km/h {exc.key} = {exc.value!r}: {exc.reason}"
                           ) from None
    try:
        check_run_length(sc)
    except ResourceError as exc:
        dt, distance = sc.analysis.time_step, sc.duration * sc.speed
        if not sc.duration / dt > MAX_STEPS:
            raise SettingError("run_sweep", "speeds_kmh", speed_kmh, "speeds whose run the scenario's analysis "
                               "allows", f"at {label} km/h: {exc}") from None
        raise SettingError("run_sweep", "speeds_kmh", speed_kmh, f"speeds whose crossing takes at most "
                           f"{MAX_STEPS:.0e} steps of analysis.time_step = {dt:g} s: here from "
                           f"{distance / (dt * MAX_STEPS) / KMH:.3g} km/h", f"at {label} km/h the crossing of "
                           f"{distance:.4g} m takes {sc.duration:.4g} s, {sc.duration / dt:.4g} steps") from None
    return sc


# ------------------------------------------------------------------------------------- resonances
@dataclass(frozen=True)
class Resonance:
    """A resonance speed v = f_n d / i: the loads spaced d apart passing a bridge mode of frequency
    f_n every i-th period."""

    direction: str
    frequency: float  # [Hz]
    distance_name: str  # "car length" or "bogie spacing"
    distance: float  # [m]
    order: int
    speed_kmh: float


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


def _setup() -> None:
    return None


def _work(_: Any, task: Task) -> dict[str, np.ndarray]:
    st: SpeedTask = task.data
    execution = Execution(workers=1, out=st.out, resume=st.resume, progress=False, slices=st.slices, where="run_sweep",
                          overwrite=st.overwrite and not st.resume, keep_checkpoint=st.keep_checkpoint)
    with warnings.catch_warnings(record=True) as caught:  # handed to the parent, which shows them once
        warnings.simplefilter("always")
        result = pem.run(st.scenario, st.engine, execution, options=st.options, keep_psd=st.keep_psd,
                         least_count=st.scenario.analysis.freq_spacing == "adaptive")
    summary = speed_summary(result)
    summary["warnings"] = np.array(list(dict.fromkeys(f"{w.message} (at {speed_label(st.scenario.speed_kmh)} km/h)"
                                                      for w in caught)), dtype=str).reshape(-1)
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
        "freq_spacing": np.array(result.scenario.analysis.freq_spacing if result.scenario is not None else ""),
        "seconds": np.array(float(result.provenance.get("seconds", math.nan))),
        "checks": np.array(json.dumps(check_columns(result))),
    }


def grid_errors(result: RandomResponse) -> np.ndarray:
    """Per channel the estimated grid error of the result (the larger of |relative error of max sigma|
    and the largest relative deviation over time: :func:`tb_exudyn.results.checks.grid_error_of`, the
    checks' own hook); NaN where it was not estimated."""
    values = (grid_error_of(result.provenance, c) for c in result.channels)
    return np.array([np.nan if v is None else v for v in values], dtype=float)


def check_columns(result: RandomResponse) -> dict[str, Any]:
    """The table columns of one speed's code checks (:meth:`RandomResponse.checks`, the default
    limits and target probability): per criterion that applies, at its deciding location
    (``ChecksTable.worst``), ``"<criterion>_utilisation"`` (the estimate over the limit),
    ``"<criterion>_probability"`` (of exceeding the limit in one passage; NaN where the criterion is
    not a random process), ``_estimate`` and ``_limit`` (SI, in ``_unit``), ``_channel``,
    ``_verdict``, ``_title`` (what the criterion checks) and ``_caveats`` (the kinds of the caveats that could change the verdict, "; "
    separated: e.g. a lightly damped mode), ``_reason`` (why a criterion was not evaluated), and
    ``"checks_exceeding"``, the number of criteria whose
    verdict is EXCEEDS. The one place that turns checks into sweep columns (rows, CSV, figure and
    report)."""
    table = result.checks()
    out: dict[str, Any] = {}
    worst = table.worst()
    for r in worst:
        ratio = r.estimate / r.limit if math.isfinite(r.limit) and r.limit != 0 else math.nan
        c = r.criterion
        out[f"{c}_utilisation"] = float(ratio)
        out[f"{c}_probability"] = math.nan if r.probability is None else float(r.probability)
        out[f"{c}_estimate"], out[f"{c}_limit"], out[f"{c}_unit"] = float(r.estimate), float(r.limit), str(r.unit)
        out[f"{c}_channel"], out[f"{c}_verdict"], out[f"{c}_title"] = str(r.channel), str(r.verdict), str(r.title)
        out[f"{c}_caveats"] = "; ".join(dict.fromkeys(k.kind for k in r.caveats if k.changes_verdict))
        out[f"{c}_reason"] = "; ".join(k.text for k in r.caveats if k.kind == "statistic") if r.verdict == "NOT EVALUATED" else ""
    out["checks_exceeding"] = float(sum(r.verdict == "EXCEEDS" for r in worst))
    return out


@dataclass(frozen=True)
class SweepResult:
    """A speed sweep: per speed the summary of its PEM (:func:`speed_summary`), the key
    quantities, the resonance speeds and the base scenario."""

    base: Scenario
    speeds: tuple[float, ...]
    summaries: tuple[dict[str, np.ndarray], ...]
    quantities: tuple[tuple[str, str, str], ...]
    resonances: tuple[Resonance, ...]
    provenance: dict[str, Any] = field(default_factory=dict)

    def rows(self) -> list[dict[str, Any]]:
        return sweep_rows(self)

    def quantity_text(self, key: str) -> str:
        """What key quantity ``key`` is, without the SI unit its description ends with (figures and
        the report show it in display units)."""
        what = next(q[2] for q in self.quantities if q[0] == key)
        return re.sub(r" *\[[^]]*\]$", "", what)

    def quantity_unit(self, key: str) -> str:
        """The SI unit of key quantity ``key``'s channels ("" when no speed has one)."""
        pattern = next(q[1] for q in self.quantities if q[0] == key)
        for s in self.summaries:
            for name, unit in zip(s["channels"], s["units"]):
                if fnmatch.fnmatchcase(str(name), pattern):
                    return str(unit)
        return ""

    def plot(self, **options: Any) -> Any:
        """The sweep's figure (:func:`tb_exudyn.plotting.plot_speed_sweep`, a matplotlib Figure)."""
        return importlib.import_module("tb_exudyn.plotting").plot_speed_sweep(self, **options)  # matplotlib on first use


def sweep_rows(result: SweepResult) -> list[dict[str, Any]]:
    """The table: one row per speed; per key quantity the largest |mean|, sigma and |mean| + 3
    sigma over its channels and time, the channel of the largest |mean| + 3 sigma and the largest
    estimated grid error of its channels (:func:`grid_errors`; NaN: not estimated); the number of
    channels whose grid error exceeds GRID_ERROR_TOLERANCE; then the check hook's columns."""
    rows = []
    for v, s in zip(result.speeds, result.summaries):
        names = list(s["channels"])
        row: dict[str, Any] = {"speed_kmh": v, "f_min_hz": float(s["band"][0]), "f_max_hz": float(s["band"][1]),
                               "n_freq": int(s["n_freq"])}
        for key, pattern, _ in result.quantities:
            idx = [i for i, n in enumerate(names) if fnmatch.fnmatchcase(n, pattern)]
            j = idx[int(np.argmax(s["max_design"][idx]))]
            row[f"{key}_max_abs_mean"] = float(s["max_abs_mean"][idx].max())
            row[f"{key}_max_sigma"] = float(s["max_sigma"][idx].max())
            row[f"{key}_max_abs_mean_plus_3sigma"] = float(s["max_design"][j])
            row[f"{key}_channel"] = names[j]
            row[f"{key}_grid_error"] = float(np.max(s["grid_error"][idx]))
        ge = np.asarray(s["grid_error"], dtype=float)
        row["channels_grid_error_over_tolerance"] = float("nan") if np.all(np.isnan(ge)) else \
            int(np.sum(ge > GRID_ERROR_TOLERANCE))
        row.update(json.loads(str(s["checks"])))
        row["seconds"] = float(s["seconds"])
        rows.append(row)
    return rows


def check_sweep(scenario: Scenario, speeds_kmh: Iterable[float], *, engine: str = "batched",
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
    """The checks of :func:`check_sweep`; (speeds, key quantities, engine class, each speed's scenario)."""
    if hasattr(speeds_kmh, "__len__") and len(speeds_kmh) > MAX_SPEEDS:  # type: ignore[arg-type]
        raise SettingError("run_sweep", "speeds_kmh", speeds_kmh, f"at most {MAX_SPEEDS} speeds",
                           f"{len(speeds_kmh)} speeds")  # type: ignore[arg-type]
    items = tuple(itertools.islice(speeds_kmh, MAX_SPEEDS + 1))  # an iterator of any length: the bound's worth
    if len(items) > MAX_SPEEDS:
        raise SettingError("run_sweep", "speeds_kmh", speeds_kmh, f"at most {MAX_SPEEDS} speeds",
                           f"more than {MAX_SPEEDS} speeds")
    speeds = check_speeds(items, "run_sweep", "speeds_kmh")
    if freq_spacing is not None and freq_spacing not in FREQ_SPACINGS:
        raise SettingError("run_sweep", "freq_spacing", freq_spacing, " or ".join(map(repr, FREQ_SPACINGS)))
    quantities = key_patterns(scenario, channels)
    cls = check_engine(engine, scenario, options)
    patterns = tuple(dict.fromkeys(q[1] for q in quantities))
    scenarios = [_speed_scenario(scenario, v, patterns, n_freq, freq_spacing) for v in speeds]
    for sc in scenarios:  # every speed's grid and spectra checked before any run
        prepare_sweep(sc)
    return speeds, quantities, cls, scenarios


def run_sweep(scenario: Scenario, speeds_kmh: Sequence[float], *, engine: str = "batched", workers: int | None = None,
              executor: Any = None, out: str | Path | None = None, resume: bool = False, progress: bool = True,
              channels: Sequence[str] | None = None, n_freq: int | None = None, options: Any = None,
              keep_psd: bool = False, slices: Sequence[float] | None = None, overwrite: bool = False,
              keep_checkpoint: bool = False, freq_spacing: str | None = None) -> SweepResult:
    """PEM of ``scenario`` at each of ``speeds_kmh`` (see the module docstring).

    Parameters
    ----------
    scenario : the base scenario (its speed only sets the approach's duration kept at other speeds)
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
    slices : the column slices of every speed's PEM (default: a separate run's on this machine)
    overwrite : replace an earlier sweep's table, checkpoint and speeds in ``out`` (without it or
        ``resume`` a folder holding them is refused)
    keep_checkpoint : keep ``out/checkpoint-sweep`` (and each speed's checkpoint) after the results are
        written (default: removed)
    """
    t0 = _time.perf_counter()
    default_limits()  # the limit files of check_columns, read and checked before any speed runs
    speeds, quantities, cls, scenarios = _plan(scenario, speeds_kmh, engine, channels, n_freq, options, freq_spacing)
    execution = Execution(workers=workers, executor=executor, out=out, resume=resume, progress=progress,
                          where="run_sweep", overwrite=overwrite, keep_checkpoint=keep_checkpoint)
    root = execution.output_folder()
    cuts = tuple(slices) if slices is not None else tuple(default_slices(execution.cores))
    tasks = [Task(f"speed-{speed_label(v)}", SpeedTask(sc, engine, options, None if root is None else
                                                        str(root / speed_label(v)), resume, cuts, keep_psd, overwrite,
                                                        keep_checkpoint))
             for v, sc in zip(speeds, scenarios)]
    identity = fingerprint_identity(
        scenario_to_toml(scenario), method="pem_sweep", engine=engine, engine_options=cls.describe_options(options),
        method_options={"keep_psd": keep_psd, "channels": [q[1] for q in quantities], "n_freq": n_freq,
                        "freq_spacing": freq_spacing,
                        "slices": list(cuts), "speeds_kmh": list(speeds)}, spectra=scenario.track.irregularities)
    summaries: list[dict[str, np.ndarray]] = [{} for _ in tasks]

    def reduce(i: int, task: Task, result: dict[str, np.ndarray]) -> None:
        summaries[i] = result
        for message in result.get("warnings", ()):
            warnings.warn(str(message), stacklevel=4)

    with execution.claim(RunFiles(SWEEP_TABLE, "checkpoint-sweep", drawn=(SWEEP_FIGURE, SWEEP_PAGE))) as root:
        checkpoint = execution.checkpoint("checkpoint-sweep", identity)
        stats = execution.run(tasks, setup=_setup, setup_args=(), work=_work, reduce=reduce, checkpoint=checkpoint,
                              desc=f"speed sweep ({engine})")
        result = SweepResult(base=scenario, speeds=speeds, summaries=tuple(summaries), quantities=quantities,
                             resonances=tuple(resonance_speeds(scenario)),
                             provenance={"seconds": _time.perf_counter() - t0, "engine": engine, **stats})
        if root is not None:
            write_sweep(result, root)
    return result


def write_sweep(result: SweepResult, folder: str | Path) -> Path:
    """The table as ``folder/speed_sweep.csv`` (the figure: :func:`tb_exudyn.plotting.plot_speed_sweep`)."""
    return write_table_csv(result.rows(), Path(folder) / SWEEP_TABLE)


__all__ = ["EN1991_SPEED_FACTOR", "FREQ_SPACINGS", "KEY_QUANTITIES", "MAX_SPEEDS", "SPEED_CHECK", "SWEEP_TABLE",
           "Resonance", "SpeedTask", "SweepResult", "check_columns", "check_speeds", "check_sweep", "en1991_speeds",
           "grid_errors", "key_patterns", "parse_speeds", "range_count", "resonance_speeds", "run_sweep",
           "speed_label", "speed_range", "speed_summary", "sweep_rows", "sweep_scenario", "train_distances",
           "write_sweep"]
