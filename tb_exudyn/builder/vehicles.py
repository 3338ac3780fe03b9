"""Vehicles as Exudyn items: rigid bodies, suspensions, gravity and the wheel-rail contact rows.

Frame: every vehicle body lives in a frame moving with the train at constant speed (a Galilean
frame: no fictitious forces). Its x coordinate there is fixed by the train's geometry: the
train's first axle at X = 0, axle j at X = -a_j (a_j = ``Train.axle_positions``); along the track
the axle is at x_j(t) = x0_j + v t, which only the wheel-rail coupling needs. Heights z are
measured from the rail top of the undeformed track (wheelset centre at the wheel radius).

Sign conventions: y left, z up; rotations rx (roll), ry (pitch), rz (yaw) right-handed about x,
y, z. Node coordinates are displacements from this reference configuration.

Coordinates outside the reference study's 15-DOF car (every body's longitudinal x, wheelset spin
ry and yaw rz) are held by weak coordinate springs to ground at the body's centre of gravity. The
suspensions have no longitudinal stiffness (their data has none) and act in global y and z, and the
wheel-rail contact uses only a wheelset's y, z and rx; so these coordinates are exactly decoupled
from the 15 car DOFs, the wheelsets and the bridge (a body's x moves no spring end in y or z; a
wheelset's spin and yaw move its spring ends only along x). The springs only make the stiffness
matrix regular for the static solution and keep the uncoupled coordinates at rest; their frequency
(``weak_spring_frequency``, 0.1 Hz by default) and damping do not enter any coupled mode.
A constraint would do the same but adds Lagrange multipliers (an index-3 DAE) for nothing.

The optional secondary yaw dampers (``Car15.yaw_damper``) are the one element acting along x: a
damper c_x per side between body and bogie at y = +-d. Their end points lie at the heights of the
body's and the bogie's centres of gravity, so the linearised x motion of an end is x - rz y (no
pitch term ry z). The pair's forces then split exactly into a relative-yaw damper 2 c_x d^2 on
rz_body - rz_bogie (the yaw damping of the 15-DOF models) and a longitudinal damper 2 c_x on
x_body - x_bogie. That second part connects the weak coordinates of body and bogie with each
other only, so the decoupling above still holds: the x coordinates form their own (overdamped)
subsystem, reached by no irregularity and by no mode of the 15 DOFs, the wheelsets or the bridge.
A damper at another height would add a pitch term and couple the car's pitch to the weakly held x.

Creep cars (``creep_car``, :func:`add_creep_car`) have longitudinal springs in both stages, at the
axle box and secondary heights: a bogie's or the body's pitch moves their ends along x, so there
the x coordinates belong to the vertical plane (the weak springs on the body's and bogies' x hold
only the train's surge, 0.1 Hz, and are not marked decoupled). The wheelsets' lateral motion, roll
and yaw are coupled by the creep rows (:mod:`tb_exudyn.system.creep`), their vertical motion by the
penalty rows as on car15 (with the coned wheels' rolling-radius terms: a laterally displaced
wheelset rolls by lambda e / b0), their x and spin ry by the common longitudinal creep (x' - r0 ry') / v of
the creep rows. The spin is a free rotation (a constant ry costs nothing): a weak spring (0.1 Hz
against the spin inertia, not decoupled) keeps the stiffness matrix regular; the creep damping
c r0^2 (c = 2 f11 / v) on the spin turns its mode into a fast real root (about -c r0^2 / I_wy;
ICE creep cars at 220 km/h: 107-114 Hz) and a slow one (about -k_weak / (c r0^2): decay times of
1.4e3 s, below 1e-3 Hz: "rigid" in a mode table, exempt from the damping guard), both outside any
analysed band and moving no channel (the creep forces depend on the spin rate only). The wheelset's
longitudinal motion against its spin is damped by that creep (37.8 Hz, 4.4-4.6 %, the same cars).

Wheel-rail contact damping (``analysis.contact_damping_ratio``, default 0.5): the damping ratio of
every contact against the wheel mass it carries (vertical: half a wheelset per wheel; lateral: the
wheelset), c = 2 zeta sqrt(k m). The contact is a penalty form of the reference model's constraint
"the wheelset follows the rail"; near-critical damping makes its transfer function from rail to
wheel flattest (least overshoot below the contact frequency, ~200 Hz) and keeps its stiff mode from
ringing, which 1 ms steps cannot resolve. Measured (1 mm irregularity, 1 ms against 0.25 ms steps):
wheel forces converge to 0.8 % with 0.5, to 30 % with 0.05. As the contact stiffness grows, c grows
as sqrt(k) and the contact still tends to the constraint.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable

import exudyn as exu
import numpy as np
from exudyn import itemInterface as ei

from ..scenario.model import (
    ArticulatedSet,
    Car15,
    Car15Geometry,
    CreepCar,
    GivenCreep,
    MovingForce,
    RigidBodyInertia,
    SprungMass,
    Suspension,
    Suspension3,
)
from ..system.contact_rows import ContactRows
from ..system.coupling import LATERAL, VERTICAL
from ..system.creep import (
    WHEEL_COORDINATES,
    CreepCoefficients,
    CreepRows,
    WheelsetContact,
    creep_rows,
    hertz_creep_coefficients,
    rolling_roll_terms,
)

# rigid-body node coordinates (NodeRigidBodyRxyz): x, y, z, rx, ry, rz
RIGID_COMPONENTS: tuple[tuple[str, int], ...] = (("y", 1), ("z", 2), ("rx", 3), ("ry", 4), ("rz", 5))
WHEELSET_COMPONENTS: tuple[tuple[str, int], ...] = (("y", 1), ("z", 2), ("rx", 3))
#: a creep-guided wheelset (creep_car) also yaws
CREEP_WHEELSET_COMPONENTS: tuple[tuple[str, int], ...] = WHEELSET_COMPONENTS + (("rz", 5),)
#: node coordinates of the creep rows' wheelset coordinates (tb_exudyn.system.creep.WHEEL_COORDINATES)
CREEP_NODE_COORDINATES: tuple[int, ...] = tuple({"x": 0, "y": 1, "rx": 3, "ry": 4, "rz": 5}[c] for c in WHEEL_COORDINATES)
VERTICAL_COMPONENTS: tuple[tuple[str, int], ...] = (("z", 0),)


#: frequency [Hz] and damping ratio of the weak springs holding x, wheelset spin and yaw (decoupled on
#: car15; on a creep car they hold the train's surge and the wheelsets' free spin)
WEAK_SPRING_FREQUENCY, WEAK_SPRING_DAMPING_RATIO = 0.1, 1.0


@dataclass(frozen=True)
class BodyOutput:
    """A node whose motion becomes output channels ``<name>.<quantity>_<component>``."""

    name: str
    node: int
    components: tuple[tuple[str, int], ...]
    mass: float


@dataclass
class TrainParts:
    """Everything the vehicles add to the system, collected while building."""

    ground_marker: int
    gravity: float
    contact_damping_ratio: float
    half_gauge: float
    contact_stiffness_z: float
    contact_stiffness_y: float
    #: train speed v [m/s] (the creep rows' damping is proportional to 1 / v)
    speed: float
    bodies: list[BodyOutput] = field(default_factory=list)
    #: (load number, parameter name, value with gravity on)
    gravity_loads: list[tuple[int, str, object]] = field(default_factory=list)
    #: (node, node coordinate, generalised gravity force [N]) for static solutions
    weights: list[tuple[int, int, float]] = field(default_factory=list)
    #: nodes with wheels in contact with the rail: (node, number of coordinates), in order
    wheel_nodes: list[tuple[int, int]] = field(default_factory=list)
    contacts: ContactRows = field(default_factory=ContactRows)
    #: moving point loads: axle index, downward force at gravity on [N], channel name
    load_axle: list[int] = field(default_factory=list)
    load_force: list[float] = field(default_factory=list)
    load_names: list[str] = field(default_factory=list)
    #: contact natural frequencies [Hz] (for time-step checks)
    contact_frequencies: list[float] = field(default_factory=list)
    #: lowest natural frequency estimate of every vehicle's suspension [Hz]
    vehicle_frequencies: list[float] = field(default_factory=list)
    #: (node, node coordinate) of every coordinate held only by a weak spring (decoupled)
    decoupled: list[tuple[int, int]] = field(default_factory=list)


def _weak_spring(mbs: exu.MainSystem, parts: TrainParts, node: int, coordinate: int, inertia: float,
                 decoupled: bool = True) -> None:
    om = 2.0 * math.pi * WEAK_SPRING_FREQUENCY
    k = inertia * om**2
    c = 2.0 * WEAK_SPRING_DAMPING_RATIO * inertia * om
    marker = mbs.AddMarker(ei.MarkerNodeCoordinate(nodeNumber=node, coordinate=coordinate))
    mbs.AddObject(ei.ObjectConnectorCoordinateSpringDamper(
        markerNumbers=[parts.ground_marker, marker], stiffness=k, damping=c,
        visualization=ei.VObjectConnectorCoordinateSpringDamper(show=False)))
    if decoupled:
        parts.decoupled.append((node, coordinate))


def add_rigid_body(
    mbs: exu.MainSystem, parts: TrainParts, *, mass: float, inertia: tuple[float, float, float],
    position: tuple[float, float, float], weak_coordinates: tuple[int, ...], decoupled: bool = True,
) -> tuple[int, int]:
    """A rigid body (NodeRigidBodyRxyz, principal axes along x, y, z) with gravity and weak
    coordinate springs on ``weak_coordinates`` (``decoupled``: they are the only elements acting
    on those coordinates, see :class:`TrainParts`); returns (node, body)."""
    node = mbs.AddNode(ei.NodeRigidBodyRxyz(referenceCoordinates=[*position, 0.0, 0.0, 0.0],
                                            initialCoordinates=[0.0] * 6, initialVelocities=[0.0] * 6))
    body = mbs.AddObject(ei.ObjectRigidBody(mass=mass, inertia=[*inertia, 0.0, 0.0, 0.0], nodeNumber=node))
    marker = mbs.AddMarker(ei.MarkerBodyMass(bodyNumber=body))
    g = [0.0, 0.0, -parts.gravity]
    load = mbs.AddLoad(ei.LoadMassProportional(markerNumber=marker, loadVector=g))
    parts.gravity_loads.append((load, "loadVector", g))
    parts.weights.append((node, 2, -mass * parts.gravity))
    inertias = (mass, mass, mass, *inertia)
    for c in weak_coordinates:
        _weak_spring(mbs, parts, node, c, inertias[c], decoupled)
    return node, body


def add_point_mass(mbs: exu.MainSystem, parts: TrainParts, *, mass: float) -> int:
    """A mass moving vertically only (one-coordinate node, z up) with gravity; returns the node."""
    node = mbs.AddNode(ei.NodeGenericODE2(referenceCoordinates=[0.0], initialCoordinates=[0.0],
                                          initialCoordinates_t=[0.0], numberOfODE2Coordinates=1))
    mbs.AddObject(ei.ObjectGenericODE2(nodeNumbers=[node], massMatrix=np.array([[mass]]),
                                       visualization=ei.VObjectGenericODE2(show=False)))
    marker = mbs.AddMarker(ei.MarkerNodeCoordinate(nodeNumber=node, coordinate=0))
    w = -mass * parts.gravity
    load = mbs.AddLoad(ei.LoadCoordinate(markerNumber=marker, load=w))
    parts.gravity_loads.append((load, "load", w))
    parts.weights.append((node, 0, w))
    return node


def _spring_damper(
    mbs: exu.MainSystem, body0: int, local0: np.ndarray, body1: int, local1: np.ndarray,
    stiffness: tuple[float, float, float], damping: tuple[float, float, float],
) -> None:
    """A linear spring-damper in global x, y and z (stiffness and damping per direction) between
    two body points."""
    m0 = mbs.AddMarker(ei.MarkerBodyRigid(bodyNumber=body0, localPosition=list(local0)))
    m1 = mbs.AddMarker(ei.MarkerBodyRigid(bodyNumber=body1, localPosition=list(local1)))
    mbs.AddObject(ei.ObjectConnectorCartesianSpringDamper(
        markerNumbers=[m0, m1], stiffness=list(stiffness), damping=list(damping),
        visualization=ei.VObjectConnectorCartesianSpringDamper(show=False)))


def _stage(s: Suspension | Suspension3) -> tuple[tuple[float, float, float], tuple[float, float, float], tuple[float, float]]:
    """One suspension element: stiffness and damping of its Cartesian spring-damper in x, y, z
    (nothing in x: a longitudinal stiffness is a :func:`_longitudinal_pair`) and its longitudinal
    (k_x, c_x); a car15 stage has nothing along x."""
    if isinstance(s, Suspension3):
        return (0.0, s.k_y, s.k_z), (0.0, s.c_y, s.c_z), (s.k_x, s.c_x)
    return (0.0, s.k_y, s.k_z), (0.0, s.c_y, s.c_z), (0.0, 0.0)


def _longitudinal_pair(
    mbs: exu.MainSystem, node0: int, ends0: list[np.ndarray], node1: int, ends1: list[np.ndarray],
    k_x: float, c_x: float,
) -> None:
    """Longitudinal springs and dampers (k_x, c_x each) between body points (offsets from each
    node's centre of gravity, pairwise), as ONE linear element on the two rigid-body nodes'
    coordinates: the x displacement of an end at offset d is x + ry d_z - rz d_y (small rotations),
    so K = k_x sum g g^T, D = c_x sum g g^T with g the relative x displacement of a pair's ends.

    Why not the Cartesian connector: it computes the spring's extension from absolute positions
    (reference + displacement), and at tens of metres along the train a 85 MN/m spring turns their
    round-off (1e-15 m) into ~1e-6 N of residual force, the Newton absolute tolerance: the
    pseudo-excitation runs (0.1 mm inputs) then stop. The linear element works on the displacements
    alone; the x springs carry no preload, so their geometric stiffness is zero and the element is
    their exact linearisation (the second-order change of an end's x under rotations, of the
    rotation squared times the offset, is left out)."""
    K = np.zeros((12, 12))
    for d0, d1 in zip(ends0, ends1):
        g = np.zeros(12)
        g[[0, 4, 5]] = -1.0, -d0[2], d0[1]
        g[[6, 10, 11]] = 1.0, d1[2], -d1[1]
        K += np.outer(g, g)
    mbs.AddObject(ei.ObjectGenericODE2(
        nodeNumbers=[node0, node1], massMatrix=np.zeros((12, 12)), stiffnessMatrix=k_x * K, dampingMatrix=c_x * K,
        visualization=ei.VObjectGenericODE2(show=False)))


@dataclass(frozen=True)
class _CarLevels:
    """Positions in the moving frame of a car with two two-axle bogies [m]: body CG x_c, bogie
    centres x_t, heights of the wheelset centres z_w, the bogie CG z_t, the secondary z_s and the
    body CG z_c."""

    x_c: float
    x_t: tuple[float, float]
    z_w: float
    z_t: float
    z_s: float
    z_c: float


def _car_levels(g: Car15Geometry, x_first: float) -> _CarLevels:
    a, s = g.half_wheelbase, g.half_bogie_spacing
    z_w = g.wheel_radius
    z_t = z_w + g.bogie_cg_above_axle
    z_s = z_t + g.secondary_above_bogie_cg
    return _CarLevels(x_c=x_first - a - s, x_t=(x_first - a, x_first - a - 2 * s), z_w=z_w, z_t=z_t, z_s=z_s,
                      z_c=z_s + g.body_cg_above_secondary)


def _inertia(rb: RigidBodyInertia) -> tuple[float, float, float]:
    return (rb.inertia_roll, rb.inertia_pitch, rb.inertia_yaw)


#: adds one wheelset and its primary suspension: (bogie node, bogie body, bogie x, wheelset x, axle index,
#: channel name)
WheelsetBuilder = Callable[[int, int, float, float, int, str], None]


def _add_two_bogie_car(
    mbs: exu.MainSystem, parts: TrainParts, car: Car15 | CreepCar, prefix: str, first_axle: int,
    levels: _CarLevels, add_wheelset: WheelsetBuilder, x_decoupled: bool,
) -> None:
    """Body and two bogies (rigid, x on weak springs), the secondary suspension per side at
    (x_t, +-b_s, z_s), the yaw dampers, and each bogie's two wheelsets by ``add_wheelset``.
    ``x_decoupled``: whether the bodies' x is decoupled from the rest (car15: nothing acts along x
    but the yaw dampers, see the module docstring)."""
    L = levels
    b_s = car.geometry.half_secondary_span
    a = car.geometry.half_wheelbase
    body_node, body = add_rigid_body(mbs, parts, mass=car.body.mass, inertia=_inertia(car.body),
                                     position=(L.x_c, 0.0, L.z_c), weak_coordinates=(0,), decoupled=x_decoupled)
    parts.bodies.append(BodyOutput(f"{prefix}.body", body_node, RIGID_COMPONENTS, car.body.mass))
    sec_k, sec_c, (sec_kx, sec_cx) = _stage(car.secondary)
    axle = first_axle
    for i, xt in enumerate(L.x_t):
        bog_node, bogie = add_rigid_body(mbs, parts, mass=car.bogie.mass, inertia=_inertia(car.bogie),
                                         position=(xt, 0.0, L.z_t), weak_coordinates=(0,), decoupled=x_decoupled)
        parts.bodies.append(BodyOutput(f"{prefix}.bogie{i + 1}", bog_node, RIGID_COMPONENTS, car.bogie.mass))
        ends: tuple[list[np.ndarray], list[np.ndarray]] = ([], [])
        for side in (1.0, -1.0):
            ends[0].append(np.array([0.0, side * b_s, L.z_s - L.z_t]))
            ends[1].append(np.array([xt - L.x_c, side * b_s, L.z_s - L.z_c]))
            _spring_damper(mbs, bogie, ends[0][-1], body, ends[1][-1], sec_k, sec_c)
            if car.yaw_damper is not None:  # at the CG heights: see the module docstring
                d = side * car.yaw_damper.half_span
                _spring_damper(mbs, bogie, np.array([0.0, d, 0.0]), body, np.array([xt - L.x_c, d, 0.0]),
                               (0.0, 0.0, 0.0), (car.yaw_damper.c_x, 0.0, 0.0))
        if sec_kx or sec_cx:
            _longitudinal_pair(mbs, bog_node, ends[0], body_node, ends[1], sec_kx, sec_cx)
        for xw in (xt + a, xt - a):
            add_wheelset(bog_node, bogie, xt, xw, axle, f"{prefix}.axle{axle - first_axle + 1}")
            axle += 1
    parts.vehicle_frequencies.append(_car15_bounce_frequency(car))


def add_car15(
    mbs: exu.MainSystem, parts: TrainParts, car: Car15, prefix: str, first_axle: int, x_first: float
) -> None:
    """A 15-DOF car: body and two bogies (rigid, y z rx ry rz) on secondary and primary
    suspensions (per side, at their lateral spans and heights) over four rigid wheelsets in
    stiff linear contact with the rails.

    ``x_first`` is the first axle's X in the moving frame; ``first_axle`` its index in the train.
    Channels: ``<prefix>.body``, ``<prefix>.bogie1/2``, ``<prefix>.axle1..4``.
    """
    L = _car_levels(car.geometry, x_first)
    _add_two_bogie_car(mbs, parts, car, prefix, first_axle, L, _rigid_wheelsets(mbs, parts, car, L), x_decoupled=True)


def _rigid_wheelsets(mbs: exu.MainSystem, parts: TrainParts, car: Car15 | ArticulatedSet, L: _CarLevels
                     ) -> WheelsetBuilder:
    """The builder of a car15-style wheelset (rigid, y z rx, on the primary suspension per side, two vertical
    and one lateral contact rows) of ``car``'s data."""
    r, b_p, b = car.geometry.wheel_radius, car.geometry.half_primary_span, parts.half_gauge
    ws = car.wheelset
    # wheelset spin and yaw inertia are not in the data and do not matter (decoupled): use roll's
    ws_inertia = (ws.inertia_roll, ws.inertia_roll, ws.inertia_roll)
    pri_k, pri_c, _ = _stage(car.primary)

    def add_wheelset(bog_node: int, bogie: int, xt: float, xw: float, axle: int, name: str) -> None:
        ws_node, wheelset = add_rigid_body(mbs, parts, mass=ws.mass, inertia=ws_inertia,
                                           position=(xw, 0.0, L.z_w), weak_coordinates=(0, 4, 5))
        parts.bodies.append(BodyOutput(name, ws_node, WHEELSET_COMPONENTS, ws.mass))
        for side in (1.0, -1.0):
            _spring_damper(mbs, wheelset, np.array([0.0, side * b_p, 0.0]),
                           bogie, np.array([xw - xt, side * b_p, L.z_w - L.z_t]), pri_k, pri_c)
        parts.wheel_nodes.append((ws_node, 6))
        _add_vertical_contacts(parts, name, axle, ws_node, ws.mass, ws.inertia_roll, b)
        _add_lateral_contact(parts, name, axle, ws_node, ws.mass, r)

    return add_wheelset


def add_articulated(
    mbs: exu.MainSystem, parts: TrainParts, veh: ArticulatedSet, prefix: str, first_axle: int, x_first: float
) -> None:
    """An articulated set: ``bodies`` car bodies and ``bodies + 1`` bogies (rigid, y z rx ry rz, as car15's),
    body i on bogies i and i + 1 (1 = leading) through the secondary suspension per side at each of its ends,
    each bogie on its two car15 wheelsets. Channels ``<prefix>.body<i>``, ``<prefix>.bogie<j>``,
    ``<prefix>.axle<k>`` (k = 1 ... 2 (bodies + 1)). A body's weight goes half to each of its bogies (its ends
    at +-half_bogie_spacing, its centre of gravity midway)."""
    g = veh.geometry
    L = _car_levels(g, x_first)
    p, a, b_s = 2 * g.half_bogie_spacing, g.half_wheelbase, g.half_secondary_span
    sec_k, sec_c, _ = _stage(veh.secondary)
    add_wheelset = _rigid_wheelsets(mbs, parts, veh, L)
    bodies = []
    for i in range(veh.bodies):
        x_c = x_first - a - (i + 0.5) * p
        node, body = add_rigid_body(mbs, parts, mass=veh.body.mass, inertia=_inertia(veh.body),
                                    position=(x_c, 0.0, L.z_c), weak_coordinates=(0,))
        parts.bodies.append(BodyOutput(f"{prefix}.body{i + 1}", node, RIGID_COMPONENTS, veh.body.mass))
        bodies.append((body, x_c))
    for j in range(veh.bodies + 1):
        xt = x_first - a - j * p
        bog_node, bogie = add_rigid_body(mbs, parts, mass=veh.bogie.mass, inertia=_inertia(veh.bogie),
                                         position=(xt, 0.0, L.z_t), weak_coordinates=(0,))
        parts.bodies.append(BodyOutput(f"{prefix}.bogie{j + 1}", bog_node, RIGID_COMPONENTS, veh.bogie.mass))
        for body, x_c in bodies[max(j - 1, 0):j + 1]:  # the bodies on this bogie: behind it and ahead of it
            for side in (1.0, -1.0):
                _spring_damper(mbs, bogie, np.array([0.0, side * b_s, L.z_s - L.z_t]), body,
                               np.array([xt - x_c, side * b_s, L.z_s - L.z_c]), sec_k, sec_c)
        for k, xw in enumerate((xt + a, xt - a)):
            axle = first_axle + 2 * j + k
            add_wheelset(bog_node, bogie, xt, xw, axle, f"{prefix}.axle{2 * j + k + 1}")
    parts.vehicle_frequencies.append(_car15_bounce_frequency(veh))


def _add_vertical_contacts(
    parts: TrainParts, name: str, axle: int, node: int, mass: float, roll_inertia: float, b: float,
    contact: WheelsetContact | None = None,
) -> None:
    """The two vertical penalty rows of a wheelset (left and right wheel at +-b: z + e rx); with
    ``contact`` (a creep car's coned wheels) also the rolling-radius terms of
    :func:`tb_exudyn.system.creep.rolling_roll_terms` (the wheelset rolls by lambda e / b0)."""
    kz, zeta = parts.contact_stiffness_z, parts.contact_damping_ratio
    cz = 2.0 * zeta * math.sqrt(kz * mass / 2.0)
    for side, label in ((1.0, "left"), (-1.0, "right")):
        wheel, alignment, rail_y = {(node, 2): 1.0, (node, 3): side * b}, 0.0, 0.0
        if contact is not None:
            roll = rolling_roll_terms(contact, side, b)
            wheel[(node, 1)] = roll.wheel_y
            wheel[(node, 3)] += roll.wheel_rx
            alignment = rail_y = roll.rail_y
        parts.contacts.add(
            name=f"{name}.{label}.force_z", axle=axle, direction=VERTICAL, rail_offset=side * b,
            stiffness=kz, damping=cz, wheel_terms=wheel, inputs=(1.0, alignment, side * b), rail_lateral=rail_y,
        )
    parts.contact_frequencies += [
        math.sqrt(2.0 * kz / mass) / (2 * math.pi),
        math.sqrt(2.0 * kz * b * b / roll_inertia) / (2 * math.pi),
    ]


def _add_lateral_contact(parts: TrainParts, name: str, axle: int, node: int, mass: float, radius: float) -> None:
    """The lateral penalty row of a car15 wheelset: contact at rail level, the wheel radius below
    the wheelset centre: y + r rx."""
    ky, zeta = parts.contact_stiffness_y, parts.contact_damping_ratio
    cy = 2.0 * zeta * math.sqrt(ky * mass)
    parts.contacts.add(
        name=f"{name}.force_y", axle=axle, direction=LATERAL, rail_offset=0.0,
        stiffness=ky, damping=cy, wheel_terms={(node, 1): 1.0, (node, 3): radius},
        inputs=(0.0, 1.0, 0.0),
    )
    parts.contact_frequencies.append(math.sqrt(ky / mass) / (2 * math.pi))


def wheelset_contact(car: CreepCar, gravity: float) -> WheelsetContact:
    """The linear contact data of each wheelset of a creep car (:mod:`tb_exudyn.system.creep`) at
    its static axle load W = ``car.static_axle_load(gravity)`` [N]: creep coefficients from Hertz's
    ellipse under W / 2 per wheel and Kalker's table (times ``creep.factor``), or given as data.
    They are the contact's linearisation at the static load, so they (and the gravitational
    stiffness W epsilon / b0) stay when a run switches gravity off (the pseudo-excitation runs)."""
    c = car.contact
    W = car.static_axle_load(gravity)
    cr = c.creep
    if isinstance(cr, GivenCreep):
        coefficients = CreepCoefficients(f11=cr.f11, f22=cr.f22, f23=cr.f23, f33=cr.f33)
    else:
        coefficients = hertz_creep_coefficients(
            W / 2, car.geometry.wheel_radius, cr.rail_transverse_radius, cr.wheel_transverse_radius,
            E=cr.youngs_modulus, nu=cr.poisson_ratio)[0].scaled(cr.factor)
    return WheelsetContact(
        coefficients=coefficients, rolling_radius=car.geometry.wheel_radius,
        half_contact_distance=c.half_contact_distance, conicity=c.conicity, axle_load=W,
        contact_angle_parameter=c.contact_angle_parameter, gravitational_yaw_stiffness=c.gravitational_yaw_stiffness,
        spin=c.spin,
    )


def add_creep_car(
    mbs: exu.MainSystem, parts: TrainParts, car: CreepCar, prefix: str, first_axle: int, x_first: float
) -> None:
    """A car whose wheelsets are guided by linear Kalker creep forces (kind ``creep_car``).

    Body and two bogies as in :func:`add_car15` (y, z, rx, ry, rz; x on weak springs). Each
    wheelset a rigid body with x, y, z, roll rx, spin ry (its perturbation of the rolling rate
    v / r0, inertia ``wheelset.inertia_spin``; a weak spring, not decoupled, makes K regular: see the
    module docstring) and yaw rz. Primary suspension per side between wheelset and bogie at
    (x_w, +-b_p, z_w) in x, y and z (the pair gives the wheelset the yaw stiffness 2 k_x b_p^2
    against the bogie); secondary per side at (x_t, +-b_s, z_s) in x, y and z; yaw dampers as
    car15's. Wheel-rail contact: the two vertical penalty rows of car15 per wheelset (z + e rx, the
    wheelset follows the rail vertically) with the coned wheels' rolling-radius terms (the wheelset
    rolls by lambda e / b0 on the rails, the normal forces act at the inclined contacts:
    :func:`tb_exudyn.system.creep.rolling_roll_terms`) and, instead of car15's lateral penalty row, the four
    linear creep rows of :func:`tb_exudyn.system.creep.creep_rows` at the train's speed (general
    linear rows of the coupling: lateral creep and gravitational force, longitudinal creep per
    wheel with the common part on x and spin, spin and gravitational yaw moment).

    Longitudinal motion is not decoupled here: the primary and secondary k_x act at the axle box
    and secondary heights, so a bogie's or the body's pitch moves their ends along x; the car's x
    coordinates join its vertical plane (the weak springs still hold the train's surge, 0.1 Hz).

    Channels: ``<prefix>.body``, ``<prefix>.bogie1/2`` as car15; ``<prefix>.axle1..4`` with y, z,
    rx, rz, the vertical wheel forces ``left/right.force_z`` and the creep rows ``force_y``
    (lateral force of the rail on the wheelset at rail level, as car15's), ``left/right.force_x``
    (longitudinal creep force per wheel: the yaw-antisymmetric and the common part) and ``moment_z`` [N m] (docs/channels.md).
    """
    L = _car_levels(car.geometry, x_first)
    b_p, b = car.geometry.half_primary_span, parts.half_gauge
    ws = car.wheelset
    ws_inertia = (ws.inertia_roll, ws.inertia_spin, ws.inertia_yaw)
    pri_k, pri_c, (pri_kx, pri_cx) = _stage(car.primary)
    contact = wheelset_contact(car, parts.gravity)
    rows = creep_rows(contact, parts.speed)

    def add_wheelset(bog_node: int, bogie: int, xt: float, xw: float, axle: int, name: str) -> None:
        ws_node, wheelset = add_rigid_body(mbs, parts, mass=ws.mass, inertia=ws_inertia,
                                           position=(xw, 0.0, L.z_w), weak_coordinates=(4,), decoupled=False)
        parts.bodies.append(BodyOutput(name, ws_node, CREEP_WHEELSET_COMPONENTS, ws.mass))
        ends: tuple[list[np.ndarray], list[np.ndarray]] = ([], [])
        for side in (1.0, -1.0):
            ends[0].append(np.array([0.0, side * b_p, 0.0]))
            ends[1].append(np.array([xw - xt, side * b_p, L.z_w - L.z_t]))
            _spring_damper(mbs, wheelset, ends[0][-1], bogie, ends[1][-1], pri_k, pri_c)
        if pri_kx or pri_cx:
            _longitudinal_pair(mbs, ws_node, ends[0], bog_node, ends[1], pri_kx, pri_cx)
        parts.wheel_nodes.append((ws_node, 6))
        _add_vertical_contacts(parts, name, axle, ws_node, ws.mass, ws.inertia_roll, b, contact)
        _add_creep_rows(parts, name, axle, ws_node, rows)

    _add_two_bogie_car(mbs, parts, car, prefix, first_axle, L, add_wheelset, x_decoupled=False)


def _add_creep_rows(parts: TrainParts, name: str, axle: int, node: int, rows: CreepRows) -> None:
    """The creep rows of one wheelset as general linear rows ``<name>.<row>`` of the coupling."""
    for i, row in enumerate(rows.rows):
        wheel = [{(node, c): float(M[i, j]) for j, c in enumerate(CREEP_NODE_COORDINATES) if M[i, j] != 0.0}
                 for M in (rows.A_w, rows.K_w, rows.C_w)]
        parts.contacts.add_linear(
            name=f"{name}.{row}", axle=axle, wheel_application=wheel[0], wheel_stiffness=wheel[1],
            wheel_damping=wheel[2], rail_application=rows.A_r[i], rail_stiffness=rows.K_r[i],
            rail_damping=rows.C_r[i],
        )


def _car15_bounce_frequency(car: Car15 | CreepCar) -> float:
    """Car body bounce on both suspension stages in series [Hz] (a lowest-mode estimate)."""
    k_corner = 1.0 / (1.0 / (2 * car.secondary.k_z) + 1.0 / (4 * car.primary.k_z))
    return math.sqrt(2 * k_corner / car.body.mass) / (2 * math.pi)


def add_sprung_mass(mbs: exu.MainSystem, parts: TrainParts, veh: SprungMass, prefix: str, axle: int,
                    x_first: float = 0.0) -> None:
    """One mass on a spring-damper over one wheel. With ``wheel_mass = 0`` the spring-damper's
    lower end follows the rail exactly (the suspension is the contact row); otherwise a wheel mass
    sits on the rail through the stiff vertical contact. Channels ``<prefix>.body`` (z),
    ``<prefix>.axle1`` (z, with a wheel mass) and ``<prefix>.axle1.force_z``."""
    mass_node = add_point_mass(mbs, parts, mass=veh.mass)
    parts.bodies.append(BodyOutput(f"{prefix}.body", mass_node, VERTICAL_COMPONENTS, veh.mass))
    name = f"{prefix}.axle1.force_z"
    if veh.wheel_mass == 0.0:
        parts.wheel_nodes.append((mass_node, 1))
        parts.contacts.add(name=name, axle=axle, direction=VERTICAL, rail_offset=0.0,
                           stiffness=veh.stiffness, damping=veh.damping,
                           wheel_terms={(mass_node, 0): 1.0}, inputs=(1.0, 0.0, 0.0))
    else:
        wheel_node = add_point_mass(mbs, parts, mass=veh.wheel_mass)
        parts.bodies.append(BodyOutput(f"{prefix}.axle1", wheel_node, VERTICAL_COMPONENTS, veh.wheel_mass))
        m0 = mbs.AddMarker(ei.MarkerNodeCoordinate(nodeNumber=wheel_node, coordinate=0))
        m1 = mbs.AddMarker(ei.MarkerNodeCoordinate(nodeNumber=mass_node, coordinate=0))
        mbs.AddObject(ei.ObjectConnectorCoordinateSpringDamper(
            markerNumbers=[m0, m1], stiffness=veh.stiffness, damping=veh.damping,
            visualization=ei.VObjectConnectorCoordinateSpringDamper(show=False)))
        kz = parts.contact_stiffness_z
        cz = 2.0 * parts.contact_damping_ratio * math.sqrt(kz * veh.wheel_mass)
        parts.wheel_nodes.append((wheel_node, 1))
        parts.contacts.add(name=name, axle=axle, direction=VERTICAL, rail_offset=0.0, stiffness=kz,
                           damping=cz, wheel_terms={(wheel_node, 0): 1.0}, inputs=(1.0, 0.0, 0.0))
        parts.contact_frequencies.append(math.sqrt(kz / veh.wheel_mass) / (2 * math.pi))
    parts.vehicle_frequencies.append(math.sqrt(veh.stiffness / veh.mass) / (2 * math.pi))


def add_moving_force(mbs: exu.MainSystem, parts: TrainParts, veh: MovingForce, prefix: str, axle: int,
                     x_first: float = 0.0) -> None:
    """A constant downward point load on the track centre line (present while gravity is on).
    Channel ``<prefix>.axle1.force_z``."""
    parts.load_axle.append(axle)
    parts.load_force.append(veh.force)
    parts.load_names.append(f"{prefix}.axle1.force_z")



#: the builder of each vehicle kind (``Vehicle.kind``), one signature:
#: ``add(mbs, parts, vehicle, prefix, first_axle, x_first)`` with ``prefix`` the channel prefix
#: (``car<k>``), ``first_axle`` the index of its first axle in the train and ``x_first`` that axle's X
#: in the moving frame. Adding a vehicle kind is a dataclass in tb_exudyn/scenario/model.py and one line here.
VEHICLE_BUILDERS = {
    "car15": add_car15,
    "articulated": add_articulated,
    "creep_car": add_creep_car,
    "sprung_mass": add_sprung_mass,
    "moving_force": add_moving_force,
}
