"""``tb-exudyn show`` and ``modes`` of any model: a scenario, a bridge, a vehicle or a train, named from the
model library or given as a TOML file (the command parses and prints; this module finds what the name is and
writes the bridge's frequency rows: f1 and f3 by direction, the closed-form f1 of its girder beside the FE
one and why they differ)."""

from __future__ import annotations

import math
import re
import textwrap
import argparse
from pathlib import Path
from typing import Any

from ..scenario.show import LISTING_WIDTH, scenario_table
from . import scenario as cli_scenario, text as cli_text
from ..codes.trains import composition_table, load_train, train_files
from ..errors import ScenarioError, SettingError
from ..scenario import load_scenario
from ..scenario.io import load_bridge, load_vehicle
from ..scenario.model import BRIDGE_KINDS, VEHICLE_KINDS
from ..scenario.registry import model_files
from ..scenario.show import model_rows, table_text
from ..scenario.toml_io import read_toml
from ..structure import StructureError, modal_bridge
from ..system.damping_guard import merged_messages
from ..system.modes import DIRECTIONS, nth_frequency

#: what `show` and `modes` take, in the order a library name is looked up
MODEL_KINDS = ("scenario", "bridge", "vehicle", "train")
_CATEGORY = {"scenario": "scenarios", "bridge": "bridges", "vehicle": "vehicles"}
#: bridge modes up to this frequency for the rows of a bridge shown alone [Hz] (analysis.mode_max_frequency's default)
SHOW_MAX_FREQUENCY = 60.0
#: the width the mode lists wrap at
LINE_WIDTH = 160


def model_kind(text: str) -> str:
    """What ``text`` names: 'scenario', 'bridge', 'vehicle' or 'train' (a TOML file by its content: a
    ``kind`` of a bridge or a vehicle, ``cars`` of a train, else a scenario; a name by the library's
    folders, scenarios first). A name in no folder is a SettingError listing where names come from."""
    path = Path(text)
    if path.suffix == ".toml" or path.exists():
        if not path.is_file():
            return "scenario"  # load_scenario names the file and why it cannot be read
        data = read_toml(path)
        kind = data.get("kind")
        if isinstance(kind, str) and kind in BRIDGE_KINDS:
            return "bridge"
        if isinstance(kind, str) and kind in VEHICLE_KINDS:
            return "vehicle"
        if "kind" in data:  # neither a bridge's nor a vehicle's: say which kinds are
            raise ScenarioError(str(path), "kind", kind, "a bridge kind (" + ", ".join(BRIDGE_KINDS) + ") or a vehicle "
                                "kind (" + ", ".join(VEHICLE_KINDS) + ")", "unknown model kind")
        return "train" if "cars" in data else "scenario"
    for kind in MODEL_KINDS:
        names = train_files() if kind == "train" else model_files(_CATEGORY[kind])
        if text in names:
            return kind
    raise SettingError("command line", "MODEL", text, "a scenario, bridge, vehicle or train name of `tb-exudyn list`, "
                       "or a path to a .toml file", "unknown name")


def homonym_note(text: str, kind: str) -> str | None:
    """A line when the library name ``text`` also names a model of another kind (ave_s103: a vehicle and a
    train): which one is shown and the file that names the other; None for a file or a unique name."""
    path = Path(text)
    if path.suffix == ".toml" or path.exists():
        return None
    files = {k: (train_files() if k == "train" else model_files(_CATEGORY[k])).get(text) for k in MODEL_KINDS}
    others = [f"the {k}: {files[k]}" for k in MODEL_KINDS if k != kind and files[k] is not None]
    return f"({text} names a {kind}, shown here, and also " + "; ".join(others) + ")" if others else None


def load_model(kind: str, text: str) -> Any:
    """The model ``text`` names, of kind ``kind`` (:func:`model_kind`)."""
    path = Path(text)
    if kind == "train":
        return load_train(path if path.suffix == ".toml" or path.exists() else train_files()[text])
    return {"scenario": load_scenario, "bridge": load_bridge, "vehicle": load_vehicle}[kind](text)


def hand_f1(bridge: Any) -> tuple[float, float] | None:
    """(f1 [Hz], span [m]): the first vertical frequency of the girder's longest span as a simply supported
    Euler-Bernoulli beam, pi / (2 L^2) sqrt(E I_y / m), m the girder's mass with the added mass (None for a
    bridge without girder sections, e.g. a modal_table)."""
    sections = getattr(bridge, "sections", None)
    if not sections:
        return None
    added = getattr(getattr(bridge, "added_mass", None), "mass_per_length", 0.0)
    best = None
    for span, g in zip(bridge.spans, sections):
        f = math.pi / (2.0 * span ** 2) * math.sqrt(g.E * g.I_y / (g.mass_per_length + added))
        if best is None or f < best[0]:
            best = (f, span)
    return best


def _vertical_f1(bridge: Any) -> float:
    mb = modal_bridge(bridge, SHOW_MAX_FREQUENCY, 0)
    return nth_frequency(mb.frequencies, mb.mode_types, "vertical", 1)


def why_f1_differs(bridge: Any, fe: float, hand: float, span: float) -> str:
    """One sentence on why the FE f1 differs from the hand value, from the model's own numbers: for
    bearings below the girder axis, the FE f1 with them moved to the axis (the split computed, not
    assumed); the rest named by what the bridge has (piers, continuity, shear deformation)."""
    d = fe / hand - 1.0
    if abs(d) < 0.001:
        return (f"FE and closed form agree ({100 * d:+.2f} %): in its first mode the girder bends as a simply "
                "supported span")
    parts = []
    bearings = getattr(bridge, "bearings", None)
    h = getattr(bearings, "height", 0.0) if bearings is not None else 0.0
    rest = d
    if h > 0.0:
        try:
            at_axis = _vertical_f1(bridge.replace(bearings=bearings.replace(height=0.0)))
        except StructureError:
            at_axis = math.nan
        if math.isfinite(at_axis):
            e = fe / at_axis - 1.0
            rest = at_axis / hand - 1.0
            said = (f"{100 * e:+.1f} % from the bearings {h:g} m below the girder axis (FE with them at the axis: "
                    f"{at_axis:.3f} Hz)")
            if bridge.kind == "frame" and e < -0.001:  # simple spans, one end fixed lengthwise: the mechanism
                r = 2 * math.pi ** 2 * (h / span) ** 2
                said += (": as the span bends its ends rotate about the bearings, so the whole girder slides along the "
                         f"bridge and its mass moves lengthwise too (a sine-shape estimate: {100 * r:.1f} % more modal "
                         f"mass, {100 * ((1 + r) ** -0.5 - 1):+.1f} % in f1)")
            parts.append(said)
    causes = []
    if getattr(bridge, "pier", None) is not None:
        causes.append("the piers' flexibility")
    if bearings is not None and any(math.isfinite(getattr(bearings, k, math.inf)) for k in ("k_z", "k_x_fixed")):
        causes.append("the bearings' springs")
    if bridge.kind == "continuous":
        causes.append("continuity over the supports")
    if any(getattr(g, "shear_area_factor", 0.0) > 0.0 for g in bridge.sections):
        causes.append("shear deformation and rotary inertia (Timoshenko beam)")
    if abs(rest) >= 0.001 or not parts:
        parts.append(f"{100 * rest:+.1f} % from " + (" and ".join(causes) or "the FE mesh"))
    return f"FE {100 * d:+.1f} % against the closed form: " + "; ".join(parts)


def frequency_rows(bridge: Any, max_frequency: float = SHOW_MAX_FREQUENCY, max_modes: int = 0,
                   key: str = "") -> list[tuple[str, str, str, str]]:
    """Rows with f1 and f3 of the bridge alone by direction (vertical, lateral, torsion) [Hz], the
    closed-form f1 of its girder and why the two differ (modes up to ``max_frequency``)."""
    try:
        mb = modal_bridge(bridge, max_frequency, max_modes)
    except StructureError as exc:
        return [(f"{key}modes", "not available", "", str(exc))]
    source = "from its modes tables" if bridge.kind == "modal_table" else "FE"
    rows = []
    for d in DIRECTIONS:
        f = [nth_frequency(mb.frequencies, mb.mode_types, d, n) for n in (1, 3)]
        text = ", ".join("-" if math.isnan(x) else f"{x:.4g}" for x in f)
        rows.append((f"{key}f1, f3 {d}", text, "Hz", f"1st and 3rd {d} mode of the bridge alone, {source} "
                     f"('-': none up to {max_frequency:g} Hz)"))
    hand = hand_f1(bridge)
    fe = nth_frequency(mb.frequencies, mb.mode_types, "vertical", 1)
    if hand is not None and math.isfinite(fe):
        rows.append((f"{key}f1 vertical, closed form", f"{hand[0]:.4g}", "Hz",
                     f"the girder's {hand[1]:g} m span simply supported, pi / (2 L^2) sqrt(E I_y / m), m with the "
                     f"added mass; FE {fe:.4g} Hz"))
        rows.append((f"{key}FE against closed form", f"{100 * (fe / hand[0] - 1):+.1f} %", "",
                     why_f1_differs(bridge, fe, hand[0], hand[1])))
    return rows


def bridge_modes_text(bridge: Any, band: tuple[float, float] | None = None) -> str:
    """``modes`` of a bridge alone (no vehicle): every mode up to :data:`SHOW_MAX_FREQUENCY` (or in
    ``band``) with its frequency, damping ratio and direction, numbered within its direction."""
    top = SHOW_MAX_FREQUENCY if band is None else band[1]
    mb = modal_bridge(bridge, top, 0)
    source = "its modes tables" if bridge.kind == "modal_table" else "finite-element model"
    lines = [f"modes of bridge {bridge.name} alone (no vehicle; {source}), up to {top:g} Hz",
             f"{'#':>4} {'f [Hz]':>9} {'zeta':>7}  mode"]
    count: dict[str, int] = {}
    shown = 0
    for f, z, t in zip(mb.frequencies, mb.damping_ratios, mb.mode_types):
        count[t] = count.get(t, 0) + 1
        if band is not None and not band[0] <= f <= band[1]:
            continue
        shown += 1
        lines.append(f"{shown:>4} {f:>9.4g} {z:>7.3g}  {t} {count[t]}")
    if not shown:
        lines.append("  (no mode in the band)")
    return "\n".join(lines)


def vehicle_scenario(vehicle: Any) -> Any:
    """A scenario of ``vehicle`` alone on the rigid approach track of the ``quick`` scenario (its contact
    springs and damping): what ``modes`` of a vehicle computes, at the start of the run (bridge free)."""
    base = load_scenario("quick")
    return base.replace(name=f"vehicle {vehicle.name}", train=base.train.replace(vehicles=(vehicle,)),
                        analysis=base.analysis.replace(channels=("*",)))


def train_vehicles(train: Any) -> tuple[list[Any], list[str]]:
    """The distinct vehicle models among a train's cars, and the names of the parts that are none (axle
    loads, articulated sets: moving forces without a vehicle model)."""
    models, others = {}, []
    for part in train.parts:
        if part.kind == "vehicle" and part.name not in models:
            models[part.name] = load_vehicle(part.name)
        elif part.kind != "vehicle" and part.name not in others:
            others.append(part.name)
    return list(models.values()), others


_CAR = re.compile(r"^car (\d+) \(([^)]*)\)")


def modes_text(table: Any) -> list[str]:
    """A mode table in few lines: one row per distinct vehicle mode, equal modes of equal cars (same
    frequency, damping and motion) on one row naming the cars and equal frequencies' motions joined; the
    wheelsets on their contact springs as one line per direction (their frequency range), the bridge's modes as
    one list per direction; "not excited here" where no track input reaches a mode."""
    bridge: dict[str, list[str]] = {}
    contact: dict[str, list[tuple[float, float]]] = {}
    rows: dict[tuple, list] = {}
    reached = table.reached()
    tau = table.decay_time
    for i in range(len(table)):
        f, label, kind, z = table.frequency[i], table.label[i], table.kind[i], table.damping_ratio[i]
        m = _CAR.match(label)
        motion = label[m.end():].removeprefix(", ") if m else label
        if kind == "bridge" and label.startswith("bridge, "):
            bridge.setdefault(label.removeprefix("bridge, ").rsplit(" ", 1)[0], []).append(f"{f:.4g}")
            continue
        if kind == "contact":
            contact.setdefault(motion.rsplit(", ", 1)[-1], []).append((f, z))
            continue
        z = 0.0 if abs(z) < 1e-9 else z  # an undamped mode's round-off (-0, 1e-17) is 0
        zs = ">= 1" if table.overdamped[i] else ("-" if not math.isfinite(z) else f"{z:.3g}")
        key = (f"{f:.4g}", zs, kind, m.group(2) if m else "", bool(reached[i]))
        row = rows.setdefault(key, [f, tau[i], [], []])
        if m and m.group(1) not in row[2]:
            row[2].append(m.group(1))
        row[3].append(motion)
    lines = [f"{'f_n [Hz]':>9} {'zeta':>9} {'decay [s]':>9} {'kind':<8} what moves"]
    for (_, zs, kind, vehicle, hit), (f, t, cars, motions) in rows.items():
        names = list(dict.fromkeys(motions))
        n_each = len(motions) // max(len(cars), 1)
        what = "; ".join(names) + (f" (x{n_each})" if len(names) == 1 and n_each > 1 else "")
        who = f"car{'s' if len(cars) > 1 else ''} {', '.join(cars)} ({vehicle}): " if cars else ""
        lines.append(f"{f:>9.4g} {zs:>9} {'inf' if not math.isfinite(t) else f'{t:.3g}':>9} {kind:<8} {who}{what}"
                     + ("" if hit else " (not excited here: no track input reaches it)"))
    for direction, fz in contact.items():
        fs, zs = [f for f, _ in fz], [z for _, z in fz]
        zr = f"{min(zs):.2g}" if f"{min(zs):.2g}" == f"{max(zs):.2g}" else f"{min(zs):.2g}-{max(zs):.2g}"
        lines.append(f"{min(fs):>9.4g} {zr:>9} {'':>9} {'contact':<8} every wheelset on its "
                     f"contact springs, {direction}: {len(fs)} modes, {min(fs):.4g}-{max(fs):.4g} Hz")
    track = [float(f) for d, fs in bridge.items() if d.split(" ")[0] == "track" for f in fs]
    for direction, fs in bridge.items():
        if direction.split(" ")[0] != "track":
            lines.append(textwrap.fill(f"bridge {direction} [Hz]: {', '.join(fs)}", LINE_WIDTH, subsequent_indent="  "))
    if track:  # the track's modes (track.structure: rails, pads, sleepers, ballast with the deck), summarised
        lines.append(f"track (rails, pads, sleepers, ballast; with the deck): {len(track)} modes, "
                     f"{min(track):.4g}-{max(track):.4g} Hz")
    lines.append("(f_n undamped |lambda| / 2 pi; zeta >= 1: a non-oscillating motion; decay = 1 / (zeta omega_n))")
    return lines


_AT = re.compile(r"first axle at x = \S+ m \(t = ([^)]*)\), (\d+ of \d+) axles on the bridge")


def _span(fs: list[float]) -> str:
    lo, hi = f"{min(fs):.4g}", f"{max(fs):.4g}"
    return lo if lo == hi else f"{lo}-{hi}"


def positions_text(tables: list[Any], positions: list[float]) -> list[str]:
    """``modes`` at several train positions as one table of f_n [Hz], a column per position, within a
    screen (one table per position took about 50 lines each): a row per group of the first position's
    vehicle modes (as :func:`modes_text` groups them), each position's vehicle modes matched to them by
    rank (the k-th lowest), a range where a group's modes split (a car on the bridge, its twin not);
    the wheelsets' contact modes by direction; the bridge's lowest mode per direction."""
    first = tables[0]
    head, _, rest = first.description.partition(":")
    lines = [f"{head}: the first axle at {len(tables)} positions; {rest.rpartition(';')[2].strip()}"]
    where = []
    for x, t in zip(positions, tables):
        m = _AT.search(t.description)
        where.append(f"x = {x:g} m" + (f" ({m[2]} axles on, t = {m[1]})" if m else ""))
    lines += textwrap.wrap("on the bridge: " + "; ".join(where), LINE_WIDTH, subsequent_indent="  ")

    def vehicle_f(t: Any) -> list[float]:
        return sorted(float(t.frequency[i]) for i in range(len(t)) if t.kind[i] == "vehicle")

    groups: dict[tuple, list] = {}  # (f, vehicle) -> [cars, motions, ranks] of the first position
    order = sorted((i for i in range(len(first)) if first.kind[i] == "vehicle"), key=lambda i: first.frequency[i])
    for rank, i in enumerate(order):
        m = _CAR.match(first.label[i])
        g = groups.setdefault((f"{first.frequency[i]:.4g}", m.group(2) if m else ""), [[], [], []])
        if m and m.group(1) not in g[0]:
            g[0].append(m.group(1))
        motion = first.label[i][m.end():].removeprefix(", ") if m else first.label[i]
        if motion not in g[1]:
            g[1].append(motion)
        g[2].append(rank)
    rows: list[tuple[str, list[str]]] = []
    vf = [vehicle_f(t) for t in tables]
    for (_, vehicle), (cars, motions, ranks) in groups.items():
        who = f"car{'s' if len(cars) > 1 else ''} {', '.join(cars)} ({vehicle}): " if cars else ""
        rows.append((who + "; ".join(motions), [_span([f[r] for r in ranks if r < len(f)] or [math.nan]) for f in vf]))
    for kind, label, pick in (("contact", "every wheelset on its contact springs, {}", None),
                              ("bridge", "bridge {}, lowest mode", min)):
        found: dict[str, list[list[float]]] = {}
        for j, t in enumerate(tables):
            for i in range(len(t)):
                if t.kind[i] != kind:
                    continue
                what = (t.label[i].removeprefix("bridge, ").split(" ", 1)[0] if kind == "bridge"  # its first
                        else t.label[i].rsplit(", ", 1)[-1])  # direction (a mixed label: "torsion 18 + pier")
                found.setdefault(what, [[] for _ in tables])[j].append(float(t.frequency[i]))
        for what, per in found.items():
            rows.append((label.format(what), [(f"{pick(fs):.4g}" if pick else _span(fs)) if fs else "-" for fs in per]))
    names = [f"x = {x:g} m" for x in positions]
    wl = max(len(r[0]) for r in rows)
    wc = [max(len(n), *(len(r[1][j]) for r in rows)) for j, n in enumerate(names)]
    lines.append(f"{'f_n [Hz] of':<{wl}} " + " ".join(f"{n:>{w}}" for n, w in zip(names, wc)))
    lines += [f"{label:<{wl}} " + " ".join(f"{c:>{w}}" for c, w in zip(cells, wc)) for label, cells in rows]
    lines.append("(f_n undamped |lambda| / 2 pi; vehicle modes matched to the first position's by rank; "
                 "one --position: damping, decay and every bridge mode)")
    return lines


def command_model(args: argparse.Namespace) -> tuple[str, object]:
    """(kind, model) of MODEL (model_kind: a scenario, bridge, vehicle or train); --set only for a scenario."""
    kind = model_kind(args.scenario)
    if kind != "scenario" and args.settings:
        raise SettingError("command line", "--set", args.settings[0], "--set with a scenario (its keys); for a "
                           f"{kind}, edit a copy of its file and name the copy", f"{args.scenario!r} is a {kind}")
    return kind, (cli_scenario.load(args) if kind == "scenario" else load_model(kind, args.scenario))


def vehicle_modes(args: argparse.Namespace, kind: str, model, methods) -> list[str]:  # noqa: ANN001
    """``modes`` of a vehicle, or of each vehicle model of a train: on rigid track, alone (``methods``:
    tb_exudyn.methods, imported by the command)."""
    out: list[str] = []
    vehicles, others = ([model], []) if kind == "vehicle" else train_vehicles(model)
    for vehicle in vehicles:
        scenario = vehicle_scenario(vehicle)
        table = methods.system_modes(scenario, None)
        table = table.select([k in ("vehicle", "contact", "decoupled") for k in table.kind])  # not the bridge's
        shown = table if args.all else table.select([k != "decoupled" for k in table.kind])
        shown = shown.in_band(*args.band) if args.band is not None else shown
        out.append(f"modes of vehicle {vehicle.name} alone on rigid track (wheel-rail contact springs and damping "
                   "of the quick scenario), linearised about rest")
        out += modes_text(shown) if len(shown) else ["  (no mode: a moving force has no degree of freedom)"]
        out.append("")
    if others:
        out.append(f"{', '.join(others)}: axle loads without a vehicle model (moving forces), no modes")
    return out


def scenario_modes(args: argparse.Namespace, scenario: Any, methods: Any) -> list[str]:
    """``modes`` of a scenario: the train at each --position (default: the start of the run: vehicles on
    rigid track, the bridge alone), in :func:`modes_text`'s few lines, and the damping guard."""
    out: list[str] = []
    model = methods.build_model(scenario, warn=False)
    if args.position and len(args.position) > 1:  # one table, a column per position: within a screen
        tables = []
        for position in args.position:
            table = methods.system_modes(scenario, position, model=model)
            shown = table if args.all else table.select([k != "decoupled" for k in table.kind])
            tables.append(shown.in_band(*args.band) if args.band is not None else shown)
        out += [*positions_text(tables, list(args.position)), ""]
    for position in [] if args.position and len(args.position) > 1 else args.position or [None]:
        table = methods.system_modes(scenario, position, model=model)
        shown = table if args.all else table.select([k != "decoupled" for k in table.kind])
        if args.band is not None:
            shown = shown.in_band(*args.band)
        out += [table.description, *modes_text(shown)]
        if len(shown) < len(table):
            why = ("outside --band; " if args.band else "") + ("" if args.all else "decoupled weak-spring modes (--all)")
            out.append(f"({len(table) - len(shown)} of {len(table)} modes not shown: {why})")
        out.append("")
    if not scenario.track.irregularities:
        return out + ["damping guard: not applicable (no track irregularities, so no random run)"]
    warnings = methods.damping_guard(scenario, model=model)
    out.append(f"damping guard ({scenario.name}, band and run of its random analysis): "
               + ("no lightly damped mode" if not warnings else f"{len(warnings)} lightly damped modes"))
    for line in merged_messages(warnings):
        out.append(textwrap.fill(f"  warning: {line}", LINE_WIDTH, subsequent_indent="    ", break_on_hyphens=False))
    return out


def bridge_text(bridge: Any) -> str:
    """``show`` of a bridge: its keys (as in its file), its length and tracks, and its frequencies."""
    rows = model_rows(bridge)
    rows += [("(derived) length", f"{bridge.length:g}", "m", "sum of spans")]
    rows += frequency_rows(bridge, key="(derived) ")
    head = [f"Bridge {bridge.name}: {getattr(bridge, 'description', '')}"]
    return table_text(head, rows, getattr(bridge, "notes", ""), getattr(bridge, "source", ""))


def vehicle_text(vehicle: Any) -> str:
    """``show`` of a vehicle: its keys (as in its file)."""
    rows = model_rows(vehicle)
    head = [f"Vehicle {vehicle.name}: {getattr(vehicle, 'description', '')}"]
    return table_text(head, rows, getattr(vehicle, "notes", ""), getattr(vehicle, "source", ""))


def train_text(train: Any) -> str:
    """``show`` of a train of models/trains or a train file: its composition."""
    return composition_table(train)

EXIT_OK = 0

#: what show and modes take
MODEL_HELP = "a scenario, bridge, vehicle or train: a name (see `tb-exudyn list`) or a .toml file"


def _cmd_list(args: argparse.Namespace) -> int:
    print(cli_text.library_listing())
    return EXIT_OK


def _cmd_show(args: argparse.Namespace) -> int:
    kind, model = command_model(args)
    if kind == "scenario":
        an = model.analysis
        rows = frequency_rows(model.bridge, an.mode_max_frequency, an.max_modes, key="(derived) bridge ")
        text = scenario_table(model, rows)
    else:
        text = {"bridge": bridge_text, "vehicle": vehicle_text, "train": train_text}[kind](model)
    note = homonym_note(args.scenario, kind)
    print(cli_text.fitted(text if note is None else f"{note}\n{text}", LISTING_WIDTH))
    return EXIT_OK


def add_parsers(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("list", help="named vehicles, bridges, scenarios and track spectra")
    p.set_defaults(func=_cmd_list)
    p = sub.add_parser("show", help="a scenario, bridge, vehicle or train as a table (a bridge: with f1 and f3)")
    p.add_argument("scenario", metavar="MODEL", help=MODEL_HELP)
    p.add_argument("--set", dest="settings", action="append", metavar="KEY=VALUE",
                   help=cli_scenario.SET_HELP)
    p.set_defaults(func=_cmd_show)


__all__ = ["MODEL_HELP", "MODEL_KINDS", "add_parsers", "bridge_modes_text", "bridge_text", "command_model", "frequency_rows", "hand_f1",
           "homonym_note", "load_model",
           "model_kind", "modes_text", "scenario_modes", "train_text", "train_vehicles", "vehicle_modes",
           "vehicle_scenario", "vehicle_text", "why_f1_differs"]
