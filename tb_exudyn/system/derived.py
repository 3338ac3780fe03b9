"""Derived channels: the quantities code limits apply to, formed from the engines' outputs.

Plain numpy, no Exudyn. A derived channel is defined on the outputs an engine produces (the
:class:`~tb_exudyn.system.channels.OutputMap`), so that PEM forms it on every complex pseudo-response
before squaring (its statistics are then exact, not a combination of sigmas) and Monte Carlo forms it
on every sample alike. The names follow the quantity vocabulary of
:mod:`tb_exudyn.scenario.limits`; what each is:

=====================================  ======  ======  =========================================================
channel                                unit    kind    definition
=====================================  ======  ======  =========================================================
bridge.span<k>.<st>.acc_z_en1990       m/s^2   linear  deck vertical acceleration at station <st> (q1, mid, q3)
                                                       along the track: on the track centre line at rail level,
                                                       w + e theta (the girder's bending plus its torsion times
                                                       the track's offset e; the rail shapes at the station),
                                                       from the bridge modes up to f_cut = max(30 Hz, 1.5 f1, f3)
                                                       only (f1, f3: first and third vertical bridge modes), EN
                                                       1990 A2.4.4.2.1 "frequencies (including ... associated
                                                       mode shapes) up to": that shape row with the modes above
                                                       f_cut set to zero (exact in every method). The plain
                                                       ``acc_z`` stays on the girder axis
bridge.span<k>.<st>.twist_3m           m       linear  deck twist over 3 m centred at station <st> (q1, mid, q3,
                                                       and ``start``/``end`` 1.5 m inside the span's ends, where
                                                       twist peaks): [z_L - z_R](x + 1.5) - [z_L - z_R](x - 1.5)
                                                       from the rail displacement channels z_L, z_R = z +- b rx
                                                       of the rail shapes (tb_exudyn.structure RailShapes) at
                                                       x +- 1.5 m, b = track.half_gauge; positive: the left rail
                                                       rises ahead relative to the right
car<k>.body.acc_z_wb                   m/s^2   weighted EN 12299 Wb-weighted car-body vertical acceleration
car<k>.body.acc_y_wd                   m/s^2   weighted EN 12299 Wd-weighted car-body lateral acceleration
car<k>.body.sperling_z / sperling_y    -       window  Sperling Wz of the car-body acceleration per window of
                                                       ``window`` s (5 s, GB/T 5599-2019, or the whole run if
                                                       shorter): a windowed index, not a Gaussian process
car<k>.axle<j>.unloading               -       ratio   (P_R - P_L) / (P_R + P_L), P = the wheels' force_z
                                                       (compressive wheel load, static load included);
                                                       |value| is dP / P_bar with dP = |P_R - P_L| / 2
car<k>.axle<j>.left.derailment         -       ratio   Q/P of the left wheel as -H / P_L, of the right wheel as
car<k>.axle<j>.right.derailment                        H / P_R, H = axle<j>.force_y (rail force on the wheelset
                                                       toward +y: H > 0 loads the right wheel's flange)
=====================================  ======  ======  =========================================================

On a deck of two tracks or more (``ModalBridge.tracks``) the two bridge rows are made along each track
instead, at its stations ``span<k>.<st>.track<i>`` (``bridge.span1.mid.track2.acc_z_en1990``, twist at
``span<k>.start.track<i>`` too) with that track's rail shapes (:func:`station_track`), and the
girder-axis stations have none.

What the 15-DOF car (``car15``) can and cannot give per wheel: it has one vertical contact per wheel
(``left.force_z``, ``right.force_z``: P per wheel is defined) but ONE lateral contact per wheelset
(``force_y`` = H = Q_L + Q_R, at rail level on the track centre line): the lateral force of a wheel
is not defined, so the derailment channels put the whole axle force on the wheel whose flange it
loads: an upper bound of that wheel's Q/P (a real wheelset shares H between its wheels by creep).
The sprung mass and the moving force have one vertical wheel load per axle: no ratio channels.

Kinds, and how each method forms them:

- ``linear``: sum_j c_j y_j over output channels (``terms``); PEM: on the pseudo-responses, Monte
  Carlo: on the samples; exact for both.
- ``weighted``: an EN 12299 weighting (``weighting`` = "wb" or "wd") of one output; Monte Carlo
  filters each sample in time (tb_exudyn.system.comfort.apply_weighting); PEM multiplies each
  pseudo-response by W(f_k) at its excitation frequency (exact for a response at f_k with a steady
  amplitude; the filter's start-up from rest and the spread of a modulated response around f_k are
  left out: see tb_exudyn.methods.reduction).
- ``ratio``: N / D with N = ``terms`` and D = ``denominator`` (linear in the outputs); first order
  about the means (docs/references.md, code limits): r~ = N~ / D - N D~ / D^2 (bars dropped), so PEM gets it from the
  covariances of N, D and their derivatives; Monte Carlo takes the exact ratio of every sample.
- ``sperling``: Sperling Wz of one acceleration per window (``window`` s): PEM from the expected
  B-weighted power averaged over the window, Monte Carlo from each sample's periodogram.

:func:`engine_outputs` is the one place that says which outputs an engine must produce for a
selection: the selected channels, the inputs of the selected derived channels (auxiliary rail and
truncated-mode bridge rows among them) and the recorded time derivatives of both
(:func:`derivative_name`: disp -> vel -> acc of the same coordinate).
"""

from __future__ import annotations

import fnmatch
import math
import re
from dataclasses import dataclass, field
from typing import Literal, Sequence

import numpy as np
from numpy.typing import NDArray

from ..scenario.errors import ScenarioError
from .channels import Channel
from .modes import nth_frequency

DerivedKind = Literal["linear", "weighted", "ratio", "sperling"]
DERIVED_KINDS: tuple[str, ...] = ("linear", "weighted", "ratio", "sperling")

#: half the twist base: EN 1990 A2.4.4.2.2 limits the twist over 3 m
TWIST_HALF_BASE = 1.5
#: EN 1990 A2.4.4.2.1: frequencies considered up to max(30 Hz, 1.5 f1, f3)
EN1990_MIN_CUT = 30.0
#: Sperling window [s] (GB/T 5599-2019 [check]; docs/references.md, ride comfort)
SPERLING_WINDOW = 5.0

_STATION = re.compile(r"span(\d+)\.(q1|mid|q3|start|end)(?:\.track(\d+))?\Z")
_FRACTION = {"q1": 0.25, "mid": 0.5, "q3": 0.75}
_DERIVATIVE = {"disp": "vel", "vel": "acc"}


@dataclass(frozen=True)
class DerivedChannel:
    """A channel formed from output channels (module docstring).

    name, unit : the channel (vocabulary of tb_exudyn.scenario.limits)
    kind : 'linear', 'weighted', 'ratio' or 'sperling'
    terms : ((output channel, coefficient), ...): the channel (linear), its input (weighted,
        sperling: one term, coefficient 1) or the numerator N (ratio)
    denominator : the denominator D of a ratio, as terms; () otherwise
    weighting : 'wb' / 'wd' (weighted), 'vertical' / 'lateral' (sperling); '' otherwise
    window : the Sperling window [s]; 0 otherwise
    description : what it is, in words
    """

    name: str
    unit: str
    kind: DerivedKind
    terms: tuple[tuple[str, float], ...]
    denominator: tuple[tuple[str, float], ...] = ()
    weighting: str = ""
    window: float = 0.0
    description: str = ""

    @property
    def inputs(self) -> tuple[str, ...]:
        """The output channels it is formed from."""
        return tuple(dict.fromkeys(n for n, _ in self.terms + self.denominator))


@dataclass(frozen=True, eq=False)
class DerivedCatalogue:
    """Every derived channel of a model, and the auxiliary outputs they need.

    channels : the derived channels, in catalogue order (bridge, then each car)
    auxiliary : bridge channels that only derived channels read (the rails at x +- 1.5 m of every
        twist station, the truncated-mode station rows): ``index`` points into the station shapes
        extended by ``shapes`` (index n_stations + row)
    shapes : (n_aux, 3, n_modes) the auxiliary station shape rows (y, z, rx)
    cut_frequency : f_cut of the EN 1990 deck acceleration [Hz] (nan without bridge modes)
    notes : remarks (e.g. f_cut above the model's highest bridge mode)
    """

    channels: tuple[DerivedChannel, ...]
    auxiliary: tuple[Channel, ...]
    shapes: NDArray[np.float64]
    cut_frequency: float = math.nan
    notes: tuple[str, ...] = field(default=())

    def names(self) -> tuple[str, ...]:
        return tuple(c.name for c in self.channels)


def derivative_name(name: str) -> str | None:
    """The channel recording the time derivative of ``name`` (same coordinate, next order:
    ``...disp_z`` -> ``...vel_z``, ``...vel_z`` -> ``...acc_z``), or None (accelerations, forces,
    derived channels: their derivative is not recorded)."""
    head, _, last = name.rpartition(".")
    quantity, sep, component = last.partition("_")
    if not sep or quantity not in _DERIVATIVE:
        return None
    return f"{head}.{_DERIVATIVE[quantity]}_{component}"


def station_positions(station_names: Sequence[str], spans: Sequence[float]) -> dict[str, float]:
    """x [m] along the track of the span stations (``span<k>.q1``, ``.mid``, ``.q3``: quarter points and
    midspan) and of the twist stations ``span<k>.start`` / ``.end`` (1.5 m inside the span's ends), from
    the span lengths (x = 0 at the bridge start, spans back to back); other stations (pier tops) have none.
    A station along a track (``span<k>.mid.track<i>``, a bridge of two tracks or more) lies where its
    span point does, and each track named among the stations gets its own twist stations
    (``span<k>.start.track<i>``)."""
    starts = np.concatenate(([0.0], np.cumsum(np.asarray(spans, dtype=float))[:-1]))
    out: dict[str, float] = {}
    tracks: set[int] = set()
    for name in station_names:
        m = _STATION.match(name)
        if m and int(m.group(1)) <= len(spans) and m.group(2) in _FRACTION:
            k = int(m.group(1)) - 1
            out[name] = float(starts[k] + _FRACTION[m.group(2)] * spans[k])
            if m.group(3):
                tracks.add(int(m.group(3)))
    for suffix in [f".track{i}" for i in sorted(tracks)] or [""]:
        for k, (x0, length) in enumerate(zip(starts, spans)):
            if length > 2 * TWIST_HALF_BASE:
                out[f"span{k + 1}.start{suffix}"] = float(x0 + TWIST_HALF_BASE)
                out[f"span{k + 1}.end{suffix}"] = float(x0 + length - TWIST_HALF_BASE)
    return out


def station_track(name: str, n_tracks: int) -> int:
    """The track whose deck channels station ``name`` carries: i of ``span<k>.<st>.track<i>``; on a
    bridge of one track, 1 for its span stations; 0 for none (a girder-axis station of a bridge of two
    tracks or more, whose deck channels are along each track instead)."""
    m = _STATION.match(name)
    if m and m.group(3):
        return int(m.group(3))
    return 1 if n_tracks == 1 else 0


def en1990_cut_frequency(frequencies: Sequence[float], mode_types: Sequence[str]) -> float:
    """f_cut = max(30 Hz, 1.5 f1, f3) [Hz], f1 and f3 the first and third vertical bridge modes (a
    missing f3 is left out of the max: the model then has fewer than 3 vertical modes)."""
    f1 = nth_frequency(frequencies, mode_types, "vertical", 1)
    f3 = nth_frequency(frequencies, mode_types, "vertical", 3)
    return max([EN1990_MIN_CUT] + [x for x in (1.5 * f1, f3) if math.isfinite(x)])


def _rail_rows(bridge, x: float, half_gauge: float, track: int = 1  # noqa: ANN001
               ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Vertical displacement of the left and right rail of ``track`` at x per unit modal coordinate:
    z +- b rx."""
    rs = bridge.track_shapes(track, np.array([x]))
    return rs.z[0] + half_gauge * rs.rx[0], rs.z[0] - half_gauge * rs.rx[0]


def derived_catalogue(channels: Sequence[Channel], stations: dict[str, float], bridge, half_gauge: float,  # noqa: ANN001
                      record_length: float) -> DerivedCatalogue:
    """The derived channels a model can give, from its channel catalogue.

    channels : the model's channels (tb_exudyn.system.channels.catalogue)
    stations : x [m] of the stations that get deck channels (:func:`station_positions`); the
        ``bridge.<station>.acc_z`` channel must exist for acc_z_en1990 (span stations)
    bridge : the ModalBridge (station_shapes, rail_shapes, frequencies, mode_types)
    half_gauge : b [m], the rails at +- b from the track centre line
    record_length : the run's output record [s] (n_outputs * output_step): the Sperling window is
        SPERLING_WINDOW or this, whichever is shorter
    """
    by_name = {c.name: c for c in channels}
    n_st, n_modes = bridge.station_shapes.shape[0], bridge.station_shapes.shape[2]
    station_index = {f"bridge.{s}": i for i, s in enumerate(bridge.station_names)}
    aux: list[Channel] = []
    rows: list[NDArray[np.float64]] = []
    out: list[DerivedChannel] = []
    notes: list[str] = []

    def add_aux(name: str, unit_orders: Sequence[tuple[str, str, int]], z_row: NDArray[np.float64]) -> None:
        block = np.zeros((3, n_modes))
        block[1] = z_row
        rows.append(block)
        for quantity, unit, order in unit_orders:
            aux.append(Channel(f"{name}.{quantity}_z", unit, "bridge", n_st + len(rows) - 1, 1, order))

    cut = math.nan
    if n_modes:
        cut = en1990_cut_frequency(bridge.frequencies, bridge.mode_types)
        top = float(np.max(bridge.frequencies))
        keep = (np.asarray(bridge.frequencies) <= cut).astype(float)
        if top < cut:
            notes.append(f"acc_z_en1990: f_cut = {cut:.4g} Hz lies above the model's highest bridge mode "
                         f"({top:.4g} Hz, analysis.mode_max_frequency): the modes between are missing")
        n_tracks = getattr(bridge, "n_tracks", 1)
        stations = {st: x for st, x in stations.items() if station_track(st, n_tracks)}
        for st, x in stations.items():
            base = f"bridge.{st}"
            if f"{base}.acc_z" in by_name and base in station_index:
                # along the track (EN 1990 A2.4.4.2.1 limits the deck acceleration of each track): the
                # rail-level vertical shape on the track centre line, w + e theta, as the wheels see it
                shape = bridge.track_shapes(station_track(st, n_tracks), np.array([x])).z[0] * keep
                add_aux(f"{base}.en1990", (("acc", "m/s^2", 2),), shape)
                out.append(DerivedChannel(
                    f"{base}.acc_z_en1990", "m/s^2", "linear", ((f"{base}.en1990.acc_z", 1.0),),
                    description=f"deck vertical acceleration on the track centre line (torsion included) from the "
                                f"bridge modes up to f_cut = {cut:.4g} Hz (EN 1990 A2.4.4.2.1: max(30 Hz, 1.5 f1, f3))"))
        for st, x in stations.items():
            base = f"bridge.{st}"
            names = []
            for side_name, along in (("ahead", x + TWIST_HALF_BASE), ("behind", x - TWIST_HALF_BASE)):
                left, right = _rail_rows(bridge, along, half_gauge, station_track(st, n_tracks))
                for label, row in (("left", left), ("right", right)):
                    name = f"{base}.rail_{label}_{side_name}"
                    add_aux(name, (("disp", "m", 0), ("vel", "m/s", 1)), row)
                    names.append(f"{name}.disp_z")
            la, ra, lb, rb = names
            out.append(DerivedChannel(
                f"{base}.twist_3m", "m", "linear", ((la, 1.0), (ra, -1.0), (lb, -1.0), (rb, 1.0)),
                description=f"deck twist over 3 m at x = {x:.4g} m: [z_L - z_R](x + 1.5 m) - [z_L - z_R](x - 1.5 m)"))
    window = min(SPERLING_WINDOW, float(record_length))
    cars = sorted({c.name.split(".")[0] for c in channels if c.name.startswith("car")},
                  key=lambda s: int(s[3:]) if s[3:].isdigit() else 0)
    for car in cars:
        for comp, weighting, direction in (("z", "wb", "vertical"), ("y", "wd", "lateral")):
            acc = f"{car}.body.acc_{comp}"
            if acc in by_name:
                out.append(DerivedChannel(f"{acc}_{weighting}", "m/s^2", "weighted", ((acc, 1.0),), weighting=weighting,
                                          description=f"EN 12299 {weighting.capitalize()}-weighted {acc}"))
        for comp, direction in (("z", "vertical"), ("y", "lateral")):
            acc = f"{car}.body.acc_{comp}"
            if acc in by_name:
                out.append(DerivedChannel(f"{car}.body.sperling_{comp}", "-", "sperling", ((acc, 1.0),),
                                          weighting=direction, window=window,
                                          description=f"Sperling Wz of {acc} per {window:.3g} s window"))
        axles = sorted({c.name.split(".")[1] for c in channels if c.name.startswith(f"{car}.axle")},
                       key=lambda s: int(s[4:]) if s[4:].isdigit() else 0)
        for axle in axles:
            p_l, p_r, h = (f"{car}.{axle}.left.force_z", f"{car}.{axle}.right.force_z", f"{car}.{axle}.force_y")
            if p_l in by_name and p_r in by_name:
                out.append(DerivedChannel(f"{car}.{axle}.unloading", "-", "ratio", ((p_r, 1.0), (p_l, -1.0)),
                                          ((p_r, 1.0), (p_l, 1.0)),
                                          description="wheel unloading (P_R - P_L) / (P_R + P_L), first order"))
                if h in by_name:
                    out.append(DerivedChannel(f"{car}.{axle}.left.derailment", "-", "ratio", ((h, -1.0),), ((p_l, 1.0),),
                                              description="Q/P of the left wheel as -H / P_L (all of H on it: upper bound)"))
                    out.append(DerivedChannel(f"{car}.{axle}.right.derailment", "-", "ratio", ((h, 1.0),), ((p_r, 1.0),),
                                              description="Q/P of the right wheel as H / P_R (all of H on it: upper bound)"))
    shapes = np.array(rows).reshape(len(rows), 3, n_modes)
    return DerivedCatalogue(tuple(out), tuple(aux), shapes, cut, tuple(notes))


def select_channels(channels: Sequence[Channel], catalogue: DerivedCatalogue, patterns: Sequence[str],
                    file: str | None = None) -> tuple[list[Channel], list[DerivedChannel]]:
    """The channels and derived channels whose names match any of the glob ``patterns`` (each in
    catalogue order). Raises ScenarioError (key ``analysis.channels``) naming a pattern that matches
    neither."""
    names = [c.name for c in channels]
    derived = list(catalogue.names())
    keep: set[str] = set()
    for i, pattern in enumerate(patterns):
        hits = fnmatch.filter(names, pattern) + fnmatch.filter(derived, pattern)
        if not hits:
            sample = ", ".join(names[:6]) + (", ..." if len(names) > 6 else "")
            raise ScenarioError(file, f"analysis.channels[{i}]", pattern,
                                f"glob patterns of this model's channels, e.g. {sample}", "matches no channel")
        keep.update(hits)
    return [c for c in channels if c.name in keep], [d for d in catalogue.channels if d.name in keep]


def engine_outputs(selected: Sequence[Channel], derived: Sequence[DerivedChannel], channels: Sequence[Channel],
                   catalogue: DerivedCatalogue, *, wheel_forces: bool = False) -> list[Channel]:
    """The outputs an engine must produce (the ONE function that says so), in this order: the
    ``selected`` channels; the inputs of the ``derived`` channels not among them; the recorded time
    derivative (:func:`derivative_name`) of every one of these that has one; with ``wheel_forces``,
    every vertical wheel-rail force (``*.force_z``) not yet there (Monte Carlo's loss-of-contact check).

    ``channels`` is the model's catalogue, ``catalogue`` its derived catalogue (whose auxiliary bridge
    channels index the station shapes extended by ``catalogue.shapes``)."""
    pool = {c.name: c for c in list(channels) + list(catalogue.auxiliary)}
    out = list(selected)
    seen = {c.name for c in out}

    def add(name: str) -> None:
        if name not in seen:
            out.append(pool[name])
            seen.add(name)

    for d in derived:
        for name in d.inputs:
            add(name)
    for c in list(out):
        dname = derivative_name(c.name)
        if dname is not None and dname in pool:
            add(dname)
    if wheel_forces:
        for c in channels:
            if c.name.endswith(".force_z"):
                add(c.name)
    return out


def extended_shapes(station_shapes: NDArray[np.float64], catalogue: DerivedCatalogue) -> NDArray[np.float64]:
    """The station shapes (n_st, 3, n_modes) followed by the auxiliary rows of the derived channels."""
    if not catalogue.shapes.shape[0]:
        return station_shapes
    return np.concatenate((station_shapes, catalogue.shapes), axis=0)


def derived_provenance(catalogue: DerivedCatalogue, derived: Sequence[DerivedChannel]) -> dict:
    """Plain data on a result's derived channels (for its provenance): f_cut, the catalogue's notes and
    per channel its kind, window [s] (Sperling) and description."""
    cut = catalogue.cut_frequency if math.isfinite(catalogue.cut_frequency) else None
    return {"cut_frequency_hz": cut, "notes": list(catalogue.notes),
            "channels": {d.name: {"kind": d.kind, "window": d.window, "description": d.description} for d in derived}}


__all__ = ["DERIVED_KINDS", "DerivedCatalogue", "DerivedChannel", "EN1990_MIN_CUT", "SPERLING_WINDOW",
           "TWIST_HALF_BASE", "derivative_name", "derived_catalogue", "derived_provenance", "en1990_cut_frequency", "engine_outputs",
           "extended_shapes", "select_channels", "station_positions", "station_track"]
