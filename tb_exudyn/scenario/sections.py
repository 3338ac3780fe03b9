"""The parts of a bridge's data that every bridge kind uses: a beam section, the added mass a girder
carries, a pier (and the base of every scenario dataclass, ``replace`` checked as the loader checks).
Pure data, no Exudyn; re-exported by :mod:`.model`."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

from .schema import (ANY, BRIDGE_AREA, BRIDGE_MASS_PER_LENGTH, BRIDGE_MODULUS, BRIDGE_ROT_MASS,
                     BRIDGE_SECOND_MOMENT, NONNEGATIVE, POSITIVE, STIFFNESS, Check, Validated, appended_fields, param,
                     replace)


class _Replaceable(Validated):
    def replace(self, **changes):
        """A copy checked as the TOML loader checks (:func:`.schema.replace`); e.g. ``sc.replace(speed_kmh=300.0)``."""
        return replace(self, **changes)


@dataclass(frozen=True, kw_only=True)
class BeamSection(_Replaceable):
    """A prismatic beam cross-section. I_y governs bending in the vertical plane (about the lateral
    y axis), I_z lateral bending (about z); J is the torsion constant (G J the torsional stiffness)."""

    E: float = param(unit="N/m^2", doc="Young's modulus", check=BRIDGE_MODULUS)
    G: float = param(unit="N/m^2", doc="shear modulus", check=BRIDGE_MODULUS)
    area: float = param(unit="m^2", doc="cross-section area (axial stiffness E A)", check=BRIDGE_AREA)
    I_y: float = param(unit="m^4", doc="second moment about y: vertical bending", check=BRIDGE_SECOND_MOMENT)
    I_z: float = param(unit="m^4", doc="second moment about z: lateral bending", check=BRIDGE_SECOND_MOMENT)
    J: float = param(unit="m^4", doc="torsion constant", check=BRIDGE_SECOND_MOMENT)
    mass_per_length: float = param(unit="kg/m", doc="mass per unit length", check=BRIDGE_MASS_PER_LENGTH)
    rot_mass_per_length: float = param(unit="kg m^2/m", doc="polar mass moment of inertia per length (torsion)", check=BRIDGE_ROT_MASS)
    shear_area_factor: float = param(0.0, unit="-", doc="Timoshenko shear area / area; 0 = Euler-Bernoulli", check=Check(low=0.0, high=1.0, low_inclusive=True))


class Spanned:
    """What every bridge of spans in running order (``spans``, m) has: its length and the check that
    it has a span (simple_beam, frame, continuous, modal_table)."""

    spans: tuple[float, ...]

    @property
    def length(self) -> float:
        return float(sum(self.spans))

    def check_spans(self, ctx) -> None:  # noqa: ANN001
        if not self.spans:
            raise ctx.child("spans").error([], "at least one span length > 0", "no spans")


class _SpanSections(_Replaceable, Spanned):
    """What a bridge of girder spans with one section for all (``girder``) or one per span (``girders``)
    has: the section of each span and its key (simple_beam, frame, continuous)."""

    @property
    def sections(self) -> tuple["BeamSection", ...]:
        """The girder section of each span."""
        return self.girders if self.girders else (self.girder,) * len(self.spans)

    def section_key(self, span: int) -> str:
        """The key of span ``span``'s section in the bridge data: 'girder' or 'girders[i]'."""
        return f"girders[{span}]" if self.girders else "girder"


def check_sections(bridge, ctx) -> None:  # noqa: ANN001
    """``girder`` (every span) or ``girders`` (one per span), not both, not neither."""
    n = len(bridge.spans)
    if bridge.girder is None and not bridge.girders:
        raise ctx.child("girder").error("<missing>", "a [girder] table (every span) or [[girders]] tables, one "
                                        "per span", "no girder section")
    if bridge.girder is not None and bridge.girders:
        raise ctx.child("girders").error(f"{len(bridge.girders)} sections", "either girder (every span) or girders "
                                         "(one per span), not both", "two girder sections")
    if bridge.girders and len(bridge.girders) != n:
        raise ctx.child("girders").error(f"{len(bridge.girders)} sections", f"{n} sections, one per span",
                                         "not one section per span")


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


@dataclass(frozen=True, kw_only=True)
class TrackLine(_Replaceable):
    """One track on the deck: its centre line's lateral offset from the girder axis and its rail level
    above the girder's shear centre (a point there moves by dy = v - h theta, dz = w + e theta)."""

    offset: float = param(unit="m", doc="track centre line from the girder axis (+y left)", check=ANY)
    height: float = param(0.0, unit="m", doc="rail level above the girder shear centre", check=ANY)


def girder_param():  # noqa: ANN201 - the dataclass field of a bridge's one section for every span
    return param(None, doc="girder section of every span (or girders: one per span)")


def girders_param():  # noqa: ANN201 - the dataclass field of a bridge's sections, one per span
    return param((), doc="girder section of each span in running order (instead of girder)")


def tracks_param():  # noqa: ANN201 - the dataclass field of a bridge's tracks (simple_beam, frame, continuous)
    return param((), doc="every track on the deck, track 1 first (instead of track_offset/track_height); the "
                         "scenario's track.on picks the train's")


def deck_width_param():  # noqa: ANN201 - the dataclass field of a bridge's deck width
    return param(0.0, unit="m", doc="deck width, centred on the girder axis (0: not given, tracks not checked "
                                    "against it)", check=NONNEGATIVE)


#: the track fields of a girder bridge (simple_beam, frame, continuous), after its own and before
#: description, source and notes: one track by offset and height, or [[tracks]] tables, and the deck width
on_deck = appended_fields(
    ("track_offset", "float", lambda: param(0.0, unit="m", doc="track centre line from the girder axis (+y left)",
                                            check=ANY)),
    ("track_height", "float", lambda: param(0.0, unit="m", doc="rail level above the girder shear centre", check=ANY)),
    ("tracks", "tuple[TrackLine, ...]", tracks_param),
    ("deck_width", "float", deck_width_param))


def track_lines(bridge) -> tuple[tuple[float, float], ...]:  # noqa: ANN001
    """(offset e, height h) [m] of every track of a bridge, track 1 first: its ``tracks`` tables, or the one
    track of ``track_offset`` / ``track_height``."""
    tracks = getattr(bridge, "tracks", ())
    if tracks:
        return tuple((float(t.offset), float(t.height)) for t in tracks)
    return ((float(getattr(bridge, "track_offset", 0.0)), float(getattr(bridge, "track_height", 0.0))),)


def check_tracks(bridge, ctx) -> None:  # noqa: ANN001
    """A bridge's tracks: ``tracks`` or ``track_offset``/``track_height``, not both; every track on the
    deck (|offset| <= deck_width / 2 when the width is given)."""
    if bridge.tracks and (getattr(bridge, "track_offset", 0.0) != 0.0 or getattr(bridge, "track_height", 0.0) != 0.0):
        raise ctx.child("tracks").error(f"{len(bridge.tracks)} tracks", "either track_offset/track_height (one "
                                        "track) or [[tracks]] tables (each track), not both", "two track definitions")
    if bridge.deck_width > 0.0:
        for i, (e, _h) in enumerate(track_lines(bridge)):
            if abs(e) > bridge.deck_width / 2:
                key = ctx.child("tracks").child(i).child("offset") if bridge.tracks else ctx.child("track_offset")
                raise key.error(e, f"|offset| <= deck_width / 2 = {bridge.deck_width / 2:g} m", "a track off the deck")


def check_track_choice(bridge, track, ctx) -> None:  # noqa: ANN001
    """The scenario's track: ``track.on`` one of the bridge's tracks; both rails of every track on the deck
    (|offset| + half_gauge <= deck_width / 2 when the width is given); tracks no closer than the gauge."""
    lines = track_lines(bridge)
    if track.on > len(lines):
        raise ctx.child("track").child("on").error(
            track.on, f"1 ... {len(lines)} (the bridge '{bridge.name}' has {len(lines)} "
            f"track{'s' if len(lines) > 1 else ''})", "no such track")
    b = track.half_gauge
    tracks = getattr(bridge, "tracks", ())
    bctx = ctx.child("bridge")

    def key(i: int):  # noqa: ANN202
        return bctx.child("tracks").child(i).child("offset") if tracks else bctx.child("track_offset")

    width = float(getattr(bridge, "deck_width", 0.0))
    for i, (e, _h) in enumerate(lines):
        if width > 0.0 and abs(e) + b > width / 2:
            raise key(i).error(e, f"|offset| + track.half_gauge = {abs(e) + b:g} m <= deck_width / 2 = {width / 2:g} m",
                               "a rail off the deck")
        for j in range(i):
            if abs(e - lines[j][0]) < 2 * b:
                raise key(i).error(e, f"at least 2 track.half_gauge = {2 * b:g} m from track {j + 1} "
                                   f"(offset {lines[j][0]:g} m)", "tracks overlap")
