"""The scenario: frozen, typed dataclasses for train, bridge, track, speed and analysis settings.

Pure data, no Exudyn. SI units everywhere; a key whose unit is not SI says so in its name
(``speed_kmh``). Axes: x along the track in the direction of travel, y lateral to the left,
z up. Every field is declared with :func:`param` (unit, description, value check), so the
dataclasses are the schema of the TOML files in ``models/``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar, Literal, Union

from ..track import spectrum_names
from .code_data import CodeData  # noqa: F401 (re-exported)
from .continuous import CONTINUOUS_SUPPORTS, Continuous, ContinuousBearings  # noqa: F401 (re-exported)
from .girders import Bearings, Frame, SimpleBeam  # noqa: F401 (re-exported: the simply supported kinds)
from .sections import AddedMass, BeamSection, Pier, TrackLine, _Replaceable, check_track_choice, track_lines  # noqa: F401
from .modal_table import ModalTable
from .track_structure import check_track_structure
from .schema import (ANY, NONNEGATIVE, POSITIVE, SPEED_KMH, STIFFNESS, VEHICLE_DAMPER, VEHICLE_DAMPING,
                     VEHICLE_INERTIA, VEHICLE_MASS, VEHICLE_MASS_OR_0, VEHICLE_STIFFNESS, VEHICLE_STIFFNESS_OR_0,
                     Check, Context, Validated, described, param, replace, source_file)

KMH = 1.0 / 3.6  # m/s per km/h


# ============================================================================================
# vehicles


class _OneAxle:
    """A vehicle of one axle (the moving force, the sprung mass): no cross-field checks."""

    @property
    def axle_offsets(self) -> tuple[float, ...]:
        """Distances of the axles behind the vehicle's first axle [m]."""
        return (0.0,)


@dataclass(frozen=True, kw_only=True)
@described
class MovingForce(_Replaceable, _OneAxle):
    """A constant vertical point load moving along the track (for closed-form checks)."""

    kind: ClassVar[str] = "moving_force"
    name: str = param(doc="identifier")
    force: float = param(unit="N", doc="load acting downward on the rail", check=POSITIVE)
    length: float = param(unit="m", doc="distance from this load to the next vehicle's first axle", check=POSITIVE)


@dataclass(frozen=True, kw_only=True)
@described
class SprungMass(_Replaceable, _OneAxle):
    """One mass on a linear spring-damper over one wheel (the VBI-2D / Yang-Yau vehicle).

    With ``wheel_mass = 0`` the spring-damper's lower end follows the rail exactly.
    """

    kind: ClassVar[str] = "sprung_mass"
    name: str = param(doc="identifier")
    mass: float = param(unit="kg", doc="sprung mass", check=VEHICLE_MASS)
    stiffness: float = param(unit="N/m", doc="suspension stiffness", check=VEHICLE_STIFFNESS)
    damping: float = param(0.0, unit="N s/m", doc="suspension damping", check=VEHICLE_DAMPING)
    wheel_mass: float = param(0.0, unit="kg", doc="unsprung (wheel) mass", check=VEHICLE_MASS_OR_0)
    length: float = param(unit="m", doc="distance from this wheel to the next vehicle's first axle", check=POSITIVE)


@dataclass(frozen=True, kw_only=True)
class RigidBodyInertia(_Replaceable):
    """Mass and principal moments of inertia about the body's centre of gravity."""

    mass: float = param(unit="kg", doc="mass", check=VEHICLE_MASS)
    inertia_roll: float = param(unit="kg m^2", doc="moment of inertia about x (roll)", check=VEHICLE_INERTIA)
    inertia_pitch: float = param(unit="kg m^2", doc="moment of inertia about y (pitch)", check=VEHICLE_INERTIA)
    inertia_yaw: float = param(unit="kg m^2", doc="moment of inertia about z (yaw)", check=VEHICLE_INERTIA)


@dataclass(frozen=True, kw_only=True)
class WheelsetInertia(_Replaceable):
    """A wheelset: it follows the rail through the wheel-rail contact."""

    mass: float = param(unit="kg", doc="mass", check=VEHICLE_MASS)
    inertia_roll: float = param(unit="kg m^2", doc="moment of inertia about x (roll)", check=VEHICLE_INERTIA)


@dataclass(frozen=True, kw_only=True)
class Suspension(_Replaceable):
    """One suspension stage, values PER SIDE (one of the two elements left and right)."""

    k_z: float = param(unit="N/m", doc="vertical stiffness per side", check=VEHICLE_STIFFNESS)
    k_y: float = param(unit="N/m", doc="lateral stiffness per side", check=VEHICLE_STIFFNESS)
    c_z: float = param(unit="N s/m", doc="vertical damping per side", check=VEHICLE_DAMPING)
    c_y: float = param(unit="N s/m", doc="lateral damping per side", check=VEHICLE_DAMPING)


@dataclass(frozen=True, kw_only=True)
class YawDamper(_Replaceable):
    """Secondary yaw dampers: at each bogie, one longitudinal (x) damper per side between the car
    body and the bogie frame, at +-``half_span`` from the car's centre line.

    Linear viscous dampers without series stiffness (a Maxwell element needs an internal
    coordinate without mass, which the second-order model cannot hold); they act in x at the
    heights of the body's and the bogie's centres of gravity, so the pair damps the relative yaw
    with 2 c_x half_span^2 [N m s/rad] and nothing of the vertical plane (see
    :mod:`tb_exudyn.builder.vehicles`).
    """

    c_x: float = param(unit="N s/m", doc="longitudinal damping of each damper (one per side and bogie)", check=VEHICLE_DAMPER)
    half_span: float = param(unit="m", doc="lateral offset of each damper from the car's centre line", check=POSITIVE)


@dataclass(frozen=True, kw_only=True)
class Car15Geometry(_Replaceable):
    """Geometry of a car with two two-axle bogies (all distances positive unless noted)."""

    half_bogie_spacing: float = param(unit="m", doc="half the distance between the bogie centres", check=POSITIVE)
    half_wheelbase: float = param(unit="m", doc="half the distance between a bogie's axles", check=POSITIVE)
    half_primary_span: float = param(unit="m", doc="half the lateral distance of the primary springs", check=POSITIVE)
    half_secondary_span: float = param(unit="m", doc="half the lateral distance of the secondary springs", check=POSITIVE)
    body_cg_above_secondary: float = param(unit="m", doc="car body CG above the secondary suspension", check=ANY)
    secondary_above_bogie_cg: float = param(unit="m", doc="secondary suspension above the bogie CG", check=ANY)
    bogie_cg_above_axle: float = param(unit="m", doc="bogie CG above the wheelset centre (may be negative)", check=ANY)
    wheel_radius: float = param(unit="m", doc="wheel rolling radius", check=POSITIVE)
    length: float = param(unit="m", doc="distance from the first axle to the next car's first axle", check=POSITIVE)


class _TwoBogieCar(_Replaceable):
    """What every car on two two-axle bogies has (Car15, CreepCar): its length, its axle positions
    and the geometry check. Subclasses are dataclasses with a ``geometry: Car15Geometry`` field."""

    geometry: Car15Geometry

    @property
    def length(self) -> float:
        return self.geometry.length

    @property
    def axle_offsets(self) -> tuple[float, ...]:
        g = self.geometry
        a, s = g.half_wheelbase, g.half_bogie_spacing
        return (0.0, 2 * a, 2 * s, 2 * s + 2 * a)

    def _validate(self, ctx: Context) -> None:
        _check_two_bogie_geometry(self.geometry, self.axle_offsets, ctx)


@dataclass(frozen=True, kw_only=True)
@described
class Car15(_TwoBogieCar):
    """The reference study's car: body and two bogies with y, z, roll, pitch, yaw; four wheelsets."""

    kind: ClassVar[str] = "car15"
    name: str = param(doc="identifier")
    body: RigidBodyInertia = param(doc="car body")
    bogie: RigidBodyInertia = param(doc="each of the two bogies")
    wheelset: WheelsetInertia = param(doc="each of the four wheelsets")
    geometry: Car15Geometry = param(doc="positions of bodies and suspensions")
    primary: Suspension = param(doc="primary suspension (axle box), per side")
    secondary: Suspension = param(doc="secondary suspension (bolster), per side")
    yaw_damper: YawDamper | None = param(None, doc="secondary yaw dampers between body and bogies (default: none)")


def _check_two_bogie_geometry(g: Car15Geometry, axle_offsets: tuple[float, ...], ctx: Context) -> None:
    """Bogies must not overlap and the car must be at least as long as its axle spread."""
    if g.half_wheelbase >= g.half_bogie_spacing:
        raise ctx.child("geometry").child("half_wheelbase").error(
            g.half_wheelbase, f"< half_bogie_spacing = {g.half_bogie_spacing:g}", "bogies overlap"
        )
    if g.length < axle_offsets[-1]:
        raise ctx.child("geometry").child("length").error(
            g.length, f">= {axle_offsets[-1]:g} (the car's axle spread)", "car shorter than its axles"
        )


@dataclass(frozen=True, kw_only=True)
class RigidWheelset(_Replaceable):
    """A wheelset with its own lateral displacement, roll, yaw, longitudinal motion and spin (guided
    by creep forces)."""

    mass: float = param(unit="kg", doc="mass", check=VEHICLE_MASS)
    inertia_roll: float = param(unit="kg m^2", doc="moment of inertia about x (roll)", check=VEHICLE_INERTIA)
    inertia_spin: float = param(unit="kg m^2", doc="moment of inertia about the axle, y (spin)", check=VEHICLE_INERTIA)
    inertia_yaw: float = param(unit="kg m^2", doc="moment of inertia about z (yaw)", check=VEHICLE_INERTIA)


@dataclass(frozen=True, kw_only=True)
class Suspension3(_Replaceable):
    """One suspension stage in all three directions, values PER SIDE (one of the two elements left
    and right, at the stage's lateral span)."""

    k_x: float = param(unit="N/m", doc="longitudinal stiffness per side", check=VEHICLE_STIFFNESS_OR_0)
    k_y: float = param(unit="N/m", doc="lateral stiffness per side", check=VEHICLE_STIFFNESS)
    k_z: float = param(unit="N/m", doc="vertical stiffness per side", check=VEHICLE_STIFFNESS)
    c_x: float = param(0.0, unit="N s/m", doc="longitudinal damping per side", check=VEHICLE_DAMPING)
    c_y: float = param(unit="N s/m", doc="lateral damping per side", check=VEHICLE_DAMPING)
    c_z: float = param(unit="N s/m", doc="vertical damping per side", check=VEHICLE_DAMPING)


@dataclass(frozen=True, kw_only=True)
class HertzCreep(_Replaceable):
    """Creep coefficients from the static wheel load: Hertz's contact ellipse and Kalker's table
    (tb_exudyn.system.creep.hertz_creep_coefficients)."""

    kind: ClassVar[str] = "hertz"
    rail_transverse_radius: float = param(unit="m", doc="rail head crown radius at the contact", check=POSITIVE)
    wheel_transverse_radius: float = param(
        math.inf, unit="m", doc="wheel profile radius at the contact (+ convex, - concave, inf: conical tread)",
        check=Check(allow_inf=True),
    )
    youngs_modulus: float = param(2.1e11, unit="N/m^2", doc="Young's modulus of wheel and rail", check=POSITIVE)
    poisson_ratio: float = param(0.3, unit="-", doc="Poisson's ratio of wheel and rail", check=Check(low=0.0, high=0.5, low_inclusive=True))
    factor: float = param(1.0, unit="-", doc="multiplier of Kalker's coefficients (< 1: a contaminated contact)", check=POSITIVE)

    def _validate(self, ctx: Context) -> None:
        if self.wheel_transverse_radius == 0.0 or 1.0 / self.wheel_transverse_radius + 1.0 / self.rail_transverse_radius <= 0:
            raise ctx.child("wheel_transverse_radius").error(
                self.wheel_transverse_radius, "nonzero with 1/R_wheel + 1/R_rail > 0 (a convex relative contact)",
                "no Hertz contact")


@dataclass(frozen=True, kw_only=True)
class GivenCreep(_Replaceable):
    """Creep coefficients of one wheel given as data (F_x = -f11 xi_x, F_y = -f22 xi_y - f23 phi,
    M_z = f23 xi_y - f33 phi)."""

    kind: ClassVar[str] = "given"
    f11: float = param(unit="N", doc="longitudinal creep coefficient per wheel", check=POSITIVE)
    f22: float = param(unit="N", doc="lateral creep coefficient per wheel", check=POSITIVE)
    f23: float = param(0.0, unit="N m", doc="lateral/spin creep coefficient per wheel", check=NONNEGATIVE)
    f33: float = param(0.0, unit="N m^2", doc="spin creep coefficient per wheel", check=NONNEGATIVE)


@dataclass(frozen=True, kw_only=True)
class WheelRailContact(_Replaceable):
    """Linear wheel-rail contact of every wheelset (tb_exudyn.system.creep)."""

    half_contact_distance: float = param(unit="m", doc="b0: half the lateral distance of the two contact points", check=POSITIVE)
    conicity: float = param(unit="-", doc="equivalent conicity lambda (r_left - r_right = 2 lambda y)", check=POSITIVE)
    contact_angle_parameter: float = param(
        unit="-", check=NONNEGATIVE,
        doc="epsilon: delta_left - delta_right = 2 epsilon y / b0 (gravitational stiffness W epsilon / b0; "
            "conical wheels on knife-edge rails: epsilon = conicity)",
    )
    gravitational_yaw_stiffness: float = param(0.0, unit="N m/rad", doc="K_gpsi per wheelset (0: neglected)", check=ANY)
    spin: bool = param(False, doc="include the spin creepage (f23, f33)")
    creep: Union[HertzCreep, GivenCreep] = param(doc="creep coefficients: kind = 'hertz' or 'given'")


@dataclass(frozen=True, kw_only=True)
@described
class CreepCar(_TwoBogieCar):
    """A car with two two-axle bogies whose wheelsets are guided by linear Kalker creep forces:
    body and bogies as in car15; every wheelset with its own lateral displacement, roll and yaw;
    primary and secondary suspension in x, y and z at their lateral spans; yaw dampers."""

    kind: ClassVar[str] = "creep_car"
    name: str = param(doc="identifier")
    body: RigidBodyInertia = param(doc="car body")
    bogie: RigidBodyInertia = param(doc="each of the two bogies")
    wheelset: RigidWheelset = param(doc="each of the four wheelsets")
    geometry: Car15Geometry = param(doc="positions of bodies and suspensions (wheel_radius: rolling radius r0)")
    primary: Suspension3 = param(doc="primary suspension (axle box), per side")
    secondary: Suspension3 = param(doc="secondary suspension (bolster), per side")
    yaw_damper: YawDamper | None = param(None, doc="secondary yaw dampers between body and bogies (default: none)")
    contact: WheelRailContact = param(doc="wheel-rail contact and creep data")

    def static_axle_load(self, gravity: float) -> float:
        """Static load of one wheelset on the rails [N]: a quarter of the body, half a bogie and
        the wheelset itself (symmetric car)."""
        return gravity * (self.body.mass / 4 + self.bogie.mass / 2 + self.wheelset.mass)


@dataclass(frozen=True, kw_only=True)
@described
class ArticulatedSet(_Replaceable):
    """Car bodies in a row on ``bodies + 1`` two-axle bogies, each inner bogie shared by the two bodies beside
    it (Jacobs bogies): bodies, bogies and wheelsets as in car15, a body's ends on the secondary suspension of
    the bogies at +-half_bogie_spacing from its centre (an inner bogie carries two, one per body)."""

    kind: ClassVar[str] = "articulated"
    name: str = param(doc="identifier")
    bodies: int = param(doc="number of car bodies", check=Check(low=1.0, low_inclusive=True, high=50.0))
    body: RigidBodyInertia = param(doc="each car body")
    bogie: RigidBodyInertia = param(doc="each of the bodies + 1 bogies")
    wheelset: WheelsetInertia = param(doc="each wheelset (two per bogie)")
    geometry: Car15Geometry = param(doc="a body and its bogies as in car15 (half_bogie_spacing: half a body's pivot "
                                        "spacing; length: from the set's first axle to the next car's)")
    primary: Suspension = param(doc="primary suspension (axle box), per side")
    secondary: Suspension = param(doc="secondary suspension of each body end, per side")

    @property
    def length(self) -> float:
        return self.geometry.length

    @property
    def axle_offsets(self) -> tuple[float, ...]:
        p, a = 2 * self.geometry.half_bogie_spacing, 2 * self.geometry.half_wheelbase
        return tuple(x for j in range(self.bodies + 1) for x in (j * p, j * p + a))

    @property
    def total_mass(self) -> float:
        return self.bodies * self.body.mass + (self.bodies + 1) * (self.bogie.mass + 2 * self.wheelset.mass)

    def _validate(self, ctx: Context) -> None:
        _check_two_bogie_geometry(self.geometry, self.axle_offsets, ctx)


Vehicle = Union[MovingForce, SprungMass, Car15, CreepCar, ArticulatedSet]
#: vehicle kinds whose contact has general linear rows (creep forces): an engine must integrate them
#: (``Engine.linear_rows``)
LINEAR_ROW_KINDS: tuple[str, ...] = ("creep_car",)
VEHICLE_KINDS: dict[str, type] = {c.kind: c for c in (MovingForce, SprungMass, Car15, CreepCar, ArticulatedSet)}


@dataclass(frozen=True, kw_only=True)
class Train(_Replaceable):
    """Vehicles in running order; vehicle k's first axle trails the train's first axle by the
    sum of the ``length`` of the vehicles ahead of it."""

    vehicles: tuple[Vehicle, ...] = param(doc="vehicles in running order (names from models/vehicles or tables)")

    @property
    def axle_positions(self) -> tuple[float, ...]:
        """Distance of every axle behind the train's first axle [m], in running order."""
        out, start = [], 0.0
        for v in self.vehicles:
            out.extend(start + a for a in v.axle_offsets)
            start += v.length
        return tuple(out)

    @property
    def length(self) -> float:
        """Distance from the first to the last axle [m]."""
        return self.axle_positions[-1] if self.vehicles else 0.0

    @property
    def mass(self) -> float:
        """Total mass [kg]; a moving force counts as its weight / g with g = 9.81."""
        total = 0.0
        for v in self.vehicles:
            if isinstance(v, MovingForce):
                total += v.force / 9.81
            elif isinstance(v, SprungMass):
                total += v.mass + v.wheel_mass
            elif isinstance(v, ArticulatedSet):
                total += v.total_mass
            else:
                total += v.body.mass + 2 * v.bogie.mass + 4 * v.wheelset.mass
        return total

    def _validate(self, ctx: Context) -> None:
        if not self.vehicles:
            raise ctx.child("vehicles").error([], "at least one vehicle", "empty train")


# ============================================================================================
# bridges


Bridge = Union[SimpleBeam, Frame, Continuous, ModalTable]
BRIDGE_KINDS: dict[str, type] = {c.kind: c for c in (SimpleBeam, Frame, Continuous, ModalTable)}


# ============================================================================================
# track, analysis, scenario


@dataclass(frozen=True, kw_only=True)
class Track(_Replaceable):
    """Track irregularities, the track before and after the bridge (rigid off the bridge) and the track
    structure between wheel and deck."""

    irregularities: tuple[str, ...] = param((), doc="spectrum names (tb-exudyn list), one independent process each")
    wavelength_min: float = param(1.0, unit="m", doc="shortest irregularity wavelength analysed", check=POSITIVE)
    wavelength_max: float = param(120.0, unit="m", doc="longest irregularity wavelength analysed", check=POSITIVE)
    lead_in: float = param(100.0, unit="m", doc="track the first axle runs before it reaches the bridge", check=POSITIVE)
    run_out: float = param(50.0, unit="m", doc="track the last axle runs after it leaves the bridge", check=NONNEGATIVE)
    half_gauge: float = param(0.75, unit="m", doc="b: half the distance between the rail centres", check=POSITIVE)
    on: int = param(1, doc="the track the train runs on: 1, 2, ... of the bridge's tracks (bridge.tracks)",
                    check=Check(low=1.0, low_inclusive=True, high=100.0))
    irregularity_level: float = param(
        1.0, unit="-", check=Check(low=0.0, high=100.0),
        doc="factor on the PSD level of every irregularity spectrum (track quality; 1: the spectra as given, "
            "2: twice their variance)",
    )
    taper_length: float = param(
        20.0, unit="m", check=NONNEGATIVE,
        doc="the irregularity rises from 0 (cosine taper) over this length after the first axle's start "
            "(longer than lead_in: it reaches onto the bridge, which the builder warns about)",
    )
    structure: str = param(
        "", doc="the track structure between wheel and deck: a name of `tb-exudyn list` (tracks, e.g. "
                "ballasted_uic60) or a .toml file; empty: none, the wheel on the deck's track line (today's model)",
    )
    structure_approach: float = param(
        0.0, unit="m", check=NONNEGATIVE,
        doc="with track.structure: the track structure reaches this far before and after the bridge, the wheels "
            "on the rigid line beyond it (fewer track modes: docs/track.md 7); 0: under the whole run",
    )

    def _validate(self, ctx: Context) -> None:
        if self.wavelength_min >= self.wavelength_max:
            raise ctx.child("wavelength_min").error(
                self.wavelength_min, f"< wavelength_max = {self.wavelength_max:g}", "empty wavelength band"
            )
        if len(set(self.irregularities)) != len(self.irregularities):
            raise ctx.child("irregularities").error(list(self.irregularities), "each spectrum once", "repeated spectrum")
        names = spectrum_names()
        for i, name in enumerate(self.irregularities):
            if name not in names:
                raise ctx.child("irregularities").child(i).error(
                    name, "a spectrum name from `tb-exudyn list`, e.g. " + ", ".join(names[:4]) + ", ...",
                    "unknown spectrum",
                )


@dataclass(frozen=True, kw_only=True)
class Analysis(_Replaceable):
    """Settings of the analysis: time stepping, frequency grid, samples, outputs, contact."""

    time_step: float = param(1e-3, unit="s", doc="integration time step", check=POSITIVE)
    output_step: float = param(1e-2, unit="s", doc="time step of stored outputs (a multiple of time_step)", check=POSITIVE)
    freq_min: float = param(0.3, unit="Hz", doc="lowest PEM frequency", check=POSITIVE)
    freq_max: float = param(60.0, unit="Hz", doc="highest PEM frequency", check=POSITIVE)
    n_freq: int = param(
        200, check=Check(low=1.0, low_inclusive=True, high=100000.0),
        doc="number of PEM frequencies (adaptive: at least what the modes and the run need, an error names that "
            "count; points beyond it refine the whole grid)",
    )
    freq_spacing: Literal["linear", "log", "adaptive"] = param(
        "linear",
        doc="spacing of the PEM frequency grid: linear, log, or adaptive (fine at the linearised system's modes "
            "and for the run's length, tb_exudyn.methods.adaptive_grid)",
    )
    pem_amplitude: float = param(1e-4, unit="m", doc="working amplitude of each pseudo-excitation run (results are scaled)", check=POSITIVE)
    n_samples: int = param(100, doc="Monte Carlo samples", check=Check(low=1.0, low_inclusive=True, high=1e7))
    seed: int = param(1, doc="seed of the Monte Carlo samples", check=Check(low=0.0, low_inclusive=True, high=2.0**63))
    channels: tuple[str, ...] = param(("*",), doc="output channel patterns (glob, e.g. 'bridge.*', 'car1.body.*')")
    contact_stiffness_z: float = param(2.0e9, unit="N/m", doc="linear wheel-rail contact stiffness, vertical, per wheel", check=POSITIVE)
    contact_stiffness_y: float = param(2.0e9, unit="N/m", doc="linear wheel-rail contact stiffness, lateral, per wheelset", check=POSITIVE)
    contact_damping_ratio: float = param(
        0.5, unit="-", check=Check(low=0.0, high=10.0, low_inclusive=True),
        doc="damping ratio of every wheel-rail contact against the wheel mass it carries (vertical: half a "
            "wheelset per wheel; lateral: the wheelset): c = 2 zeta sqrt(k m)",
    )
    mode_max_frequency: float = param(100.0, unit="Hz", doc="bridge modes up to this frequency", check=POSITIVE)
    track_mode_max_frequency: float = param(
        2000.0, unit="Hz", check=POSITIVE,
        doc="with track.structure: the track-and-deck body's modes up to this frequency; the left-out modes' static "
            "flexibility at each contact is kept in series with the contact spring (docs/track.md 7)",
    )
    max_modes: int = param(0, doc="at most this many bridge modes (0: no limit)", check=Check(low=0.0, low_inclusive=True, high=1e5))
    spectral_radius: float = param(0.9, unit="-", doc="generalized-alpha spectral radius at infinite frequency", check=Check(low=0.0, high=1.0, low_inclusive=True))
    gravity: float = param(9.81, unit="m/s^2", doc="gravitational acceleration", check=POSITIVE)
    linearization: Literal["rest", "static"] = param(
        "rest", doc="linear engines: the model linearised about rest (PEM's model, as the Exudyn PEM engine's "
                    "pseudo-runs) or about the static equilibrium under gravity (with the suspensions' preload stiffness)",
    )

    def _validate(self, ctx: Context) -> None:
        ratio = self.output_step / self.time_step
        if abs(ratio - round(ratio)) > 1e-9 * ratio or round(ratio) < 1:
            raise ctx.child("output_step").error(
                self.output_step, f"a whole multiple of time_step = {self.time_step:g} s", "not a multiple"
            )
        if self.freq_min >= self.freq_max:
            raise ctx.child("freq_min").error(self.freq_min, f"< freq_max = {self.freq_max:g} Hz", "empty frequency band")
        if self.freq_spacing == "adaptive" and self.n_freq < 2:
            raise ctx.child("n_freq").error(self.n_freq, "at least 2 with freq_spacing 'adaptive'", "too few frequencies")
        resolved = 0.1 / self.time_step
        if self.freq_max > resolved:
            raise ctx.child("freq_max").error(
                self.freq_max,
                f"<= {resolved:g} Hz: at least 10 time steps per period with time_step = {self.time_step:g} s",
                "frequency band above what the time step resolves",
            )
        if not self.channels:
            raise ctx.child("channels").error([], "at least one channel pattern, e.g. '*'", "no channels")


@dataclass(frozen=True, kw_only=True)
class Scenario(_Replaceable):
    """A train crossing a bridge at constant speed over an irregular track, with analysis settings."""

    name: str = param(doc="identifier")
    speed_kmh: float = param(unit="km/h", doc="train speed", check=SPEED_KMH)
    train: Train = param(doc="the train")
    bridge: Bridge = param(doc="the bridge")
    track: Track = param(Track(), doc="track irregularities and approach lengths")
    analysis: Analysis = param(Analysis(), doc="analysis settings")
    description: str = param("", doc="one line for listings")
    source: str = param("", doc="citation of the study")
    notes: str = param("", doc="remarks")

    @property
    def source_file(self) -> str | None:
        """The file this scenario was read from (None when it was built in Python). Not part of the
        scenario's value: not compared, not saved, kept by ``replace``."""
        return source_file(self)

    @property
    def where(self) -> str:
        """Where the scenario came from, the first part of an error message about it: its file, or
        ``scenario 'NAME'`` for one built in Python."""
        return self.source_file or f"scenario {self.name!r}"

    @property
    def speed(self) -> float:
        """Train speed [m/s]."""
        return self.speed_kmh * KMH

    @property
    def duration(self) -> float:
        """From the first axle at -lead_in until the last axle is run_out past the bridge [s]."""
        distance = self.track.lead_in + self.bridge.length + self.train.length + self.track.run_out
        return distance / self.speed

    def _validate(self, ctx: Context) -> None:
        check_track_choice(self.bridge, self.track, ctx)
        if self.track.structure:
            height = track_lines(self.bridge)[self.track.on - 1][1]
            check_track_structure(self.track.structure, self.bridge, height, ctx)
        track_length = self.track.lead_in + self.bridge.length + self.track.run_out
        for i, v in enumerate(self.train.vehicles):
            if v.axle_offsets[-1] > track_length:
                raise ctx.child("train").child("vehicles").child(i).error(
                    v.name, f"vehicles no longer than the track ({track_length:g} m)", "vehicle longer than the track"
                )
