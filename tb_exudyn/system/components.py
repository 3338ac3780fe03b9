"""Independent components of a linear train-bridge system.

The graph of the nonzero entries of M, K0, D0 and of the coupling's Jacobians (including the
convective term, at every output time: :func:`coupling_pattern`) splits the coordinates into
independent parts; for a symmetric car on a symmetric track, the vertical in-plane and the lateral
out-of-plane motions (the left and right wheel contacts' cross terms cancel). A part no irregularity
kind reaches (longitudinal coordinates, wheelset spin and yaw, pier modes without rail motion) stays
at rest and is not integrated at all. Entries below ``COUPLING_ZERO`` of the largest coupling entry
are taken as zero (round-off of cancelling terms; a coupling that small changes no response by more
than 1e-12 relative).
"""

from __future__ import annotations

import hashlib
import weakref
from collections import OrderedDict
from dataclasses import dataclass
from typing import Any, Iterator

import numpy as np
from numpy.typing import NDArray
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import connected_components

from .coupling import RAIL_SHAPE_ROWS
from .excitation import KINDS
from .linear import LinearSystem

#: entries of the coupling below this fraction of its largest entry count as zero (round-off)
COUPLING_ZERO = 1e-12

IntArray = NDArray[np.int64]
FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class VehiclePart:
    """A vehicle's coordinates inside a component: a contiguous local range, its dense diagonal
    blocks (local ranges) and its contact rows (a contiguous range of the component's rows)."""

    start: int
    stop: int
    blocks: tuple[tuple[int, int], ...]
    row_start: int
    row_stop: int


@dataclass(frozen=True)
class Component:
    """An independent part of the system.

    Attributes
    ----------
    coords : (n,) global ODE2 indices in local order: bridge modes first, then the vehicles
    n_bridge : number of bridge modes (local 0 .. n_bridge-1)
    modes : (n_bridge,) their indices among the bridge's modes
    vehicles : the vehicle parts (local coordinate ranges and contact rows)
    rows : (n_rows,) the contact rows acting on the component (indices into the coupling's rows:
        penalty rows, then general rows, :class:`~.coupling.RowMaps`), grouped by vehicle in the
        vehicles' order, in layout order within a vehicle
    kinds : indices into ``KINDS`` of the irregularity kinds that excite the component
    coupled : whether the bridge block is coupled in M, K0 or D0 (a track's modes with the pads' and
        the ballast's non-proportional damping, :func:`tb_exudyn.system.track_model.modal_track`);
        False: diagonal, a modal bridge body's
    """

    coords: IntArray
    n_bridge: int
    modes: IntArray
    vehicles: tuple[VehiclePart, ...]
    rows: IntArray
    kinds: tuple[int, ...]
    coupled: bool = False

    @property
    def size(self) -> int:
        return int(self.coords.size)


def _bridge_parts(lin: LinearSystem, times: FloatArray) -> Iterator[tuple[FloatArray, FloatArray, FloatArray]]:
    """The bridge parts S^a, S^k, S^d of every contact row's maps at each of the times, stacked over
    chunks of times: arrays (n_t_chunk, n_rows, n_b) (:class:`~.coupling.RowMaps`); the wheel parts
    are constant. Each part is the sum over the rail shapes (RAIL_SHAPE_ROWS) that any row uses of
    the row's coefficient times the shape at its axle (0.10 -> 0.04 s on li_zhu_2011's output times
    against one stacked product over all six shapes)."""
    cp = lin.coupling
    rm = cp.row_maps()
    nb = cp.n_bridge
    maps = (rm.app_shape, rm.stiff_shape, rm.damp_shape)  # (n_rows, 6) each
    used = [s for s in range(len(RAIL_SHAPE_ROWS)) if any(P[:, s].any() for P in maps)]
    for chunk in np.array_split(np.asarray(times, dtype=float), max(1, len(times) // 128)):
        if chunk.size == 0:
            continue
        x = np.stack([cp.positions(float(t)) for t in chunk])
        rs = cp.bridge.rail_shapes(x.reshape(-1))
        parts = tuple(np.zeros((chunk.size, rm.n_rows, nb)) for _ in maps)
        for s in used:
            shape = getattr(rs, RAIL_SHAPE_ROWS[s]).reshape(chunk.size, -1, nb)[:, rm.axle]  # (n_t, n_r, n_b)
            for part, P in zip(parts, maps):
                if P[:, s].any():
                    part += P[None, :, s, None] * shape
        yield parts


class _CouplingSums:
    """The sums behind :func:`coupling_pattern`, over chunks of times (:meth:`add`)."""

    def __init__(self, lin: LinearSystem, joined: IntArray | None = None) -> None:
        cp = lin.coupling
        self.rm, self.nb, self.n = cp.row_maps(), cp.n_bridge, cp.n
        #: the bridge-bridge columns summed: all but ``joined`` (bridge coordinates M, K0, D0 already join)
        self.cols = None if joined is None else np.setdiff1d(np.arange(self.nb), joined)
        self.rng = np.random.default_rng(2)
        self.K = np.zeros((2, cp.n, cp.n))
        self.D = np.zeros((2, cp.n, cp.n))
        self.rows = np.zeros((self.rm.n_rows, cp.n))
        self.n_times = 0

    def add(self, Sa: FloatArray, Sk: FloatArray, Sd: FloatArray) -> None:
        rm, nb = self.rm, self.nb
        n_t = Sa.shape[0]
        self.n_times += n_t
        self.rows[:, :nb] += (np.abs(Sa) + np.abs(Sk) + np.abs(Sd)).sum(axis=0)
        for d in range(2):
            rho = 1.0 + self.rng.random(n_t)
            wSa = np.einsum("t,trb->rb", rho, Sa)
            for X, S, G in ((self.K[d], Sk, rm.stiff_wheel), (self.D[d], Sd, rm.damp_wheel)):
                if self.cols is None:
                    X[:nb, :nb] += (Sa * rho[:, None, None]).reshape(-1, nb).T @ S.reshape(-1, nb)
                else:  # an edge inside the joined set adds nothing: (n_b x n_kept), not n_b^2
                    X[:nb, self.cols] += (Sa * rho[:, None, None]).reshape(-1, nb).T @ S.reshape(-1, nb)[:, self.cols]
                X[:nb, nb:] -= wSa.T @ G
                X[nb:, :nb] -= rm.app_wheel.T @ np.einsum("t,trb->rb", rho, S)
                X[nb:, nb:] += rho.sum() * (rm.app_wheel.T @ G)

    def result(self) -> tuple[NDArray[np.bool_], NDArray[np.bool_]]:
        rm, nb, rows = self.rm, self.nb, self.rows
        rows[:, nb:] = self.n_times * (np.abs(rm.app_wheel) + np.abs(rm.stiff_wheel) + np.abs(rm.damp_wheel))
        pattern = np.zeros((self.n, self.n), dtype=bool)
        for X in (*self.K, *self.D):
            pattern |= np.abs(X) > COUPLING_ZERO * np.abs(X).max(initial=0.0)
        return pattern | pattern.T, rows > COUPLING_ZERO * rows.max(initial=0.0)


class _InputReach:
    """The sums behind :func:`excited_coordinates`, over chunks of times (:meth:`add`)."""

    def __init__(self, lin: LinearSystem) -> None:
        cp = lin.coupling
        self.lin, self.rm, self.nb = lin, cp.row_maps(), cp.n_bridge
        rng = np.random.default_rng(1)
        xi = 1.0 + rng.random(cp.axle_start.size)[self.rm.axle][:, None]
        self.weights = [self.rm.input_value * xi, self.rm.input_slope * xi]
        self.reach = np.zeros((len(KINDS), cp.n))
        for W in self.weights:
            np.maximum(self.reach[:, self.nb:], np.abs(self.rm.app_wheel.T @ W).T, out=self.reach[:, self.nb:])

    def add(self, Sa: FloatArray, Sk: FloatArray, Sd: FloatArray) -> None:
        nb = self.nb
        for W in self.weights:
            np.maximum(self.reach[:, :nb], np.abs(np.einsum("trb,rk->tkb", Sa, W)).max(axis=0), out=self.reach[:, :nb])

    def result(self) -> NDArray[np.bool_]:
        lin, reach = self.lin, self.reach
        out = np.zeros((len(KINDS), lin.n), dtype=bool)
        ci = np.concatenate((lin.bridge, lin.wheel))
        out[:, ci] = reach > COUPLING_ZERO * reach.max(axis=1, keepdims=True).clip(min=1e-300)
        return out


def _scan(lin: LinearSystem, times: FloatArray, *sums: "_CouplingSums | _InputReach") -> None:
    """One pass over the bridge parts at the times (:func:`_bridge_parts`), added to each of ``sums``."""
    for parts in _bridge_parts(lin, times):
        for acc in sums:
            acc.add(*parts)


def coupling_pattern(lin: LinearSystem, times: FloatArray) -> tuple[NDArray[np.bool_], NDArray[np.bool_]]:
    """Nonzero pattern of the coupling's Jacobians (n_loc, n_loc) over the given times, and of the
    contact rows' maps P, F^k, F^d (n_rows, n_loc; penalty rows, then general rows).

    The Jacobians' pattern is that of sum_t rho_t P(t)^T F(t) for two draws of random weights rho_t
    in [1, 2] (a stacked product instead of one Jacobian per time), by blocks of bridge and wheel
    coordinates: P = [S^a(t), -G^a], F = [S(t), -G] with G constant. An entry cancels across times
    only with probability zero, while the exact cancellations within a time (left and right wheel)
    stay at round-off, below the threshold.
    """
    sums = _CouplingSums(lin)
    _scan(lin, times, sums)
    return sums.result()


def excited_coordinates(lin: LinearSystem, times: FloatArray) -> NDArray[np.bool_]:
    """(3, n) whether an input of each kind reaches each global coordinate at any of the times:
    the generalised input forces P^T (w_v xi) and P^T (w_s xi) of every row (its value and slope
    weights of the kind, :class:`~.coupling.RowMaps`) with the same random value xi at all rows of
    an axle (which sit at the same x)."""
    sums = _InputReach(lin)
    _scan(lin, times, sums)
    return sums.result()


#: the last results of :func:`find_components` by their inputs (a run's damping guard and its engine
#: ask for the same ones; 0.15-0.2 s each on the reference study): key -> (the coupling, components)
_FOUND: "OrderedDict[bytes, tuple[weakref.ref, tuple[Component, ...]]]" = OrderedDict()
_FOUND_KEPT = 4


#: the last scans of the bridge parts (:func:`_scanned`) by what they read: the coupling object, the
#: times, the bridge and wheel indices (not M, K0, D0: the linear mean's system about the static state
#: has its own, and the columns' coupling, so its search repeats only the graph part, 0.01 of 0.09 s)
_SCANNED: "OrderedDict[bytes, tuple[weakref.ref, tuple[NDArray[np.bool_], ...]]]" = OrderedDict()


def _digest(coupling: Any, *arrays: np.ndarray) -> bytes:
    """A digest of the arrays (their dtype, shape and bytes) and the coupling object's identity."""
    h = hashlib.blake2b(digest_size=20)
    for a in arrays:
        a = np.ascontiguousarray(a)
        h.update(f"{a.dtype.str}{a.shape}".encode())
        h.update(a.tobytes())
    h.update(str(id(coupling)).encode())
    return h.digest()


def _kept(memo: "OrderedDict[bytes, tuple[weakref.ref, Any]]", key: bytes, coupling: Any) -> Any:
    """The kept value of ``key`` in ``memo`` if it was made with this very coupling object, else None."""
    hit = memo.get(key)
    if hit is None or hit[0]() is not coupling:
        return None
    memo.move_to_end(key)
    return hit[1]


def _keep(memo: "OrderedDict[bytes, tuple[weakref.ref, Any]]", key: bytes, coupling: Any, value: Any) -> None:
    memo[key] = (weakref.ref(coupling), value)
    while len(memo) > _FOUND_KEPT:
        memo.popitem(last=False)


def _joined_bridge(base: NDArray[np.bool_], bridge: IntArray) -> IntArray | None:
    """The bridge modes (indices among them) of the largest set that ``base`` (M, K0, D0's pattern) already
    joins, if it has more than one (a track's modes, joined by the pads' and the ballast's damping); None for a
    modal bridge body's diagonal block, whose every mode stands alone."""
    block = base[np.ix_(bridge, bridge)]
    if not (block.sum() > bridge.size):  # diagonal (or empty): nothing joined
        return None
    _, label = connected_components(csr_matrix(block), directed=False)
    counts = np.bincount(label)
    return np.flatnonzero(label == np.argmax(counts)) if counts.max() > 1 else None


def _scanned(lin: LinearSystem, times: FloatArray, joined: IntArray | None = None) -> tuple[NDArray[np.bool_], ...]:
    """(coupling pattern, contact rows' pattern, excited coordinates) of one pass over the bridge parts
    at the times (:func:`_scan` with :class:`_CouplingSums` and :class:`_InputReach`), read-only; the
    last few kept by what they read (``_SCANNED``). ``joined``: bridge modes M, K0, D0 already join
    (:func:`_joined_bridge`), whose coupling among themselves is not summed (left False in the pattern;
    the threshold is then taken of the entries summed)."""
    times = np.asarray(times, dtype=float)
    key = _digest(lin.coupling, lin.bridge, lin.wheel, np.array([lin.n]), times,
                  np.array([-1]) if joined is None else joined)
    hit = _kept(_SCANNED, key, lin.coupling)
    if hit is not None:
        return hit
    coupling, reach = _CouplingSums(lin, joined), _InputReach(lin)
    _scan(lin, times, coupling, reach)
    out = (*coupling.result(), reach.result())
    for a in out:
        a.setflags(write=False)
    _keep(_SCANNED, key, lin.coupling, out)
    return out


def find_components(lin: LinearSystem, times: FloatArray) -> list[Component]:
    """The independent, excited components of the system (see the module docstring).

    The bridge's block of M, K0, D0 may be coupled (a track's modes: :attr:`Component.coupled`);
    NotImplementedError when a bridge coordinate is coupled to a vehicle's in them (no model makes
    such a system). The last few results are kept by a digest of their inputs (the same inputs give
    the same components, which are immutable).
    """
    # what the search reads: M, K0, D0, the bridge and wheel indices, the times and the coupling object
    key = _digest(lin.coupling, lin.M, lin.K0, lin.D0, lin.bridge, lin.wheel, np.asarray(times, dtype=float))
    hit = _kept(_FOUND, key, lin.coupling)
    if hit is not None:
        return list(hit)
    out = _find_components(lin, times)
    for comp in out:  # shared by every caller from now on
        for a in (comp.coords, comp.modes, comp.rows):
            a.setflags(write=False)
    _keep(_FOUND, key, lin.coupling, tuple(out))
    return out


def _find_components(lin: LinearSystem, times: FloatArray) -> list[Component]:
    """:func:`find_components` without its kept components (its scan of the bridge parts is kept: :func:`_scanned`)."""
    n = lin.n
    base = (lin.M != 0) | (lin.K0 != 0) | (lin.D0 != 0)
    base = base | base.T
    ci = np.concatenate((lin.bridge, lin.wheel))
    # one pass over the bridge parts for both
    coup, rows_pattern, excited = _scanned(lin, times, _joined_bridge(base, lin.bridge))
    full = base.copy()
    full[np.ix_(ci, ci)] |= coup
    n_comp, label = connected_components(csr_matrix(full), directed=False)
    is_bridge = np.zeros(n, dtype=bool)
    is_bridge[lin.bridge] = True
    offdiag = base.copy()
    np.fill_diagonal(offdiag, False)
    if offdiag[lin.bridge][:, ~is_bridge].any():
        raise NotImplementedError("bridge coordinates coupled to vehicle coordinates in M, K0 or D0")
    # vehicles: blocks of M, K0, D0 joined by their wheels' contact rows
    rm = lin.coupling.row_maps()
    veh_graph = base.copy()
    G_glob = np.zeros((rm.n_rows, n), dtype=bool)
    G_glob[:, lin.wheel] = (rm.app_wheel != 0) | (rm.stiff_wheel != 0) | (rm.damp_wheel != 0)
    for r in G_glob:
        idx = np.flatnonzero(r)
        veh_graph[np.ix_(idx, idx)] = True
    _, vehicle_label = connected_components(csr_matrix(veh_graph), directed=False)
    _, block_label = connected_components(csr_matrix(base), directed=False)
    # which global coordinates each contact row touches (wheel maps and, over time, bridge shapes)
    row_touch = np.zeros((rm.n_rows, n), dtype=bool)
    row_touch[:, ci] = rows_pattern
    out: list[Component] = []
    for lab in range(n_comp):
        members = np.flatnonzero(label == lab)
        kinds = tuple(int(k) for k in range(len(KINDS)) if excited[k, members].any())
        if not kinds:
            continue  # never excited: stays at rest
        bridge = members[is_bridge[members]]
        modes = np.searchsorted(lin.bridge, bridge)
        touching = np.flatnonzero(row_touch[:, members].any(axis=1))
        veh_of_row = np.full(touching.size, -1)
        for j, row in enumerate(touching):
            wheels = np.flatnonzero(G_glob[row] & (label == lab))
            if wheels.size:
                veh_of_row[j] = vehicle_label[wheels[0]]
        vehicle_ids = list(dict.fromkeys(vehicle_label[m] for m in members if not is_bridge[m]))
        vehicle_ids.sort(key=lambda v: (np.flatnonzero(veh_of_row == v)[:1].tolist() or [touching.size])[0])
        # rows grouped by vehicle (in running order), in layout order within a vehicle (penalty rows,
        # then general rows); rows on no vehicle last
        rank = {v: i for i, v in enumerate(vehicle_ids)}
        order = sorted(range(touching.size), key=lambda j: (rank.get(veh_of_row[j], len(rank)), touching[j]))
        rows, veh_of_row = touching[order], veh_of_row[order]
        coords = [bridge]
        vehicles = []
        local = bridge.size
        for v in vehicle_ids:
            vm = members[(vehicle_label[members] == v) & ~is_bridge[members]]
            blocks = []
            start = local
            for b in dict.fromkeys(block_label[vm]):
                bm = vm[block_label[vm] == b]
                blocks.append((local, local + bm.size))
                coords.append(bm)
                local += bm.size
            vrows = np.flatnonzero(veh_of_row == v)
            r0, r1 = (int(vrows[0]), int(vrows[-1]) + 1) if vrows.size else (0, 0)
            vehicles.append(VehiclePart(start, local, tuple(blocks), r0, r1))
        out.append(Component(coords=np.concatenate(coords).astype(np.int64), n_bridge=int(bridge.size),
                             modes=modes.astype(np.int64), vehicles=tuple(vehicles),
                             rows=rows.astype(np.int64), kinds=kinds,
                             coupled=bool(offdiag[np.ix_(bridge, bridge)].any())))
    return out


__all__ = ["COUPLING_ZERO", "Component", "VehiclePart", "coupling_pattern", "excited_coordinates", "find_components"]
