"""The track alone as a linear system in plain numpy and scipy.sparse: one rail on discrete supports.

The rail is an Euler-Bernoulli beam of cubic Hermite elements (two DOFs per node: the vertical
displacement w, z up, and the rotation dw/dx), ``elements_per_bay`` elements between two supports. Under
each support hangs the chain of its track structure (``TrackStructure.chain``): the pad's spring-damper
from the rail's node to the first mass (the half sleeper, the slab's share), the next spring-damper to the
next mass (the ballast's, the base's), the last to the ground. The supports stand at (i + 1/2) a, i = 0 ...
n - 1, on a rail of length n a with free ends, so that the rail reaches half a bay past the first and the
last support. DOFs: the rail's nodes first (w_0, theta_0, w_1, ...), then each support's masses from the
rail down, support by support.

No Exudyn, no vehicle: M, K, C and what a contact needs of the rail (``TrackModel.shape``: the Hermite row
that gives w at a point, the row a point force enters by). The rail's own damping is not modelled (the
dampers are the pads' and the layers').
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Literal

import numpy as np
import scipy.sparse as sp

from ..scenario.track_structure import TrackStructure
from ..structure.modal import ModalBridge, RailShapes


def beam_element(ei: float, mass_per_length: float, h: float) -> tuple[np.ndarray, np.ndarray]:
    """(K_e, M_e): the Euler-Bernoulli element of length h, DOFs (w1, theta1, w2, theta2); consistent mass."""
    k = ei / h**3 * np.array([[12, 6 * h, -12, 6 * h], [6 * h, 4 * h * h, -6 * h, 2 * h * h],
                              [-12, -6 * h, 12, -6 * h], [6 * h, 2 * h * h, -6 * h, 4 * h * h]])
    m = mass_per_length * h / 420.0 * np.array([
        [156, 22 * h, 54, -13 * h], [22 * h, 4 * h * h, 13 * h, -3 * h * h],
        [54, 13 * h, 156, -22 * h], [-13 * h, -3 * h * h, -22 * h, 4 * h * h]])
    return k, m


def hermite(xi: np.ndarray, h: float) -> np.ndarray:
    """(n, 4): the cubic Hermite shape functions at local coordinates xi in [0, 1] of an element of length h."""
    xi = np.asarray(xi, dtype=float)
    return np.stack([1 - 3 * xi**2 + 2 * xi**3, h * (xi - 2 * xi**2 + xi**3), 3 * xi**2 - 2 * xi**3,
                     h * (xi**3 - xi**2)], axis=-1)


@dataclass(frozen=True)
class TrackModel:
    """One rail on ``n_supports`` discrete supports: ``M``, ``K``, ``C`` (scipy CSR, n_dof x n_dof).

    ``length`` the rail [m] (x from 0); ``support_x`` (n_supports,) [m]; ``h`` the element length;
    ``n_rail`` the rail's DOFs (2 per node); ``support_dofs`` (n_supports, n_masses) the DOF of each
    support's masses, from the rail down; ``chain`` the (k, c, m) chain under each support.
    """

    structure_name: str
    length: float
    support_x: np.ndarray = field(repr=False)
    h: float
    n_rail: int
    support_dofs: np.ndarray = field(repr=False)
    chain: tuple[tuple[float, float, float], ...]
    M: sp.csr_matrix = field(repr=False)
    K: sp.csr_matrix = field(repr=False)
    C: sp.csr_matrix = field(repr=False)
    #: the deck's modal coordinates appended after the track's DOFs (:func:`track_on_deck`; empty: rigid ground)
    deck_dofs: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=int), repr=False)

    @property
    def n_dof(self) -> int:
        return self.M.shape[0]

    def shape(self, x: float | np.ndarray) -> sp.csr_matrix:
        """(n_x, n_dof): the rows that give the rail's displacement w at the points x (0 <= x <= length);
        their transposes spread a point force onto the DOFs (consistent load vector)."""
        x = np.atleast_1d(np.asarray(x, dtype=float))
        if np.any((x < 0) | (x > self.length)):
            raise ValueError(f"points on the rail, 0 ... {self.length:g} m, not {x[(x < 0) | (x > self.length)]}")
        n_el = int(round(self.length / self.h))
        e = np.minimum((x / self.h).astype(int), n_el - 1)
        vals = hermite(x / self.h - e, self.h)
        cols = 2 * e[:, None] + np.arange(4)[None, :]
        rows = np.repeat(np.arange(x.size), 4)
        return sp.csr_matrix((vals.ravel(), (rows, cols.ravel())), shape=(x.size, self.n_dof))

    def receptance(self, x: float, freqs: np.ndarray) -> np.ndarray:
        """(n_f,) complex: the rail's displacement at x per unit harmonic force at x [m/N], w = alpha F e^{i w t}."""
        from scipy.sparse.linalg import splu

        f = self.shape(x).toarray().ravel()
        out = np.empty(np.size(freqs), dtype=complex)
        for i, fr in enumerate(np.atleast_1d(freqs)):
            w = 2 * np.pi * fr
            z = (self.K - w * w * self.M + 1j * w * self.C).tocsc()
            out[i] = f @ splu(z).solve(f.astype(complex))
        return out


def track_model(structure: TrackStructure, n_supports: int, elements_per_bay: int = 6,
                ground: Literal["rigid", "subgrade"] = "rigid") -> TrackModel:
    """The rail of ``structure`` on ``n_supports`` supports at (i + 1/2) a, free ends half a bay beyond the
    first and the last; ``elements_per_bay`` (even: a node at mid-bay) Hermite elements between supports;
    ``ground``: the chain ends at the ballast (mortar) on rigid ground, or reaches the subgrade."""
    if n_supports < 1 or elements_per_bay < 2 or elements_per_bay % 2:
        raise ValueError("n_supports >= 1 and an even elements_per_bay >= 2")
    a = structure.spacing
    h = a / elements_per_bay
    n_el = n_supports * elements_per_bay
    n_rail = 2 * (n_el + 1)
    chain = structure.chain(ground)
    n_mass = len(chain) - 1
    n_dof = n_rail + n_supports * n_mass
    ke, me = beam_element(structure.rail.E * structure.rail.I, structure.rail.mass_per_length, h)
    rows, cols, kv, mv = [], [], [], []
    idx = 2 * np.arange(n_el)[:, None] + np.arange(4)[None, :]  # (n_el, 4)
    rows.append(np.repeat(idx, 4, axis=1).ravel())
    cols.append(np.tile(idx, (1, 4)).ravel())
    kv.append(np.tile(ke.ravel(), n_el))
    mv.append(np.tile(me.ravel(), n_el))
    support_x = (np.arange(n_supports) + 0.5) * a
    rail_node = 2 * (np.arange(n_supports) * elements_per_bay + elements_per_bay // 2)
    support_dofs = n_rail + np.arange(n_supports)[:, None] * n_mass + np.arange(n_mass)[None, :]
    top = np.concatenate([rail_node[:, None], support_dofs], axis=1)  # (n_s, n_mass + 1): rail, masses
    c_rows, c_cols, c_vals = [], [], []
    for j, (k, c, m) in enumerate(chain):
        upper = top[:, j]
        lower = top[:, j + 1] if j < n_mass else None
        for store, value in ((kv, k), (c_vals, c)):
            r_, c_, v_ = _spring(upper, lower, value)
            if store is kv:
                rows.append(r_), cols.append(c_), kv.append(v_), mv.append(np.zeros_like(v_))
            else:
                c_rows.append(r_), c_cols.append(c_), c_vals.append(v_)
        if j < n_mass:
            rows.append(lower), cols.append(lower), kv.append(np.zeros(n_supports)), mv.append(np.full(n_supports, m))
    r, cc = np.concatenate(rows), np.concatenate(cols)
    shape = (n_dof, n_dof)
    K = sp.csr_matrix((np.concatenate(kv), (r, cc)), shape=shape)
    M = sp.csr_matrix((np.concatenate(mv), (r, cc)), shape=shape)
    C = sp.csr_matrix((np.concatenate(c_vals), (np.concatenate(c_rows), np.concatenate(c_cols))), shape=shape)
    return TrackModel(structure_name=structure.name, length=n_supports * a, support_x=support_x, h=h,
                      n_rail=n_rail, support_dofs=support_dofs, chain=chain, M=M, K=K, C=C)


def track_on_deck(track: TrackModel, deck: ModalBridge, deck_start: float) -> TrackModel:
    """The track with its supports on a deck: the lowest spring-damper of every support that stands on the
    deck (deck_start <= x_s <= deck_start + deck.length) ends on the deck's track line, w_d(x_s) =
    phi(x_s - deck_start) q_d (the deck's vertical rail-level shapes ``deck.rail_shapes(x).z``, bending and
    torsion times the track's offset), instead of the ground; the deck's mass-normalised modal coordinates
    q_d (with their own omega^2 and 2 zeta omega) are appended to the DOFs. Supports off the deck stay on
    rigid ground (the chain of ``ground="rigid"``; the ballast's mass on the deck is the deck's). The track's masses move with the deck: the deck's own modes must leave them out (a bridge
    whose added mass holds the rails and sleepers counts them twice)."""
    if track.deck_dofs.size:
        raise ValueError("the track already stands on a deck")
    if len(track.chain) != 2:  # ground="subgrade": its subgrade spring would end on the deck
        raise ValueError("track_on_deck takes the track built with ground='rigid' (the ballast or the mortar "
                         "ends on the deck); a subgrade off the deck is not modelled yet")
    chain = track.chain
    k, c = chain[-1][0], chain[-1][1]
    bottom = track.support_dofs[:, -1]  # the lowest mass of each support (a chain has at least one)
    xs = track.support_x - deck_start
    on = (xs >= 0.0) & (xs <= deck.length)
    p = np.zeros((xs.size, deck.n_modes))
    if np.any(on):
        p[on] = deck.rail_shapes(xs[on]).z
    n_t, n_d = track.n_dof, deck.n_modes
    e = sp.csr_matrix((np.ones(xs.size), (bottom, np.arange(xs.size))), shape=(n_t, xs.size))  # DOF of each support
    pd = sp.csr_matrix(p)

    def coupled(a: sp.csr_matrix, value: float, own: np.ndarray) -> sp.csr_matrix:
        """The track's matrix with its lowest springs (or dampers) ``value`` ending on the deck."""
        off = -value * (e @ pd)  # (n_t, n_d)
        dd = value * (pd.T @ pd) + sp.diags(own)
        return sp.bmat([[a, off], [off.T, dd]], format="csr")

    om, zeta = deck.omega, deck.damping_ratios
    M = sp.bmat([[track.M, None], [None, sp.identity(n_d)]], format="csr")
    return TrackModel(structure_name=track.structure_name, length=track.length, support_x=track.support_x,
                      h=track.h, n_rail=track.n_rail, support_dofs=track.support_dofs, chain=chain, M=M,
                      K=coupled(track.K, k, om**2), C=coupled(track.C, c, 2 * zeta * om),
                      deck_dofs=n_t + np.arange(n_d))


def hermite_slope(xi: np.ndarray, h: float) -> np.ndarray:
    """(n, 4): d/dx of the cubic Hermite shape functions at local coordinates xi of an element of length h."""
    xi = np.asarray(xi, dtype=float)
    return np.stack([(-6 * xi + 6 * xi**2) / h, 1 - 4 * xi + 3 * xi**2, (6 * xi - 6 * xi**2) / h,
                     3 * xi**2 - 2 * xi], axis=-1)


@dataclass(frozen=True)
class ModalTrack:
    """The track in the form the wheel-rail coupling reads (tb_exudyn.system.coupling): ``bridge`` a
    :class:`~tb_exudyn.structure.modal.ModalBridge` whose modes are the track's (mass-normalised, undamped
    modes of M, K up to ``max_frequency``) and whose rail shapes are the rail's Hermite rows times the
    modes (``z``, ``dz``; the lateral rows zero; zero off the rail); ``damping`` (n, n) the track's damping
    in these coordinates, Phi^T C Phi: not diagonal (the pads' and the ballast's dampers are not
    proportional), so it belongs in the linear system's D0, not in modal ratios."""

    bridge: ModalBridge
    damping: np.ndarray = field(repr=False)
    modes: np.ndarray = field(repr=False)


def modal_track(track: TrackModel, max_frequency: float | None = None) -> ModalTrack:
    """The track's modes (all of them, or up to ``max_frequency`` [Hz]) as a ModalTrack (dense eigen-
    solution: for tracks of a few hundred DOFs)."""
    from scipy.linalg import eigh

    lam, phi = eigh(track.K.toarray(), track.M.toarray())
    lam = np.maximum(lam, 0.0)
    freq = np.sqrt(lam) / (2 * np.pi)
    keep = np.ones(freq.size, bool) if max_frequency is None else freq <= max_frequency
    freq, phi = freq[keep], phi[:, keep]
    damping = phi.T @ (track.C @ phi)
    ratios = np.diag(damping) / (2 * np.maximum(2 * np.pi * freq, 1e-300))
    n_el = int(round(track.length / track.h))
    length = track.length

    def shapes(x: np.ndarray) -> RailShapes:
        x = np.atleast_1d(np.asarray(x, dtype=float))
        on = (x >= 0.0) & (x <= length)
        xc = np.clip(x, 0.0, length)
        e = np.minimum((xc / track.h).astype(int), n_el - 1)
        xi = xc / track.h - e
        dofs = 2 * e[:, None] + np.arange(4)[None, :]
        rows = phi[dofs]  # (n_x, 4, n)
        z = np.einsum("xk,xkn->xn", hermite(xi, track.h), rows) * on[:, None]
        dz = np.einsum("xk,xkn->xn", hermite_slope(xi, track.h), rows) * on[:, None]
        zero = np.zeros_like(z)
        return RailShapes(zero, z, zero, zero.copy(), dz, zero.copy())

    bridge = ModalBridge(frequencies=freq, damping_ratios=ratios, length=length,
                         mode_types=("track",) * freq.size, station_names=(),
                         station_shapes=np.zeros((0, 3, freq.size)), rail_shape_function=shapes,
                         description=f"track {track.structure_name}: {freq.size} modes of one rail on "
                                     f"{track.support_x.size} supports")
    return ModalTrack(bridge=bridge, damping=damping, modes=phi)


def _spring(upper: np.ndarray, lower: np.ndarray | None, value: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """COO entries of springs (or dampers) of one value between DOFs ``upper`` and ``lower`` (None: the ground)."""
    n = upper.size
    if lower is None:
        return upper, upper, np.full(n, value)
    r = np.concatenate([upper, lower, upper, lower])
    c = np.concatenate([upper, lower, lower, upper])
    v = np.concatenate([np.full(2 * n, value), np.full(2 * n, -value)])
    return r, c, v


__all__ = ["ModalTrack", "TrackModel", "track_on_deck", "beam_element", "hermite", "hermite_slope", "modal_track", "track_model"]
