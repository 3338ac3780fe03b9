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
from .storage import _error, recover_folder


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


def meta_band(meta: Mapping[str, Any], key: str, path: Path) -> tuple[float, float]:
    """A frequency band [f_low, f_high] [Hz] with 0 <= f_low < f_high < inf."""
    allowed = "[f_low, f_high] in Hz with 0 <= f_low < f_high, finite"
    value = _get(meta, key, path, allowed)
    ok = (isinstance(value, list) and len(value) == 2
          and all(isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) for v in value)
          and 0 <= value[0] < value[1])
    if not ok:
        raise _where(path, key, value, allowed, "bad value")
    return float(value[0]), float(value[1])


def meta_dict(meta: Mapping[str, Any], key: str, path: Path, optional: bool = False) -> dict[str, Any]:
    if optional and key not in meta:
        return {}
    value = _get(meta, key, path, "a JSON object")
    if not isinstance(value, dict):
        raise _where(path, key, value, "a JSON object", "wrong type")
    return value


_UNIT = re.compile(r"[A-Za-z0-9_/^*.()+\- ]{0,32}\Z")
UNIT_RULE = "units such as m, m/s^2, rad/s, N (at most 32 of A-Z a-z 0-9 _ / ^ * . ( ) + - and space)"


def meta_channels(meta: Mapping[str, Any], path: Path) -> tuple[list[str], list[str]]:
    """Channel names (the naming rule of :mod:`tb_exudyn.system.channels`, all different) and their units."""
    names = meta_str_list(meta, "channels", path, check=is_channel_name, rule=f"channel names: {CHANNEL_NAME_RULE}",
                          unique=True)
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


__all__ = ["open_result_folder", "meta_str", "meta_str_list", "meta_int", "meta_band", "meta_dict", "meta_channels", "meta_scenario", "UNIT_RULE"]
