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

import exudyn as exu
import numpy as np
from exudyn import itemInterface as ei

from ..scenario.model import Car15, MovingForce, SprungMass
from ..system.contact_rows import ContactRows
from ..system.coupling import LATERAL, VERTICAL

# rigid-body node coordinates (NodeRigidBodyRxyz): x, y, z, rx, ry, rz
RIGID_COMPONENTS: tuple[tuple[str, int], ...] = (("y", 1), ("z", 2), ("rx", 3), ("ry", 4), ("rz", 5))
WHEELSET_COMPONENTS: tuple[tuple[str, int], ...] = (("y", 1), ("z", 2), ("rx", 3))
VERTICAL_COMPONENTS: tuple[tuple[str, int], ...] = (("z", 0),)


#: frequency [Hz] and damping ratio of the weak decoupled springs holding x, wheelset spin and yaw
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


def _weak_spring(mbs: exu.MainSystem, parts: TrainParts, node: int, coordinate: int, inertia: float) -> None:
    om = 2.0 * math.pi * WEAK_SPRING_FREQUENCY
    k = inertia * om**2
    c = 2.0 * WEAK_SPRING_DAMPING_RATIO * inertia * om
    marker = mbs.AddMarker(ei.MarkerNodeCoordinate(nodeNumber=node, coordinate=coordinate))
    mbs.AddObject(ei.ObjectConnectorCoordinateSpringDamper(
        markerNumbers=[parts.ground_marker, marker], stiffness=k, damping=c,
        visualization=ei.VObjectConnectorCoordinateSpringDamper(show=False)))
    parts.decoupled.append((node, coordinate))


def add_rigid_body(
    mbs: exu.MainSystem, parts: TrainParts, *, mass: float, inertia: tuple[float, float, float],
    position: tuple[float, float, float], weak_coordinates: tuple[int, ...],
) -> tuple[int, int]:
    """A rigid body (NodeRigidBodyRxyz, principal axes along x, y, z) with gravity and weak
    coordinate springs on ``weak_coordinates``; returns (node, body)."""
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
        _weak_spring(mbs, parts, node, c, inertias[c])
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
    k_y: float, k_z: float, c_y: float, c_z: float, c_x: float = 0.0,
) -> None:
    """A linear spring-damper in global y and z (and a damper in x if c_x > 0; no stiffness in
    x) between two body points."""
    m0 = mbs.AddMarker(ei.MarkerBodyRigid(bodyNumber=body0, localPosition=list(local0)))
    m1 = mbs.AddMarker(ei.MarkerBodyRigid(bodyNumber=body1, localPosition=list(local1)))
    mbs.AddObject(ei.ObjectConnectorCartesianSpringDamper(
        markerNumbers=[m0, m1], stiffness=[0.0, k_y, k_z], damping=[c_x, c_y, c_z],
        visualization=ei.VObjectConnectorCartesianSpringDamper(show=False)))


def add_car15(
    mbs: exu.MainSystem, parts: TrainParts, car: Car15, prefix: str, first_axle: int, x_first: float
) -> None:
    """A 15-DOF car: body and two bogies (rigid, y z rx ry rz) on secondary and primary
    suspensions (per side, at their lateral spans and heights) over four rigid wheelsets in
    stiff linear contact with the rails.

    ``x_first`` is the first axle's X in the moving frame; ``first_axle`` its index in the train.
    Channels: ``<prefix>.body``, ``<prefix>.bogie1/2``, ``<prefix>.axle1..4``.
    """
    g = car.geometry
    a, s = g.half_wheelbase, g.half_bogie_spacing
    r = g.wheel_radius
    z_w = r
    z_t = z_w + g.bogie_cg_above_axle
    z_s = z_t + g.secondary_above_bogie_cg
    z_c = z_s + g.body_cg_above_secondary
    x_c = x_first - a - s
    x_t = (x_first - a, x_first - a - 2 * s)
    b_p, b_s, b = g.half_primary_span, g.half_secondary_span, parts.half_gauge

    def inertia(rb) -> tuple[float, float, float]:
        return (rb.inertia_roll, rb.inertia_pitch, rb.inertia_yaw)

    body_node, body = add_rigid_body(mbs, parts, mass=car.body.mass, inertia=inertia(car.body),
                                     position=(x_c, 0.0, z_c), weak_coordinates=(0,))
    parts.bodies.append(BodyOutput(f"{prefix}.body", body_node, RIGID_COMPONENTS, car.body.mass))
    ws = car.wheelset
    # wheelset spin and yaw inertia are not in the data and do not matter (decoupled): use roll's
    ws_inertia = (ws.inertia_roll, ws.inertia_roll, ws.inertia_roll)
    sec, pri = car.secondary, car.primary
    axle = first_axle
    for i, xt in enumerate(x_t):
        bog_node, bogie = add_rigid_body(mbs, parts, mass=car.bogie.mass, inertia=inertia(car.bogie),
                                         position=(xt, 0.0, z_t), weak_coordinates=(0,))
        parts.bodies.append(BodyOutput(f"{prefix}.bogie{i + 1}", bog_node, RIGID_COMPONENTS, car.bogie.mass))
        for side in (1.0, -1.0):
            _spring_damper(mbs, bogie, np.array([0.0, side * b_s, z_s - z_t]),
                           body, np.array([xt - x_c, side * b_s, z_s - z_c]),
                           sec.k_y, sec.k_z, sec.c_y, sec.c_z)
            if car.yaw_damper is not None:  # at the CG heights: see the module docstring
                d = side * car.yaw_damper.half_span
                _spring_damper(mbs, bogie, np.array([0.0, d, 0.0]), body, np.array([xt - x_c, d, 0.0]),
                               0.0, 0.0, 0.0, 0.0, c_x=car.yaw_damper.c_x)
        for xw in (xt + a, xt - a):
            ws_node, wheelset = add_rigid_body(mbs, parts, mass=ws.mass, inertia=ws_inertia,
                                               position=(xw, 0.0, z_w), weak_coordinates=(0, 4, 5))
            name = f"{prefix}.axle{axle - first_axle + 1}"
            parts.bodies.append(BodyOutput(name, ws_node, WHEELSET_COMPONENTS, ws.mass))
            for side in (1.0, -1.0):
                _spring_damper(mbs, wheelset, np.array([0.0, side * b_p, 0.0]),
                               bogie, np.array([xw - xt, side * b_p, z_w - z_t]),
                               pri.k_y, pri.k_z, pri.c_y, pri.c_z)
            _add_wheelset_contacts(parts, name, axle, ws_node, ws.mass, ws.inertia_roll, r, b)
            axle += 1
    parts.vehicle_frequencies.append(_car15_bounce_frequency(car))


def _add_wheelset_contacts(
    parts: TrainParts, name: str, axle: int, node: int, mass: float, roll_inertia: float, radius: float, b: float
) -> None:
    kz, ky, zeta = parts.contact_stiffness_z, parts.contact_stiffness_y, parts.contact_damping_ratio
    cz = 2.0 * zeta * math.sqrt(kz * mass / 2.0)
    cy = 2.0 * zeta * math.sqrt(ky * mass)
    parts.wheel_nodes.append((node, 6))
    for side, label in ((1.0, "left"), (-1.0, "right")):
        parts.contacts.add(
            name=f"{name}.{label}.force_z", axle=axle, direction=VERTICAL, rail_offset=side * b,
            stiffness=kz, damping=cz, wheel_terms={(node, 2): 1.0, (node, 3): side * b},
            inputs=(1.0, 0.0, side * b),
        )
    # lateral contact at rail level, the wheel radius below the wheelset centre: y + r rx
    parts.contacts.add(
        name=f"{name}.force_y", axle=axle, direction=LATERAL, rail_offset=0.0,
        stiffness=ky, damping=cy, wheel_terms={(node, 1): 1.0, (node, 3): radius},
        inputs=(0.0, 1.0, 0.0),
    )
    parts.contact_frequencies += [
        math.sqrt(2.0 * kz / mass) / (2 * math.pi),
        math.sqrt(ky / mass) / (2 * math.pi),
        math.sqrt(2.0 * kz * b * b / roll_inertia) / (2 * math.pi),
    ]


def _car15_bounce_frequency(car: Car15) -> float:
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
    "sprung_mass": add_sprung_mass,
    "moving_force": add_moving_force,
}
