"""The speeds of a sweep: a series as text (START:STOP:STEP, a comma list, EN 1991-2's
series up to 1.2 x the line speed), each checked as a scenario's speed_kmh, and a speed's folder
name (used by :mod:`tb_exudyn.methods.sweep`, which re-exports them)."""

from __future__ import annotations

import dataclasses
import math
from typing import Any, Sequence

import numpy as np

from ..errors import SettingError
from ..scenario import Scenario

#: EN 1991-2, 6.4.6.2: speeds up to this factor times the maximum line speed
EN1991_SPEED_FACTOR = 1.2


# ------------------------------------------------------------------------------------- speeds
#: a sweep's speeds follow the scenario's rule for speed_kmh (the schema's check: what a scenario file
#: and ``run --speed-kmh`` accept, finite, > 0 and <= 1000 km/h)
SPEED_CHECK = next(f.metadata["check"] for f in dataclasses.fields(Scenario) if f.name == "speed_kmh")
#: at most this many speeds in one sweep: each speed is a whole PEM run (13.6-25.5 s of a worker for
#: the reference study, docs/speed.md) and its own folder, so 1000 speeds are already 4-7 hours on
#: one core, a 0.6 km/h step over the whole range of speeds, and 18 times EN 1991-2's series at 5 km/h
#: steps up to 1.2 x 350 km/h (56 speeds); more is a slip (a step in m/s, a missing digit)
MAX_SPEEDS = 1000


#: the speeds' arguments, as a message names them (the library's keys; the command line maps them to
#: its flags when it prints)
KEYS = {"speeds": "speeds_kmh", "line": "line_speed_kmh", "step": "step_kmh", "start": "start_kmh"}


def check_speeds(speeds: Sequence[float], where: str = "run_sweep", key: str | None = None,
                 shown: Any = None) -> tuple[float, ...]:
    """The speeds of a sweep [km/h] as floats, checked before any work (SettingError naming ``where``
    and ``key``, showing ``shown``, default the speeds): at most :data:`MAX_SPEEDS`, each within
    :data:`SPEED_CHECK`, no two with the same :func:`speed_label` (the folder and task key of a speed)."""
    key = key or KEYS["speeds"]
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
            raise SettingError(where, key, shown, "speeds differing in 6 significant digits",
                               f"{seen[label]!r} and {float(v)!r} are the same speed {label!r}")
        seen[label] = float(v)
    return tuple(seen.values())


def _is_number(x: Any) -> bool:
    return isinstance(x, (int, float, np.integer, np.floating)) and not isinstance(x, (bool, np.bool_))


def parse_speeds(text: str, where: str = "parse_speeds") -> tuple[float, ...]:
    """'START:STOP:STEP' (km/h, STOP included) or a comma list '160,220,300', checked by
    :func:`check_speeds` (the count before the list is made); errors name ``where`` (the caller) and
    ``speeds_kmh``."""
    key = KEYS["speeds"]
    allowed = (f"START:STOP:STEP (0 < START <= STOP <= {SPEED_CHECK.high:g}, STEP > 0) or a comma list, "
               f"at most {MAX_SPEEDS} speeds")
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
    ``where`` and the argument): the top speed within
    :data:`SPEED_CHECK`, the step finite and > 0, at most :data:`MAX_SPEEDS` speeds."""
    keys = KEYS
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


__all__ = ["EN1991_SPEED_FACTOR", "MAX_SPEEDS", "SPEED_CHECK", "check_speeds", "en1991_speeds", "parse_speeds",
           "range_count", "speed_label", "speed_range"]
