"""A readable table of a resolved scenario (for ``tb-exudyn show``)."""

from __future__ import annotations

import math
from dataclasses import fields, is_dataclass
from typing import Any, Sequence

from .model import Scenario


def _fmt(value: Any) -> str:
    if value is None:
        return "none"
    if isinstance(value, float):
        return "inf" if math.isinf(value) else f"{value:.6g}"
    if isinstance(value, tuple):
        if value and all(is_dataclass(v) for v in value):
            return ", ".join(getattr(v, "name", type(v).__name__) for v in value)
        return "[" + ", ".join(_fmt(v) for v in value) + "]"
    return str(value)


def _rows(obj: Any, prefix: str, out: list[tuple[str, str, str, str]]) -> None:
    kind = getattr(type(obj), "kind", None)
    if isinstance(kind, str):
        out.append((f"{prefix}.kind" if prefix else "kind", kind, "", "model kind"))
    for f in fields(obj):
        value = getattr(obj, f.name)
        key = f"{prefix}.{f.name}" if prefix else f.name
        if f.name in ("notes", "source") and prefix:
            continue
        if is_dataclass(value):
            _rows(value, key, out)
        elif isinstance(value, tuple) and value and all(is_dataclass(v) for v in value):
            out.append((key, _fmt(value), f.metadata.get("unit", ""), f.metadata.get("doc", "")))
            for i, v in enumerate(value):
                _rows(v, f"{key}[{i}]", out)
        else:
            out.append((key, _fmt(value), f.metadata.get("unit", ""), f.metadata.get("doc", "")))


def scenario_table(scenario: Scenario, extra_rows: Sequence[tuple[str, str, str, str]] = (), *,
                   vehicles_once: bool = True) -> str:
    """Key, value, unit and meaning of every setting, with derived quantities (and ``extra_rows``,
    e.g. the bridge's frequencies) at the end.

    With ``vehicles_once`` a vehicle that appears several times in the train is listed once.
    """
    rows: list[tuple[str, str, str, str]] = []
    _rows(scenario, "", rows)
    if vehicles_once:
        seen: dict[str, str] = {}
        kept = []
        for row in rows:
            head = row[0].split(".")[0:2]
            if len(head) == 2 and head[0] == "train" and head[1].startswith("vehicles["):
                idx = head[1]
                name = next((r[1] for r in rows if r[0] == f"train.{idx}.name"), idx)
                if name in seen and seen[name] != idx:
                    continue
                seen.setdefault(name, idx)
            kept.append(row)
        rows = kept
    rows += [
        ("(derived) speed", _fmt(scenario.speed), "m/s", "train speed"),
        ("(derived) train length", _fmt(scenario.train.length), "m", "first to last axle"),
        ("(derived) axles", str(len(scenario.train.axle_positions)), "", "number of axles"),
        ("(derived) bridge length", _fmt(scenario.bridge.length), "m", "sum of spans"),
        ("(derived) duration", _fmt(scenario.duration), "s", "first axle at -lead_in until last axle run_out past the bridge"),
        ("(derived) time steps", str(int(round(scenario.duration / scenario.analysis.time_step))), "", "duration / time_step"),
        *extra_rows,
    ]
    w0 = max(len(r[0]) for r in rows)
    w1 = min(max(len(r[1]) for r in rows), 40)
    w2 = max(len(r[2]) for r in rows)
    lines = [f"Scenario {scenario.name}: {scenario.description}", f"Source: {scenario.source}", ""]
    lines.append(f"{'key':<{w0}}  {'value':<{w1}}  {'unit':<{w2}}  meaning")
    lines.append("-" * (w0 + w1 + w2 + 20))
    for key, value, unit, doc in rows:
        if key in ("name", "description", "source", "notes"):
            continue
        lines.append(f"{key:<{w0}}  {value:<{w1}}  {unit:<{w2}}  {doc}")
    if scenario.notes:
        lines += ["", f"Notes: {scenario.notes}"]
    return "\n".join(lines)


__all__ = ["scenario_table"]
