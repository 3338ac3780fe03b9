"""How channels are shown: readable labels of channel names (the naming rule of :mod:`.channels`),
``car1.bogie1.acc_y`` -> "car 1, leading bogie, lateral acceleration"; engineering display units
(kN, mm, m/s^2); and the key channels that figures, summaries and stored PSD maps show by default.
Plain Python (no matplotlib): figures, the report, exports and the command line share it."""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Sequence

import numpy as np

_COMPONENT = {"y": "lateral", "z": "vertical", "rx": "roll", "ry": "pitch", "rz": "yaw"}
_BRIDGE_COMPONENT = {"y": "lateral", "z": "vertical", "rx": "torsional"}
_QUANTITY_TRANSLATION = {"disp": "displacement", "vel": "velocity", "acc": "acceleration"}
_QUANTITY_ROTATION = {"disp": "angle", "vel": "angular velocity", "acc": "angular acceleration"}
_STATION = {"mid": "mid-span", "q1": "first quarter point", "q3": "third quarter point", "top": "top",
            "start": "1.5 m from the span's start", "end": "1.5 m from the span's end"}
_BOGIE = {"1": "leading bogie", "2": "trailing bogie"}

_MOTION = re.compile(r"(disp|vel|acc)_(y|z|rx|ry|rz)")
#: the derived channels of tb_exudyn.system.derived (what follows the station, body or axle)
_BRIDGE_DERIVED = {"acc_z_en1990": "EN 1990 acceleration at the track", "twist_3m": "deck twist over 3 m"}
_BODY_DERIVED = {"acc_z_wb": "Wb-weighted vertical acceleration", "acc_y_wd": "Wd-weighted lateral acceleration",
                 "sperling_z": "vertical Sperling index", "sperling_y": "lateral Sperling index"}
_BRIDGE = re.compile(r"bridge\.(span|pier)(\d+)\.(\w+)\.(.+)")
_CAR = re.compile(r"car(\d+)\.(.+)")
_TRACK = re.compile(r"track(\d+)\.")
#: the track's channels (tb_exudyn.system.track_bridge): track.<station>.<rail side>.<part>.<what>
_TRACK_CHANNEL = re.compile(r"track\.span(\d+)\.(\w+)\.(left|right)\.(rail|sleeper|deck|pad|ballast)\.(\w+)")
_TRACK_PART = {"rail": "rail above the sleeper", "sleeper": "sleeper", "deck": "deck under the sleeper",
               "pad": "pad", "ballast": "ballast"}


def _motion_label(what: str, components: dict[str, str]) -> str | None:
    m = _MOTION.fullmatch(what)
    if not m or m.group(2) not in components:
        return None
    quantity, comp = m.groups()
    words = (_QUANTITY_TRANSLATION if comp in ("y", "z") else _QUANTITY_ROTATION)[quantity]
    return f"{components[comp]} {words}"


def channel_label(name: str) -> str:
    """A readable label of a channel name (``tb_exudyn.system.channels`` naming), e.g.
    ``car1.bogie1.acc_y`` -> "car 1, leading bogie, lateral acceleration",
    ``bridge.span2.mid.disp_z`` -> "span 2, mid-span, vertical displacement",
    ``car1.axle3.left.force_z`` -> "car 1, axle 3, left wheel, vertical wheel-rail force",
    ``track.span1.mid.left.pad.force_z`` -> "track at span 1, mid-span, left rail, pad, vertical force"; the derived
    channels of :mod:`tb_exudyn.system.derived` too (``car1.axle2.left.derailment`` -> "car 1, axle 2,
    left wheel, derailment quotient Q/P"). A name of another form is returned as it is."""
    m = _BRIDGE.fullmatch(name)
    if m:
        kind, number, station, what = m.groups()
        track = _TRACK.match(what)  # a station along a track of a deck of two or more: span1.mid.track2
        if track:
            what = what[track.end():]
        motion = _motion_label(what, _BRIDGE_COMPONENT) or _BRIDGE_DERIVED.get(what)
        if motion is not None:
            on = f", track {track.group(1)}" if track else ""
            return f"{kind} {number}, {_STATION.get(station, station)}{on}, {motion}"
        return name
    m = _TRACK_CHANNEL.fullmatch(name)
    if m:  # the track at the sleeper nearest a span station
        span, station, side, part, what = m.groups()
        head = f"track at span {span}, {_STATION.get(station, station)}, {side} rail, {_TRACK_PART[part]}"
        if what == "force_z" and part in ("pad", "ballast"):
            return f"{head}, vertical force"
        motion = _motion_label(what, {"z": "vertical"})
        return f"{head}, {motion}" if motion else name
    m = _CAR.fullmatch(name)
    if not m:
        return name
    car, rest = m.groups()
    parts = rest.split(".")
    head = f"car {car}"
    if len(parts) == 2 and parts[0] == "body":
        motion = _motion_label(parts[1], _COMPONENT) or _BODY_DERIVED.get(parts[1])
        return f"{head}, body, {motion}" if motion else name
    if len(parts) == 2 and parts[0].startswith("bogie") and parts[0][5:] in _BOGIE:
        motion = _motion_label(parts[1], _COMPONENT)
        return f"{head}, {_BOGIE[parts[0][5:]]}, {motion}" if motion else name
    numbered = re.fullmatch(r"(body|bogie)(\d+)", parts[0]) if len(parts) == 2 else None  # an articulated set's
    if numbered:
        motion = _motion_label(parts[1], _COMPONENT)
        return f"{head}, {numbered.group(1)} {numbered.group(2)}, {motion}" if motion else name
    if parts[0].startswith("axle") and parts[0][4:].isdigit():
        axle = f"{head}, axle {parts[0][4:]}"
        if len(parts) == 2 and parts[1] == "force_y":
            return f"{axle}, lateral wheel-rail force"
        if len(parts) == 2 and parts[1] == "force_z":
            return f"{axle}, vertical wheel-rail force"
        if len(parts) == 3 and parts[1] in ("left", "right") and parts[2] == "force_z":
            return f"{axle}, {parts[1]} wheel, vertical wheel-rail force"
        if len(parts) == 3 and parts[1] in ("left", "right") and parts[2] == "derailment":
            return f"{axle}, {parts[1]} wheel, derailment quotient Q/P"
        if parts[-2:-1] == ["rail"] and len(parts) in (3, 4) and (len(parts) == 3 or parts[1] in ("left", "right")):
            motion = _motion_label(parts[-1], {"z": "vertical", "y": "lateral"})  # the rail under the wheel
            if motion:
                where = (f"{parts[1]} wheel, rail under it" if len(parts) == 4 else "rail under the wheel"
                         if parts[-1].endswith("_z") else "rails' centre line under the wheelset")
                return f"{axle}, {where}, {motion}"
        if len(parts) == 2 and parts[1] == "unloading":
            return f"{axle}, wheel unloading dP/P"
        if len(parts) == 2:
            motion = _motion_label(parts[1], _COMPONENT)
            if motion:
                return f"{axle}, wheelset {motion}"
    return name


@dataclass(frozen=True)
class DisplayUnit:
    """How a channel's values are shown: ``shown = factor * si_value`` in ``unit``."""

    unit: str
    factor: float


#: SI unit -> (display unit, factor). Forces in kN and displacements in mm (the magnitudes of a
#: train-bridge run: wheel loads of 10-100 kN, deflections of 0.01-10 mm); rotations in mrad;
#: accelerations stay in m/s^2 and rad/s^2, the unit the codes' limits use (EN 1990 A2: 3.5 m/s^2).
DISPLAY_UNITS: dict[str, DisplayUnit] = {
    "N": DisplayUnit("kN", 1e-3),
    "m": DisplayUnit("mm", 1e3),
    "m/s": DisplayUnit("mm/s", 1e3),
    "m/s^2": DisplayUnit("m/s^2", 1.0),
    "rad": DisplayUnit("mrad", 1e3),
    "rad/s": DisplayUnit("mrad/s", 1e3),
    "rad/s^2": DisplayUnit("rad/s^2", 1.0),
}


def display_unit(si_unit: str) -> DisplayUnit:
    """The engineering unit and factor for a channel stored in ``si_unit`` (the one place this
    convention lives); a unit not in :data:`DISPLAY_UNITS` (e.g. a ratio) is shown as it is."""
    return DISPLAY_UNITS.get(si_unit, DisplayUnit(si_unit, 1.0))


def psd_unit(unit: str) -> str:
    """Unit of a one-sided PSD per Hz of a channel in ``unit``."""
    if not unit:
        return "1/Hz"
    return f"({unit})^2/Hz" if "/" in unit or " " in unit else f"{unit}^2/Hz"


def format_number(x: float, digits: int = 4) -> str:
    """``digits`` significant digits, without an exponent for 1e-3 <= |x| < 1e6 (the range of
    values in display units); an exponent outside it; '' for None or NaN."""
    if x is None or (isinstance(x, float) and np.isnan(x)):
        return ""
    x = float(x)
    if x == 0.0:
        return "0"
    if not np.isfinite(x):
        return "inf" if x > 0 else "-inf"
    if 1e-3 <= abs(x) < 1e6:
        return np.format_float_positional(x, precision=digits, unique=False, fractional=False, trim="-")
    return f"{x:.{digits - 1}e}"


def _middle_span(names: Sequence[str]) -> int | None:
    spans = sorted({int(m.group(1)) for n in names if (m := re.match(r"bridge\.span(\d+)\.mid\.", n))})
    return spans[(len(spans) - 1) // 2] if spans else None


def default_patterns(names: Sequence[str]) -> tuple[tuple[str, tuple[str, ...]], ...]:
    """(component, glob patterns) of the channels drawn by default, a short list per component:

    - those the verdicts check (EN 1990 deck vertical acceleration at every mid-span, along each track
      of a deck of two tracks or more; car-body
      vertical and lateral accelerations; the lateral axle force of each car's leading axle);
    - those of the reference study's figures 3-8 (Li & Zhu, section 4.3-4.4): the middle span's
      mid-point lateral and vertical displacement and acceleration, the first car's body and
      leading bogie lateral displacement and acceleration, the wheel-rail forces of its first axle.
    """
    mid = _middle_span(names)
    bridge = ("bridge.span*.mid.acc_z", "bridge.span*.mid.track*.acc_z")  # the girder axis; along each track
    if mid is not None:
        bridge += (f"bridge.span{mid}.mid.disp_[yz]", f"bridge.span{mid}.mid.acc_y")
    return (
        ("bridge", bridge),
        ("car bodies", ("car*.body.acc_[yz]", "car1.body.disp_y")),
        ("bogies", ("car1.bogie1.disp_y", "car1.bogie1.acc_y")),
        ("wheelsets", ("car*.axle1.force_y", "car1.axle1.left.force_z", "car1.axle1.right.force_z",
                       "car1.axle1.force_z")),
    )


__all__ = ["DISPLAY_UNITS", "DisplayUnit", "channel_label", "default_patterns", "display_unit", "format_number", "psd_unit"]
