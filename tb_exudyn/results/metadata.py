"""The metadata of result folders read defensively: every field typed and checked, one-line
ResultsErrors naming the file and the key (the folder itself: :func:`open_result_folder`)."""

from __future__ import annotations

import math
import os
import re
import tomllib
from pathlib import Path
from typing import Any, Callable, Mapping, Sequence

from ..errors import ResultsError, format_message
from ..scenario import ScenarioError, scenario_from_dict
from ..system.channels import CHANNEL_NAME_RULE, is_channel_name
from ..storage import _error, recover_folder


def open_result_folder(folder: str | Path) -> Path:
    """Check a result folder before reading it: it exists, is a folder, and holds no symbolic links
    (its figures folder included); leftovers of killed writes are resolved first. Returns it."""
    folder = Path(folder)
    if str(folder) == "":
        raise ResultsError("results folder '': empty path (give a folder)")
    recover_folder(Path(os.path.realpath(folder)))
    if not folder.exists():
        raise _error(folder, "no such results folder")
    if not folder.is_dir():
        raise _error(folder, "not a folder (a results folder holds meta.json and arrays.npz)")
    try:
        with os.scandir(folder) as it:
            for entry in it:
                if entry.is_symlink():
                    raise _error(Path(entry.path), f"is a symbolic link (to {os.readlink(entry.path)!r}): a results "
                                                   "folder holds only its own files and folders")
    except OSError as exc:
        raise _error(folder, f"cannot be read ({exc.strerror or exc})") from None
    return folder


def _where(path: Path, key: str, value: Any, allowed: str, reason: str) -> ResultsError:
    return ResultsError(format_message(str(path), key, value, allowed, reason))


def _get(meta: Mapping[str, Any], key: str, path: Path, allowed: str) -> Any:
    if key not in meta:
        raise _where(path, key, "<missing>", allowed, "missing key")
    return meta[key]


def meta_str(meta: Mapping[str, Any], key: str, path: Path, choices: Sequence[str] | None = None,
             optional: bool = False) -> str | None:
    """A string value of ``meta`` (one of ``choices`` if given; None allowed if ``optional``)."""
    allowed = ("one of " + ", ".join(map(repr, choices))) if choices else "a string"
    if optional and meta.get(key) is None:
        return None
    value = _get(meta, key, path, allowed)
    if not isinstance(value, str) or (choices is not None and value not in choices):
        raise _where(path, key, value, allowed, "wrong type" if not isinstance(value, str) else "unknown value")
    return value


def meta_str_list(meta: Mapping[str, Any], key: str, path: Path, length: int | None = None,
                  check: Callable[[str], bool] | None = None, rule: str = "strings",
                  unique: bool = False) -> list[str]:
    """A list of strings (of ``length`` items, each passing ``check``, all different if ``unique``)."""
    allowed = f"a list of {length if length is not None else ''} {rule}".replace("  ", " ")
    value = _get(meta, key, path, allowed)
    if not isinstance(value, list):
        raise _where(path, key, value, allowed, "wrong type")
    if length is not None and len(value) != length:
        raise _where(path, key, value, allowed, f"{len(value)} items, not {length}")
    for i, item in enumerate(value):
        if not isinstance(item, str) or (check is not None and not check(item)):
            raise _where(path, f"{key}[{i}]", item, rule, "wrong type" if not isinstance(item, str) else "bad name")
    if unique and len(set(value)) != len(value):
        dup = next(v for i, v in enumerate(value) if v in value[:i])
        raise _where(path, key, dup, f"different {rule}", "repeated")
    return value


def meta_int(meta: Mapping[str, Any], key: str, path: Path, low: int = 0) -> int:
    allowed = f"an integer >= {low}"
    value = _get(meta, key, path, allowed)
    if isinstance(value, bool) or not isinstance(value, int) or value < low:
        raise _where(path, key, value, allowed, "bad value")
    return value


def meta_band(meta: Mapping[str, Any], key: str, path: Path, high: float = math.inf,
              high_text: str = "") -> tuple[float, float]:
    """A frequency band [f_low, f_high] [Hz] with 0 <= f_low < f_high < inf, and f_high <= ``high``
    (``high_text`` says where that bound comes from)."""
    allowed = "0 <= f_low < f_high" + (f" <= {high_text or f'{high:.4g} Hz'}" if math.isfinite(high) else " Hz, finite")
    value = _get(meta, key, path, allowed)
    ok = (isinstance(value, list) and len(value) == 2
          and all(isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) for v in value)
          and 0 <= value[0] < value[1])
    if not ok:
        raise _where(path, key, value, allowed, "bad value")
    if not value[1] <= high:
        raise _where(path, key, value, allowed, "above the scenario's band")
    return float(value[0]), float(value[1])


def meta_dict(meta: Mapping[str, Any], key: str, path: Path, optional: bool = False) -> dict[str, Any]:
    if optional and key not in meta:
        return {}
    value = _get(meta, key, path, "a JSON object")
    if not isinstance(value, dict):
        raise _where(path, key, value, "a JSON object", "wrong type")
    return value


def _is_number(v: Any) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def _number_or_null(v: Any) -> bool:
    return v is None or _is_number(v)


def _list_of(check: Callable[[Any], bool]) -> Callable[[Any], bool]:
    return lambda v: isinstance(v, list) and all(check(x) for x in v)


def _object_of(fields: Mapping[str, Callable[[Any], bool]], closed: bool = False) -> Callable[[Any], bool]:
    """A JSON object whose ``fields`` (those present) pass their checks; ``closed``: no other field."""
    return lambda v: (isinstance(v, dict) and all(f not in v or ok(v[f]) for f, ok in fields.items())
                      and (not closed or set(v) <= set(fields)))


def _grid_error(v: Any) -> bool:
    if not isinstance(v, dict):
        return True  # a sentence saying why it was not estimated: not read as numbers
    table = v.get("channels", v)
    if not isinstance(table, dict):
        return True
    return all(not isinstance(e, dict) or all(_is_number(e[k]) for k in ("rel_error_max_sigma", "rel_deviation")
                                              if k in e) for e in table.values())


_STR_LIST = _list_of(lambda x: isinstance(x, str))
_MODE = {"frequency": _is_number, "damping_ratio": _is_number, "label": lambda x: isinstance(x, str),
         "context": lambda x: isinstance(x, str), "warning": lambda x: isinstance(x, str)}
#: the provenance fields the code reads back (report, checks, command line), with the types it writes:
#: key -> (check, what is allowed)
PROVENANCE_FIELDS: dict[str, tuple[Callable[[Any], bool], str]] = {
    "warnings": (_STR_LIST, "a list of strings (one warning each)"),
    "damping_warnings": (_list_of(_object_of({
        "channels": _STR_LIST, "frequency": _is_number, "damping_ratio": _is_number, "decay_time": _number_or_null,
        "growth_on_bridge": _is_number, "label": lambda x: isinstance(x, str)})),
        "a list of damping-warning objects"),
    "damped_modes": (_list_of(lambda m: _object_of(_MODE, closed=True)(m) and "frequency" in m and "damping_ratio" in m
                              and "label" in m),
                     "objects of frequency, damping_ratio, label (+ context, warning) only"),
    "grid_error": (_grid_error, "a sentence or {channel: number or object}"),
    "derived_channels": (_object_of({"channels": lambda c: isinstance(c, dict) and all(
        not isinstance(e, dict) or _object_of({"window": _is_number})(e) for e in c.values())}),
        "{'channels': {name: {'window': seconds}}}"),
    "samples_with_loss_of_contact": (lambda v: _is_number(v) and 0 <= v < math.inf, "a number of samples >= 0"),
    "min_wheel_force_N": (_number_or_null, "a force in N or null"),
    "seconds": (_is_number, "a run time in s"),
}


def meta_provenance(meta: Mapping[str, Any], path: Path, optional: bool = False) -> dict[str, Any]:
    """The ``provenance`` object: any JSON, but the fields the code reads back (:data:`PROVENANCE_FIELDS`)
    of the types it writes them with (e.g. ``warnings`` a list of strings)."""
    provenance = meta_dict(meta, "provenance", path, optional=optional)
    for key, (ok, allowed) in PROVENANCE_FIELDS.items():
        if key in provenance and not ok(provenance[key]):
            raise _where(path, f"provenance.{key}", provenance[key], allowed, "wrong type")
    return provenance


_UNIT = re.compile(r"[A-Za-z0-9_/^*.()+\- ]{0,32}\Z")
UNIT_RULE = "units such as m, m/s^2, rad/s, N (at most 32 of A-Z a-z 0-9 _ / ^ * . ( ) + - and space)"


def meta_channels(meta: Mapping[str, Any], path: Path) -> tuple[list[str], list[str]]:
    """Channel names (the naming rule of :mod:`tb_exudyn.system.channels`, all different, at least one) and their units."""
    names = meta_str_list(meta, "channels", path, check=is_channel_name, rule=f"channel names: {CHANNEL_NAME_RULE}",
                          unique=True)
    if not names:
        raise _where(path, "channels", names, f"a list of channel names: {CHANNEL_NAME_RULE}", "no channel")
    units = meta_str_list(meta, "units", path, length=len(names), check=lambda u: _UNIT.match(u) is not None,
                          rule=UNIT_RULE)
    return names, units


def meta_scenario(meta: Mapping[str, Any], path: Path, optional: bool = False) -> Any:
    """The scenario stored as TOML text under ``scenario_toml`` (None if absent and ``optional``)."""
    text = meta_str(meta, "scenario_toml", path, optional=optional)
    if text is None:
        return None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise _where(path, "scenario_toml", text, "the scenario as TOML text", f"not valid TOML ({exc})") from None
    except RecursionError:
        raise _where(path, "scenario_toml", text, "the scenario as TOML text", "nested too deeply") from None
    try:
        return scenario_from_dict(data, str(path), resolve_names=False)
    except ScenarioError as exc:
        raise ResultsError(f"{exc} [in scenario_toml]") from None
    except RecursionError:
        raise _where(path, "scenario_toml", text, "the scenario as TOML text", "nested too deeply") from None


__all__ = ["open_result_folder", "meta_str", "meta_str_list", "meta_int", "meta_band", "meta_dict", "meta_channels",
           "meta_provenance", "meta_scenario", "PROVENANCE_FIELDS", "UNIT_RULE"]
