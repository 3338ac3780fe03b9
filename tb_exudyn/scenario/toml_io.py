"""Reading and writing TOML: tomllib to read, a small writer for the scenario's plain data."""

from __future__ import annotations

import math
import tomllib
from pathlib import Path
from typing import Any

from ..atomic import write_text_atomic  # noqa: F401  (re-exported for scenario.io)
from ..files import MIB, FileRefused, read_text
from .errors import ScenarioError


#: largest scenario, vehicle or bridge file read [bytes] (a resolved scenario is a few kB)
MAX_TOML_BYTES = 4 * MIB


def read_toml(path: Path) -> dict:
    """Parse a TOML file; a missing, unreadable, non-regular (FIFO, device, directory), oversized,
    non-UTF-8 or malformed file becomes a ScenarioError naming the file."""
    allowed = f"UTF-8 TOML, <= {MAX_TOML_BYTES // MIB} MiB"
    try:
        text = read_text(path, max_bytes=MAX_TOML_BYTES, follow_symlinks=True)
    except FileNotFoundError:
        tried = "" if Path(path).is_absolute() else f" (looked for {Path(path).absolute()})"
        raise ScenarioError(str(path), "<file>", str(path), "an existing TOML file", "file not found" + tried) from None
    except FileRefused as exc:
        raise ScenarioError(str(path), "<file>", str(path), allowed, str(exc)) from None
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ScenarioError(str(path), "<file>", str(exc), "valid TOML (https://toml.io)", "syntax error") from None
    except RecursionError:
        raise ScenarioError(str(path), "<file>", str(path), "valid TOML nested a few levels deep",
                            "nested too deeply") from None


def _scalar(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        if math.isnan(value):
            return "nan"
        return repr(value)
    if isinstance(value, str):
        escaped = value.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n").replace("\t", "\\t")
        return f'"{escaped}"'
    if isinstance(value, list):
        return "[" + ", ".join(_scalar(v) for v in value) + "]"
    raise TypeError(f"cannot write {type(value).__name__} to TOML")


def _is_table_array(value: Any) -> bool:
    return isinstance(value, list) and bool(value) and all(isinstance(v, dict) for v in value)


def _write_table(lines: list[str], table: dict, prefix: str) -> None:
    for key, value in table.items():
        if not isinstance(value, dict) and not _is_table_array(value):
            lines.append(f"{key} = {_scalar(value)}")
    for key, value in table.items():
        name = f"{prefix}.{key}" if prefix else key
        if isinstance(value, dict):
            lines.append("")
            lines.append(f"[{name}]")
            _write_table(lines, value, name)
        elif _is_table_array(value):
            for item in value:
                lines.append("")
                lines.append(f"[[{name}]]")
                _write_table(lines, item, name)


def dumps_toml(data: dict, header: str = "") -> str:
    """TOML text of nested dicts/lists of str, int, float (inf allowed) and bool."""
    lines = [f"# {h}" for h in header.splitlines()] if header else []
    _write_table(lines, data, "")
    return "\n".join(lines).lstrip("\n") + "\n"
