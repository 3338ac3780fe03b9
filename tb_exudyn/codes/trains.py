"""Trains of moving forces for the EN 1991-2 dynamic check: the HSLM-A universal trains and real trains
given as compositions of vehicle models.

A :class:`ForceTrain` is a list of axle positions (m behind the first axle, ascending, the first 0) and
axle loads (N, downwards). HSLM-A1 ... A10 are generated from the code's table (EN 1991-2:2003 Annex E,
Table E.1 and Figure E.1); real trains are read from ``models/trains/*.toml``, each a list of vehicles
of ``models/vehicles`` whose axle spacing and masses give the axle loads, axle-load sets given as such
(a power car's axles and loads) and articulated sets (car bodies on bogies shared by neighbouring cars,
Jacobs bogies), in running order. Pure numpy.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from ..errors import ScenarioError, SettingError
from ..scenario.io import load_vehicle
from ..scenario.model import MovingForce, SprungMass
from ..scenario.registry import model_files, models_dir
from ..scenario.toml_io import read_toml

#: g for the weight of a vehicle model's masses (as ``Train.mass``) [m/s^2]
GRAVITY = 9.81

#: EN 1991-2:2003 Table E.1 (HSLM-A): train -> (N intermediate coaches, D coach length [m],
#: d bogie axle spacing [m], P point force per axle [kN])
HSLM_A_TABLE: dict[int, tuple[int, float, float, float]] = {
    1: (18, 18.0, 2.0, 170.0),
    2: (17, 19.0, 3.5, 200.0),
    3: (16, 20.0, 2.0, 180.0),
    4: (15, 21.0, 3.0, 190.0),
    5: (14, 22.0, 2.0, 170.0),
    6: (13, 23.0, 2.0, 180.0),
    7: (13, 24.0, 2.0, 190.0),
    8: (12, 25.0, 2.5, 190.0),
    9: (11, 26.0, 2.0, 210.0),
    10: (11, 27.0, 2.0, 210.0),
}
#: Figure E.1: the power car's axles [m from its first axle] and the gap from its last axle to the end
#: coach's first axle [m]
HSLM_POWER_CAR_AXLES = (0.0, 3.0, 14.0, 17.0)
HSLM_POWER_TO_COACH = 3.525
#: the longest train a file may give, first to last axle [m] (the longest freight trains are about 750 m)
MAX_TRAIN_LENGTH = 1000.0
#: names that select all ten HSLM-A trains
HSLM_A_GROUP = "hslm_a"


@dataclass(frozen=True)
class ForceTrain:
    """A train of constant vertical moving forces.

    ``positions`` (n_axles,) distance of each axle behind the first [m], ascending, first 0;
    ``loads`` (n_axles,) axle loads [N], positive downwards; ``regular_length`` the length D of the
    regular axle group [m] whose passing frequency v / D excites resonance (coach length of HSLM-A, car
    length of a real train); ``vehicles`` the vehicle models the loads come from, in running order (a
    real train of models/trains: its cars, a ``body_mass`` applied; empty for HSLM-A and forces given
    as such): what the check's stochastic rows run (tb_exudyn.codes.stochastic).
    """

    name: str
    positions: np.ndarray = field(repr=False)
    loads: np.ndarray = field(repr=False)
    regular_length: float
    description: str = ""
    source: str = ""
    vehicles: tuple = field(default=(), repr=False)
    #: the composition, one :class:`TrainPart` per car or set in running order (empty for HSLM-A)
    parts: tuple = field(default=(), repr=False)

    def __post_init__(self) -> None:
        x = np.asarray(self.positions, dtype=float)
        p = np.asarray(self.loads, dtype=float)
        where = f"ForceTrain {self.name!r}"
        if x.ndim != 1 or x.size == 0 or not np.all(np.isfinite(x)) or x[0] != 0.0 or np.any(np.diff(x) < 0):
            raise SettingError(where, "positions", self.positions, "axle positions [m] from 0, ascending, finite")
        if p.shape != x.shape or not np.all(np.isfinite(p)):
            raise SettingError(where, "loads", self.loads, f"{x.size} finite axle loads [N], one per position")
        if x[-1] > MAX_TRAIN_LENGTH:
            raise SettingError(where, "positions", f"first to last axle {x[-1]:g} m",
                               f"a train at most {MAX_TRAIN_LENGTH:g} m long")
        if not (math.isfinite(self.regular_length) and self.regular_length > 0):
            raise SettingError(where, "regular_length", self.regular_length, "a length D > 0 m")
        object.__setattr__(self, "positions", x)
        object.__setattr__(self, "loads", p)
        object.__setattr__(self, "vehicles", tuple(self.vehicles))
        object.__setattr__(self, "parts", tuple(self.parts))

    @property
    def n_axles(self) -> int:
        return int(self.positions.size)

    @property
    def length(self) -> float:
        """First to last axle [m]."""
        return float(self.positions[-1])

    @property
    def total_load(self) -> float:
        return float(self.loads.sum())


@dataclass(frozen=True)
class TrainPart:
    """One car or set of a train's composition: ``name``, ``kind`` ('vehicle': a vehicle model; 'axle_loads':
    axles and loads given; 'articulated': car bodies on shared bogies), its first axle [m behind the
    train's first], its number of axles, car bodies and bogies, and its weight [N] (the sum of its axle loads)."""

    name: str
    kind: str
    first_axle: float
    n_axles: int
    n_bodies: int
    n_bogies: int
    weight: float


def composition_table(train: ForceTrain) -> str:
    """A plain-text table of a train's composition (its cars and sets, their axles and weights) and its
    axle-load view (what the EN 1991-2 check moves over the bridge)."""
    lines = [f"train {train.name}: {train.n_axles} axles, first to last {train.length:.4g} m, "
             f"{train.total_load / 1e3:.6g} kN, D = {train.regular_length:g} m"]
    if train.parts:
        lines.append(f"  {'#':>3} {'car or set':<20} {'kind':<12} {'first axle [m]':>14} {'axles':>5} {'bodies':>6} "
                     f"{'bogies':>6} {'weight [kN]':>11}")
        for i, p in enumerate(train.parts):
            lines.append(f"  {i + 1:>3} {p.name:<20} {p.kind:<12} {p.first_axle:>14.4f} {p.n_axles:>5} {p.n_bodies:>6} "
                         f"{p.n_bogies:>6} {p.weight / 1e3:>11.2f}")
    lines.append("  axle loads [kN] at [m]: " + ", ".join(
        f"{q / 1e3:.4g} @ {x:.4g}" for x, q in zip(train.positions, train.loads)))
    return "\n".join(lines)


def train_view(name: str) -> str | None:
    """:func:`composition_table` of the train ``name`` of models/trains, or None when ``name`` is no such
    train or is also a scenario's name (``tb-exudyn show NAME``: a scenario comes first)."""
    trains = train_files()
    if name not in trains or name in model_files("scenarios"):
        return None
    return composition_table(load_train(trains[name]))


# ---------------------------------------------------------------------------------------- HSLM-A
def hslm_a_positions(n: int, coach_length: float, bogie_spacing: float) -> np.ndarray:
    """Axle positions of an HSLM-A train (EN 1991-2 Figure E.1) [m behind the first axle].

    Front half: the power car's four axles at 0, 3, 14, 17 m; the end coach's outer bogie 3.525 m
    behind (axles at 17 + 3.525 and 17 + 3.525 + d); then N + 1 articulated bogies centred at
    17 + 3.525 / 2 + i D (i = 1 ... N + 1) with axles at +- d / 2. The rear end coach and power car
    mirror the front ones about the middle of the articulated bogies: 2 N + 14 axles, first to last
    37.525 + (N + 2) D.
    """
    d, big_d = float(bogie_spacing), float(coach_length)
    last = HSLM_POWER_CAR_AXLES[-1]
    front = list(HSLM_POWER_CAR_AXLES) + [last + HSLM_POWER_TO_COACH, last + HSLM_POWER_TO_COACH + d]
    centres = last + HSLM_POWER_TO_COACH / 2.0 + big_d * np.arange(1, n + 2)
    middle = np.concatenate([[c - d / 2.0, c + d / 2.0] for c in centres])
    axis = 0.5 * (centres[0] + centres[-1])  # the train's axis of symmetry
    rear = 2.0 * axis - np.array(front[::-1])
    return np.concatenate([front, middle, rear])


def hslm_a(number: int) -> ForceTrain:
    """HSLM-A<number> (1 ... 10) of EN 1991-2:2003 Annex E, Table E.1: every axle carries P."""
    if number not in HSLM_A_TABLE:
        raise SettingError("hslm_a", "number", number, "1 ... 10 (EN 1991-2 Table E.1)")
    n, big_d, d, p_kn = HSLM_A_TABLE[number]
    x = hslm_a_positions(n, big_d, d)
    return ForceTrain(
        name=f"HSLM-A{number}", positions=x, loads=np.full(x.size, 1e3 * p_kn), regular_length=big_d,
        description=f"HSLM-A{number}: N = {n} coaches, D = {big_d:g} m, d = {d:g} m, P = {p_kn:g} kN",
        source="EN 1991-2:2003 Annex E, Table E.1 and Figure E.1",
    )


# ----------------------------------------------------------------------------------- real trains
def trains_dir() -> Path:
    """models/trains of the model library (next to vehicles/ and bridges/)."""
    return models_dir() / "trains"


def train_files() -> dict[str, Path]:
    """Name -> file of the real trains in models/trains, sorted by name."""
    folder = trains_dir()
    return {p.stem: p for p in sorted(folder.glob("*.toml"))} if folder.is_dir() else {}


def _train_error(file: str, key: str, value, allowed: str, reason: str = "") -> ScenarioError:
    return ScenarioError(file, key, value, allowed, reason)


def _positive(file: str, key: str, value) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value) or value <= 0:
        raise _train_error(file, key, value, "a number > 0")
    return float(value)


#: the keys of each kind of [[cars]] table (the key that says the kind first)
CAR_KEYS: dict[str, tuple[str, ...]] = {
    "vehicle": ("vehicle", "count", "body_mass"),
    "axle_loads": ("axles", "axle_loads", "axle_load", "length", "name", "count"),
    "articulated": ("bodies", "pivot_spacing", "wheelbase", "body_mass", "bogie_mass", "wheelset_mass", "length",
                    "name", "count"),
}
_KIND_KEY = {"vehicle": "vehicle", "axle_loads": "axles", "articulated": "bodies"}


@dataclass(frozen=True)
class _Car:
    """One car or set read from a [[cars]] table: axle offsets from its first axle [m], axle loads [N],
    the distance to the next car's first axle [m], the lengths of its car bodies (for D), its vehicle
    model (None: a set of loads), and its part's name, kind and counts."""

    offsets: tuple[float, ...]
    loads: tuple[float, ...]
    length: float
    body_lengths: tuple[float, ...]
    model: object
    name: str
    kind: str
    n_bodies: int
    n_bogies: int


def _number_list(file: str, key: str, value, n: int | None = None, first_zero: bool = False) -> list[float]:
    """A list of numbers > 0 (``n`` of them if given; with ``first_zero`` the first may be 0)."""
    if not isinstance(value, list) or not value or (n is not None and len(value) != n):
        raise _train_error(file, key, value, f"a list of {n if n is not None else 'one or more'} numbers")
    return [_nonnegative(file, f"{key}[0]", v) if first_zero and i == 0 else _positive(file, f"{key}[{i}]", v)
            for i, v in enumerate(value)]


def _nonnegative(file: str, key: str, value) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value) or value < 0:
        raise _train_error(file, key, value, "a number >= 0")
    return float(value)


def _vehicle_car(file: str, path: Path, where: str, car: dict) -> _Car:
    name = car.get("vehicle")
    if not isinstance(name, str) or not name:
        raise _train_error(file, f"{where}.vehicle", name, "a vehicle name of models/vehicles or a .toml path")
    ref = name if not name.endswith(".toml") else str((path.parent / name).resolve())
    try:
        vehicle = load_vehicle(ref)
    except ScenarioError as exc:
        raise _train_error(file, f"{where}.vehicle", name, exc.allowed, exc.reason or "not a valid vehicle") from None
    if isinstance(vehicle, (MovingForce, SprungMass)):
        raise _train_error(file, f"{where}.vehicle", name, "a car with two bogies (kind car15 or creep_car)",
                           f"kind {vehicle.kind}")
    body = vehicle.body.mass
    if "body_mass" in car:
        body = _positive(file, f"{where}.body_mass", car["body_mass"])
        vehicle = vehicle.replace(body=vehicle.body.replace(mass=body))
    weight = GRAVITY * (body + 2.0 * vehicle.bogie.mass + 4.0 * vehicle.wheelset.mass)
    return _Car(tuple(vehicle.axle_offsets), (weight / 4.0,) * 4, vehicle.length, (vehicle.length,), vehicle,
                vehicle.name, "vehicle", 1, 2)


def _axle_set(file: str, where: str, car: dict) -> _Car:
    """An axle-load set: ``axles`` [m from its first axle: 0, ascending], ``axle_loads`` [N] (one per axle) or
    ``axle_load`` (every axle), ``length`` [m] to the next car's first axle."""
    axles = _number_list(file, f"{where}.axles", car.get("axles"), first_zero=True)
    if axles[0] != 0.0 or any(b <= a for a, b in zip(axles, axles[1:])):
        raise _train_error(file, f"{where}.axles", car.get("axles"), "axle positions [m] from 0, ascending")
    if ("axle_loads" in car) == ("axle_load" in car):
        raise _train_error(file, f"{where}.axle_loads", car.get("axle_loads", "<missing>"),
                           "either axle_loads (a load [N] per axle) or axle_load (every axle), not both",
                           "no axle loads" if "axle_loads" not in car else "two axle loads")
    loads = (_number_list(file, f"{where}.axle_loads", car["axle_loads"], len(axles)) if "axle_loads" in car
             else [_positive(file, f"{where}.axle_load", car["axle_load"])] * len(axles))
    length = _length(file, where, car, axles[-1])
    name = str(car.get("name", "axle loads"))
    return _Car(tuple(axles), tuple(loads), length, (length,), None, name, "axle_loads", 1, 0)


def _length(file: str, where: str, car: dict, spread: float) -> float:
    if "length" not in car:
        raise _train_error(file, f"{where}.length", "<missing>", "the distance [m] from its first axle to the next "
                           "car's first axle", "missing key")
    length = _positive(file, f"{where}.length", car["length"])
    if length < spread:
        raise _train_error(file, f"{where}.length", length, f">= {spread:g} m (its axle spread)",
                           "shorter than its axles")
    return length


def _articulated_set(file: str, where: str, car: dict) -> _Car:
    """``bodies`` car bodies in a row on ``bodies + 1`` two-axle bogies, each inner bogie shared by the two
    bodies beside it (Jacobs bogies), ``pivot_spacing`` [m] between a body's two bogie centres, ``wheelbase``
    [m] a bogie's axle spacing, ``body_mass`` [kg] (one for all or a list, one per body), ``bogie_mass``
    and ``wheelset_mass`` [kg]; ``length`` [m] from its first axle to the next car's first axle. A bogie
    carries half of each body it supports (statics of a body on two pivots, its centre of gravity midway)
    and its own mass; its two axles share that equally."""
    n = car.get("bodies")
    if isinstance(n, bool) or not isinstance(n, int) or not 1 <= n <= 100:
        raise _train_error(file, f"{where}.bodies", n, "a whole number 1 ... 100 (car bodies of the set)")
    for key in ("pivot_spacing", "wheelbase", "bogie_mass", "wheelset_mass"):
        if key not in car:
            raise _train_error(file, f"{where}.{key}", "<missing>", "a number > 0", "missing key")
    pivot = _positive(file, f"{where}.pivot_spacing", car["pivot_spacing"])
    wheelbase = _positive(file, f"{where}.wheelbase", car["wheelbase"])
    if wheelbase >= pivot:
        raise _train_error(file, f"{where}.wheelbase", wheelbase, f"< pivot_spacing = {pivot:g} m", "bogies overlap")
    bogie = _positive(file, f"{where}.bogie_mass", car["bogie_mass"])
    wheelset = _positive(file, f"{where}.wheelset_mass", car["wheelset_mass"])
    raw = car.get("body_mass")
    bodies = (_number_list(file, f"{where}.body_mass", raw, n) if isinstance(raw, list)
              else [_positive(file, f"{where}.body_mass", raw if raw is not None else "<missing>")] * n)
    offsets, loads = [], []
    for j in range(n + 1):
        share = 0.5 * ((bodies[j - 1] if j > 0 else 0.0) + (bodies[j] if j < n else 0.0))
        axle = GRAVITY * (share + bogie + 2.0 * wheelset) / 2.0
        offsets += [j * pivot, j * pivot + wheelbase]
        loads += [axle, axle]
    length = _length(file, where, car, offsets[-1])
    name = str(car.get("name", "articulated set"))
    return _Car(tuple(offsets), tuple(loads), length, (pivot,) * n, None, name, "articulated", n, n + 1)


def load_train(path: str | Path) -> ForceTrain:
    """A real train from its TOML file: ``[[cars]]`` tables in running order, each one of
    (docs/en1991.md, trains):

    - a vehicle model: ``vehicle`` (a name in models/vehicles or a path), optional ``body_mass`` [kg]
      (replacing the vehicle's car body mass); its four axle loads are its weight (body + 2 bogies + 4
      wheelsets) / 4;
    - an axle-load set: ``axles`` [m from its first axle], ``axle_loads`` [N] or ``axle_load``, ``length``;
    - an articulated set: ``bodies``, ``pivot_spacing``, ``wheelbase``, ``body_mass``, ``bogie_mass``,
      ``wheelset_mass``, ``length`` (:func:`_articulated_set`);

    each with an optional ``count`` (default 1). Car k's first axle trails the first car's by the lengths
    of the cars ahead. ``regular_length`` [m] (default: the most frequent car body length) is D of the
    resonant speeds. The train's ``vehicles`` are its vehicle models when every car is one (what the
    check's stochastic rows run), else none."""
    path = Path(path)
    file = str(path)
    data = read_toml(path)
    known = {"name", "description", "source", "notes", "cars", "regular_length"}
    for key in data:
        if key not in known:
            raise _train_error(file, key, data[key], ", ".join(sorted(known)), "unknown key")
    cars = data.get("cars")
    if not isinstance(cars, list) or not cars or not all(isinstance(c, dict) for c in cars):
        raise _train_error(file, "cars", cars, "one or more [[cars]] tables with a 'vehicle', 'axles' or 'bodies'")
    positions, loads, lengths, models, parts, start = [], [], [], [], [], 0.0
    for i, car in enumerate(cars):
        where = f"cars[{i}]"
        kinds = [k for k, key in _KIND_KEY.items() if key in car]
        if len(kinds) != 1:
            raise _train_error(file, where, ", ".join(sorted(car)) or "<empty>",
                               "one of: vehicle (a vehicle model), axles (an axle-load set), bodies (an articulated "
                               "set)", "no kind of car" if not kinds else "two kinds of car")
        for key in car:
            if key not in CAR_KEYS[kinds[0]]:
                raise _train_error(file, f"{where}.{key}", car[key], ", ".join(CAR_KEYS[kinds[0]]), "unknown key")
        count = car.get("count", 1)
        if isinstance(count, bool) or not isinstance(count, int) or not 1 <= count <= 100:
            raise _train_error(file, f"{where}.count", count, "a whole number 1 ... 100")
        one = (_vehicle_car(file, path, where, car) if kinds[0] == "vehicle"
               else _axle_set(file, where, car) if kinds[0] == "axle_loads" else _articulated_set(file, where, car))
        for _ in range(count):
            positions.extend(start + a for a in one.offsets)
            loads.extend(one.loads)
            lengths.extend(one.body_lengths)
            models.append(one.model)
            parts.append(TrainPart(one.name, one.kind, start, len(one.offsets), one.n_bodies, one.n_bogies,
                                   float(sum(one.loads))))
            start += one.length
            if start > 2 * MAX_TRAIN_LENGTH:  # stop reading a train far too long (its error follows)
                break
    if positions[-1] > MAX_TRAIN_LENGTH:
        raise _train_error(file, "cars", f"{len(parts)} cars", f"a train at most {MAX_TRAIN_LENGTH:g} m long",
                           f"first to last axle {positions[-1]:g} m")
    if "regular_length" in data:
        regular = _positive(file, "regular_length", data["regular_length"])
    else:
        values, counts = np.unique(np.round(lengths, 9), return_counts=True)
        regular = float(values[np.argmax(counts)])
    return ForceTrain(
        name=str(data.get("name", path.stem)), positions=np.array(positions), loads=np.array(loads),
        regular_length=regular, description=str(data.get("description", "")), source=str(data.get("source", "")),
        vehicles=tuple(models) if all(m is not None for m in models) else (), parts=tuple(parts),
    )


# ----------------------------------------------------------------------------------- selection
def train_names() -> list[str]:
    """Every train a check can name: HSLM-A1 ... HSLM-A10 and the real trains of models/trains."""
    return [f"HSLM-A{i}" for i in HSLM_A_TABLE] + list(train_files())


def list_trains() -> list[tuple[str, str]]:
    """(name, one-line description) of every train, for ``tb-exudyn list``."""
    rows = [(f"HSLM-A{i}", hslm_a(i).description) for i in HSLM_A_TABLE]
    for name, path in train_files().items():
        try:
            rows.append((name, str(read_toml(path).get("description", ""))))
        except ScenarioError as exc:
            rows.append((name, f"(unreadable: {exc})"))
    return rows


def _hslm_number(name: str) -> int | None:
    key = name.strip().lower().replace("-", "_")
    if key.startswith("hslm_a") and key[6:].isdigit():
        number = int(key[6:])
        return number if number in HSLM_A_TABLE else None
    return None


@dataclass(frozen=True)
class TrainSource:
    """Where a train of a check comes from: ``given`` as the user wrote it (a name or a path), ``label``
    as a message names it, ``identity`` equal for two givens of the same train (an HSLM-A number, a
    file's resolved path, a ForceTrain object)."""

    given: str
    label: str
    identity: Any


def distinct_trains(pairs: Sequence[tuple["ForceTrain", TrainSource]], where: str = "check",
                    key: str = "trains") -> list["ForceTrain"]:
    """The trains of ``pairs``, each once (a train given twice, e.g. ``hslm_a`` and ``HSLM-A3``, or a file
    by two spellings of its path, counts once), in order. Two different trains with one name (two train
    files with the same ``name``, or a file named like an HSLM-A train) raise SettingError naming both:
    the rows are by train name, so one would be lost."""
    first: dict[str, TrainSource] = {}
    out: list[ForceTrain] = []
    for train, source in pairs:
        seen = first.get(train.name)
        if seen is None:
            first[train.name] = source
            out.append(train)
        elif seen.identity != source.identity:
            raise SettingError(where, key, train.name, "distinct names (a train file's name key)",
                               f"two trains named {train.name!r}: {seen.label} and {source.label}")
    return out


def train_sources(name: Any, where: str = "check", key: str = "trains") -> list[tuple["ForceTrain", TrainSource]]:
    """The trains one given ``name`` stands for (``hslm_a``: all ten), each with its :class:`TrainSource`."""
    text = str(name)
    number = _hslm_number(text)
    if text.strip().lower() == HSLM_A_GROUP or number is not None:
        numbers = list(HSLM_A_TABLE) if number is None else [number]
        return [(hslm_a(i), TrainSource(text, f"EN 1991-2's HSLM-A{i} ({text!r})", ("hslm_a", i))) for i in numbers]
    files = train_files()
    if text in files:
        path = files[text]
        label = f"{text!r} (models/trains/{path.name})"
    elif text.endswith(".toml"):  # read_toml names a missing, non-regular or malformed file
        path, label = Path(text), f"file {text!r}"
    else:
        allowed = "hslm_a, HSLM-A1 ... HSLM-A10, " + ", ".join(files) + " or a train .toml file"
        raise SettingError(where, key, text, allowed, "unknown train")
    train = load_train(path)
    return [(train, TrainSource(text, label, ("file", os.path.realpath(path))))]


def resolve_trains(names, where: str = "check", key: str = "trains") -> list[ForceTrain]:
    """The trains named by ``names``: ``hslm_a`` (all ten), ``HSLM-A3`` or ``hslm_a3``, a real train of
    models/trains, or a path to a train .toml file; each at most once, in the order given. An unknown
    name raises SettingError naming ``where`` and ``key`` and listing the names; two different trains
    with one name (:func:`distinct_trains`) too."""
    if isinstance(names, str):
        names = [names]
    names = list(names)
    if not names:
        raise SettingError(where, key, names, "hslm_a, HSLM-A1 ... HSLM-A10 or a train of models/trains", "no train")
    return distinct_trains([pair for name in names for pair in train_sources(name, where, key)], where, key)


__all__ = ["CAR_KEYS", "ForceTrain", "GRAVITY", "TrainPart", "composition_table", "train_view", "HSLM_A_GROUP", "HSLM_A_TABLE", "hslm_a", "hslm_a_positions", "list_trains",
           "TrainSource", "distinct_trains", "load_train", "resolve_trains", "train_sources", "train_files", "train_names", "trains_dir"]
