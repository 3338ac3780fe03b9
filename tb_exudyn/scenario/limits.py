"""Code limits as data: models/limits/*.toml, their validated dataclasses and the quantity vocabulary.
The kinds of a limit (fixed, speed bands, grades, static load, span ratio, comfort figure): :mod:`.limit_kinds`.

A limit file holds criteria; each names its clause and source, the quantity it applies to (a name of
:data:`QUANTITIES`), how the quantity is reduced to the number compared with the limit (a name of
:data:`STATISTICS`, with a window, an averaging length or a frequency band where that statistic or
the code needs one), and the limit itself: a fixed value, speed bands, graded levels or a formula in
the static wheel or axle load. ``check = true`` (with a note saying what) marks a criterion whose
clause text was not read. No limit lives in Python code.

A file is refused as a whole (a ScenarioError naming the file, the key and what is allowed) unless every
criterion can give a verdict: each key of the schema present and of its type, a quantity of
:data:`QUANTITIES` and a statistic of :data:`STATISTICS` that fits it (``window_max`` for the windowed
indices of :data:`INDEX_QUANTITIES` and only for them), a window or averaging length only where the
statistic uses one, limit values finite (NaN is never evaluated, inf always passes) and > 0 for every
statistic but ``min`` (a lower bound, which may be 0 or negative), ids unique, at least one criterion,
and ``name`` an identifier. The file itself is read as scenarios are (:func:`.toml_io.read_toml`: a
regular UTF-8 file of bounded size; a FIFO, device, directory or binary file is refused).

    [[criteria]]
    id = "deck_twist_3m"
    title = "deck twist over 3 m, straight track"
    clause = "EN 1990:2002+A1:2005 Annex A2, A2.4.4.2.2"
    source = "..."
    quantity = "deck_twist_3m"
    statistic = "max_abs"

    [criteria.limit]
    kind = "speed_bands"
    speed_max_kmh = [120.0, 200.0, inf]
    values = [4.5e-3, 3.0e-3, 1.5e-3]

Quantities and their channels
-----------------------------
Channel names follow tb_exudyn/system/channels.py. Plain quantities are channels the engines already
produce; derived ones (``derived = True``) are formed on the complex pseudo-responses (PEM) and on
every Monte Carlo sample alike, so that PEM statistics are exact for them: defined in
tb_exudyn.system.derived (which also has twist stations ``span<k>.start`` / ``.end`` 1.5 m inside the
span ends, and takes the EN 1990 range as the bridge modes up to f_cut), reduced in
tb_exudyn.methods.reduction, checked against these files by tb_exudyn.results.checks. The names:

=====================================  ======  ===========================================================
channel (proposed)                     unit    definition
=====================================  ======  ===========================================================
bridge.<station>.acc_z_en1990          m/s^2   deck vertical acceleration keeping only the bridge modes
                                               up to max(30 Hz, 1.5 f1, f3) (f1, f3: first and third
                                               vertical deck frequencies; EN 1990 A2.4.4.2.1 "including
                                               ... associated mode shapes"): the modes above are left
                                               out, the kept modes' forced response at any excitation
                                               frequency stays
bridge.<station>.twist_3m              m       twist at the station x: [z_L - z_R](x + 1.5 m) -
                                               [z_L - z_R](x - 1.5 m), z_L, z_R the vertical displacement
                                               of the left and right rail on the deck (the deck's z and
                                               rx at x, the rail offsets of the track); stations near
                                               the deck ends are where twist peaks
car<k>.axle<j>.unloading               -       wheel unloading (P_R - P_L) / (P_R + P_L) (first order
                                               about the mean; positive: left wheel lighter); |value|
                                               is dP/P_bar with dP = |P_R - P_L|/2, P_bar = (P_R + P_L)/2
car<k>.axle<j>.left.derailment         -       Q/P of the left wheel taken as -H / P_L and of the right
car<k>.axle<j>.right.derailment                wheel as H / P_R (H = axle<j>.force_y, positive toward
                                               +y: the right wheel's flange is loaded): the whole axle
                                               force on the flanging wheel, an upper bound, because the
                                               15-DOF model has one lateral contact per wheelset and
                                               no Q per wheel (first order; docs/references.md, running safety)
car<k>.body.acc_z_wb                   m/s^2   car-body vertical acceleration, EN 12299 Wb-weighted
car<k>.body.acc_y_wd                   m/s^2   car-body lateral acceleration, EN 12299 Wd-weighted
car<k>.body.sperling_z                 -       Sperling Wz of car<k>.body.acc_z per window (PEM: of the
car<k>.body.sperling_y                         time-dependent PSD averaged over the window; Monte Carlo:
                                               of each sample's periodogram; tb_exudyn.system.comfort)
=====================================  ======  ===========================================================

The weighted accelerations come from tb_exudyn.system.comfort.apply_weighting applied to the
pseudo-responses (linear, so PEM stays exact); the Sperling channels are windowed indices, not
Gaussian processes: their limits use the statistic ``window_max`` (no exceedance probability).
"""

from __future__ import annotations

import fnmatch
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Literal, Sequence, get_args

from ..errors import SettingError, one_of
from .schema import NONNEGATIVE, Check, Context, Validated, convert, param, set_source_file
from .limit_kinds import (LIMIT_KINDS, RESPONSE_LIMITS, STRUCTURAL_LIMITS, ComfortFigureLimit, FixedLimit,  # noqa: F401
                          GradedLimit, Limit, SpanRatioLimit, SpeedBandLimit, StaticLoadLimit)
from .io import resolve_model_path
from .toml_io import read_toml


# ============================================================================================ vocabulary
@dataclass(frozen=True)
class Quantity:
    """A physical quantity a limit applies to.

    name : the key used in limit files
    unit : SI unit of the channel values ('-' for ratios and indices)
    description : what it is, sign convention, and what the model can and cannot give
    channels : glob patterns of the channel names that carry it (tb_exudyn/system/channels.py naming)
    derived : True when the engines must form the channel (see the module's table); False when the
        existing channel catalogue has it
    """

    name: str
    unit: str
    description: str
    channels: tuple[str, ...]
    derived: bool

    def matches(self, channel: str) -> bool:
        """Whether a channel name carries this quantity."""
        return any(fnmatch.fnmatchcase(channel, p) for p in self.channels)


QUANTITIES: dict[str, Quantity] = {q.name: q for q in (
    Quantity("deck_acc_z", "m/s^2", "deck vertical acceleration at a station, the whole analysed band",
             ("bridge.span*.acc_z",), False),
    Quantity("deck_acc_z_en1990", "m/s^2",
             "deck vertical acceleration at a station along the track (the track centre line at rail level: "
             "bending plus torsion times the track's offset) with frequencies up to max(30 Hz, 1.5 f1, f3) only "
             "(EN 1990 A2.4.4.2.1; f1, f3 the first and third deck frequencies)",
             ("bridge.span*.acc_z_en1990",), True),
    Quantity("deck_twist_3m", "m",
             "deck twist: change over 3 m of track of the height difference between the two rails, "
             "[z_L - z_R](x + 1.5 m) - [z_L - z_R](x - 1.5 m) at the station x",
             ("bridge.span*.twist_3m",), True),
    Quantity("wheel_force_z", "N",
             "vertical wheel-rail force per wheel, compressive wheel load including the static load "
             "(car15: left/right per wheelset; sprung mass and moving force: one per axle)",
             ("car*.axle*.force_z",), False),
    Quantity("axle_force_y", "N",
             "lateral wheel-rail force on a wheelset H = Q_L + Q_R, positive toward +y (left). The 15-DOF "
             "model has one lateral contact per wheelset: H is defined, Q per wheel is not",
             ("car*.axle*.force_y",), False),
    Quantity("wheel_unloading", "-",
             "wheel unloading (P_R - P_L)/(P_R + P_L) of a wheelset, first order about the mean; |value| is "
             "dP/P_bar with dP = |P_R - P_L|/2, P_bar = (P_R + P_L)/2",
             ("car*.axle*.unloading",), True),
    Quantity("derailment_coefficient", "-",
             "derailment coefficient Q/P of a wheel, first order. The 15-DOF model has no Q per wheel: the "
             "channel puts the whole axle force H on the flanging wheel (right: H/P_R, left: -H/P_L), an upper "
             "bound of the wheel's Q/P",
             ("car*.axle*.left.derailment", "car*.axle*.right.derailment"), True),
    Quantity("body_acc_z", "m/s^2", "car-body vertical acceleration at its centre of gravity, unweighted",
             ("car*.body.acc_z",), False),
    Quantity("body_acc_y", "m/s^2", "car-body lateral acceleration at its centre of gravity, unweighted",
             ("car*.body.acc_y",), False),
    Quantity("body_acc_z_wb", "m/s^2", "car-body vertical acceleration, EN 12299 Wb-weighted",
             ("car*.body.acc_z_wb",), True),
    Quantity("body_acc_y_wd", "m/s^2", "car-body lateral acceleration, EN 12299 Wd-weighted",
             ("car*.body.acc_y_wd",), True),
    Quantity("sperling_z", "-", "Sperling ride index Wz of the car-body vertical acceleration, per window",
             ("car*.body.sperling_z",), True),
    Quantity("sperling_y", "-", "Sperling ride index Wz of the car-body lateral acceleration, per window",
             ("car*.body.sperling_y",), True),
)}

#: How a quantity's time history is reduced to the number compared with the limit.
STATISTICS: dict[str, str] = {
    "max_abs": "largest |value| over the analysed window (PEM: first passage out of [-limit, limit])",
    "max": "largest value (PEM: first passage above the limit)",
    "min": "smallest value; the limit is a lower bound (PEM: first passage below the limit)",
    "rms_window": "r.m.s. over consecutive windows of `window` s, the largest window",
    "window_max": "largest value of an index evaluated per window of `window` s (Sperling)",
    "sliding_mean_max_abs": "largest |value| of the sliding mean over `averaging_length` m of track "
                            "(EN 14363 style post-processing)",
}
Statistic = Literal["max_abs", "max", "min", "rms_window", "window_max", "sliding_mean_max_abs"]
_OptionalStatistic = Literal[("", *get_args(Statistic))]  # '': a structural criterion

#: the quantities that are windowed indices, not Gaussian processes: checked by ``window_max`` only (and
#: ``window_max`` checks only them: on a random process it would read the mean and drop sigma)
INDEX_QUANTITIES = ("sperling_z", "sperling_y")
#: the statistics that use ``window`` and ``averaging_length`` (a value given to another one would be ignored)
WINDOW_STATISTICS = ("rms_window", "window_max")
AVERAGING_STATISTICS = ("sliding_mean_max_abs",)


def quantity(name: str) -> Quantity:
    """The quantity of that name (SettingError listing the names otherwise)."""
    if name not in QUANTITIES:
        raise SettingError("quantity", "name", name, " | ".join(QUANTITIES))
    return QUANTITIES[name]


def channels_for(name: str, channels: Sequence[str]) -> list[str]:
    """The channels (of a result's or model's list) that carry quantity ``name``, in their order."""
    q = quantity(name)
    return [c for c in channels if q.matches(c)]



_ID = re.compile(r"[a-z][a-z0-9_]*")


# ============================================================================================ criteria
@dataclass(frozen=True, kw_only=True)
class Criterion(Validated):
    """One criterion of a code: what is limited, how it is evaluated, the limit and where it comes from.

    Two forms, one type: a criterion on a result's channels (models/limits/: a ``quantity`` of
    :data:`QUANTITIES` reduced by a ``statistic``, its unit the quantity's) and a structural one that the
    EN 1991-2 check computes on the bridge (models/criteria/: no statistic; the quantity in words, its
    ``unit``, its ``bound``, the ``load_model`` and where it is ``read_at``; limits also ``span_ratio``,
    ``comfort_figure``)."""

    id: str = param(doc="identifier, unique in its file (lower case, digits, _)")
    title: str = param(doc="one line: the criterion in words")
    clause: str = param(doc="the code and clause (or why there is none)")
    source: str = param(doc="where the value was read or from what it was recalled")
    quantity: str = param(doc="the quantity it applies to (a name of tb_exudyn.scenario.limits.QUANTITIES; a "
                               "structural criterion: the quantity in words)")
    statistic: _OptionalStatistic = param("", doc="how the time history is reduced (tb_exudyn.scenario.limits.STATISTICS); "
                                                  "'': a structural criterion")
    limit: Limit = param(doc="the limit: a table with kind = fixed | speed_bands | grades | static_load (structural: "
                             "fixed | speed_bands | span_ratio | comfort_figure)")
    load_model: str = param("", doc="the load model it applies to ('': the result's train)")
    tracks: str = param("", doc="which tracks carry the load ('': the result's)")
    read_at: str = param("", doc="where the quantity is read ('': the channels of its quantity)")
    bound: Literal["", "upper", "lower"] = param("", doc="upper: value <= limit; lower: value >= limit ('': from the "
                                                         "statistic, lower for 'min')")
    unit: str = param("", doc="unit of the quantity and the limit ('': the quantity's, QUANTITIES)")
    window: float = param(0.0, unit="s", doc="window length of rms_window and window_max", check=NONNEGATIVE)
    averaging_length: float = param(0.0, unit="m", doc="sliding-mean length of sliding_mean_max_abs", check=NONNEGATIVE)
    band: tuple[float, ...] = param((), unit="Hz", doc="(f_low, f_high) the quantity is band-limited to first; empty: none",
                                    check=Check(low=0.0, low_inclusive=True, allow_inf=True))
    condition: str = param("", doc="where the criterion applies (e.g. 'ballasted track')")
    check: bool = param(False, doc="true when the clause text was not read: the value must be checked")
    note: str = param("", doc="remarks; required when check is true (what to check)")
    unverified: str = param("limit", doc="with check = true: what of the clause is not read in its text: 'limit' (the "
                                         "value itself) or the part that is not, e.g. 'frequency range' (the value read)")

    def unverified_caveat(self) -> tuple[str, str]:
        """(kind, text) of the caveat on a ``check = true`` criterion: 'limit_unverified' only where the limit
        value itself is not read, each saying what would verify it (reading the clause named)."""
        verify = f"reading {self.clause or 'the clause'} in the code text would verify it"
        if self.unverified == "limit":
            return "limit_unverified", f"limit not read in the code text [check]; {verify}: {self.note}"
        return "limit_note", f"limit value read; its {self.unverified} not read [check], {verify}: {self.note}"

    @property
    def structural(self) -> bool:
        """True for a criterion the check computes on the bridge (no statistic of a result)."""
        return not self.statistic

    @property
    def lower_bound(self) -> bool:
        """True when the limit is a lower bound (statistic 'min', or bound 'lower')."""
        return self.statistic == "min" or self.bound == "lower"

    def limit_value(self, *, speed_kmh: float | None = None, static_axle_load: float | None = None,
                    static_wheel_load: float | None = None, span: float | None = None) -> float:
        """The limit for a train speed [km/h], static loads [N] or a span [m] (those that the limit kind needs);
        the comfort figure's depends on more (tb_exudyn.codes.comfort_deflection.comfort_limit)."""
        lim = self.limit
        if isinstance(lim, SpanRatioLimit):
            return lim.value_at(span=span)
        if isinstance(lim, ComfortFigureLimit):
            raise SettingError("Criterion.limit_value", "id", self.id, "a criterion without the comfort figure "
                               "(comfort_deflection.comfort_limit computes it)")
        return lim.value_at(speed_kmh=speed_kmh, static_axle_load=static_axle_load, static_wheel_load=static_wheel_load)

    def _validate(self, ctx: Context) -> None:
        if not _ID.fullmatch(self.id):
            raise ctx.child("id").error(self.id, "lower-case letters, digits and _, starting with a letter", "bad identifier")
        for key in ("title", "clause", "source") + (("quantity", "load_model", "read_at", "unit") if self.structural else ()):
            if not getattr(self, key).strip():
                raise ctx.child(key).error(getattr(self, key), "a non-empty string" + (
                    " (a criterion without a statistic is structural)" if self.structural else ""), "empty")
        allowed = STRUCTURAL_LIMITS if self.structural else RESPONSE_LIMITS
        if self.limit.kind not in allowed:
            raise ctx.child("limit").child("kind").error(self.limit.kind, " | ".join(allowed) + (
                " (a structural criterion)" if self.structural else " (a criterion with a statistic)"), "wrong limit kind")
        if self.check and not self.note.strip():
            raise ctx.child("note").error(self.note, "a note saying what to check (check = true)", "empty")
        if self.structural:
            if not self.bound:
                raise ctx.child("bound").error(self.bound, "upper | lower (a criterion without a statistic)", "missing")
            self._validate_limit(ctx.child("limit"))
            return
        own = "lower" if self.statistic == "min" else "upper"
        if self.bound not in ("", own):
            raise ctx.child("bound").error(self.bound, f"'' or {own!r} (statistic {self.statistic!r})", "contradicts the statistic")
        if self.quantity in QUANTITIES and self.unit not in ("", QUANTITIES[self.quantity].unit):
            raise ctx.child("unit").error(self.unit, f"'' or {QUANTITIES[self.quantity].unit!r} (quantity {self.quantity!r})",
                                          "not the quantity's unit")
        self._validate_response(ctx)
        object.__setattr__(self, "unit", QUANTITIES[self.quantity].unit)  # a response criterion's unit: its quantity's

    def _validate_response(self, ctx: Context) -> None:
        if self.quantity not in QUANTITIES:
            raise ctx.child("quantity").error(self.quantity, one_of(QUANTITIES, self.quantity), "unknown quantity")
        index = self.quantity in INDEX_QUANTITIES
        if index != (self.statistic == "window_max"):
            allowed = ("'window_max' (a windowed index, not a random process)" if index else
                       ", ".join(s for s in STATISTICS if s != "window_max"))
            raise ctx.child("statistic").error(self.statistic, allowed, f"not a statistic of {self.quantity!r}")
        if self.window and self.statistic not in WINDOW_STATISTICS:
            raise ctx.child("window").error(self.window, f"0 or absent: statistic {self.statistic!r} has no window "
                                            f"(only {', '.join(WINDOW_STATISTICS)})", "would be ignored")
        if self.averaging_length and self.statistic not in AVERAGING_STATISTICS:
            raise ctx.child("averaging_length").error(self.averaging_length, f"0 or absent: statistic {self.statistic!r} "
                                                      f"averages nothing (only {', '.join(AVERAGING_STATISTICS)})",
                                                      "would be ignored")
        if self.statistic in ("rms_window", "window_max") and self.window <= 0:
            raise ctx.child("window").error(self.window, f"a window length > 0 s for statistic {self.statistic!r}", "missing window")
        if self.statistic == "sliding_mean_max_abs" and self.averaging_length <= 0:
            raise ctx.child("averaging_length").error(self.averaging_length, "a length > 0 m for statistic "
                                                      "'sliding_mean_max_abs'", "missing averaging length")
        if self.band and (len(self.band) != 2 or not self.band[0] < self.band[1]):
            raise ctx.child("band").error(list(self.band), "[] or [f_low, f_high] in Hz with f_low < f_high", "bad band")
        self._validate_limit(ctx.child("limit"))

    def _validate_limit(self, ctx: Context) -> None:
        """The limit's sign. Every statistic but 'min' compares a largest value (|value|, value, window r.m.s.,
        index, sliding mean) with an upper bound: a limit <= 0 fails every run (max_abs, rms_window, window_max and
        the sliding mean are >= 0) and is no code value. A lower bound ('min') may be 0 or negative (e.g. a wheel
        load >= 0: no loss of contact). Upper grades make no lower bound."""
        lim = self.limit
        if self.lower_bound and isinstance(lim, GradedLimit):
            raise ctx.child("kind").error(lim.kind, "fixed | speed_bands | static_load with statistic 'min' (grades "
                                          "are upper ends, best first)", "grades with a lower bound")
        if self.lower_bound or isinstance(lim, (StaticLoadLimit, SpanRatioLimit, ComfortFigureLimit)):  # > 0 by their checks
            return
        key, values = ("value", (lim.value,)) if isinstance(lim, FixedLimit) else ("values", lim.values)
        for i, v in enumerate(values):
            if not v > 0:
                sub = ctx.child(key) if key == "value" else ctx.child(key).child(i)
                raise sub.error(v, "a number > 0 (only 'min' takes a limit <= 0)", "not a positive limit")


@dataclass(frozen=True, kw_only=True)
class LimitSet(Validated):
    """The criteria of one limit file."""

    name: str = param(doc="identifier (the file's stem)")
    description: str = param(doc="one line for listings")
    source: str = param(doc="the codes and documents the file draws on")
    notes: str = param("", doc="remarks; values marked [check]")
    criteria: tuple[Criterion, ...] = param(doc="the criteria ([[criteria]] tables)")

    def criterion(self, criterion_id: str) -> Criterion:
        """The criterion with that id (SettingError listing the ids otherwise)."""
        for c in self.criteria:
            if c.id == criterion_id:
                return c
        raise SettingError(f"limits {self.name!r}", "id", criterion_id, " | ".join(c.id for c in self.criteria))

    def for_quantity(self, name: str) -> list[Criterion]:
        """The criteria that apply to a quantity."""
        return [c for c in self.criteria if c.quantity == name]

    def _validate(self, ctx: Context) -> None:
        if not _ID.fullmatch(self.name):
            raise ctx.child("name").error(self.name, "lower-case letters, digits and _, starting with a letter (the "
                                          "file's stem; the verdicts are named <name>/<criterion id>)", "bad identifier")
        if not self.criteria:
            raise ctx.child("criteria").error([], "at least one [[criteria]] table", "empty")
        seen: set[str] = set()
        for i, c in enumerate(self.criteria):
            if c.id in seen:
                raise ctx.child("criteria").child(i).child("id").error(c.id, "an id not used before in the file", "duplicate id")
            seen.add(c.id)


def limits_from_dict(data: dict, file: str | None = None, structural: bool = False) -> LimitSet:
    """Build and validate a LimitSet from a plain dict (the TOML table); ScenarioError names file and key. A
    limit file (models/limits) holds criteria on a result's channels, each with a statistic; ``structural``:
    the check's criteria file (models/criteria), none with a statistic."""
    tables = data.get("criteria") if isinstance(data, dict) else None
    for i, c in enumerate(tables if isinstance(tables, list) else []):
        if isinstance(c, dict) and bool(c.get("statistic")) == structural:
            allowed = ("absent: the criteria of this file are computed on the bridge" if structural else
                       " | ".join(get_args(Statistic)) + ": the criteria of a limit file are statistics of a result")
            raise Context(file).child("criteria").child(i).child("statistic").error(
                c.get("statistic", "(missing)"), allowed, "given" if structural else "missing")
    return convert(LimitSet, data, Context(file))


def load_limits(name_or_path: str | Path) -> LimitSet:
    """Load a limit file by name (models/limits/<name>.toml, see ``list_models()``) or by path.

    Raises ScenarioError naming the file, key, value and what is allowed for any bad input.
    """
    path = resolve_model_path(name_or_path, "limits")
    return set_source_file(limits_from_dict(read_toml(path), str(path)), str(path))


__all__ = [
    "ComfortFigureLimit", "Criterion", "FixedLimit", "RESPONSE_LIMITS", "STRUCTURAL_LIMITS", "SpanRatioLimit", "GradedLimit", "INDEX_QUANTITIES", "LIMIT_KINDS", "Limit", "LimitSet", "QUANTITIES", "Quantity", "STATISTICS",
    "SpeedBandLimit", "StaticLoadLimit", "channels_for", "limits_from_dict", "load_limits", "quantity",
]
