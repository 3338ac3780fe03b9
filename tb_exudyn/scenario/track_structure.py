"""The track between wheel and deck as data: rail, pads, sleepers and ballast, or a slab on mortar and its base.

A track structure is a file of ``models/tracks/`` (``ballasted_uic60``, ``slab_track``), named by a
scenario's ``track.structure``. Every mass and spring is per rail and per rail support (one sleeper end
or one fastener): the model of one rail (tb_exudyn.system.track_model) puts the same chain under each
support, from the rail down:

- ballasted: pad (spring-damper) -> sleeper (mass) -> ballast (spring-damper) -> ballast (mass, may be 0)
  -> subgrade (spring-damper) -> ground;
- slab: pad -> slab (mass) -> mortar (spring-damper) -> base (mass) -> the base's support (spring-damper)
  -> ground.

On rigid ground the chain ends at the ballast (or the mortar): what lies below sits on the ground and
does not move. Pure data, no numpy.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from pathlib import Path
from typing import ClassVar, Literal

from .errors import ScenarioError
from .registry import model_path
from .schema import NONNEGATIVE, POSITIVE, Check, Context, convert, described, param
from .sections import _Replaceable
from .toml_io import read_toml

#: a spring of the track [N/m]: real pads, ballast and mortar per support are 1e6-1e10 N/m; beyond 1e12 the
#: spring is a rigid link no time step resolves (as the vehicle springs' bound, scenario/schema.py)
TRACK_STIFFNESS = Check(low=0.0, high=1e12)
TRACK_DAMPING = Check(low=0.0, high=1e9, low_inclusive=True)
TRACK_MASS = Check(low=0.0, high=1e5, low_inclusive=True)


@dataclass(frozen=True, kw_only=True)
class Rail(_Replaceable):
    """One rail as an Euler-Bernoulli beam in vertical bending."""

    E: float = param(unit="N/m^2", doc="Young's modulus", check=POSITIVE)
    I: float = param(unit="m^4", doc="second moment of area for vertical bending", check=POSITIVE)  # noqa: E741
    mass_per_length: float = param(unit="kg/m", doc="mass per unit length", check=POSITIVE)
    height: float = param(unit="m", doc="rail height (foot to head)", check=POSITIVE)
    I_lateral: float = param(0.0, unit="m^4", doc="second moment of area for lateral bending (about the vertical "
                                                  "axis); 0: not given, no lateral rail", check=NONNEGATIVE)


@dataclass(frozen=True, kw_only=True)
class Layer(_Replaceable):
    """A resilient layer under one rail support: a spring-damper; ``mass`` the vibrating mass of the layer
    itself, which the spring below it carries (the ballast's cone, the base's share; 0 for a pad, the
    mortar and the subgrade)."""

    stiffness: float = param(unit="N/m", doc="vertical stiffness per rail support", check=TRACK_STIFFNESS)
    damping: float = param(0.0, unit="N s/m", doc="viscous damping per rail support", check=TRACK_DAMPING)
    mass: float = param(0.0, unit="kg", doc="the layer's own vibrating mass per rail support", check=TRACK_MASS)
    thickness: float = param(0.0, unit="m", doc="depth this layer adds below the rail foot", check=NONNEGATIVE)
    lateral_stiffness: float = param(0.0, unit="N/m", doc="lateral stiffness per rail support (0: not given)",
                                     check=Check(low=0.0, high=1e12, low_inclusive=True))
    lateral_damping: float = param(0.0, unit="N s/m", doc="lateral viscous damping per rail support", check=TRACK_DAMPING)


@dataclass(frozen=True, kw_only=True)
class Block(_Replaceable):
    """A rigid mass on the resilient layer below it: a half sleeper, the slab's share of one rail support."""

    mass: float = param(unit="kg", doc="mass per rail support", check=Check(low=0.0, high=1e5))
    thickness: float = param(0.0, unit="m", doc="depth this block adds below the pad", check=NONNEGATIVE)
    width: float = param(0.0, unit="m", doc="bearing width along the track (EN 1991-2 6.3.6.2's load spread "
                                            "starts from it; 0: unknown, a line)", check=Check(low=0.0, high=2.0, low_inclusive=True))


@dataclass(frozen=True, kw_only=True)
@described
class TrackStructure(_Replaceable):
    """A track structure (models/tracks/*.toml): ``kind`` ballasted (pad, sleeper, ballast, subgrade) or
    slab (pad, slab, mortar, base). Masses and springs per rail and per rail support."""

    file_kind: ClassVar[str] = "track structure"
    kind: Literal["ballasted", "slab"] = param(doc="ballasted: sleepers on ballast; slab: a slab on mortar and its base")
    name: str = param(doc="identifier")
    spacing: float = param(unit="m", doc="distance between rail supports (sleepers, or fasteners on a slab)",
                           check=Check(low=0.0, high=5.0))
    rail: Rail = param(doc="the rail")
    pad: Layer = param(doc="the rail pad (its mass: none)")
    sleeper: Block | None = param(None, doc="ballasted: the half sleeper (mass) and its depth")
    ballast: Layer | None = param(None, doc="ballasted: the ballast under a half sleeper, with its vibrating mass (> 0)")
    subgrade: Layer | None = param(None, doc="ballasted: the subgrade under the ballast, off the bridge (no mass)")
    slab: Block | None = param(None, doc="slab: the slab's share per rail support (mass) and its depth")
    mortar: Layer | None = param(None, doc="slab: the mortar layer under the slab (no mass)")
    base: Layer | None = param(None, doc="slab: the base (mass per support) on its support (stiffness, damping)")

    _PARTS: ClassVar[dict[str, tuple[str, ...]]] = {
        "ballasted": ("sleeper", "ballast", "subgrade"), "slab": ("slab", "mortar", "base")}
    #: the parts whose mass the chain carries, from the rail down
    _MASSIVE: ClassVar[dict[str, tuple[str, ...]]] = {"ballasted": ("sleeper", "ballast"), "slab": ("slab", "base")}

    def _validate(self, ctx: Context) -> None:
        own = self._PARTS[self.kind]
        other = self._PARTS["slab" if self.kind == "ballasted" else "ballasted"]
        for part in own:
            if getattr(self, part) is None:
                raise ctx.child(part).error("<missing>", f"a [{part}] table: a {self.kind} track has "
                                            + ", ".join(own), f"a {self.kind} track without a {part}")
        for part in other:
            if getattr(self, part) is not None:
                raise ctx.child(part).error("a table", f"no [{part}] in a {self.kind} track (it has "
                                            + ", ".join(own) + ")", f"{part} in a {self.kind} track")
        for part in self._MASSIVE[self.kind]:  # the chain's masses (tb_exudyn.system.track_model): none may be 0
            if getattr(self, part).mass <= 0.0:
                raise ctx.child(part).child("mass").error(getattr(self, part).mass, "> 0 kg", f"a {part} without mass")
        for part in ("pad",) + own:
            layer = getattr(self, part)
            if part not in self._MASSIVE[self.kind] and isinstance(layer, Layer) and layer.mass != 0.0:
                raise ctx.child(part).child("mass").error(layer.mass, "0 (the masses are the "
                                                          + " and ".join(self._MASSIVE[self.kind]) + "'s)",
                                                          f"a mass on the {part}")

    @property
    def depth(self) -> float:
        """Rail head to the bottom of the layer that stands on the deck [m]: the rail, pad, sleeper and
        ballast (ballasted) or the rail, pad, slab, mortar and base (slab)."""
        parts = ("pad", "sleeper", "ballast") if self.kind == "ballasted" else ("pad", "slab", "mortar", "base")
        return self.rail.height + sum(getattr(self, p).thickness for p in parts)

    def chain(self, ground: Literal["rigid", "subgrade"] = "rigid") -> tuple[tuple[float, float, float], ...]:
        """The support under one rail seat, from the rail down: ((k, c, m), ...), spring k [N/m] and
        damper c [N s/m] above mass m [kg]; the last spring's lower end is the ground (m of the last entry
        is 0). ``rigid``: the chain ends at the ballast (mortar) on rigid ground; ``subgrade``: the ballast
        (base) mass on the subgrade (the base's support), the track off the bridge. Ballasted: pad,
        sleeper, ballast, ballast mass, subgrade; slab: pad, slab, mortar, base mass, the base's support."""
        if self.kind == "ballasted":
            springs, masses = (self.pad, self.ballast, self.subgrade), (self.sleeper.mass, self.ballast.mass)
        else:
            springs, masses = (self.pad, self.mortar, self.base), (self.slab.mass, self.base.mass)
        n = 2 if ground == "rigid" else 3
        return tuple((springs[i].stiffness, springs[i].damping, masses[i] if i < n - 1 else 0.0) for i in range(n))

    @property
    def has_lateral(self) -> bool:
        """Whether the file gives the lateral data: the rail's I_lateral, the pad's and the lowest layer on
        the deck's (ballast, mortar) lateral stiffness."""
        low = self.ballast if self.kind == "ballasted" else self.mortar
        return self.rail.I_lateral > 0.0 and self.pad.lateral_stiffness > 0.0 and low.lateral_stiffness > 0.0

    def lateral(self) -> "TrackStructure":
        """The same track in lateral bending, as a structure whose chain on rigid ground is the lateral one:
        the rail's I_lateral; the pad's lateral spring-damper, the half sleeper (slab share), the ballast's
        (mortar's) lateral spring-damper to the ground; no lower mass or spring in that direction (the
        ballast's mass and the subgrade act vertically only, as in Zhai's lateral track model)."""
        if not self.has_lateral:
            raise ValueError(f"track structure {self.name!r} gives no lateral data (rail.I_lateral, "
                             "pad.lateral_stiffness and the ballast's or mortar's)")
        low = "ballast" if self.kind == "ballasted" else "mortar"
        side = lambda layer: layer.replace(stiffness=layer.lateral_stiffness, damping=layer.lateral_damping)  # noqa: E731
        return self.replace(rail=self.rail.replace(I=self.rail.I_lateral), pad=side(self.pad),
                            **{low: side(getattr(self, low))})


@functools.lru_cache(maxsize=16)
def _load(path: str, mtime_ns: int) -> TrackStructure:
    ctx = Context(path, "")
    return convert(TrackStructure, read_toml(Path(path)), ctx)


def track_structure_path(name_or_path: str, referrer: str | None = None, key: str = "track.structure") -> Path:
    """The file of a track structure: a name of models/tracks/ or a path to a .toml file (relative to the
    scenario file ``referrer`` when one is given)."""
    if name_or_path.endswith(".toml"):
        base = Path(referrer).parent if referrer and not referrer.startswith("<") else Path.cwd()
        path = (base / name_or_path).resolve()
        if not path.is_file():
            raise ScenarioError(referrer, key, name_or_path, "a track structure name or an existing .toml file",
                                "no such file")
        return path
    return model_path("tracks", name_or_path, referrer, key)


def load_track_structure(name_or_path: str | Path, referrer: str | None = None,
                         key: str = "track.structure") -> TrackStructure:
    """A track structure by name (``tb-exudyn list``: tracks) or path. ScenarioError names the file and key."""
    path = track_structure_path(str(name_or_path), referrer, key)
    return _load(str(path), path.stat().st_mtime_ns)


def check_track_structure(structure: str, bridge, track_line_height: float, ctx: Context) -> None:  # noqa: ANN001
    """A scenario's ``track.structure`` against its bridge: the file reads and validates; the support
    spacing is no longer than the shortest span; the structure fits under the rail level (its depth at
    most the track line's height above the girder's shear centre, ``bridge.track_height`` or the track's
    ``height``). One ScenarioError naming the key."""
    key = ctx.child("track").child("structure")
    ts = load_track_structure(structure, ctx.file, key.path)
    spans = tuple(float(s) for s in getattr(bridge, "spans", ()) or (float(bridge.length),))
    if ts.spacing > min(spans):
        raise key.error(structure, f"a structure whose support spacing ({ts.spacing:g} m) is at most the "
                        f"shortest span ({min(spans):g} m)", "support spacing longer than a span")
    if ts.depth > track_line_height + 1e-12:
        raise key.error(structure, f"at most {track_line_height:g} m deep; '{ts.name}' is {ts.depth:.3g} m",
                        "the track does not fit the bridge's track height")


#: the vehicle kinds whose contacts the track layer carries: vertical contacts on the track centre line or on
#: either rail, and the wheelsets' lateral contact (car15, the articulated sets: the rails' lateral bending is
#: built for them, system/track_bridge.py ``lateral``); the creep cars' general rows are not carried yet
TRACK_VEHICLE_KINDS = ("sprung_mass", "moving_force", "car15", "articulated")
#: the kinds with a lateral contact: with them the track is built with the rails' lateral bending
LATERAL_TRACK_KINDS = ("car15", "articulated")


def refuse_unbuilt_track(scenario) -> None:  # noqa: ANN001
    """What a run of a scenario with a ``track.structure`` cannot do yet, refused before any work (one
    ScenarioError naming the key): a vehicle whose contacts the track layer does not carry (the creep cars:
    their creep rows are not written on the rails, docs/track.md)."""
    if not scenario.track.structure:
        return
    kinds = sorted({v.kind for v in scenario.train.vehicles} - set(TRACK_VEHICLE_KINDS))
    if kinds:
        raise ScenarioError(scenario.where, "train.vehicles", ", ".join(kinds),  # one line within 200 characters
                            ", ".join(TRACK_VEHICLE_KINDS) + "; or no track.structure", "no creep rows on rails")


__all__ = ["Block", "Layer", "Rail", "TrackStructure", "check_track_structure", "load_track_structure",
           "TRACK_VEHICLE_KINDS", "LATERAL_TRACK_KINDS", "refuse_unbuilt_track", "track_structure_path"]
