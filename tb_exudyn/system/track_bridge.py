"""The scenario's track between wheel and deck: both rails on discrete supports over the whole stretch the
wheels travel, on the deck where it is and on the subgrade off it, and the deck's modes, reduced to one modal
body that the wheel-rail coupling (tb_exudyn.system.coupling) reads as its "bridge". Pure numpy / scipy.

The DOFs before reduction (:func:`track_and_deck`):

- two rails (left at +b, right at -b from the track centre line, b = the half gauge), each the rail of
  :func:`~.track_model.track_model` built with the subgrade chain (pad, sleeper, ballast, ballast mass,
  subgrade to the ground; slab: pad, slab, mortar, base mass, the base's support), supports at
  x0 + (i + 1/2) a;
- the deck's mass-normalised modal coordinates q_d.

A support on the deck (0 <= x_s <= deck length) loses its lowest mass and the spring below it: its ballast
(mortar) spring ends on the deck's rail level under that rail, w = (z_d +- b rx_d)(x_s) q_d (the deck's
rail-level shapes on the track centre line; the ballast (base) on the deck is the deck's mass, as
:func:`~.track_model.track_on_deck`). The rails and sleepers (slabs) on the deck move with the track, so
their mass is taken out of the deck's: M_dd = I - sum_s (m_sleeper + mu a) p_s^T p_s over the supports on
the deck, p_s the rail-level row under each rail (the shipped bridges' added mass holds the track; a
bridge whose mass does not would lose that share, about 2 % of a concrete box girder's).

The whole (K, M, C) is reduced to its undamped modes up to ``max_frequency`` (mass-normalised), its damping
Phi^T C Phi kept whole (``ModalBridge.coupled_damping``: the pads' and the ballast's dampers are not
proportional). The body's rail shapes (the contact rows) are the rails' Hermite rows times the modes:
z = (z_L + z_R) / 2 and rx = (z_L - z_R) / (2 b), so that z + e rx is the left rail at e = +b and the
right at e = -b (a contact on the centre line, e = 0, loads both rails by halves); y the deck's lateral
rail-level shapes, or with ``lateral`` the rails' (below). Its station shapes are the deck's (the deck
channels as without the track), followed by the rows of :class:`TrackPoint` (the track's channels).

With ``lateral`` (a train with lateral contacts: car15's wheelsets) both rails bend laterally as well: each
the rail of :func:`~.track_model.track_model` on ``structure.lateral()`` (I_lateral; the pad's lateral
spring-damper, the half sleeper (slab share), the ballast's (mortar's) lateral spring-damper to the ground;
no ballast mass, no subgrade laterally), whose lowest spring on the deck ends on the deck's lateral rail
level y_d(x_s) q_d instead of the ground; the rails' and sleepers' lateral inertia leaves the deck's mass as
their vertical one does. The two directions meet only in the deck's modes (no rail torsion, no
vertical-lateral coupling in the pad). The body's y = (y_L + y_R) / 2: a lateral contact on the centre line
loads each rail by half, the alignment irregularity between wheel and rails.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np
import scipy.sparse as sp

from ..scenario.errors import ScenarioError
from ..scenario.track_structure import LATERAL_TRACK_KINDS, TrackStructure, load_track_structure
from ..structure.modal import ModalBridge, RailShapes, TrackShapes
from .channels import Channel
from .coupling import LATERAL
from .derived import DerivedChannel, station_positions
from .track_model import hermite, hermite_slope, track_model

#: the default of analysis.track_mode_max_frequency [Hz]: the rail's receptance left out above f_c is about 1 / (3 pi EI k_c^3)
#: (k_c the bending wavenumber at f_c): 0.8 % at 2 kHz (docs/track.md, 3b)
TRACK_MODE_MAX_FREQUENCY = 2000.0
#: Hermite elements per bay (a node at each support and at mid-bay)
ELEMENTS_PER_BAY = 2
#: bays of rail beyond the first and the last wheel position of the run (a free rail end 6 m away at
#: 0.6 m: the deflection under a load decays as exp(-beta x), beta = 1.2-1.3 /m on ballast: 1e-3 at 6 m)
MARGIN_BAYS = 10
#: most DOFs the dense eigen-solution takes (about 1 GB of work arrays at 6000)
MAX_TRACK_DOFS = 6000


@dataclass(frozen=True)
class TrackPoint:
    """A track channel's place: the left rail's support nearest a deck station ``station`` (x [m] from the
    bridge start), its rows over the body's modes: ``rail`` (the rail above the support), ``sleeper`` (the
    first mass), ``deck`` (the deck's rail level under it); the pad (k_p, c_p) between rail and sleeper and
    the ballast (k_b, c_b) between sleeper and deck."""

    station: str
    x: float
    rail: np.ndarray = field(repr=False)
    sleeper: np.ndarray = field(repr=False)
    deck: np.ndarray = field(repr=False)
    pad: tuple[float, float]
    ballast: tuple[float, float]


@dataclass(frozen=True)
class TrackBridge:
    """The track and the deck as one modal body: ``bridge`` (what the coupling reads; its
    ``coupled_damping`` the full Phi^T C Phi), ``points`` the track channels' places, ``n_dof`` the DOFs
    reduced, ``x_range`` the rails' extent [m] (x = 0 at the bridge's start)."""

    bridge: ModalBridge
    points: tuple[TrackPoint, ...]
    n_dof: int
    x_range: tuple[float, float]
    #: the static flexibility [m/N] of the modes left out, at a point of one rail (``z``, vertical) and of the
    #: rails' lateral centre line (``y``; 0 without the lateral rails): the mean over a bay on the deck and off it
    residual: dict = field(default_factory=dict)

    def series_contacts(self, layout):  # noqa: ANN001, ANN201 - a ContactLayout
        """``layout`` with each penalty contact's spring in series with the left-out modes' static flexibility r
        at its rail: k / (1 + k r), c / (1 + k r)^2 (the damper's low-frequency form). A vertical contact at
        rail_offset e loads the left rail by (1 + e / b) / 2 and the right by (1 - e / b) / 2 (module docstring),
        so its r is r_z ((1 + e/b)^2 + (1 - e/b)^2) / 4; a lateral one the rails' centre line's r_y."""
        b = self.bridge.rail_shape_function.b
        e = np.asarray(layout.rail_offset, dtype=float) / b
        r = np.where(np.asarray(layout.direction) == LATERAL, self.residual.get("y", 0.0),
                     self.residual.get("z", 0.0) * ((1 + e) ** 2 + (1 - e) ** 2) / 4)
        k = np.asarray(layout.stiffness, dtype=float)
        return replace(layout, stiffness=k / (1 + k * r), damping=np.asarray(layout.damping) / (1 + k * r) ** 2)


def track_extent(axle_start: np.ndarray, speed: float, duration: float, spacing: float) -> tuple[float, int]:
    """(x0, n_supports): the rails of a run reach MARGIN_BAYS bays beyond every wheel position of the run."""
    x_first = float(np.min(axle_start))
    x_last = float(np.max(axle_start)) + speed * duration
    x0 = x_first - MARGIN_BAYS * spacing
    n = int(math.ceil((x_last + MARGIN_BAYS * spacing - x0) / spacing))
    return x0, n


def approach_extent(x0: float, n: int, spacing: float, approach: float, length: float) -> tuple[float, int]:
    """(x0, n) of rails that reach ``approach`` [m] before and after a bridge of ``length`` (and MARGIN_BAYS bays
    further, where no wheel is carried: :func:`carried_extent`), within the run's (x0, n) (to the nearest support
    beyond it); approach 0: the run's. The cut rails' supports stand at x = (j + 1/2) a from the bridge's start
    (j whole): placed by the bridge, not by the run's lead-in, so that every speed of a sweep (whose lead-in the
    speed rule scales) has the same track, solved once (docs/track.md 8)."""
    if approach <= 0.0:
        return x0, n
    first = max(math.floor(-approach / spacing) - MARGIN_BAYS, math.floor(x0 / spacing))
    last = min(math.ceil((length + approach) / spacing) + MARGIN_BAYS, math.ceil((x0 + n * spacing) / spacing))
    return first * spacing, max(last - first, 1)


def carried_extent(x0: float, n: int, spacing: float, cut: bool) -> tuple[float, float]:
    """Where the rails carry a wheel: the whole rail under a run (no wheel comes within MARGIN_BAYS of its free
    ends), or, when the rails were cut short of the run (``track.structure_approach``), the rail less
    MARGIN_BAYS bays at each end, so that a wheel rolls from the rigid line onto a rail that is not its free
    end's."""
    if not cut:
        return x0, x0 + n * spacing
    return x0 + MARGIN_BAYS * spacing, x0 + (n - MARGIN_BAYS) * spacing


def track_dofs(structure: TrackStructure, n_supports: int, n_deck_supports: int, lateral: bool = False) -> int:
    """DOFs of the unreduced track and deck (two rails, with ``lateral`` their lateral bending and the
    sleepers' lateral motion as well; the deck's modes not counted)."""
    n_rail = 2 * (n_supports * ELEMENTS_PER_BAY + 1)
    n_mass = len(structure.chain("subgrade")) - 1
    return 2 * (n_rail + n_supports * n_mass - n_deck_supports) + (2 * (n_rail + n_supports) if lateral else 0)


def scenario_lateral(scenario) -> bool:  # noqa: ANN001 - a Scenario
    """Whether a scenario's track is built with the rails' lateral bending: when a vehicle has a lateral
    contact (``LATERAL_TRACK_KINDS``: car15 and the articulated sets' wheelsets)."""
    return any(v.kind in LATERAL_TRACK_KINDS for v in scenario.train.vehicles)


def scenario_extent(scenario) -> tuple[TrackStructure, float, int]:  # noqa: ANN001 - a Scenario
    """(structure, x0, n_supports) of a scenario's track (``track.structure``): the rails reach
    MARGIN_BAYS bays beyond every wheel position of the run. ScenarioError (key ``track.lead_in``) when
    the unreduced track would have more than MAX_TRACK_DOFS DOFs: checked before any work."""
    sc = scenario
    structure = load_track_structure(sc.track.structure, sc.source_file)
    axle_start = -sc.track.lead_in - np.asarray(sc.train.axle_positions, dtype=float)
    x0, n = track_extent(axle_start, sc.speed, sc.duration, structure.spacing)
    x0, n = approach_extent(x0, n, structure.spacing, sc.track.structure_approach, sc.bridge.length)
    on = int(np.sum((x0 + (np.arange(n) + 0.5) * structure.spacing >= 0.0)
                    & (x0 + (np.arange(n) + 0.5) * structure.spacing <= sc.bridge.length)))
    dofs = track_dofs(structure, n, on, scenario_lateral(sc))
    if dofs > MAX_TRACK_DOFS:
        most = MAX_TRACK_DOFS * n * structure.spacing / dofs
        raise ScenarioError(sc.where, "track.lead_in", sc.track.lead_in,  # one line within 200 characters
                            f"rails up to about {most:.0f} m, or a track.structure_approach",
                            f"{n * structure.spacing:.0f} m of rails under the run: {dofs} DOFs, more than "
                            f"{MAX_TRACK_DOFS}")
    return structure, x0, n


def scenario_track(scenario, deck: ModalBridge) -> TrackBridge:  # noqa: ANN001 - a Scenario
    """The scenario's track (``track.structure``) under its whole run, on the deck ``deck`` (the bridge's
    modes on the train's track), as one modal body; the track channels at the deck's span stations."""
    structure, x0, n = scenario_extent(scenario)
    stations = {k: x for k, x in station_positions(deck.station_names, getattr(scenario.bridge, "spans", (deck.length,))).items()
                if k in deck.station_names}
    args = (structure, x0, n, scenario.track.half_gauge, scenario.analysis.track_mode_max_frequency,
            tuple(stations.items()), scenario_lateral(scenario), scenario.track.structure_approach > 0.0)
    key = (args, _deck_key(deck, x0 + (np.arange(n) + 0.5) * structure.spacing))
    last = _LAST.get("track")
    if last is not None and last[0] == key:  # the same track on the same deck: its modes solved once per process
        return last[1]
    track = track_and_deck(structure, deck, x0, n, scenario.track.half_gauge, max_frequency=args[4],
                           stations=stations, lateral=args[6], cut=args[7])
    _LAST["track"] = (key, track)
    return track


#: the last track solved in this process (a run builds its model several times: the analysis, the engine, the
#: mean; the track's eigen-solution is most of a build: 45 s of CPU for li_zhu_2011's 5178 DOFs)
_LAST: dict = {}


def solved_tracks() -> tuple:
    """The tracks solved (or kept) in this process, as entries for :func:`keep_tracks` in another: a sweep's
    parent solves its track once and its workers keep it (one eigen-solution and static correction per sweep
    when its speeds' tracks are the same: a cut track, ``track.structure_approach``)."""
    last = _LAST.get("track")
    return () if last is None else (last,)


def keep_tracks(entries: tuple) -> None:
    """Keep the tracks of :func:`solved_tracks` (from another process) for this process's builds: a build whose
    track is one of them (the same structure, extent, cut-off and deck, to the bit) takes it instead of solving."""
    for entry in entries:
        _LAST["track"] = entry


def _deck_key(deck: ModalBridge, xs: np.ndarray) -> tuple:
    """What the track takes of a deck: its modes, damping, stations and rail-level shapes at the supports."""
    rs = deck.rail_shapes(xs)
    arrays = (deck.frequencies, deck.damping_ratios, deck.station_shapes, rs.y, rs.z, rs.rx)
    return (deck.description, deck.length, deck.track, deck.station_names, deck.mode_types) + tuple(
        (np.asarray(a).shape, np.asarray(a).tobytes()) for a in arrays)


@dataclass(frozen=True)
class _Assembled:
    """The unreduced track and deck (:func:`_assemble`): ``K``, ``M``, ``C`` in the kept DOFs (CSR), ``T`` the
    map from them to every DOF (the lowest mass of a support on the deck is the deck's rail level under it),
    ``one`` a rail's TrackModel, ``lat`` the lateral rails or None, ``xs``/``on`` the supports and which stand
    on the deck, ``p_left`` the deck's rows under the left rail, ``n_t``/``n_l`` a rail's vertical/lateral DOFs."""

    K: sp.csr_matrix
    M: sp.csr_matrix
    C: sp.csr_matrix
    T: sp.csr_matrix
    one: object
    lat: object
    xs: np.ndarray
    on: np.ndarray
    p_left: np.ndarray
    n_t: int
    n_l: int

    def rail_rows(self, x: np.ndarray, h: float, n_el: int) -> dict[str, sp.csr_matrix]:
        """The rows (in the kept DOFs) of the left rail's vertical displacement ``z_left`` and, with the lateral
        rails, of the rails' lateral centre line ``y`` (half each rail's) at points ``x`` of the rails' frame
        (x = 0 at the rail's start)."""
        x = np.atleast_1d(np.asarray(x, dtype=float))
        e = np.minimum((x / h).astype(int), n_el - 1)
        xi = x / h - e
        H = hermite(xi, h)
        cols = 2 * e[:, None] + np.arange(4)[None, :]
        rows = np.repeat(np.arange(x.size), 4)
        n_full = self.T.shape[0]
        out = {"z_left": sp.csr_matrix((H.ravel(), (rows, cols.ravel())), shape=(x.size, n_full)) @ self.T}
        if self.lat is not None:
            base = 2 * self.n_t
            y = sum(sp.csr_matrix((0.5 * H.ravel(), (rows, base + side * self.n_l + cols.ravel())),
                                  shape=(x.size, n_full)) for side in range(2))
            out["y"] = y @ self.T
        return out


def _assemble(structure: TrackStructure, deck: ModalBridge, x0: float, n_supports: int, half_gauge: float,
              lateral: bool) -> _Assembled:
    """Both rails of ``structure`` on ``n_supports`` supports from x0 on ``deck`` (module docstring), before
    the modal reduction."""
    one = track_model(structure, n_supports, ELEMENTS_PER_BAY, ground="subgrade")
    b = float(half_gauge)
    xs = one.support_x + x0
    on = (xs >= 0.0) & (xs <= deck.length)
    n_t, n_d = one.n_dof, deck.n_modes
    rs = deck.rail_shapes(xs[on]) if np.any(on) else None
    # the deck's rows under each rail at the supports on it (left: z + b rx, right: z - b rx)
    p_side = [np.zeros((xs.size, n_d)), np.zeros((xs.size, n_d))]
    if rs is not None:
        p_side[0][on], p_side[1][on] = rs.z + b * rs.rx, rs.z - b * rs.rx
    lowest = one.support_dofs[:, -1]
    chain = one.chain
    k_low, c_low, m_low = chain[-1][0], chain[-1][1], chain[-2][2]
    blocks_k, blocks_m, blocks_c = [], [], []
    for _ in range(2):  # the support on the deck: no lowest mass, no spring below it
        drop = sp.csr_matrix((np.ones(int(on.sum())), (lowest[on], lowest[on])), shape=(n_t, n_t))
        blocks_k.append(one.K - k_low * drop)
        blocks_c.append(one.C - c_low * drop)
        blocks_m.append(one.M - m_low * drop)
    sleeper_mass = chain[0][2] + structure.rail.mass_per_length * structure.spacing
    dm = sum(sleeper_mass * (p[on].T @ p[on]) for p in p_side) if np.any(on) else np.zeros((n_d, n_d))
    om, zeta = deck.omega, deck.damping_ratios
    lat = _lateral_rails(structure, n_supports, on, deck.rail_shapes(xs[on]).y if np.any(on) else None, n_d) \
        if lateral else None
    if lat is not None:
        blocks_k, blocks_m, blocks_c = blocks_k + lat.K, blocks_m + lat.M, blocks_c + lat.C
        dm = dm + lat.deck_mass
    n_l = lat.n_dof if lat is not None else 0
    K = sp.block_diag((*blocks_k, sp.diags(om**2)), format="csr")
    M = sp.block_diag((*blocks_m, sp.csr_matrix(np.eye(n_d) - dm)), format="csr")
    C = sp.block_diag((*blocks_c, sp.diags(2 * zeta * om)), format="csr")
    if lat is not None:  # the lateral ballast (mortar) springs ending on the deck's lateral rail level
        K, C = K + lat.couple(lat.k_low, 2 * n_t, K.shape[0]), C + lat.couple(lat.c_low, 2 * n_t, K.shape[0])
    # the transformation to the kept DOFs: the lowest mass of a support on the deck is the deck under it
    n_full = 2 * n_t + 2 * n_l + n_d
    removed = np.concatenate([side * n_t + lowest[on] for side in range(2)])
    kept = np.setdiff1d(np.arange(n_full), removed)
    T = sp.lil_matrix((n_full, kept.size))
    T[kept, np.arange(kept.size)] = 1.0
    deck_cols = np.searchsorted(kept, 2 * n_t + 2 * n_l + np.arange(n_d))
    for side in range(2):
        for s in np.flatnonzero(on):
            T[side * n_t + lowest[s], deck_cols] = p_side[side][s]
    T = T.tocsr()
    Kr, Mr, Cr = ((T.T @ A @ T).tocsr() for A in (K, M, C))
    return _Assembled(K=Kr, M=Mr, C=Cr, T=T, one=one, lat=lat, xs=xs, on=on, p_left=p_side[0], n_t=n_t, n_l=n_l)


def track_and_deck(structure: TrackStructure, deck: ModalBridge, x0: float, n_supports: int, half_gauge: float,
                   max_frequency: float = TRACK_MODE_MAX_FREQUENCY,
                   stations: dict[str, float] | None = None, lateral: bool = False, cut: bool = False) -> TrackBridge:
    """Both rails of ``structure`` on ``n_supports`` supports from x0 (module docstring), on ``deck`` (x = 0
    at its start) where it is, reduced to the modes up to ``max_frequency``; ``stations`` (name -> x on
    the deck) the places of the track channels; ``lateral``: the rails' lateral bending as well (module
    docstring), their centre line the body's lateral rail shape y; ``cut``: the rails end short of the run
    (:func:`carried_extent`). The left-out modes' static flexibility at the rails: ``TrackBridge.residual``."""
    from scipy.linalg import eigh

    a = _assemble(structure, deck, x0, n_supports, half_gauge, lateral)
    one, lat, xs, on, n_t, n_l, n_d = a.one, a.lat, a.xs, a.on, a.n_t, a.n_l, deck.n_modes
    b = float(half_gauge)
    lam, phi = eigh(a.K.toarray(), a.M.toarray(), subset_by_value=(-np.inf, (2 * np.pi * max_frequency) ** 2))
    lam = np.maximum(lam, 0.0)
    freq = np.sqrt(lam) / (2 * np.pi)
    full = a.T @ phi  # (n_full, n): every DOF's share of each mode
    damping = phi.T @ (a.C @ phi)
    damping = 0.5 * (damping + damping.T)
    ratios = np.diag(damping) / (2 * np.maximum(2 * np.pi * freq, 1e-300))
    phi_d = full[2 * n_t + 2 * n_l:]
    rails = (full[:one.n_rail], full[n_t:n_t + one.n_rail])
    lateral_rails = None if lat is None else tuple(full[2 * n_t + i * n_l:2 * n_t + i * n_l + lat.n_rail] for i in range(2))
    carried = carried_extent(x0, n_supports, structure.spacing, cut)
    shapes = _RailFunction(rails, phi_d, deck, x0, one.h, n_supports * ELEMENTS_PER_BAY, b, lateral_rails,
                           (carried[0] - x0, carried[1] - x0))
    points = _points(stations or {}, xs, on, one, full, a.p_left, phi_d, structure)
    zero = np.zeros(freq.size)
    extra = np.array([[zero, row, zero] for p in points for row in (p.rail, p.sleeper, p.deck)]).reshape(-1, 3, freq.size)
    station_shapes = np.concatenate((np.einsum("sij,jn->sin", deck.station_shapes, phi_d), extra), axis=0)
    tracks = tuple(TrackShapes(t.offset, t.height, _through(t.shapes, phi_d)) for t in deck.tracks)
    deck_share = np.einsum("in,ij,jn->n", phi_d, np.eye(n_d), phi_d)
    types = tuple(deck.mode_types[int(np.argmax(np.abs(phi_d[:, j])))] if deck_share[j] > 0.5 else "track"
                  for j in range(freq.size))
    body = ModalBridge(
        frequencies=freq, damping_ratios=ratios, length=deck.length, mode_types=types,
        station_names=deck.station_names, station_shapes=station_shapes, rail_shape_function=shapes,
        description=(f"{deck.description}; under the track {structure.name}{' (vertical and lateral)' if lat else ''} "
                     f"({n_supports} supports per rail from "
                     f"x = {x0:.4g} m, {int(on.sum())} on the deck): {freq.size} modes of the track and the deck "
                     f"up to {max_frequency:g} Hz"),
        tracks=tracks, track=deck.track, rail_extent=carried,
        coupled_damping=damping)
    return TrackBridge(bridge=body, points=points, n_dof=a.K.shape[0], x_range=(x0, x0 + n_supports * structure.spacing),
                       residual=_residual(a, phi, lam, structure.spacing, deck.length, x0, one.h,
                                          n_supports * ELEMENTS_PER_BAY))


def residual_points(xs: np.ndarray, on: np.ndarray, spacing: float) -> np.ndarray:
    """Where the left-out modes' flexibility is sampled [m, bridge frame]: above a support and mid-bay, at the
    support on the deck nearest its middle and at the off-deck support farthest from both the deck and the
    rails' ends (none off it when every support is on it)."""
    pts = []
    if np.any(on):
        mid = xs[on][np.argmin(np.abs(xs[on] - 0.5 * (xs[on][0] + xs[on][-1])))]
        pts += [mid, mid + 0.5 * spacing]
    off = xs[~on]
    if off.size:
        margin = np.minimum(np.abs(off - xs[0]), np.abs(off - xs[-1]))
        away = np.minimum(margin, np.min(np.abs(off[:, None] - xs[on][None, :]), axis=1) if np.any(on) else margin)
        s = off[np.argmax(away)]
        pts += [s, s + 0.5 * spacing]
    return np.asarray(pts)


def _residual(a: _Assembled, phi: np.ndarray, lam: np.ndarray, spacing: float, length: float, x0: float,
              h: float, n_el: int) -> dict:
    """The static flexibility of the modes left out [m/N]: the unreduced model's (a sparse solve) less the kept
    modes' sum s_i^2 / omega_i^2, at :func:`residual_points`, its mean ('z' one rail, 'y' the rails' lateral
    centre line) and its spread ('z_spread', 'y_spread': (max - min) / mean)."""
    import scipy.sparse.linalg as sla

    pts = residual_points(a.xs, a.on, spacing)
    rows = a.rail_rows(pts - x0, h, n_el)
    lu = sla.splu(a.K.tocsc())
    out = {}
    for key, R in rows.items():
        R = R.toarray()
        full = np.array([r @ lu.solve(r) for r in R])
        kept = np.sum((R @ phi) ** 2 / np.maximum(lam, 1e-300), axis=1)
        left = np.maximum(full - kept, 0.0)
        out[key.split("_")[0]] = float(np.mean(left))
        out[key.split("_")[0] + "_spread"] = float((left.max() - left.min()) / max(np.mean(left), 1e-300))
    return out


#: a track point's rows, in this order after the deck's stations (channels ``track.<station>.left.<part>``)
POINT_PARTS = ("rail", "sleeper", "deck")


def track_channels(track: TrackBridge, n_deck_stations: int) -> list[Channel]:
    """The track's channels: at each span station, the left rail above the nearest support on the deck, its
    sleeper (slab) and the deck's rail level under it, displacement, velocity and acceleration
    (``track.span1.mid.left.sleeper.acc_z``); rows of the body's station shapes after the deck's."""
    out: list[Channel] = []
    for i, p in enumerate(track.points):
        for j, part in enumerate(POINT_PARTS):
            row = n_deck_stations + len(POINT_PARTS) * i + j
            for order, (quantity, unit) in enumerate((("disp", "m"), ("vel", "m/s"), ("acc", "m/s^2"))):
                out.append(Channel(f"track.{p.station}.left.{part}.{quantity}_z", unit, "bridge", row, 1, order))
    return out


def track_forces(track: TrackBridge) -> list[DerivedChannel]:
    """The pad's and the ballast's (mortar's) force at each track point [N], compression positive (the
    force_z convention): pad k_p (w_sleeper - w_rail) + c_p (its rate), ballast k_b (w_deck - w_sleeper) + c_b
    (its rate); linear derived channels of the track channels."""
    out = []
    for p in track.points:
        base = f"track.{p.station}.left"
        for name, (k, c), upper, lower in (("pad", p.pad, "rail", "sleeper"), ("ballast", p.ballast, "sleeper", "deck")):
            terms = ((f"{base}.{lower}.disp_z", k), (f"{base}.{upper}.disp_z", -k),
                     (f"{base}.{lower}.vel_z", c), (f"{base}.{upper}.vel_z", -c))
            out.append(DerivedChannel(f"{base}.{name}.force_z", "N", "linear", terms,
                                      description=f"{name} force under the left rail at x = {p.x:.4g} m, compression "
                                                  f"positive: {k:.3g} N/m and {c:.3g} N s/m"))
    return out


class _RailFunction:
    """x -> RailShapes of the two rails (module docstring), zero where the rails carry no wheel (outside
    ``carried``, [m] from the rails' start: :func:`carried_extent`); picklable (no closure)."""

    def __init__(self, rails, phi_d, deck, x0, h, n_el, b, lateral=None, carried=None) -> None:  # noqa: ANN001
        self.rails, self.phi_d, self.deck, self.x0, self.h, self.n_el, self.b = rails, phi_d, deck, x0, h, n_el, b
        self.lateral = lateral
        self.carried = (0.0, n_el * h) if carried is None else carried

    def in_basis(self, X: np.ndarray) -> "_RailFunction":
        """The same function for coordinates y with q = X y (X: (n_modes, m)): each row S becomes S X, its
        rails' and the deck's rows multiplied once here (S(x) X at a point is then an interpolation of 4
        rows, not a product with X: the batched engine's coupled block, docs/track.md 3d)."""
        lateral = None if self.lateral is None else [r @ X for r in self.lateral]
        return _RailFunction([r @ X for r in self.rails], self.phi_d @ X, self.deck, self.x0, self.h, self.n_el,
                             self.b, lateral, self.carried)

    def __call__(self, x: np.ndarray) -> RailShapes:
        x = np.atleast_1d(np.asarray(x, dtype=float))
        u = x - self.x0
        length = self.n_el * self.h
        inside = (u >= self.carried[0]) & (u <= self.carried[1])
        uc = np.clip(u, 0.0, length)
        e = np.minimum((uc / self.h).astype(int), self.n_el - 1)
        xi = uc / self.h - e
        dofs = 2 * e[:, None] + np.arange(4)[None, :]
        H, dH = hermite(xi, self.h), hermite_slope(xi, self.h)
        zl, zr = (np.einsum("xk,xkn->xn", H, r[dofs]) * inside[:, None] for r in self.rails)
        dzl, dzr = (np.einsum("xk,xkn->xn", dH, r[dofs]) * inside[:, None] for r in self.rails)
        if self.lateral is None:  # the lateral contact on the deck's track line
            d = self.deck.rail_shapes(x)
            y, dy = d.y @ self.phi_d, d.dy @ self.phi_d
        else:  # on the rails' centre line: a lateral force loads each rail by half
            y = sum(np.einsum("xk,xkn->xn", H, r[dofs]) for r in self.lateral) * (0.5 * inside[:, None])
            dy = sum(np.einsum("xk,xkn->xn", dH, r[dofs]) for r in self.lateral) * (0.5 * inside[:, None])
        return RailShapes(y, 0.5 * (zl + zr), (zl - zr) / (2 * self.b), dy,
                          0.5 * (dzl + dzr), (dzl - dzr) / (2 * self.b))


@dataclass(frozen=True)
class _Lateral:
    """The two rails in lateral bending (their blocks of K, M, C, left then right), the deck's mass they
    take (rail and sleeper on the deck, under both rails) and the lateral ballast (mortar) springs of the
    supports on the deck, whose lower end the deck's lateral rail level is (:meth:`couple`)."""

    K: list
    M: list
    C: list
    n_dof: int
    n_rail: int
    deck_mass: np.ndarray
    k_low: float
    c_low: float
    sleepers: np.ndarray  # (n_on,) the DOF of each support on the deck's sleeper within one rail's block
    p_y: np.ndarray  # (n_on, n_d) the deck's lateral rail-level rows under them

    def couple(self, value: float, offset: int, n: int) -> sp.csr_matrix:
        """The spring (damper) ``value`` between each sleeper on the deck and the deck's rail level under it,
        less its end on rigid ground (which the rail's block holds): cross terms -v p and the deck's v p^T p;
        ``offset`` the first lateral DOF, the deck's modes the last of the ``n``."""
        n_d = self.p_y.shape[1]
        deck = n - n_d + np.arange(n_d)
        rows, cols, vals = [], [], []
        for side in range(2):
            j = offset + side * self.n_dof + self.sleepers
            rows += [np.repeat(j, n_d), np.tile(deck, j.size)]
            cols += [np.tile(deck, j.size), np.repeat(j, n_d)]
            vals += [-value * self.p_y.ravel()] * 2
        dd = 2 * value * (self.p_y.T @ self.p_y)
        rows.append(np.repeat(deck, n_d)), cols.append(np.tile(deck, n_d)), vals.append(dd.ravel())
        return sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(n, n))


def _lateral_rails(structure: TrackStructure, n_supports: int, on: np.ndarray, p_y: np.ndarray | None,
                   n_d: int) -> _Lateral:
    """Both rails of ``structure.lateral()`` on rigid ground (pad, sleeper, ballast laterally), the supports
    ``on`` the deck to be coupled to its lateral rail-level rows ``p_y``."""
    side = track_model(structure.lateral(), n_supports, ELEMENTS_PER_BAY, ground="rigid")
    (_, _, m_sleeper), (k_low, c_low, _) = side.chain
    p = np.zeros((0, n_d)) if p_y is None else p_y
    mass = 2 * (m_sleeper + structure.rail.mass_per_length * structure.spacing) * (p.T @ p)
    return _Lateral(K=[side.K, side.K], M=[side.M, side.M], C=[side.C, side.C], n_dof=side.n_dof, n_rail=side.n_rail,
                    deck_mass=mass, k_low=k_low, c_low=c_low, sleepers=side.support_dofs[on, 0], p_y=p)


class _through:  # noqa: N801 - a function object
    """The deck's shapes (of its modes) through the body's modes: shapes(x) @ phi_d."""

    def __init__(self, shapes, phi_d) -> None:  # noqa: ANN001
        self.shapes, self.phi_d = shapes, phi_d

    def __call__(self, x: np.ndarray) -> RailShapes:
        s = self.shapes(x)
        return RailShapes(*(a @ self.phi_d for a in (s.y, s.z, s.rx, s.dy, s.dz, s.drx)))


def _points(stations: dict[str, float], xs: np.ndarray, on: np.ndarray, one, full: np.ndarray,  # noqa: ANN001
            p_left: np.ndarray, phi_d: np.ndarray, structure: TrackStructure) -> tuple[TrackPoint, ...]:
    out = []
    if not np.any(on):
        return ()
    candidates = np.flatnonzero(on)
    rail_node = 2 * (np.arange(xs.size) * ELEMENTS_PER_BAY + ELEMENTS_PER_BAY // 2)
    pad, low = one.chain[0], one.chain[1]
    for name, x in stations.items():
        s = int(candidates[np.argmin(np.abs(xs[candidates] - x))])
        out.append(TrackPoint(station=name, x=float(xs[s]), rail=full[rail_node[s]],
                              sleeper=full[one.support_dofs[s, 0]], deck=p_left[s] @ phi_d,
                              pad=(pad[0], pad[1]), ballast=(low[0], low[1])))
    return tuple(out)


__all__ = ["scenario_lateral", "POINT_PARTS", "track_channels", "track_forces", "scenario_extent", "scenario_track", "MARGIN_BAYS", "MAX_TRACK_DOFS", "TRACK_MODE_MAX_FREQUENCY", "TrackBridge", "TrackPoint",
           "track_and_deck", "track_dofs", "track_extent", "approach_extent", "carried_extent",
           "residual_points", "keep_tracks", "solved_tracks"]
