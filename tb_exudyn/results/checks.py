"""Code checks of a result: per criterion of the limit files and location, the estimate, the limit, the
probability of exceeding it in one passage, the verdict and the caveats that apply.

:func:`checks` (also ``RandomResponse.checks``) returns a :class:`ChecksTable` of frozen
:class:`CheckRow` s, with a text form (:meth:`ChecksTable.text`), plain data for the report
(:meth:`ChecksTable.as_dicts`) and one line per criterion for a terminal (:func:`verdict_lines`).

What is compared, per statistic of the criterion (tb_exudyn.scenario.limits.STATISTICS):

- ``max_abs``, ``max``, ``min`` (a random process): the probability P that the channel leaves the
  allowed range at least once in the result's time window (the passage): PEM by Rice's rate and
  Poisson's first passage (``method``; Vanmarcke's is given alongside), Monte Carlo as the fraction of
  samples with its Clopper-Pearson interval. Verdict OK when P <= the target probability per passage
  (Monte Carlo: the interval's upper end), EXCEEDS when above (Monte Carlo: the lower end), else
  UNDETERMINED. The estimate is the level exceeded with the target probability (PEM: the inverse of
  the first passage; Monte Carlo: the empirical quantile of the per-sample extremes).
- ``window_max`` (Sperling): the index's largest window value against the limit (no probability: a
  windowed index is not a Gaussian process). PEM: the index of the expected energy of each window
  (tb_exudyn.system.comfort: about 0.5 % above the mean of per-window indices); Monte Carlo: the
  largest window value of the sample mean, and the fraction of samples whose largest window exceeds.
- ``sliding_mean_max_abs`` (EN 14363's 2 m sliding mean) and ``rms_window``: NOT EVALUATED (no such
  channel yet).

The target probability (``probability``) is a choice, not a code value: the clauses state limits on
peaks without a probability. The default is the per-passage target used in the literature for 100
train pairs a day over a one-year return period, 2.74e-5 (a target used in the literature [abstract]; docs/references.md, code limits).

What a model can answer (:data:`MODEL_REQUIREMENTS`): a criterion on a quantity the result's vehicle
model cannot give (running safety on a car whose wheelsets follow the rail) is NOT EVALUATED, with
the reason and what to run instead as its first caveat.

Caveats (:class:`Caveat`; ``changes_verdict`` marks those that could turn the verdict, and a row with
one says "conditional"; a caveat whose effect on the estimate is a number is a condition only where
that number reaches the limit, :func:`can_turn`, docs/verdicts.md): a lightly damped mode whose channel patterns match the location (the
damping guard, ``provenance["damping_warnings"]``); a grid error above 1 % on the channel
(:func:`grid_error_of`, reading ``provenance["grid_error"]``); Monte Carlo samples that lost wheel-rail
contact, or a PEM probability of a wheel load below 0 above the target; a quantity the linear model
cannot represent (Q/P with the whole axle force on one wheel: an upper bound; a ratio to first order
when its denominator varies by more than 10 %); Poisson and Vanmarcke disagreeing on the verdict;
a Sperling window shorter than the criterion's; a limit value not read in its code text ([check]).

The limit files in use and a criterion's limit at a channel: :mod:`tb_exudyn.results.limit_values`.
"""

from __future__ import annotations

import fnmatch
import math
import re
import weakref
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import SettingError
from ..scenario.limits import Criterion, GradedLimit, quantity
from ..system import statistics as st
from ..system.labels import channel_label
from .caveats import (_CAR_ANY, MODEL_REQUIREMENTS, ModelRequirement, can_turn, contact_judged, effect_on_estimate, judged,
                      unmet_requirement, window_effect)
from .checks_table import VERDICTS, Caveat, CheckRow, ChecksTable, format_probability, format_value, wrapped_line
from .empirical import binomial_interval
from .kinds import DETERMINISTIC, ResultKind
from .limit_values import default_limits, limit_at, limit_sets, static_axle_load

#: the literature's per-passage target (docs/references.md, code limits [abstract]): 100 train pairs a day, 1-year return period
DEFAULT_TARGET_PROBABILITY = 2.74e-5
#: grid errors of max sigma above this make a caveat (the grid-error estimate's tolerance)
GRID_ERROR_TOLERANCE = 0.01
#: a ratio's denominator varying by more than this (sigma / mean) makes the first order a caveat
RATIO_CV_TOLERANCE = 0.1


# ============================================================================================ hooks
def grid_error_of(provenance: dict[str, Any], channel: str) -> float | None:
    """The hook for the frequency grid's error: the relative error of the channel's sigma from
    ``provenance["grid_error"]`` when present (the grid-error estimate's form: {"channels": {name:
    {"rel_error_max_sigma": e, "rel_deviation": d, ...}}}, the larger of |e| and d; or a plain
    {name: error}), else None."""
    ge = provenance.get("grid_error")
    if not isinstance(ge, dict):
        return None
    table = ge.get("channels", ge)
    entry = table.get(channel) if isinstance(table, dict) else None
    if isinstance(entry, (int, float)):
        return abs(float(entry))
    if isinstance(entry, dict):
        vals = [abs(float(entry[k])) for k in ("rel_error_max_sigma", "rel_deviation") if k in entry]
        return max(vals) if vals else None
    return None


def damping_caveats(provenance: dict[str, Any], channel: str) -> list[Caveat]:
    """The damping guard's warnings (``provenance["damping_warnings"]``: dicts with 'channels' patterns,
    'frequency', 'label', 'damping_ratio', 'decay_time', 'growth_on_bridge') whose patterns match the channel."""
    return [c for c, _ in _damping_effects(provenance, channel)]


def _damping_effects(provenance: dict[str, Any], channel: str) -> list[tuple[Caveat, float | None]]:
    """:func:`damping_caveats` with each mode's growth on the bridge: how much the channel's sigma
    could still change with the run's length (the envelope's growth, a relative change)."""
    out = []
    seen = set()
    for w in provenance.get("damping_warnings", []) or []:
        pats = w.get("channels", ()) if isinstance(w, dict) else ()
        if not any(fnmatch.fnmatchcase(channel, p) for p in pats):
            continue
        key = (f"{w.get('frequency', math.nan):.4g}", f"{w.get('damping_ratio', math.nan):.3g}")
        if key in seen:
            continue
        seen.add(key)
        tau = w.get("decay_time", math.inf)
        tau_text = "infinite" if not (isinstance(tau, (int, float)) and math.isfinite(tau)) else f"{tau:.3g} s"
        growth = w.get("growth_on_bridge", math.nan)
        growth = float(growth) if isinstance(growth, (int, float)) else math.nan
        out.append((Caveat("lightly_damped_mode",
                           f"lightly damped mode at {w.get('frequency', math.nan):.4g} Hz ({w.get('label', '')}), damping "
                           f"ratio {w.get('damping_ratio', math.nan):.2g}, decay time {tau_text}: its sigma grows through "
                           f"the run (about {100 * growth:.0f} % on the bridge) and depends on the run's length and the "
                           "frequency grid", True), growth if math.isfinite(growth) else None))
    return out


# ============================================================================================ the checks
def _bounds(statistic: str, limit: float) -> tuple[float | None, float | None, str]:
    if statistic == "max_abs":
        return -limit, limit, "symmetric"
    if statistic == "max":
        return None, limit, "upper"
    return limit, None, "lower"


def _loss_of_contact(result: Any, target: float, method: str) -> dict[int | None, tuple[Caveat, float | None]]:
    """Loss-of-contact caveats by car (key: the car's number; None: every row), each with the
    probability of the loss (None: not a probability). Monte Carlo: samples that lost contact are
    not physical, whatever the channel (key None). PEM: per car, the largest probability per passage
    that one of its wheel loads falls below 0, a caveat of that car's rows where it is above the
    target probability (the linear contact cannot lose contact). On a car whose wheel loads cannot
    answer running safety (:func:`unmet_requirement`) it is a note, not a condition: the loads come
    from the model that cannot answer."""
    prov = result.provenance
    if not result.kind.gaussian:
        lost = int(prov.get("samples_with_loss_of_contact", 0) or 0)
        if lost:
            return {None: (Caveat("loss_of_contact", f"{lost} of {result.n_samples} samples lost wheel-rail contact "
                                  f"(minimum wheel force {prov.get('min_wheel_force_N', math.nan):.4g} N): the linear "
                                  "contact pulls the wheel back, so these samples are not physical", True), None)}
        return {}
    worst: dict[int, tuple[float, str]] = {}
    for name in result.channels:
        m = _CAR_ANY.match(name)
        if m and name.endswith(".force_z") and ".axle" in name:
            try:
                p = result.exceedance_probability(name, lower=0.0, method=method).probability
            except Exception:  # noqa: BLE001 - a channel without statistics gives no caveat
                continue
            car = int(m.group(1))
            if p > worst.get(car, (0.0, ""))[0]:
                worst[car] = (p, name)
    out: dict[int | None, tuple[Caveat, float | None]] = {}
    for car, (p, where) in worst.items():
        if p <= target:
            continue
        text = (f"a wheel load of car {car} falls below 0 (loss of contact) with probability {p:.2g} per passage "
                f"({where}), above the target {target:.3g}: the linear contact model cannot lose contact")
        unmet = unmet_requirement(result, "wheel_unloading", where)
        if unmet is not None:
            out[car] = (Caveat("loss_of_contact", text + "; a note, not a condition: these wheel loads cannot answer "
                               "it (" + unmet.split(":")[0] + ")", False), None)
        else:
            out[car] = (Caveat("loss_of_contact", text + ", so this car's results past it are not physical", True), p)
    return out


def _ratio_caveat(result: Any, channel: str) -> tuple[Caveat, float] | None:
    """First-order caveat of a ratio: the denominator's sigma / mean, when its channels are in the
    result, with its effect: the second order's largest relative rise of the ratio's sigma."""
    m = re.match(r"(car\d+\.axle\d+)\.(left|right)?\.?(derailment|unloading)\Z", channel)
    if m is None:
        return None
    base, side, kind = m.group(1), m.group(2), m.group(3)
    parts = [f"{base}.{side}.force_z"] if kind == "derailment" else [f"{base}.left.force_z", f"{base}.right.force_z"]
    if not all(p in result.channels for p in parts):
        return None
    mean = sum(result.mean[result.index(p)] for p in parts)
    sigma = np.sqrt(sum(result.std[result.index(p)] ** 2 for p in parts)) if kind == "derailment" else None
    if sigma is None:  # the sum's sigma needs the covariance: bound it by the sum of sigmas
        sigma = sum(result.std[result.index(p)] for p in parts)
    with np.errstate(divide="ignore", invalid="ignore"):
        cv = float(np.nanmax(np.where(np.abs(mean) > 0, sigma / np.abs(mean), np.inf)))
    if cv <= RATIO_CV_TOLERANCE:
        return None
    return Caveat("linear_model", f"the ratio is taken to first order about the means, but its denominator varies by "
                  f"sigma / mean = {cv:.2g}: the second order raises the ratio's sigma by 1.5 cv^2 (1 + 2 rho^2), up to "
                  f"{4.5 * cv ** 2:.1%} (rho: correlation of numerator and denominator), more in the tails", True), \
        4.5 * cv ** 2


def _not_answerable(base: dict[str, Any], caveats: list[Caveat], reason: str) -> CheckRow:
    """A row the model cannot answer: NOT EVALUATED, the reason first among its caveats."""
    return CheckRow(**base, estimate=math.nan, estimate_text="", probability=None, interval=None,
                    probability_vanmarcke=None, verdict="NOT EVALUATED",
                    caveats=(Caveat("model", reason, False),) + tuple(caveats))


def _rows_for(c: Criterion, set_name: str, result: Any, channel: str, target: float, method: str,
              confidence: float, contact_caveats: dict[int | None, Caveat]) -> CheckRow:
    i = result.index(channel)
    unit = result.units[i]
    limit, limit_text = limit_at(c, result, channel)
    with np.errstate(invalid="ignore"):
        peak3 = float(np.nanmax(np.abs(result.mean[i]) + 3.0 * result.std[i], initial=-np.inf))
    # (caveat, its relative effect on the estimate or None): judged against the margin at the end
    effects: list[tuple[Caveat, float | None]] = list(_damping_effects(result.provenance, channel))
    ge = grid_error_of(result.provenance, channel)
    if ge is not None and ge > GRID_ERROR_TOLERANCE:
        effects.append((Caveat("grid_error", f"the frequency grid changes this channel's sigma by {100 * ge:.2g} % "
                               f"(> {100 * GRID_ERROR_TOLERANCE:g} %)", True), ge))
    m = _CAR_ANY.match(channel)
    contact = [contact_caveats[k] for k in dict.fromkeys((None, int(m.group(1)) if m else None)) if k in contact_caveats]
    for cav, _ in contact:
        effects.append((cav, None))
    if c.check:
        effects.append((Caveat(*c.unverified_caveat(), False), None))
    elif c.note:  # what the limits file says of how the criterion applies here (e.g. the total twist on straight track)
        effects.append((Caveat("limit_note", c.note, False), None))
    caveats = [e for e, _ in effects]
    base = dict(criterion=f"{set_name}/{c.id}", title=c.title, clause=c.clause, channel=channel, unit=unit,
                statistic=c.statistic, limit=limit, limit_text=limit_text, peak_3sigma=peak3, target=target)
    reason = unmet_requirement(result, c.quantity, channel)
    if reason is not None:
        return _not_answerable(base, [e for e in caveats if e.kind == "limit_unverified"], reason)
    if c.statistic in ("sliding_mean_max_abs", "rms_window"):
        return CheckRow(**base, estimate=math.nan, estimate_text="", probability=None, interval=None,
                        probability_vanmarcke=None, verdict="NOT EVALUATED",
                        caveats=tuple(caveats) + (Caveat("statistic", f"statistic {c.statistic!r} is not evaluated: "
                                                         "no such channel (EN 14363's sliding mean of the low-passed force "
                                                         "is not formed yet)", False),))
    if not math.isfinite(limit):
        return CheckRow(**base, estimate=math.nan, estimate_text="", probability=None, interval=None,
                        probability_vanmarcke=None, verdict="NOT EVALUATED",
                        caveats=tuple(caveats) + (Caveat("statistic", f"no limit value: {limit_text}", False),))
    grade = ""
    if c.statistic == "window_max":
        with np.errstate(invalid="ignore"):
            estimate = float(np.nanmax(result.mean[i], initial=-np.inf))
        text = ("largest window value of the index of the expected energy" if result.kind.gaussian
                else "largest window value of the samples' mean index")
        prob = interval = None
        if not result.kind.gaussian and result.sample_max is not None:
            prob, interval = _index_exceedance(result, i, limit, confidence)
        verdict = "OK" if estimate <= limit else "EXCEEDS"
        win = _channel_window(result, channel)
        if win is not None and c.window and win + 1e-9 < c.window:
            cav = Caveat("window", f"the index is over windows of {win:.3g} s (the run is shorter than the "
                         f"criterion's {c.window:g} s): the index depends on the window length", True)
            caveats.append(judged(*window_effect(cav, result, channel), estimate, limit))
        if isinstance(c.limit, GradedLimit):
            grade = c.limit.grade(estimate) or "beyond the last grade"
        kept = [judged(e, effect_on_estimate(c.quantity, eff), estimate, limit) for e, eff in effects] \
            + caveats[len(effects):]
        return CheckRow(**base, estimate=estimate, estimate_text=text, probability=prob, interval=interval,
                        probability_vanmarcke=None, verdict=verdict, grade=grade, caveats=tuple(kept))
    lower, upper, kind = _bounds(c.statistic, limit)
    pv = None
    if result.kind.gaussian:
        ex = result.exceedance_probability(channel, upper=upper, lower=lower, method=method)
        p = ex.probability
        other = "vanmarcke" if method == "poisson" else "poisson"
        pv = result.exceedance_probability(channel, upper=upper, lower=lower, method=other).probability
        level = result.exceedance_level(channel, target, kind=kind, method=method)
        estimate, text = level.level, f"level exceeded with probability {target:.3g} per passage ({method})"
        verdict = "OK" if p <= target else "EXCEEDS"
        verdict_other = "OK" if pv <= target else "EXCEEDS"
        if verdict_other != verdict:
            caveats.append(Caveat("first_passage", f"{other.capitalize()}'s first passage gives P = {pv:.3g}: the "
                                  f"verdict would be {verdict_other} (Poisson errs high for narrow-band responses)", True))
        interval = None
        losses = {id(cav): pl for cav, pl in contact}
        caveats = [contact_judged(cv, losses.get(id(cv)), verdict, p, target) for cv in caveats]
        effects = [(cv, eff) for cv, (_, eff) in zip(caveats, effects)]
    else:
        ex = result.exceedance_probability(channel, upper=upper, lower=lower, confidence=confidence)
        p, interval = ex.probability, ex.interval
        level = result.exceedance_level(channel, target, kind=kind, confidence=confidence)
        estimate = level.level
        text = f"empirical level exceeded with probability {target:.3g} ({ex.n_samples} samples)"
        if ex.n_samples * target < 10:
            text += f"; not resolved by {ex.n_samples} samples (fewer than 10 expected beyond it)"
        assert interval is not None
        verdict = "OK" if interval[1] <= target else ("EXCEEDS" if interval[0] > target else "UNDETERMINED")
    if c.quantity == "derailment_coefficient":
        caveats.append(Caveat("linear_model", "the model has one lateral wheel-rail force per wheelset: the whole axle "
                              "force H is put on this wheel, an upper bound of its Q/P", verdict != "OK"))
    kept = [judged(e, eff, estimate, limit) for e, eff in effects] + caveats[len(effects):]
    rc = _ratio_caveat(result, channel) if quantity(c.quantity).derived and c.quantity in (
        "derailment_coefficient", "wheel_unloading") else None
    if rc is not None:
        kept.append(judged(rc[0], rc[1], estimate, limit, raises_only=True))  # the second order only raises it
    if isinstance(c.limit, GradedLimit):
        grade = c.limit.grade(abs(estimate)) or "beyond the last grade"
    return CheckRow(**base, estimate=estimate, estimate_text=text, probability=p, interval=interval,
                    probability_vanmarcke=pv, verdict=verdict, grade=grade, caveats=tuple(kept))


def _channel_window(result: Any, channel: str) -> float | None:
    info = result.provenance.get("derived_channels", {})
    if isinstance(info, dict):
        entry = info.get("channels", {}).get(channel)
        if isinstance(entry, dict) and "window" in entry:
            return float(entry["window"])
    return None


def _index_exceedance(result: Any, i: int, limit: float, confidence: float
                      ) -> tuple[float, tuple[float, float]]:
    """Monte Carlo: the fraction of samples whose largest window value exceeds the limit, with its interval."""
    hi = result.sample_max[:, i]
    hi = hi[np.isfinite(hi)]
    k, n = int((hi > limit).sum()), int(hi.size)
    return k / n, binomial_interval(k, n, confidence)


@dataclass(frozen=True, eq=False)
class _RunView:
    """A TimeHistory seen as a result without randomness (sigma 0): one deterministic run."""

    channels: tuple[str, ...]
    units: tuple[str, ...]
    mean: np.ndarray
    std: np.ndarray
    time: np.ndarray
    scenario: Any
    provenance: dict[str, Any]
    kind: ResultKind = DETERMINISTIC
    n_samples: int = 0
    sample_max: Any = None

    def index(self, channel: str) -> int:
        return self.channels.index(channel)


def _run_view(th: Any) -> _RunView:
    names = tuple(th.names)
    values = np.array([th[n] for n in names], dtype=float).reshape(len(names), -1)
    return _RunView(names, tuple(th.unit(n) for n in names), values, np.zeros_like(values), np.asarray(th.time),
                    th.scenario, dict(th.provenance))


def _run_row(c: Criterion, set_name: str, result: _RunView, channel: str, target: float) -> CheckRow:
    """A criterion on one deterministic run: the statistic of the values against the limit."""
    i = result.index(channel)
    limit, limit_text = limit_at(c, result, channel)
    v = result.mean[i]
    with np.errstate(invalid="ignore"):
        stat = {"max_abs": np.nanmax(np.abs(v), initial=-np.inf), "max": np.nanmax(v, initial=-np.inf),
                "min": np.nanmin(v, initial=np.inf), "window_max": np.nanmax(v, initial=-np.inf)}.get(c.statistic)
    caveats = [Caveat("statistic", "one deterministic run: a single sample of the response (no probability)", False)]
    if c.check:
        caveats.append(Caveat(*c.unverified_caveat(), False))
    reason = unmet_requirement(result, c.quantity, channel)
    if reason is not None:
        caveats.insert(0, Caveat("model", reason, False))
    if stat is None or not math.isfinite(limit) or reason is not None:
        verdict, estimate = "NOT EVALUATED", math.nan
    else:
        estimate = float(stat)
        verdict = "OK" if (estimate >= limit if c.statistic == "min" else estimate <= limit) else "EXCEEDS"
    grade = (c.limit.grade(abs(estimate)) or "beyond the last grade") if isinstance(c.limit, GradedLimit) and \
        math.isfinite(estimate) else ""
    return CheckRow(criterion=f"{set_name}/{c.id}", title=c.title, clause=c.clause, channel=channel, unit=result.units[i],
                    statistic=c.statistic, limit=limit, limit_text=limit_text, estimate=estimate,
                    estimate_text=f"{c.statistic} of the run", peak_3sigma=float(np.nanmax(np.abs(v), initial=-np.inf)),
                    probability=None, interval=None, probability_vanmarcke=None, target=target, verdict=verdict,
                    grade=grade, caveats=tuple(caveats))


def checks(result: Any, limits: Any = None, *, probability: float = DEFAULT_TARGET_PROBABILITY,
           method: str = "poisson", confidence: float = 0.99) -> ChecksTable:
    """The checks of a RandomResponse (or of one deterministic run, a TimeHistory: its statistic of
    the values against the limit, no probability) against code limits (module docstring).

    limits : None (every file in models/limits), a limit file's name or path, a LimitSet, or a list of them
    probability : the target probability of exceeding a limit in one passage (default: the literature's
        2.74e-5, not a code value)
    method : PEM first passage, 'poisson' (default: errs on the safe side) or 'vanmarcke'
    confidence : Monte Carlo intervals' level
    """
    if not (isinstance(probability, (int, float)) and 0.0 < probability < 1.0):
        raise SettingError("checks", "probability", probability, "a target probability per passage in (0, 1)")
    if method not in st.METHODS:
        raise SettingError("checks", "method", method, " | ".join(st.METHODS))
    sets = limit_sets(limits)
    run = None if result.kind.random else _run_view(result)
    contact_caveats = {} if run is not None else _loss_of_contact(result, probability, method)
    rows: list[CheckRow] = []
    notes = [f"target probability per passage {probability:.3g}"
             + (" (the default: 1 / (365 x 100), one exceedance in a year at 100 passages a day, a target used in the "
                "literature, docs/references.md [abstract]; not a code value: the clauses give no probability)"
                if probability == DEFAULT_TARGET_PROBABILITY
                else " (chosen by the caller)")]
    if result.kind.gaussian:
        notes.append("PEM probabilities from Rice's non-stationary rate (derivative statistics: recorded velocities for "
                     "displacements, pseudo-derivatives otherwise; provenance['derivatives'])")
    view = run if run is not None else result
    for ls in sets:
        for c in ls.criteria:
            names = [n for n in view.channels if quantity(c.quantity).matches(n)]
            if not names:
                notes.append(f"{ls.name}/{c.id}: no channel of quantity {c.quantity!r} in this result "
                             f"(patterns {', '.join(quantity(c.quantity).channels)})")
                continue
            for name in names:
                rows.append(_run_row(c, ls.name, run, name, probability) if run is not None else
                            _rows_for(c, ls.name, result, name, probability, method, confidence, contact_caveats))
    sc = result.scenario
    return ChecksTable(
        kind=result.kind, scenario=getattr(sc, "name", "?"), speed_kmh=float(getattr(sc, "speed_kmh", math.nan)),
        target=float(probability), first_passage=method, window=(float(result.time[0]), float(result.time[-1])),
        rows=tuple(rows), notes=tuple(notes),
    )


#: the order of the limit sets on a terminal: the bridge's first (deck acceleration, twist), then
#: the vehicle's (ride comfort, running safety); others after them
SET_ORDER = ("en1990_deck", "ride_comfort", "running_safety")


#: the checks tables computed, per result (by identity: results are frozen and compared by identity) and per
#: (limit sets, target probability, first-passage method, confidence): :func:`cached_checks`
_TABLES: "weakref.WeakKeyDictionary[Any, dict[tuple[Any, ...], ChecksTable]]" = weakref.WeakKeyDictionary()


def cached_checks(result: Any, limits: Any = None, *, probability: float = DEFAULT_TARGET_PROBABILITY,
                  method: str = "poisson", confidence: float = 0.99) -> ChecksTable:
    """:func:`checks` of ``result``, computed once per result and per limits, target probability,
    first-passage method and confidence, then kept as long as the result lives (``result.checks()``):
    the terminal, the report and the sweep's table read the same table. The limits are resolved first
    (a file named twice is read twice, compared by its values), so ``None`` and
    :func:`default_limits` are one key. A result is frozen; its arrays, when changed in place after a
    check, are not seen (change a copy: ``dataclasses.replace``)."""
    sets = limit_sets(limits)
    key = (repr(sets), probability, method, confidence)
    tables = _TABLES.setdefault(result, {})
    if key not in tables:
        tables[key] = checks(result, sets, probability=probability, method=method, confidence=confidence)
    return tables[key]


def verdict_lines(result: Any, limits: Any = None, **options: Any) -> list[str]:
    """Lines for a terminal summary (the CLI), wrapped at 100 characters: the counts by criterion, then per limit set
    (the bridge's first) a line per criterion with its deciding location, estimate, limit and probability (those
    not evaluated on one line), and once per set why its rows are not evaluated or conditional."""
    table = cached_checks(result, limits, **options)
    n_cond = sum(r.conditional for r in table.rows)
    worst = table.worst()  # one row per criterion: the location that decides it; counted by criterion first
    said = lambda rows: ", ".join(f"{n} {v}" for v in VERDICTS if (n := sum(r.verdict == v for r in rows)))  # noqa: E731
    lines = [f"code checks ({table.method}, target P <= {table.target:.3g}): {len(worst)} criteria: "
             f"{said(worst)} (at {len(table.rows)} locations{f'; {n_cond} conditional' if n_cond else ''})"]
    if table.kind.random:  # what the numbers are (the report's "Estimate" sentence)
        lines.append(f" values: the level exceeded with P {table.target:.3g} per passage, where most likely to exceed")
    pad = max((len(r.verdict_text) for r in worst if r.verdict != "NOT EVALUATED"), default=2)  # the verdicts' column
    sets = sorted(dict.fromkeys(r.criterion.split("/")[0] for r in worst),
                  key=lambda n: (SET_ORDER.index(n) if n in SET_ORDER else len(SET_ORDER), n))
    for name in sets:
        lines.append(f" {name}:")
        notes: list[str] = []
        for r in (r for r in worst if r.criterion.split("/")[0] == name):
            shown = "" if r.probability is None else format_probability(r)
            p = "" if not shown else f", P {shown}" if shown.startswith("<") else f", P = {shown}"
            est = format_value(r.estimate, r.unit, with_unit=False)
            where = channel_label(r.channel).rsplit(", ", 1)[0]  # the place in words (the criterion names the quantity)
            value = "" if r.verdict == "NOT EVALUATED" else f": {est} vs {format_value(r.limit, r.unit)}{p}"
            short = r.criterion.split("/", 1)[1]
            if r.verdict == "NOT EVALUATED" and lines[-1].startswith("  NOT EVALUATED  "):  # one line for them all
                lines[-1] += f", {short}"
            elif r.verdict == "NOT EVALUATED":
                lines.append(f"  NOT EVALUATED  {short}")
            else:
                lines.append(f"  {r.verdict_text:<{pad}} {short} at {where}{value}")
            for c in r.caveats:
                if c.kind == "model":
                    text = c.text
                elif r.verdict == "NOT EVALUATED" and c.kind == "statistic":
                    text = f"{short} not evaluated, {c.text.split(':')[0].replace('is not evaluated', 'not formed')}"
                elif c.changes_verdict and r.verdict != "NOT EVALUATED":  # conditional: by how much, if it says
                    how = c.text.rsplit("; it moves ", 1)
                    text = f"{short} conditional, {c.kind.replace('_', ' ')}" + (
                        f": it moves {how[1].replace(' between the estimate and the limit', ' to the limit')}"
                        if len(how) == 2 else "")
                else:
                    continue
                if text not in notes:
                    notes.append(text)
        for text in notes:  # a model's reason and what to run instead on two lines
            first, _, then = text.partition(": ")
            lines.append(f"    note: {first}" + ("" if not then else f"\n          {then}"))
    return [w for line in lines for ln in line.split("\n") for w in wrapped_line(ln, 100)]



__all__ = ["Caveat", "CheckRow", "ChecksTable", "DEFAULT_TARGET_PROBABILITY", "GRID_ERROR_TOLERANCE", "MODEL_REQUIREMENTS",
           "ModelRequirement", "VERDICTS", "can_turn", "cached_checks", "checks", "damping_caveats", "default_limits", "grid_error_of",
           "SET_ORDER", "static_axle_load", "unmet_requirement", "verdict_lines"]
