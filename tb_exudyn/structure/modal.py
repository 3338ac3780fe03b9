"""The modal bridge: what the train-bridge model needs to know about the structure.

A :class:`ModalBridge` holds mass-normalised modes (modal mass = identity), their frequencies and
damping ratios, and evaluates, for any position x along the track on the bridge, the rail-level
motion of every mode. Two sources fill it: the closed form of uniform simply supported spans
(:func:`simply_supported_modes`, for checks and as a fallback) and the spatial-beam finite-element
model (``tb_exudyn.structure.fe``). Pure numpy, no Exudyn.

Sign conventions (x along the track, y left, z up): a modal coordinate q_k moves the girder's shear
centre by (v_k, w_k) and rotates it by theta_k about x; a point of the cross-section at lateral
offset e and height h above the shear centre moves by dy = v - h theta, dz = w + e theta.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Callable, Sequence

import numpy as np


@dataclass(frozen=True)
class RailShapes:
    """Mode shapes at rail level on the track centre line, each array of shape (n_x, n_modes).

    ``y``, ``z``: lateral and vertical displacement per unit modal coordinate [m];
    ``rx``: rotation about x (track cant from the deck's torsion) [rad];
    ``dy``, ``dz``, ``drx``: their derivatives along x [1/m] (for the convective rail velocity
    v * d(phi)/dx * q of a moving wheel). Zero for x off the bridge.
    """

    y: np.ndarray
    z: np.ndarray
    rx: np.ndarray
    dy: np.ndarray
    dz: np.ndarray
    drx: np.ndarray

    def at_line(self, offset: float, height: float) -> "RailShapes":
        """These shapes (of the girder axis, offset 0 and height 0) moved to a line at lateral ``offset``
        e and ``height`` h: dy = v - h theta, dz = w + e theta, the rotation unchanged (module docstring)."""
        e, h = float(offset), float(height)
        return RailShapes(self.y - h * self.rx, self.z + e * self.rx, self.rx,
                          self.dy - h * self.drx, self.dz + e * self.drx, self.drx)

    def truncated(self, n: int) -> "RailShapes":
        return RailShapes(*(a[:, :n] for a in (self.y, self.z, self.rx, self.dy, self.dz, self.drx)))


@dataclass(frozen=True)
class TrackShapes:
    """One track of a bridge: its centre line's offset e from the girder axis and its rail level h above
    the shear centre [m] (nan where the data do not say, an imported bridge) and its rail-level shapes,
    x -> :class:`RailShapes` on that track's centre line."""

    offset: float
    height: float
    shapes: Callable[[np.ndarray], RailShapes] = field(repr=False)


def _truncated_function(full: Callable[[np.ndarray], RailShapes], n: int) -> Callable[[np.ndarray], RailShapes]:
    own = getattr(full, "truncated", None)  # an evaluator that can drop modes itself (faster)
    if callable(own):
        return own(n)
    return lambda x: full(x).truncated(n)


def track_stations(names: Sequence[str], x: Sequence[float], tracks: Sequence[TrackShapes]
                   ) -> tuple[tuple[str, ...], np.ndarray | None]:
    """The deck stations along each track of a bridge with two tracks or more: '<name>.track<i>' at
    each x, rows (y, z, rx) of track i's rail-level shapes there, shape (n, 3, n_modes) (None: one
    track, whose deck channels are the train's track's rail shapes, tb_exudyn.system.derived)."""
    if len(tracks) < 2 or not len(names):
        return (), None
    out_names, rows = [], []
    for i, track in enumerate(tracks):
        r = track.shapes(np.asarray(x, dtype=float))
        out_names += [f"{n}.track{i + 1}" for n in names]
        rows.append(np.stack([r.y, r.z, r.rx], axis=1))
    return tuple(out_names), np.concatenate(rows, axis=0)


class ModeSet:
    """What a set of modes with ``frequencies`` [Hz] (an (n,) array) gives: their number and circular
    frequencies (shared by :class:`ModalBridge` and the FE model's modes)."""

    frequencies: np.ndarray

    @property
    def n_modes(self) -> int:
        return int(self.frequencies.size)

    @property
    def omega(self) -> np.ndarray:
        """Circular frequencies [rad/s]."""
        return 2.0 * np.pi * self.frequencies


@dataclass(frozen=True)
class ModalBridge(ModeSet):
    """Mass-normalised modal model of a bridge.

    Attributes
    ----------
    frequencies : (n,) natural frequencies [Hz], ascending
    damping_ratios : (n,) modal damping ratios [-]
    length : length of track on the bridge [m]; x = 0 at the bridge start
    mode_types : (n,) labels, e.g. 'vertical', 'lateral', 'torsion', 'longitudinal', 'pier', 'mixed'
    station_names : names of output stations, e.g. 'span1.mid', 'span1.q1', 'pier1.top'
    station_shapes : (n_stations, 3, n) shape rows (y, z, rx) of the girder axis / pier top
    rail_shape_function : callable x -> RailShapes (vectorised over x)
    effective_masses : (n, 3) effective modal masses in y, z, rx directions, if known
    node_positions : (n_nodes, 3) positions of the finite-element nodes [m], if known (mesh for
        visualisation and for the FFRF body)
    node_shapes : (n_nodes, 3, n) translations (x, y, z) of those nodes per mode, if known
    node_masses : (n_nodes,) lumped translational mass of those nodes [kg], if known
    tracks : every track of the bridge, track 1 first (:class:`TrackShapes`); () for one track whose
        shapes are ``rail_shape_function``
    track : the track the train runs on (1, 2, ...): ``rail_shape_function`` is its shapes
        (:meth:`on_track`)
    rail_extent : (x_start, x_end) [m] of the rail this body carries when it is longer than the bridge (the
        track and the deck as one body, tb_exudyn.system.track_bridge); None: the bridge, 0 ... length
    coupled_damping : (n, n) the body's damping when it is not modal (the track's pads and ballast); None:
        diag(2 zeta omega)
    """

    frequencies: np.ndarray
    damping_ratios: np.ndarray
    length: float
    mode_types: tuple[str, ...]
    station_names: tuple[str, ...]
    station_shapes: np.ndarray
    rail_shape_function: Callable[[np.ndarray], RailShapes] = field(repr=False)
    effective_masses: np.ndarray | None = None
    description: str = ""
    node_positions: np.ndarray | None = field(default=None, repr=False)
    node_shapes: np.ndarray | None = field(default=None, repr=False)
    node_masses: np.ndarray | None = field(default=None, repr=False)
    tracks: tuple[TrackShapes, ...] = ()
    track: int = 1
    rail_extent: tuple[float, float] | None = None
    coupled_damping: np.ndarray | None = field(default=None, repr=False)

    def carries(self, x: np.ndarray) -> np.ndarray:
        """Whether the body's rail is at x [m] (bool per x): on the bridge, or on the track's whole extent."""
        lo, hi = (0.0, self.length) if self.rail_extent is None else self.rail_extent
        return (x >= lo) & (x <= hi)

    @property
    def n_tracks(self) -> int:
        return max(1, len(self.tracks))

    def track_shapes(self, track: int, x: np.ndarray) -> RailShapes:
        """Rail-level shapes on the centre line of track ``track`` (1, 2, ...) at x [m]."""
        if not self.tracks:
            return self.rail_shapes(x)
        return self.tracks[track - 1].shapes(np.atleast_1d(np.asarray(x, dtype=float)))

    def on_track(self, track: int) -> "ModalBridge":
        """The same bridge with the train on track ``track`` (1, 2, ...): its rail shapes are that
        track's. ValueError for a track the bridge does not have (the scenario checks track.on first)."""
        if not 1 <= track <= self.n_tracks:
            raise ValueError(f"track {track} of a bridge with {self.n_tracks} track(s)")
        if not self.tracks or track == self.track:
            return self
        return replace(self, rail_shape_function=self.tracks[track - 1].shapes, track=int(track))

    def track_text(self) -> str:
        """Which track the train runs on, in words ('' for a bridge of one track)."""
        if not self.tracks:
            return ""
        t = self.tracks[self.track - 1]
        where = "" if math.isnan(t.offset) else f" (offset {t.offset:g} m, rail level {t.height:g} m)"
        return f"the train on track {self.track} of {self.n_tracks}{where}"

    @property
    def mass_matrix(self) -> np.ndarray:
        return np.eye(self.n_modes)

    @property
    def stiffness_matrix(self) -> np.ndarray:
        return np.diag(self.omega**2)

    @property
    def damping_matrix(self) -> np.ndarray:
        if self.coupled_damping is not None:
            return self.coupled_damping
        return np.diag(2.0 * self.damping_ratios * self.omega)

    def rail_shapes(self, x: np.ndarray) -> RailShapes:
        """Rail-level mode shapes on the track centre line at positions x [m] (zero off the bridge)."""
        return self.rail_shape_function(np.atleast_1d(np.asarray(x, dtype=float)))

    def truncated(self, n_modes: int) -> "ModalBridge":
        """The same bridge with only its lowest ``n_modes`` modes."""
        n = int(n_modes)
        tracks = tuple(TrackShapes(t.offset, t.height, _truncated_function(t.shapes, n)) for t in self.tracks)
        shapes = tracks[self.track - 1].shapes if tracks else _truncated_function(self.rail_shape_function, n)
        return ModalBridge(
            self.frequencies[:n], self.damping_ratios[:n], self.length, self.mode_types[:n],
            self.station_names, self.station_shapes[:, :, :n], shapes,
            None if self.effective_masses is None else self.effective_masses[:n], self.description,
            self.node_positions, None if self.node_shapes is None else self.node_shapes[:, :, :n],
            self.node_masses, tracks, self.track, self.rail_extent,
            None if self.coupled_damping is None else self.coupled_damping[:n, :n],
        )


def simply_supported_modes(
    spans: tuple[float, ...] | list[float],
    EI_vertical: float,
    EI_lateral: float,
    GJ: float,
    mass_per_length: float,
    rot_mass_per_length: float,
    damping_ratio: float,
    max_frequency: float,
    track_offset: float = 0.0,
    track_height: float = 0.0,
    max_modes: int = 0,
    tracks: Sequence[tuple[float, float]] = (),
) -> ModalBridge:
    """Closed-form modes of independent uniform simply supported spans (Euler-Bernoulli, St-Venant torsion).

    Vertical and lateral bending: omega_j = (j pi / L)^2 sqrt(EI / m), shape sin(j pi x / L);
    torsion: omega_j = (j pi / L) sqrt(G J / I_p), same shape. Mass-normalised over the span:
    shape amplitude sqrt(2 / (m L)) (bending) and sqrt(2 / (I_p L)) (torsion). Bending and torsion
    are uncoupled (shear centre = mass centre). The section values are one for all spans or one per span
    (sequences in span order: spans of different sections). Modes up to ``max_frequency`` [Hz] (and at most
    ``max_modes`` if > 0), sorted by frequency. ``tracks``: (offset, height) of every track, track 1
    first (instead of ``track_offset``, ``track_height``: one track); the train on track 1.
    """
    spans = tuple(float(s) for s in spans)
    starts = np.concatenate([[0.0], np.cumsum(spans)[:-1]])
    per_span = [np.broadcast_to(np.asarray(v, dtype=float), (len(spans),))
                for v in (EI_vertical, EI_lateral, GJ, mass_per_length, rot_mass_per_length)]
    rows = []  # (freq, span index, j, type, amplitude)
    for s, L in enumerate(spans):
        EI_v, EI_l, GJ_s, m, I_p = (float(v[s]) for v in per_span)
        for kind, stiff, inertia in (("vertical", EI_v, m), ("lateral", EI_l, m)):
            j = 1
            while True:
                f = (j * np.pi / L) ** 2 * np.sqrt(stiff / inertia) / (2 * np.pi)
                if f > max_frequency:
                    break
                rows.append((f, s, j, kind, np.sqrt(2.0 / (inertia * L))))
                j += 1
        j = 1
        while True:
            f = (j * np.pi / L) * np.sqrt(GJ_s / I_p) / (2 * np.pi)
            if f > max_frequency:
                break
            rows.append((f, s, j, "torsion", np.sqrt(2.0 / (I_p * L))))
            j += 1
    rows.sort(key=lambda r: r[0])
    if max_modes > 0:
        rows = rows[:max_modes]
    if not rows:
        raise ValueError(f"no bridge mode below max_frequency = {max_frequency:g} Hz")
    freq = np.array([r[0] for r in rows])
    span_idx = np.array([r[1] for r in rows])
    j_idx = np.array([r[2] for r in rows], dtype=float)
    kinds = tuple(r[3] for r in rows)
    amp = np.array([r[4] for r in rows])
    is_v = np.array([k == "vertical" for k in kinds], dtype=float)
    is_l = np.array([k == "lateral" for k in kinds], dtype=float)
    is_t = np.array([k == "torsion" for k in kinds], dtype=float)
    L_mode = np.array(spans)[span_idx]
    x0_mode = starts[span_idx]
    lines = tuple((float(e), float(h)) for e, h in tracks) or ((float(track_offset), float(track_height)),)

    def axis(x: np.ndarray) -> RailShapes:
        xi = x[:, None] - x0_mode[None, :]
        inside = (xi >= 0.0) & (xi <= L_mode[None, :])
        k = j_idx * np.pi / L_mode
        s = np.where(inside, amp * np.sin(k * xi), 0.0)
        ds = np.where(inside, amp * k * np.cos(k * xi), 0.0)
        return RailShapes(s * is_l, s * is_v, s * is_t, ds * is_l, ds * is_v, ds * is_t)

    def line(e: float, h: float) -> Callable[[np.ndarray], RailShapes]:
        return lambda x: axis(x).at_line(e, h)

    track_list = tuple(TrackShapes(e, h, line(e, h)) for e, h in lines)
    names, rows_st, xs = [], [], []
    for s, L in enumerate(spans):
        for label, frac in (("q1", 0.25), ("mid", 0.5), ("q3", 0.75)):
            xs.append(starts[s] + frac * L)
            names.append(f"span{s + 1}.{label}")
            inside = span_idx == s
            val = np.where(inside, amp * np.sin(j_idx * np.pi * frac), 0.0)
            rows_st.append(np.stack([val * is_l, val * is_v, val * is_t]))
    along, along_rows = track_stations(names, xs, track_list)
    station_rows = np.array(rows_st) if along_rows is None else np.concatenate([np.array(rows_st), along_rows])
    return ModalBridge(
        frequencies=freq,
        damping_ratios=np.full(freq.size, float(damping_ratio)),
        length=float(sum(spans)),
        mode_types=kinds,
        station_names=tuple(names) + along,
        station_shapes=station_rows,
        rail_shape_function=track_list[0].shapes,
        description="closed-form simply supported spans",
        tracks=track_list if len(track_list) > 1 else (),
    )
