"""The continuous girder (bridge kind ``continuous``, issue 29): its data and their rules. Pure data, no
Exudyn; re-exported by :mod:`.model` (its ``Bridge`` union); the structural model is
:mod:`tb_exudyn.structure.continuous`."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar, Literal

from .code_data import CodeData, check_ballast
from .schema import NONNEGATIVE, POSITIVE, RATIO, STIFFNESS, Check, Context, described, param
from .sections import (AddedMass, BeamSection, Pier, _Replaceable, _SpanSections, check_sections, check_tracks,
                       girder_param, girders_param, on_deck)
from .sections import TrackLine  # noqa: F401 (the type of on_deck's tracks field, resolved in this module)
from .girders import girder_on_piers


@dataclass(frozen=True, kw_only=True)
class ContinuousBearings(_Replaceable):
    """Bearings of a continuous girder: one bearing line at every support (the two abutments and each
    intermediate support), stiffness per direction (inf = rigid, 0 = free)."""

    k_x_fixed: float = param(math.inf, unit="N/m", doc="longitudinal, at the fixed support", check=STIFFNESS)
    k_x_sliding: float = param(0.0, unit="N/m", doc="longitudinal, at every other support", check=STIFFNESS)
    k_y: float = param(math.inf, unit="N/m", doc="lateral", check=STIFFNESS)
    k_z: float = param(math.inf, unit="N/m", doc="vertical", check=STIFFNESS)
    k_rx: float = param(math.inf, unit="N m/rad", doc="torsional restraint of the girder", check=STIFFNESS)
    fixed_support: int = param(0, doc="the support held longitudinally, counted along the track: 0 the start abutment, "
                                      "1 the first intermediate support, ..., len(spans) the end abutment",
                               check=Check(low=0.0, low_inclusive=True, high=1e4))
    height: float = param(0.0, unit="m", doc="girder shear centre above the bearing's support (pier top or ground)",
                          check=NONNEGATIVE)


#: kinds of an intermediate support of a continuous girder
CONTINUOUS_SUPPORTS = ("pier", "rigid")


@dataclass(frozen=True, kw_only=True)
@described
@on_deck
@girder_on_piers
class Continuous(_SpanSections):
    """One girder continuous over all its spans, on bearings at both abutments (rigid ground) and at
    every intermediate support, each a pier (``supports`` entry 'pier', the bearings on its top) or
    rigid ground ('rigid'). The girder section is one for all spans (``girder``) or one per span
    (``girders``)."""

    kind: ClassVar[str] = "continuous"
    name: str = param(doc="identifier")
    spans: tuple[float, ...] = param(unit="m", doc="span lengths in running order (at least two)", check=POSITIVE)
    girder: BeamSection | None = girder_param()
    girders: tuple[BeamSection, ...] = girders_param()
    supports: tuple[Literal["pier", "rigid"], ...] = param(
        doc="each intermediate support in running order (len(spans) - 1 of them): 'pier' (bearings on the pier top) "
            "or 'rigid' (bearings on rigid ground)")
    pier: Pier | None = param(None, doc="every pier of the supports 'pier' (needed if there is one)")
    bearings: ContinuousBearings = param(ContinuousBearings(), doc="bearings at every support line")

    def _validate(self, ctx: Context) -> None:
        n = len(self.spans)
        if n < 2:
            raise ctx.child("spans").error(list(self.spans), "at least two span lengths > 0 (one span: kind 'frame' "
                                           "or 'simple_beam')", "a continuous girder of fewer than two spans")
        check_sections(self, ctx)
        if len(self.supports) != n - 1:
            entries = f"{n - 1} {'entry' if n == 2 else 'entries'}"
            raise ctx.child("supports").error(
                list(self.supports), f"{entries} 'pier' or 'rigid', one per intermediate support",
                "a continuous girder without supports" if not self.supports else "not one support per span joint")
        if "pier" in self.supports and self.pier is None:
            raise ctx.child("pier").error("<missing>", "a [pier] table (supports include 'pier')", "no pier data")
        if self.bearings.fixed_support > n:
            raise ctx.child("bearings").child("fixed_support").error(
                self.bearings.fixed_support, f"0 ... {n} (0: the start abutment, {n}: the end abutment)",
                "no such support")
        check_ballast(self.code, self.added_mass.mass_per_length, "added_mass.mass_per_length", ctx)
        check_tracks(self, ctx)
