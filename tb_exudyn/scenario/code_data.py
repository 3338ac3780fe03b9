"""EN 1991-2 data of a bridge beyond its model (the ``[code]`` table of a bridge file) and the code's
mass cases. Pure data, no Exudyn."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Literal

from .schema import NONNEGATIVE, POSITIVE, Context, Validated, param, replace


#: construction types of EN 1991-2 Table 6.6 (the lower limit of damping by type and span)
CONSTRUCTION_TYPES: tuple[str, ...] = ("steel_composite", "prestressed_concrete", "reinforced_concrete", "filler_beam")
#: mass cases of EN 1991-2 6.4.6.3.2: the lower estimate (minimum ballast density) for the largest
#: deck acceleration, the upper one (saturated ballast) for the lowest resonant speeds
MASS_CASES: tuple[str, ...] = ("nominal", "lower", "upper")


@dataclass(frozen=True, kw_only=True)
class CodeData(Validated):
    """What EN 1991-2's dynamic analysis (clause 6.4.6) needs of a bridge beyond its model: the
    construction type that sets Table 6.6's damping, and the ballast whose density range gives the
    mass cases (6.4.6.3.2). The densities' defaults are EN 1991-1-1's range for railway ballast,
    recalled, not read in the code text [check]."""

    construction: Literal["steel_composite", "prestressed_concrete", "reinforced_concrete", "filler_beam"] = param(
        doc="construction type for the code's damping (EN 1991-2 Table 6.6): steel_composite, prestressed_concrete, "
            "reinforced_concrete or filler_beam")
    ballast_mass_per_length: float = param(
        0.0, unit="kg/m", doc="ballast mass per length at the nominal density, included in the model's mass "
                              "(0: no ballast, one mass case)", check=NONNEGATIVE)
    ballast_density: float = param(1800.0, unit="kg/m^3", doc="the ballast density the model's mass is at [check]",
                                   check=POSITIVE)
    ballast_density_min: float = param(1700.0, unit="kg/m^3", doc="lower estimate of the ballast density [check]",
                                       check=POSITIVE)
    ballast_density_max: float = param(2000.0, unit="kg/m^3", doc="upper estimate: saturated ballast [check]",
                                       check=POSITIVE)

    def replace(self, **changes: Any) -> "CodeData":
        """A modified copy, validated again."""
        return replace(self, **changes)

    def _validate(self, ctx: Context) -> None:
        if not self.ballast_density_min <= self.ballast_density <= self.ballast_density_max:
            raise ctx.child("ballast_density").error(
                self.ballast_density, f"between ballast_density_min ({self.ballast_density_min:g}) and "
                f"ballast_density_max ({self.ballast_density_max:g}) kg/m^3", "outside the density range")

    def ballast_change(self, case: str) -> float:
        """The change of the mass per length [kg/m] in a mass case (:data:`MASS_CASES`): the ballast's
        mass at the case's density less its nominal mass."""
        if case not in MASS_CASES:
            raise ValueError(f"mass case {case!r}: one of {', '.join(MASS_CASES)}")
        rho = {"nominal": self.ballast_density, "lower": self.ballast_density_min,
               "upper": self.ballast_density_max}[case]
        return self.ballast_mass_per_length * (rho / self.ballast_density - 1.0)


def check_ballast(code: "CodeData | None", carrier: float, carrier_key: str, ctx: Context) -> None:
    """The ballast is part of the mass that carries it, and its lower case leaves a positive mass."""
    if code is None or code.ballast_mass_per_length <= carrier:
        return
    raise ctx.child("code").child("ballast_mass_per_length").error(
        code.ballast_mass_per_length, f"at most {carrier_key} ({carrier:g} kg/m), the mass that includes it",
        "more ballast than mass")


def with_mass_case(bridge: Any, case: str) -> Any:
    """The bridge in an EN 1991-2 mass case (:data:`MASS_CASES`, :meth:`CodeData.ballast_change`):
    the ballast's mass change added where the model carries it (a frame's added mass, a simple
    beam's girder mass), its polar mass moment scaled by the same ratio; the copy's code data hold
    the ballast at the case's density. 'nominal' and a bridge without ballast return the bridge
    itself."""
    if bridge.code is None:
        raise ValueError(f"bridge {bridge.name!r} has no code data ([code] table): no mass cases")
    code = bridge.code
    dm = code.ballast_change(case)
    if dm == 0.0:
        return bridge
    return _with_ballast_change(bridge, dm, code.ballast_density * (1.0 + dm / code.ballast_mass_per_length))


def with_ballast_density(bridge: Any, density: float) -> Any:
    """The bridge with its ballast at ``density`` [kg/m^3] (an uncertain ballast density: the key
    ``bridge.code.ballast_density`` of an uncertainty study): the ballast's mass per length
    ``ballast_mass_per_length x density / ballast_density`` and the mass change added where the model
    carries it, as a mass case's (:func:`with_mass_case`); the copy's code data hold the ballast at
    ``density``, which their check keeps within ``ballast_density_min`` ... ``ballast_density_max``.
    A bridge without ballast, or at its own density, is returned itself."""
    code = bridge.code
    if code is None or code.ballast_mass_per_length == 0.0 or density == code.ballast_density:
        return bridge
    return _with_ballast_change(bridge, code.ballast_mass_per_length * (density / code.ballast_density - 1.0), density)


def _with_ballast_change(bridge: Any, dm: float, density: float) -> Any:
    """The bridge with ``dm`` [kg/m] more ballast, held at ``density`` in its code data (so that it
    validates as any bridge), the change where the model carries it (:func:`with_mass_case`)."""
    code = bridge.code
    code = code.replace(ballast_mass_per_length=code.ballast_mass_per_length + dm, ballast_density=density)
    if hasattr(bridge, "added_mass"):  # a frame carries its ballast in the added mass
        am = bridge.added_mass
        ratio = (am.mass_per_length + dm) / am.mass_per_length
        return bridge.replace(code=code, added_mass=am.replace(mass_per_length=am.mass_per_length * ratio,
                                                               rot_mass_per_length=am.rot_mass_per_length * ratio))
    def scaled(g):  # noqa: ANN001, ANN202 - a girder section carrying the ballast
        ratio = (g.mass_per_length + dm) / g.mass_per_length
        return g.replace(mass_per_length=g.mass_per_length * ratio, rot_mass_per_length=g.rot_mass_per_length * ratio)

    if getattr(bridge, "girders", ()):  # a section per span: each carries the same ballast per length
        return bridge.replace(code=code, girders=tuple(scaled(g) for g in bridge.girders))
    return bridge.replace(code=code, girder=scaled(bridge.girder))


__all__ = ["CONSTRUCTION_TYPES", "MASS_CASES", "CodeData", "check_ballast", "with_ballast_density", "with_mass_case"]
