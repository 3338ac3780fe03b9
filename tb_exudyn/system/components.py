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

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import connected_components

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
    rows : (n_rows,) the contact rows (layout indices) acting on the component, in layout order
    kinds : indices into ``KINDS`` of the irregularity kinds that excite the component
    """

    coords: IntArray
    n_bridge: int
    modes: IntArray
    vehicles: tuple[VehiclePart, ...]
    rows: IntArray
    kinds: tuple[int, ...]

    @property
    def size(self) -> int:
        return int(self.coords.size)


def coupling_pattern(lin: LinearSystem, times: FloatArray) -> tuple[NDArray[np.bool_], NDArray[np.bool_]]:
    """Nonzero pattern of the coupling's Jacobians (n_loc, n_loc) over the given times (penalty
    rows and general linear rows), and of the penalty rows' gap maps B (n_c, n_loc).

    The Jacobians' pattern is that of sum_t rho_t J(t) for two draws of random weights rho_t in
    [1, 2] (a stacked product instead of one Jacobian per time): an entry cancels across times only
    with probability zero, while the exact cancellations within a time (left and right wheel) stay
    at round-off, below the threshold.
    """
    cp = lin.coupling
    nb = cp.n_bridge
    rng = np.random.default_rng(2)
    K = np.zeros((2, cp.n, cp.n))
    D = np.zeros((2, cp.n, cp.n))
    rows = np.zeros((cp.n_contacts, cp.n))
    for chunk in np.array_split(np.asarray(times, dtype=float), max(1, len(times) // 128)):
        states = [cp.contact_state(float(t)) for t in chunk]
        Bs = np.concatenate([st.B for st in states])
        dSs = np.concatenate([st.speed * st.dS for st in states])
        rows += sum(np.abs(st.B) + np.abs(np.hstack((st.dS, np.zeros_like(lin.G)))) for st in states)
        for d in range(2):
            rho = np.repeat(1.0 + rng.random(len(states)), cp.n_contacts)
            kw = (rho * np.tile(lin.k, len(states)))[:, None]
            cw = (rho * np.tile(lin.c, len(states)))[:, None]
            K[d] += Bs.T @ (kw * Bs)
            K[d][:, :nb] += Bs.T @ (cw * dSs)
            D[d] += Bs.T @ (cw * Bs)
            if cp.n_linear:  # the general rows' A^T K, A^T D (e.g. creep)
                As = np.concatenate([st.A_lin for st in states])
                gw = np.repeat(rho[:: cp.n_contacts] if cp.n_contacts else 1.0 + rng.random(len(states)),
                               cp.n_linear)[:, None]
                K[d] += As.T @ (gw * np.concatenate([st.K_lin for st in states]))
                D[d] += As.T @ (gw * np.concatenate([st.D_lin for st in states]))
    pattern = np.zeros((cp.n, cp.n), dtype=bool)
    for X in (*K, *D):
        pattern |= np.abs(X) > COUPLING_ZERO * np.abs(X).max(initial=0.0)
    return pattern | pattern.T, rows > COUPLING_ZERO * rows.max(initial=0.0)


def excited_coordinates(lin: LinearSystem, times: FloatArray) -> NDArray[np.bool_]:
    """(3, n) whether an input of each kind reaches each global coordinate at any of the times:
    the generalised input forces B^T (k r) and B^T (c r) of the penalty rows and A^T W^v, A^T W^s of
    the general rows (creep: alignment and cross-level as rail motion), with the same random value
    of the input at all rows of an axle (which sit at the same x)."""
    cp = lin.coupling
    rng = np.random.default_rng(1)
    xi = 1.0 + rng.random(cp.axle_start.size)
    W = cp.contacts.input_map * xi[cp.contacts.axle][:, None]
    reach = np.zeros((len(KINDS), cp.n))
    lin_rows = cp.contacts.linear
    if lin_rows is not None:  # general rows: input forces W^v . val + W^s . slope, applied by A^T
        Wg = [Wm * xi[lin_rows.axle][:, None] for Wm in (lin_rows.input_value, lin_rows.input_slope)]
    for t in times:
        st = cp.contact_state(float(t))
        for coef in (lin.k, lin.c):
            np.maximum(reach, np.abs(st.B.T @ (coef[:, None] * W)).T, out=reach)
        if lin_rows is not None:
            for Wm in Wg:
                np.maximum(reach, np.abs(st.A_lin.T @ Wm).T, out=reach)
    out = np.zeros((len(KINDS), lin.n), dtype=bool)
    ci = np.concatenate((lin.bridge, lin.wheel))
    out[:, ci] = reach > COUPLING_ZERO * reach.max(axis=1, keepdims=True).clip(min=1e-300)
    return out


def find_components(lin: LinearSystem, times: FloatArray) -> list[Component]:
    """The independent, excited components of the system (see the module docstring).

    Raises NotImplementedError when a bridge coordinate is not diagonal in M, K0, D0 or a vehicle's
    contact rows are not contiguous (neither happens for the models the builder makes).
    """
    n = lin.n
    base = (lin.M != 0) | (lin.K0 != 0) | (lin.D0 != 0)
    base = base | base.T
    ci = np.concatenate((lin.bridge, lin.wheel))
    coup, rows_pattern = coupling_pattern(lin, times)
    full = base.copy()
    full[np.ix_(ci, ci)] |= coup
    n_comp, label = connected_components(csr_matrix(full), directed=False)
    excited = excited_coordinates(lin, times)
    is_bridge = np.zeros(n, dtype=bool)
    is_bridge[lin.bridge] = True
    offdiag = base.copy()
    np.fill_diagonal(offdiag, False)
    if offdiag[lin.bridge].any():
        raise NotImplementedError("bridge coordinates coupled to others in M, K0 or D0: not a modal bridge body")
    # vehicles: blocks of M, K0, D0 joined by their wheels' contact rows
    veh_graph = base.copy()
    G_glob = np.zeros((lin.G.shape[0], n), dtype=bool)
    G_glob[:, lin.wheel] = lin.G != 0
    for r in G_glob:
        idx = np.flatnonzero(r)
        veh_graph[np.ix_(idx, idx)] = True
    _, vehicle_label = connected_components(csr_matrix(veh_graph), directed=False)
    _, block_label = connected_components(csr_matrix(base), directed=False)
    # which global coordinates each contact row touches (wheel map and, over time, bridge shapes)
    row_touch = np.zeros((lin.G.shape[0], n), dtype=bool)
    row_touch[:, ci] = rows_pattern
    out: list[Component] = []
    for lab in range(n_comp):
        members = np.flatnonzero(label == lab)
        kinds = tuple(int(k) for k in range(len(KINDS)) if excited[k, members].any())
        if not kinds:
            continue  # never excited: stays at rest
        bridge = members[is_bridge[members]]
        modes = np.searchsorted(lin.bridge, bridge)
        rows = np.flatnonzero(row_touch[:, members].any(axis=1))
        coords = [bridge]
        vehicles = []
        local = bridge.size
        veh_of_row = np.full(rows.size, -1)
        for j, row in enumerate(rows):
            wheels = np.flatnonzero(G_glob[row] & (label == lab))
            if wheels.size:
                veh_of_row[j] = vehicle_label[wheels[0]]
        vehicle_ids = list(dict.fromkeys(vehicle_label[m] for m in members if not is_bridge[m]))
        vehicle_ids.sort(key=lambda v: (np.flatnonzero(veh_of_row == v)[:1].tolist() or [rows.size])[0])
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
            if vrows.size and np.any(np.diff(vrows) != 1):
                raise NotImplementedError("a vehicle's contact rows are not contiguous")
            r0, r1 = (int(vrows[0]), int(vrows[-1]) + 1) if vrows.size else (0, 0)
            vehicles.append(VehiclePart(start, local, tuple(blocks), r0, r1))
        out.append(Component(coords=np.concatenate(coords).astype(np.int64), n_bridge=int(bridge.size),
                             modes=modes.astype(np.int64), vehicles=tuple(vehicles),
                             rows=rows.astype(np.int64), kinds=kinds))
    return out


__all__ = ["COUPLING_ZERO", "Component", "VehiclePart", "coupling_pattern", "excited_coordinates", "find_components"]
