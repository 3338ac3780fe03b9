"""The parts of a bridge's data that every bridge kind uses: a beam section, the added mass a girder
carries, a pier (and the base of every scenario dataclass, ``replace`` checked as the loader checks).
Pure data, no Exudyn; re-exported by :mod:`.model`."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

from .schema import ANY, NONNEGATIVE, POSITIVE, STIFFNESS, Check, Validated, param, replace


class _Replaceable(Validated):
    def replace(self, **changes):
        """A copy checked as the TOML loader checks (:func:`.schema.replace`); e.g. ``sc.replace(speed_kmh=300.0)``."""
        return replace(self, **changes)


@dataclass(frozen=True, kw_only=True)
class BeamSection(_Replaceable):
    """A prismatic beam cross-section. I_y governs bending in the vertical plane (about the lateral
    y axis), I_z lateral bending (about z); J is the torsion constant (G J the torsional stiffness)."""

    E: float = param(unit="N/m^2", doc="Young's modulus", check=POSITIVE)
    G: float = param(unit="N/m^2", doc="shear modulus", check=POSITIVE)
    area: float = param(unit="m^2", doc="cross-section area (axial stiffness E A)", check=POSITIVE)
    I_y: float = param(unit="m^4", doc="second moment about y: vertical bending", check=POSITIVE)
    I_z: float = param(unit="m^4", doc="second moment about z: lateral bending", check=POSITIVE)
    J: float = param(unit="m^4", doc="torsion constant", check=POSITIVE)
    mass_per_length: float = param(unit="kg/m", doc="mass per unit length", check=POSITIVE)
    rot_mass_per_length: float = param(unit="kg m^2/m", doc="polar mass moment of inertia per length (torsion)", check=POSITIVE)
    shear_area_factor: float = param(0.0, unit="-", doc="Timoshenko shear area / area; 0 = Euler-Bernoulli", check=Check(low=0.0, high=1.0, low_inclusive=True))


@dataclass(frozen=True, kw_only=True)
class AddedMass(_Replaceable):
    """Non-structural mass carried by the girder (ballast or slab, rails, secondary dead load)."""

    mass_per_length: float = param(0.0, unit="kg/m", doc="added mass per length", check=NONNEGATIVE)
    rot_mass_per_length: float = param(0.0, unit="kg m^2/m", doc="its polar moment of inertia per length about its own centre", check=NONNEGATIVE)
    offset: float = param(0.0, unit="m", doc="lateral position of its centre from the girder axis (+y left)", check=ANY)
    height: float = param(0.0, unit="m", doc="height of its centre above the girder shear centre", check=ANY)


@dataclass(frozen=True, kw_only=True)
class Pier(_Replaceable):
    """A pier: a vertical beam from its footing up to the pier cap carrying the bearings."""

    height: float = param(unit="m", doc="footing to pier top", check=POSITIVE)
    section: BeamSection = param(doc="pier section (I_y: bending in the x-z plane, I_z: in the y-z plane)")
    footing: Literal["fixed", "springs"] = param("fixed", doc="clamped footing or footing on springs")
    k_translation: float = param(math.inf, unit="N/m", doc="footing springs, each translation (footing = 'springs')", check=STIFFNESS)
    k_rotation: float = param(math.inf, unit="N m/rad", doc="footing springs, each rotation (footing = 'springs')", check=STIFFNESS)
    cap_mass: float = param(0.0, unit="kg", doc="lumped mass of the pier cap", check=NONNEGATIVE)
