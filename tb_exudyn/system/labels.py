"""Readable labels of channel names (the naming rule of :mod:`.channels`), for figures, the report
and labelled exports: ``car1.bogie1.acc_y`` -> "car 1, leading bogie, lateral acceleration"."""

from __future__ import annotations

import re

_COMPONENT = {"y": "lateral", "z": "vertical", "rx": "roll", "ry": "pitch", "rz": "yaw"}
_BRIDGE_COMPONENT = {"y": "lateral", "z": "vertical", "rx": "torsional"}
_QUANTITY_TRANSLATION = {"disp": "displacement", "vel": "velocity", "acc": "acceleration"}
_QUANTITY_ROTATION = {"disp": "angle", "vel": "angular velocity", "acc": "angular acceleration"}
_STATION = {"mid": "mid-span", "q1": "first quarter point", "q3": "third quarter point", "top": "top"}
_BOGIE = {"1": "leading bogie", "2": "trailing bogie"}

_MOTION = re.compile(r"(disp|vel|acc)_(y|z|rx|ry|rz)")
_BRIDGE = re.compile(r"bridge\.(span|pier)(\d+)\.(\w+)\.(.+)")
_CAR = re.compile(r"car(\d+)\.(.+)")


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
    ``car1.axle3.left.force_z`` -> "car 1, axle 3, left wheel, vertical wheel-rail force".
    A name of another form (a derived quantity) is returned as it is."""
    m = _BRIDGE.fullmatch(name)
    if m:
        kind, number, station, what = m.groups()
        motion = _motion_label(what, _BRIDGE_COMPONENT)
        if motion is not None:
            return f"{kind} {number}, {_STATION.get(station, station)}, {motion}"
        return name
    m = _CAR.fullmatch(name)
    if not m:
        return name
    car, rest = m.groups()
    parts = rest.split(".")
    head = f"car {car}"
    if len(parts) == 2 and parts[0] == "body":
        motion = _motion_label(parts[1], _COMPONENT)
        return f"{head}, body, {motion}" if motion else name
    if len(parts) == 2 and parts[0].startswith("bogie") and parts[0][5:] in _BOGIE:
        motion = _motion_label(parts[1], _COMPONENT)
        return f"{head}, {_BOGIE[parts[0][5:]]}, {motion}" if motion else name
    if parts[0].startswith("axle") and parts[0][4:].isdigit():
        axle = f"{head}, axle {parts[0][4:]}"
        if len(parts) == 2 and parts[1] == "force_y":
            return f"{axle}, lateral wheel-rail force"
        if len(parts) == 2 and parts[1] == "force_z":
            return f"{axle}, vertical wheel-rail force"
        if len(parts) == 3 and parts[1] in ("left", "right") and parts[2] == "force_z":
            return f"{axle}, {parts[1]} wheel, vertical wheel-rail force"
        if len(parts) == 2:
            motion = _motion_label(parts[1], _COMPONENT)
            if motion:
                return f"{axle}, wheelset {motion}"
    return name


__all__ = ["channel_label"]
