"""Simply supported spans: the bridge kinds ``simple_beam`` (ideal supports) and ``frame`` (girders on bearings
carried by piers), their data and rules. Pure data, no Exudyn; re-exported by :mod:`.model` (its ``Bridge``
union); the structural model is :mod:`tb_exudyn.structure.assembly`."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar, Literal

from .code_data import CodeData, check_ballast
from .schema import NONNEGATIVE, POSITIVE, RATIO, STIFFNESS, Check, Context, appended_fields, described, param
from .sections import (AddedMass, BeamSection, Pier, _Replaceable, _SpanSections, check_sections, check_tracks,
                       girder_param, girders_param, on_deck)
from .sections import TrackLine  # noqa: F401 (the type of on_deck's tracks field, resolved in this module)


def _damping() -> object:
    return param(0.0, unit="-", doc="modal damping ratio of every mode", check=RATIO)


def _elements(default: int, where: str) -> object:
    return param(default, doc=f"beam elements per {where}", check=Check(low=1.0, low_inclusive=True, high=1000.0))


def _code() -> object:
    return param(None, doc="EN 1991-2 data: construction type and ballast (none: the code check refuses the bridge)")


#: the model fields of a girder bridge after its own (before the track fields of ``on_deck``): modal damping,
#: mesh and EN 1991-2 data; ``girder_on_piers`` adds the non-structural mass and the pier mesh (frame, continuous)
beam_fields = appended_fields(("damping_ratio", "float", _damping),
                              ("elements_per_span", "int", lambda: _elements(16, "span")),
                              ("code", "CodeData | None", _code))
girder_on_piers = appended_fields(("added_mass", "AddedMass",
                                   lambda: param(AddedMass(), doc="non-structural mass on the girder")),
                                  ("damping_ratio", "float", _damping),
                                  ("elements_per_span", "int", lambda: _elements(16, "span")),
                                  ("elements_per_pier", "int", lambda: _elements(8, "pier")),
                                  ("code", "CodeData | None", _code))


@dataclass(frozen=True, kw_only=True)
@described
@on_deck
@beam_fields
class SimpleBeam(_SpanSections):
    """Uniform simply supported spans with ideal supports (for closed-form checks).

    Every span is simply supported on its own (vertical, lateral and torsional restraint at both
    ends, longitudinal at its start)."""

    kind: ClassVar[str] = "simple_beam"
    name: str = param(doc="identifier")
    spans: tuple[float, ...] = param(unit="m", doc="span lengths in running order", check=POSITIVE)
    girder: BeamSection | None = girder_param()
    girders: tuple[BeamSection, ...] = girders_param()

    def _validate(self, ctx: Context) -> None:
        self.check_spans(ctx)
        check_sections(self, ctx)
        light = min(range(len(self.spans)), key=lambda i: self.sections[i].mass_per_length)
        check_ballast(self.code, self.sections[light].mass_per_length, f"{self.section_key(light)}.mass_per_length", ctx)
        check_tracks(self, ctx)


@dataclass(frozen=True, kw_only=True)
class Bearings(_Replaceable):
    """Bearing stiffness per bearing line and direction (inf = rigid, 0 = free)."""

    k_x_fixed: float = param(math.inf, unit="N/m", doc="longitudinal, at each span's fixed end", check=STIFFNESS)
    k_x_sliding: float = param(0.0, unit="N/m", doc="longitudinal, at each span's sliding end", check=STIFFNESS)
    k_y: float = param(math.inf, unit="N/m", doc="lateral", check=STIFFNESS)
    k_z: float = param(math.inf, unit="N/m", doc="vertical", check=STIFFNESS)
    k_rx: float = param(math.inf, unit="N m/rad", doc="torsional restraint of the girder end", check=STIFFNESS)
    fixed_end: Literal["start", "end"] = param("start", doc="which end of each span is longitudinally fixed")
    height: float = param(0.0, unit="m", doc="girder shear centre above the pier top", check=NONNEGATIVE)


@dataclass(frozen=True, kw_only=True)
@described
@on_deck
@girder_on_piers
class Frame(_SpanSections):
    """Simply supported girders on bearings, carried by piers between spans and abutments at the ends."""

    kind: ClassVar[str] = "frame"
    name: str = param(doc="identifier")
    spans: tuple[float, ...] = param(unit="m", doc="span lengths in running order", check=POSITIVE)
    girder: BeamSection | None = girder_param()
    girders: tuple[BeamSection, ...] = girders_param()
    pier: Pier = param(doc="every intermediate pier")
    bearings: Bearings = param(doc="bearings at every girder end")

    def _validate(self, ctx: Context) -> None:
        self.check_spans(ctx)
        check_sections(self, ctx)
        check_ballast(self.code, self.added_mass.mass_per_length, "added_mass.mass_per_length", ctx)
        check_tracks(self, ctx)
