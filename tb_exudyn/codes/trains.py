"""Trains of moving forces for the EN 1991-2 dynamic check: the HSLM-A universal trains and real trains
given as compositions of vehicle models.

A :class:`ForceTrain` is a list of axle positions (m behind the first axle, ascending, the first 0) and
axle loads (N, downwards). HSLM-A1 ... A10 are generated from the code's table (EN 1991-2:2003 Annex E,
Table E.1 and Figure E.1); real trains are read from ``models/trains/*.toml``, each a list of vehicles
of ``models/vehicles`` whose axle spacing and masses give the axle loads. Pure numpy.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import ScenarioError, SettingError
from ..scenario.io import load_vehicle
from ..scenario.model import MovingForce, SprungMass
from ..scenario.registry import models_dir
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


def load_train(path: str | Path) -> ForceTrain:
    """A real train from its TOML file: ``[[cars]]`` tables in running order, each ``vehicle`` (a name in
    models/vehicles or a path), optional ``count`` (default 1) and ``body_mass`` [kg] (replacing the
    vehicle's car body mass). Each car's four axle loads are its weight (body + 2 bogies + 4 wheelsets)
    / 4; car k's first axle trails the first car's by the lengths of the cars ahead. ``regular_length``
    [m] (default: the most frequent car length) is D of the resonant speeds."""
    path = Path(path)
    file = str(path)
    data = read_toml(path)
    known = {"name", "description", "source", "notes", "cars", "regular_length"}
    for key in data:
        if key not in known:
            raise _train_error(file, key, data[key], ", ".join(sorted(known)), "unknown key")
    cars = data.get("cars")
    if not isinstance(cars, list) or not cars or not all(isinstance(c, dict) for c in cars):
        raise _train_error(file, "cars", cars, "one or more [[cars]] tables with a 'vehicle'")
    positions, loads, lengths, models, start = [], [], [], [], 0.0
    for i, car in enumerate(cars):
        where = f"cars[{i}]"
        for key in car:
            if key not in ("vehicle", "count", "body_mass"):
                raise _train_error(file, f"{where}.{key}", car[key], "vehicle, count, body_mass", "unknown key")
        name = car.get("vehicle")
        if not isinstance(name, str) or not name:
            raise _train_error(file, f"{where}.vehicle", name, "a vehicle name of models/vehicles or a .toml path")
        count = car.get("count", 1)
        if isinstance(count, bool) or not isinstance(count, int) or not 1 <= count <= 100:
            raise _train_error(file, f"{where}.count", count, "a whole number 1 ... 100")
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
        for _ in range(count):
            positions.extend(start + a for a in vehicle.axle_offsets)
            loads.extend([weight / 4.0] * 4)
            lengths.append(vehicle.length)
            models.append(vehicle)
            start += vehicle.length
    if positions[-1] > MAX_TRAIN_LENGTH:
        raise _train_error(file, "cars", f"{len(lengths)} cars", f"a train at most {MAX_TRAIN_LENGTH:g} m long",
                           f"first to last axle {positions[-1]:g} m")
    if "regular_length" in data:
        regular = _positive(file, "regular_length", data["regular_length"])
    else:
        values, counts = np.unique(np.round(lengths, 9), return_counts=True)
        regular = float(values[np.argmax(counts)])
    return ForceTrain(
        name=str(data.get("name", path.stem)), positions=np.array(positions), loads=np.array(loads),
        regular_length=regular, description=str(data.get("description", "")), source=str(data.get("source", "")),
        vehicles=tuple(models),
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


def resolve_trains(names, where: str = "check", key: str = "trains") -> list[ForceTrain]:
    """The trains named by ``names``: ``hslm_a`` (all ten), ``HSLM-A3`` or ``hslm_a3``, a real train of
    models/trains, or a path to a train .toml file; each at most once, in the order given. An unknown
    name raises SettingError naming ``where`` and ``key`` and listing the names."""
    if isinstance(names, str):
        names = [names]
    names = list(names)
    if not names:
        raise SettingError(where, key, names, "hslm_a, HSLM-A1 ... HSLM-A10 or a train of models/trains", "no train")
    files = train_files()
    out: list[ForceTrain] = []
    for name in names:
        text = str(name)
        if text.strip().lower() == HSLM_A_GROUP:
            out.extend(hslm_a(i) for i in HSLM_A_TABLE)
        elif _hslm_number(text) is not None:
            out.append(hslm_a(_hslm_number(text)))
        elif text in files:
            out.append(load_train(files[text]))
        elif text.endswith(".toml"):  # read_toml names a missing, non-regular or malformed file
            out.append(load_train(text))
        else:
            allowed = "hslm_a, HSLM-A1 ... HSLM-A10, " + ", ".join(files) + " or a train .toml file"
            raise SettingError(where, key, text, allowed, "unknown train")
    seen, unique = set(), []
    for t in out:
        if t.name not in seen:
            seen.add(t.name)
            unique.append(t)
    return unique


__all__ = ["ForceTrain", "GRAVITY", "HSLM_A_GROUP", "HSLM_A_TABLE", "hslm_a", "hslm_a_positions", "list_trains",
           "load_train", "resolve_trains", "train_files", "train_names", "trains_dir"]
