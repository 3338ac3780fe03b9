"""Output channels: names, units, glob selection, and their values from recorded coordinates.

Pure numpy, no Exudyn. A channel name says where and what:

    bridge.<station>.<quantity>_<component>     e.g. bridge.span1.mid.acc_z
    car<k>.body.<quantity>_<component>          car body (car15) or sprung mass (z only)
    car<k>.bogie<i>.<quantity>_<component>      car15 bogies, i = 1 (leading), 2
    car<k>.axle<j>.<quantity>_<component>       wheelsets (y, z, rx; creep_car also rz) and sprung-mass wheels (z)
    car<k>.axle<j>.left.force_z, .right.force_z vertical wheel-rail force per wheel (car15, creep_car)
    car<k>.axle<j>.force_y                      lateral wheel-rail force per wheelset (car15, creep_car)
    car<k>.axle<j>.left.force_x, .right.force_x longitudinal creep force per wheel (creep_car)
    car<k>.axle<j>.moment_z                     spin creep and gravitational yaw moment [N m] (creep_car)
    car<k>.axle1.force_z                        the wheel load of a sprung mass or moving force
    car<k>.axle<j>[.left|.right].rail.<q>_z     with a track structure: the rail under a wheel (vertical
    car<k>.axle<j>.rail.<q>_y                   contact), the rails' centre line under a wheelset (lateral)

quantity: ``disp`` [m or rad], ``vel`` [m/s or rad/s], ``acc`` [m/s^2 or rad/s^2];
component: ``y``, ``z`` (translations, y left, z up), ``rx``, ``ry``, ``rz`` (rotations about x,
y, z: roll, pitch, yaw; right-handed). Displacements are measured from the unloaded reference
configuration (they include the static sag under gravity). Vehicles are numbered car1, car2, ...
in running order whatever their kind.

Force signs: ``force_z`` is the force the rail exerts on the wheel upward, i.e. the compressive
wheel load (positive = the rail is pushed down); ``force_y`` is the force the rail exerts on the
wheelset toward +y (left); ``force_x`` the force the rail exerts on a wheel toward +x (forward);
``moment_z`` the moment about +z the rails exert on the wheelset; the rail receives the opposite.
"""

from __future__ import annotations

import fnmatch
import re
from dataclasses import dataclass
from typing import Callable, Iterable, Sequence

import numpy as np
from numpy.typing import NDArray

from ..scenario.errors import ScenarioError

QUANTITIES: tuple[str, ...] = ("disp", "vel", "acc")
#: the rule every channel name follows (what :func:`is_channel_name` checks)
CHANNEL_NAME_RULE = "A-Z, a-z, 0-9, '_' joined by dots, <= 200 characters"
_CHANNEL_NAME = re.compile(r"[A-Za-z0-9_]+(?:\.[A-Za-z0-9_]+)*\Z")
_UNITS = {
    True: ("m", "m/s", "m/s^2"),  # translation
    False: ("rad", "rad/s", "rad/s^2"),  # rotation
}
BRIDGE_COMPONENTS: tuple[str, ...] = ("y", "z", "rx")


@dataclass(frozen=True)
class Channel:
    """One output channel.

    ``source``: "node" (a node coordinate: ``index`` = node, ``coordinate`` = its coordinate),
    "bridge" (``index`` = station, ``coordinate`` = row y/z/rx of the station shapes),
    "contact" (``index`` = contact row), "load" (``index`` = moving point load) or "rail" (``index`` = a
    penalty contact row: its rail shape row S(t) at the moving wheel times the bridge body's coordinates).
    ``order``: 0 displacement, 1 velocity, 2 acceleration (node, bridge and rail channels).
    """

    name: str
    unit: str
    source: str
    index: int
    coordinate: int = 0
    order: int = 0


def is_channel_name(name: object) -> bool:
    """Whether ``name`` follows :data:`CHANNEL_NAME_RULE` (so it is also a safe file-name part: no
    '/', no '..', no leading dot, nothing outside ASCII letters, digits, '_' and '.')."""
    return isinstance(name, str) and len(name) <= 200 and _CHANNEL_NAME.match(name) is not None


def _motion_channels(prefix: str, source: str, index: int, components: Iterable[tuple[str, int]]) -> list[Channel]:
    components = tuple(components)
    out = []
    for order, quantity in enumerate(QUANTITIES):
        for label, coord in components:
            unit = _UNITS[label in ("y", "z")][order]
            out.append(Channel(f"{prefix}.{quantity}_{label}", unit, source, index, coord, order))
    return out


def contact_unit(name: str) -> str:
    """Unit of a contact-row channel: "N m" for a moment (``...moment_z``), else "N"."""
    return "N m" if name.rsplit(".", 1)[-1].startswith("moment") else "N"


def rail_channels(contact_names: Sequence[str], directions: Sequence[int]) -> list[Channel]:
    """With a track structure: the rail under each wheel (:func:`rail_channel_name`), displacement, velocity
    and acceleration of the body's rail shape row S(t) at the moving contact (the rail's own motion at the
    wheel's place: S(x(t)) q'' for the acceleration, no convective term); 0 while the wheel is on the rigid
    line (off the rails). ``directions``: each penalty row's (0 vertical, 1 lateral); other rows none."""
    out = []
    for i, (name, d) in enumerate(zip(contact_names, directions)):
        rail = rail_channel_name(name, int(d))
        if rail is None:
            continue
        label = "z" if int(d) == 0 else "y"
        for order, quantity in enumerate(QUANTITIES):
            out.append(Channel(f"{rail}.{quantity}_{label}", _UNITS[True][order], "rail", i, 0, order))
    return out


def rail_channel_name(contact_name: str, direction: int) -> str | None:
    """The prefix of the rail channels of a penalty contact row: ``car1.axle1.left.force_z`` (vertical) ->
    ``car1.axle1.left.rail``, ``car1.axle1.force_y`` (lateral) -> ``car1.axle1.rail``; None for other rows."""
    head, _, last = contact_name.rpartition(".")
    if (direction, last) in ((0, "force_z"), (1, "force_y")) and head:
        return f"{head}.rail"
    return None


def rail_under(contacts, y: NDArray[np.float64], z: NDArray[np.float64], rx: NDArray[np.float64]) -> NDArray[np.float64]:  # noqa: ANN001
    """The rail under each contact of ``contacts`` (a ContactLayout: direction, axle, rail_offset) from the
    rail shapes y, z, rx at the axles (n_axles, n) (the rail channels' rows, one convention for every
    engine): a vertical contact's z + e rx (e its rail offset; not the a y a coned wheel's contact geometry
    adds to its row S), a lateral contact's y (the rails' centre line)."""
    a, e = contacts.axle, np.broadcast_to(np.asarray(contacts.rail_offset, dtype=float), contacts.axle.shape)
    vertical = (np.asarray(contacts.direction) == 0)[:, None]
    return np.where(vertical, z[a] + e[:, None] * rx[a], y[a])


def rail_rows(coupling, t: float) -> NDArray[np.float64]:  # noqa: ANN001
    """:func:`rail_under` of a WheelRailCoupling's contacts at time t, (n_c, n_b) over its bridge's
    coordinates; zero for an axle off the body's rail (on the rigid line)."""
    x = coupling.positions(t)
    if not np.any(coupling.bridge.carries(x)):
        return np.zeros((coupling.n_contacts, coupling.n_bridge))
    rs = coupling.bridge.rail_shapes(x)  # zero rows off the bridge
    return rail_under(coupling.contacts, rs.y, rs.z, rs.rx)


def catalogue(
    station_names: Sequence[str],
    bodies: Sequence[tuple[str, int, Sequence[tuple[str, int]]]],
    contact_names: Sequence[str],
    load_names: Sequence[str],
) -> list[Channel]:
    """Every channel of a model, bridge first, then vehicles in running order.

    ``bodies``: (name, node, ((component, node coordinate), ...)) per output body.
    """
    out: list[Channel] = []
    for s, station in enumerate(station_names):
        out += _motion_channels(f"bridge.{station}", "bridge", s, tuple((c, i) for i, c in enumerate(BRIDGE_COMPONENTS)))
    for name, node, comps in bodies:
        out += _motion_channels(name, "node", node, comps)
    out += [Channel(n, contact_unit(n), "contact", i) for i, n in enumerate(contact_names)]
    out += [Channel(n, "N", "load", i) for i, n in enumerate(load_names)]
    return _vehicle_order(out)


def catalogue_order(channels: list[Channel]) -> list[Channel]:
    """``channels`` in the catalogue's order: bridge (and track) channels first, then each car's together."""
    return _vehicle_order(channels)


def _vehicle_order(channels: list[Channel]) -> list[Channel]:
    """Bridge channels first, then each car's channels together (stable within a car)."""

    def key(ch: Channel) -> tuple[int, int]:
        head = ch.name.split(".", 1)[0]
        if head == "bridge":
            return (0, 0)
        digits = head[3:] if head.startswith("car") else ""
        return (1, int(digits) if digits.isdigit() else 0)

    return sorted(channels, key=key)


def select(channels: Sequence[Channel], patterns: Sequence[str], file: str | None = None) -> list[Channel]:
    """The channels whose names match any of the glob ``patterns`` (in catalogue order).

    Raises ScenarioError (key ``analysis.channels``, in ``file``: the scenario's file or label) naming
    the pattern when it matches no channel.
    """
    names = [c.name for c in channels]
    keep = set()
    for i, pattern in enumerate(patterns):
        hits = fnmatch.filter(names, pattern)
        if not hits:
            sample = ", ".join(names[:6]) + (", ..." if len(names) > 6 else "")
            raise ScenarioError(file, f"analysis.channels[{i}]", pattern,
                                f"glob patterns of this model's channels, e.g. {sample}", "matches no channel")
        keep.update(hits)
    return [c for c in channels if c.name in keep]


@dataclass(frozen=True)
class Recording:
    """Recorded coordinates at the output times.

    ``nodes[node] = (disp, vel, acc)``, each (n_t, n_coords) (node coordinates without
    reference values); ``contact_forces`` (n_t, n_c) and ``load_forces`` (n_t, n_l) [N].
    """

    times: NDArray[np.float64]
    nodes: dict[int, tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]]
    bridge_node: int
    contact_forces: NDArray[np.float64]
    load_forces: NDArray[np.float64]


def evaluate(channels: Sequence[Channel], rec: Recording, station_shapes: NDArray[np.float64],
             rail_rows: Callable[[float], NDArray[np.float64]] | None = None) -> dict[str, NDArray[np.float64]]:
    """Channel name -> (n_t,) values from a recording (``station_shapes``: (n_st, 3, n_modes);
    ``rail_rows(t)``: the contacts' rail shape rows (n_c, n_modes) at t, for rail channels)."""
    out: dict[str, NDArray[np.float64]] = {}
    bridge = rec.nodes.get(rec.bridge_node)
    rails = None  # (n_t, n_c, n_modes): the contacts' rail rows at the recording's times, made once
    for ch in channels:
        if ch.source == "node":
            out[ch.name] = np.ascontiguousarray(rec.nodes[ch.index][ch.order][:, ch.coordinate])
        elif ch.source == "bridge":
            assert bridge is not None
            out[ch.name] = bridge[ch.order] @ station_shapes[ch.index, ch.coordinate]
        elif ch.source == "contact":
            out[ch.name] = np.ascontiguousarray(rec.contact_forces[:, ch.index])
        elif ch.source == "load":
            out[ch.name] = np.ascontiguousarray(rec.load_forces[:, ch.index])
        elif ch.source == "rail":
            if rail_rows is None:
                raise NotImplementedError(f"channel {ch.name}: a rail channel needs the contacts' rail rows")
            assert bridge is not None
            if rails is None:
                rails = np.array([rail_rows(float(t)) for t in rec.times])
            out[ch.name] = np.einsum("tn,tn->t", bridge[ch.order], rails[:, ch.index])
        else:  # pragma: no cover - catalogue only makes the five kinds
            raise ValueError(f"unknown channel source {ch.source!r}")
    return out


@dataclass(frozen=True)
class OutputMap:
    """Where every output channel (in ``names`` order) comes from, in the system's global terms:
    (channel, global coordinate, order) of node channels, (channel, station shape row over the
    bridge's modal coordinates, order) of bridge channels, (channel, contact row) of contact forces
    (channel, point load) of the moving point loads and (channel, penalty contact row, order) of the rail
    channels (the moving row S(t) of that contact over the bridge's coordinates). The engines that integrate global state
    vectors (batched, dense) read their channels through it; :func:`evaluate` reads the same
    channels from an Exudyn recording."""

    names: tuple[str, ...]
    units: tuple[str, ...]
    node: tuple[tuple[int, int, int], ...]
    bridge: tuple[tuple[int, NDArray[np.float64], int], ...]
    contact: tuple[tuple[int, int], ...]
    load: tuple[tuple[int, int], ...]
    rail: tuple[tuple[int, int, int], ...] = ()


def output_map(channels: Sequence[Channel], node_indices: Callable[[int], NDArray[np.int64]],
               station_shapes: NDArray[np.float64]) -> OutputMap:
    """The :class:`OutputMap` of ``channels``; ``node_indices(node)`` gives a node's global
    coordinate indices, ``station_shapes`` (n_st, 3, n_modes) the bridge's station shapes."""
    node, bridge, contact, load, rail = [], [], [], [], []
    for i, ch in enumerate(channels):
        if ch.source == "node":
            node.append((i, int(node_indices(ch.index)[ch.coordinate]), ch.order))
        elif ch.source == "bridge":
            bridge.append((i, station_shapes[ch.index, ch.coordinate], ch.order))
        elif ch.source == "contact":
            contact.append((i, ch.index))
        elif ch.source == "load":
            load.append((i, ch.index))
        elif ch.source == "rail":
            rail.append((i, ch.index, ch.order))
        else:  # pragma: no cover - catalogue only makes the four kinds
            raise ValueError(f"unknown channel source {ch.source!r}")
    return OutputMap(tuple(c.name for c in channels), tuple(c.unit for c in channels), tuple(node), tuple(bridge),
                     tuple(contact), tuple(load), tuple(rail))
