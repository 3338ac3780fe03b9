"""A readable table of a resolved scenario (for ``tb-exudyn show``)."""

from __future__ import annotations

import math
import textwrap
from dataclasses import fields, is_dataclass
from typing import Any, Sequence

from .model import Scenario
from .sections import track_lines
from .track_structure import load_track_structure


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


def track_rows(scenario: Scenario) -> list[tuple[str, str, str, str]]:
    """The ``show`` rows of a bridge with two tracks or more: each track's offset and rail level, and
    the one the train runs on (none for one track: its track_offset/track_height rows say it)."""
    lines = track_lines(scenario.bridge)
    if len(lines) < 2:
        return []
    rows = [(f"(derived) track {i + 1}", f"{e:g}, {h:g}", "m",
             "offset from the girder axis (+y left), rail level above the shear centre"
             + ("; the train's track (track.on)" if i + 1 == scenario.track.on else ""))
            for i, (e, h) in enumerate(lines)]
    return rows


def track_structure_rows(scenario: Scenario) -> list[tuple[str, str, str, str]]:
    """The ``show`` rows of a scenario's track structure (none without one): its kind, spacing, depth and
    the chain under one rail seat (docs/track.md)."""
    if not scenario.track.structure:
        return []
    ts = load_track_structure(scenario.track.structure, scenario.source_file)
    parts = ("pad", "sleeper", "ballast", "subgrade") if ts.kind == "ballasted" else ("pad", "slab", "mortar", "base")
    chain = "; ".join(
        f"{p} {getattr(ts, p).mass:g} kg" if not hasattr(getattr(ts, p), "stiffness") else
        f"{p} {getattr(ts, p).stiffness:.3g} N/m, {getattr(ts, p).damping:.3g} N s/m"
        + (f", {getattr(ts, p).mass:g} kg" if getattr(ts, p).mass else "") for p in parts)
    return [("(derived) track structure", f"{ts.kind}, {ts.spacing:g} m, {ts.depth:.3g} m deep", "",
             f"'{ts.name}': support spacing, rail head to deck; per rail and support: {chain}. Both rails on "
             "these supports under the whole run, the subgrade off the bridge; runs on the linear engines (batched, dense) with "
             "sprung masses and moving forces (docs/track.md)")]


#: the model kinds in a bridge engineer's words (the value shown is what a file's ``kind`` holds)
KIND_WORDS = {"car15": "15-DOF car (body, two bogies, four wheelsets that follow the rail)",
              "creep_car": "15-DOF car with creep-guided wheelsets (running safety)",
              "articulated": "articulated set (car bodies on shared bogies)",
              "sprung_mass": "sprung mass on one axle", "moving_force": "moving force (no mass)",
              "simple_beam": "simply supported spans on ideal supports",
              "frame": "simply supported girders on bearings and piers",
              "continuous": "girder continuous over its supports", "modal_table": "modes imported from tables"}
#: a listing's line width (a terminal line is at most 200 characters; 160 leaves the meaning readable)
LISTING_WIDTH = 160
#: keys said in the heading or the notes, not as rows
_HEAD_KEYS = ("name", "description", "source", "notes")


def model_rows(obj: Any) -> list[tuple[str, str, str, str]]:
    """(key, value, unit, meaning) of every setting of a scenario, bridge or vehicle, keys as in its file."""
    rows: list[tuple[str, str, str, str]] = []
    _rows(obj, "", rows)
    return [(k, v, u, f"model kind: {KIND_WORDS[v]}" if k.endswith("kind") and v in KIND_WORDS else d)
            for k, v, u, d in rows]


def _group(key: str) -> str:
    """The group a key is listed under: its first part (a vehicle of the train: train.vehicles[i])."""
    if key.startswith("(derived)"):
        return "derived"
    parts = key.split(".")
    if len(parts) > 2 and parts[0] == "train" and parts[1].startswith("vehicles["):
        return ".".join(parts[:2])
    return parts[0] if len(parts) > 1 else ""


def table_text(head: Sequence[str], rows: Sequence[tuple[str, str, str, str]], notes: str = "", source: str = "",
               width: int = LISTING_WIDTH) -> str:
    """Key, value, unit and meaning, grouped by the key's first part (a blank line between groups),
    aligned, the meaning (and a long value) wrapped within ``width`` characters."""
    rows = [r for r in rows if r[0] not in _HEAD_KEYS]
    w0 = max((len(r[0]) for r in rows), default=3)
    w1 = min(max((len(r[1]) for r in rows), default=5), 16)
    w2 = max((len(r[2]) for r in rows), default=4)
    indent = " " * (w0 + w1 + w2 + 6)
    fill = max(width - len(indent), 40)
    lines = [textwrap.fill(h, width, subsequent_indent="  ", break_on_hyphens=False) for h in head if h]
    if source:
        lines.append(textwrap.fill(f"Source: {source}", width, subsequent_indent="  ", break_on_hyphens=False))
    lines += ["", f"{'key':<{w0}}  {'value':<{w1}}  {'unit':<{w2}}  meaning"]
    group = None
    for key, value, unit, doc in rows:
        if _group(key) != group and group is not None:
            lines.append("")
        group = _group(key)
        meaning = textwrap.wrap(doc, fill, break_on_hyphens=False) or [""]
        if len(value) > w1:  # a long value on its own lines, the unit and meaning below it
            lines += textwrap.wrap(f"{key:<{w0}}  {value}", width, subsequent_indent=" " * (w0 + 2),
                                   break_on_hyphens=False)
            lines.append(f"{'':<{w0}}  {'':<{w1}}  {unit:<{w2}}  {meaning[0]}".rstrip())
        else:
            lines.append(f"{key:<{w0}}  {value:<{w1}}  {unit:<{w2}}  {meaning[0]}".rstrip())
        lines += [indent + m for m in meaning[1:]]
    if notes:
        lines += ["", textwrap.fill(f"Notes: {' '.join(notes.split())}", width, break_on_hyphens=False)]
    return "\n".join(lines)


def scenario_table(scenario: Scenario, extra_rows: Sequence[tuple[str, str, str, str]] = (), *,
                   vehicles_once: bool = True) -> str:
    """Key, value, unit and meaning of every setting, with derived quantities (and ``extra_rows``,
    e.g. the bridge's frequencies) at the end, grouped and wrapped (:func:`table_text`).

    With ``vehicles_once`` a vehicle that appears several times in the train is listed once.
    """
    rows = model_rows(scenario)
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
    rows = [r for r in rows if not r[0].endswith((".notes", ".source"))]
    rows += [
        ("(derived) speed", f"{scenario.speed:.4g}", "m/s", "train speed"),
        ("(derived) train length", _fmt(scenario.train.length), "m", "first to last axle"),
        ("(derived) axles", str(len(scenario.train.axle_positions)), "", "number of axles"),
        ("(derived) bridge length", _fmt(scenario.bridge.length), "m", "sum of spans"),
        *track_rows(scenario),
        *track_structure_rows(scenario),
        ("(derived) duration", f"{scenario.duration:.4g}", "s", "first axle at -lead_in until last axle run_out past the bridge"),
        ("(derived) time steps", str(int(round(scenario.duration / scenario.analysis.time_step))), "", "duration / time_step"),
        *extra_rows,
    ]
    return table_text([f"Scenario {scenario.name}: {scenario.description}"], rows, scenario.notes, scenario.source)


def run_label(scenario: Scenario) -> str:
    """One line saying what a run is, from its own settings (not the scenario's description, which
    an override such as ``--speed-kmh`` does not change): the train, the speed, the bridge, the
    irregularities and the PEM frequency band and grid. E.g. "4 vehicles (ice_motor, ice_trailer x2,
    ice_motor) at 300 km/h over li_zhu_2011_bridge (3 x 32 m); german_low vertical, alignment,
    cross_level; 0.3-60 Hz, 200 linear frequencies"."""
    names = [v.name for v in scenario.train.vehicles]
    runs: list[str] = []
    for name in names:  # neighbours of one name as "name xN"
        if runs and runs[-1].split(" x")[0] == name:
            head, _, count = runs[-1].partition(" x")
            runs[-1] = f"{head} x{int(count or 1) + 1}"
        else:
            runs.append(name)
    n = len(names)
    train = f"{n} vehicle{'s' if n != 1 else ''} ({', '.join(runs)})"
    spans = scenario.bridge.spans
    if len(set(spans)) == 1:
        layout = f"{len(spans)} x {spans[0]:g} m" if len(spans) > 1 else f"{spans[0]:g} m"
    else:
        layout = " + ".join(f"{x:g}" for x in spans) + " m"
    types = list(scenario.track.irregularities)
    groups: dict[str, list[str]] = {}
    for t in types:
        spectrum, _, kind = t.partition(".")
        groups.setdefault(spectrum, []).append(kind or spectrum)
    irr = "; ".join(f"{k} {', '.join(v)}" for k, v in groups.items()) or "no irregularity"
    an = scenario.analysis
    n_tracks = len(track_lines(scenario.bridge))
    if n_tracks > 1:
        layout += f", track {scenario.track.on} of {n_tracks}"
    return (f"{train} at {scenario.speed_kmh:.1f}".removesuffix(".0") + f" km/h over {scenario.bridge.name} ({layout}); {irr}; "
            f"{an.freq_min:.3g}-{an.freq_max:.3g} Hz, {an.n_freq} {an.freq_spacing} frequencies")


__all__ = ["KIND_WORDS", "LISTING_WIDTH", "model_rows", "run_label", "scenario_table", "table_text", "track_rows", "track_structure_rows"]
