"""Where a component's state goes at an output time (the batched engine's channel evaluation).

The channels come from the engine's :class:`~tb_exudyn.system.channels.OutputMap` (the same map of
node coordinates, bridge station shapes and contact rows that defines the channels of an Exudyn
recording); only the selected channels are evaluated.
"""

from __future__ import annotations

from types import SimpleNamespace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..alpha import GeneralizedAlpha
from ...jit import blas_scratch
from ...system.channels import rail_under

ComplexArray = NDArray[np.complex128]
IntArray = NDArray[np.int64]


class _Outputs:
    """Where a component's state goes at an output time, in an internal channel order that makes
    its node channels of one order a contiguous block of rows (written without scatter): row
    gathers of (q, v, qdd) = (q~ + Delta, v~ + gamma' Delta, beta' Delta), station-shape products
    over its modes (bridge channels, summed over components) and its contact forces. With
    components sharing a contact row, each one's force f_I = F_I u_I + f_in carries the input once:
    the true force is sum_I f_I - (n - 1) f_in for n components integrating that column."""

    def __init__(self, cm: Any, run: Any, overlap: NDArray[np.int64], order: list[int],
                 bridge_rows: dict[int, int], contact_rows: dict[int, int], like: "_Outputs | None" = None,
                 rail_rows: dict[int, int] | None = None, coupling: Any = None) -> None:
        """``order``: the internal channel order, extended by this component's node channels (unless
        ``like``, another column chunk of the same component, already placed them); ``rail_rows``: the
        internal rows of the rail channels (moving rows S(t) of ``coupling``'s contacts, summed over
        components like the bridge channels)."""
        local = {int(gi): j for j, gi in enumerate(run.comp.coords)}
        block = run.ops.bridge_block  # a coupled bridge block's state is in its basis (.coupled)
        self.orders = []
        for o in range(3):
            pairs = [(i, local[g]) for i, g, oo in cm.node if oo == o and g in local]
            if block is not None and block.T is not None and any(j < run.nb for _, j in pairs):
                raise NotImplementedError("a node channel on a coupled bridge block's coordinate")
            if like is None:
                start = len(order)
                order.extend(i for i, _ in pairs)
                end = len(order)
            else:
                start, end = like.orders[o][:2]
            node_loc = np.array([j for _, j in pairs], dtype=np.int64)
            items = [(bridge_rows[i], s[run.modes] if block is None else block.to_basis(s[run.modes]))
                     for i, s, oo in cm.bridge if oo == o and np.any(s[run.modes] != 0)]
            brows = np.array([r for r, _ in items], dtype=np.int64)
            shapes = np.array([s for _, s in items]).reshape(len(items), run.nb)
            self.orders.append((start, end, node_loc, brows, shapes))
        #: the rail channels over this component's modes: their internal rows, contacts (axle, rail offset,
        #: direction: :func:`~tb_exudyn.system.channels.rail_under`) and orders
        rail = [(rail_rows[i], c, o) for i, c, o in cm.rail] if rail_rows and run.nb else []
        self.rail = None
        if rail:
            c = np.array([c for _, c, _ in rail], dtype=np.int64)
            lay = coupling.contacts
            self.rail = (np.array([r for r, _, _ in rail], dtype=np.int64), np.array([o for _, _, o in rail]),
                         SimpleNamespace(axle=lay.axle[c], direction=np.asarray(lay.direction)[c],
                                         rail_offset=np.broadcast_to(np.asarray(lay.rail_offset, dtype=float),
                                                                     lay.axle.shape)[c]))
        rowpos = {int(r): j for j, r in enumerate(run.rows)}
        pairs = [(contact_rows[i], rowpos[r]) for i, r in cm.contact if r in rowpos]
        self.contact = (np.array([i for i, _ in pairs], dtype=np.int64),
                        np.array([j for _, j in pairs], dtype=np.int64))
        n = overlap[np.ix_(run.rows[self.contact[1]], run.cols)].astype(float)
        self.shared = (n - 1.0) / np.maximum(n, 1.0) if np.any(n > 1) else None
        self.x = np.zeros((3, *run.QP.shape), dtype=run.QP.dtype)  # (q, v, qdd) of the component
        self.same = run.QP.dtype == np.float64  # node channels gathered straight into Y
        self._kargs: tuple[tuple, tuple] | None = None  # write_compiled's tables, built on first use

    def write_compiled(self, run: Any, Y: ComplexArray, ga: GeneralizedAlpha) -> None:
        """:meth:`write` (not the first output) by the compiled step's :func:`.compiled.write_outputs`, for
        a run whose columns are contiguous (else :meth:`write`): no (q, v, qdd) copies of the state, only
        the rows the channels read."""
        if self.rail is not None:  # pragma: no cover - a coupled bridge block (a track) is never compiled (.loop)
            raise NotImplementedError("rail channels in the compiled step")
        if not isinstance(run.sel, slice):
            self.write(run, Y, ga, False)
            return
        if self._kargs is None:
            self._kargs = self._compiled_tables(run, ga)
        head, tail = self._kargs
        run.kwrite(*head, run.QP, run.VP, run.DL, run.F, run.R, *tail[:2], Y.view(np.float64), 2 * run.sel.start,
                   *tail[2:])

    def _compiled_tables(self, run: Any, ga: GeneralizedAlpha) -> tuple[tuple, tuple]:
        """The arguments of :func:`.compiled.write_outputs` that stay: the BLAS scratch of float64 and
        the channels' tables (module docstring of :mod:`.compiled`)."""
        dt = run.QP.dtype
        nodes = [(o, s + i, int(r)) for o, (s, e, loc, _, _) in enumerate(self.orders) if e > s for i, r in enumerate(loc)]
        btab = np.zeros((3, 3), dtype=np.int64)
        parts, rows, size, nrow = [], [], 0, 0
        for o, (_, _, _, brows, shapes) in enumerate(self.orders):
            btab[o] = (size, brows.size, nrow)
            if brows.size:
                parts.append(np.ascontiguousarray(shapes, dtype=np.float64).reshape(-1))
                rows.append(brows)
                size, nrow = size + shapes.size, nrow + brows.size
        nb, w = max(run.nb, 1), run.QP.shape[1]
        crows, cloc = self.contact
        head = blas_scratch(np.dtype(np.float64))
        tail = (np.array([ga.gamma_p], dtype=dt), np.array([ga.beta_p], dtype=dt),
                np.array(nodes, dtype=np.int64).reshape(-1, 3), btab,
                np.concatenate(rows).astype(np.int64) if rows else np.zeros(1, dtype=np.int64),
                np.concatenate(parts) if parts else np.zeros(1),
                np.ascontiguousarray(crows, dtype=np.int64), np.ascontiguousarray(cloc, dtype=np.int64),
                np.ascontiguousarray(self.shared) if self.shared is not None else np.zeros((crows.size, w // 2)),
                self.shared is not None, np.zeros((nb, w)), np.zeros((max(int(btab[:, 1].max()), 1), w)))
        return head, tail

    def write(self, run: Any, Y: ComplexArray, ga: GeneralizedAlpha, first: bool, rails: Any = None) -> None:
        """Write (node channels) or add (bridge, contact, rail) the component's part at this output time;
        ``rails``: the rail shapes at the axles at this step (n_axles, 6, nb) of the component's modes (its
        step block's, :func:`.steps.step_block`; None while no axle is on the body: the rail channels 0)."""
        Yf = Y.view(np.float64)
        x = self.x  # (q, v, qdd) of the component: q~ + D, v~ + gamma' D, beta' D
        if first:
            x[:2] = 0.0
            x[2] = run.qdd0
        else:
            np.add(run.QP, run.DL, out=x[0])
            np.multiply(run.DL, ga.gamma_p, out=x[1])
            x[1] += run.VP
            np.multiply(run.DL, ga.beta_p, out=x[2])
        sel = run.sel
        whole = isinstance(sel, slice) and sel.start == 0 and sel.stop == Y.shape[1]
        real = slice(2 * sel.start, 2 * sel.stop) if isinstance(sel, slice) else None
        for o, (s, e, loc, brows, shapes) in enumerate(self.orders):
            if e > s:
                if whole and self.same:
                    np.take(x[o], loc, axis=0, out=Yf[s:e])
                elif real is not None:
                    Yf[s:e, real] = x[o][loc]
                else:
                    Y[s:e, sel] = x[o][loc].view(run.cdtype)
            if brows.size:
                _add(Y, brows, run.sel, np.ascontiguousarray(shapes @ x[o][: run.nb]).view(np.complex128))
        if self.rail is not None and rails is not None:  # the rail under each wheel now (.rail_under)
            rows, orders, contacts = self.rail
            S = rail_under(contacts, rails[:, 0], rails[:, 1], rails[:, 2])
            block = run.ops.bridge_block
            if block is not None and not run.ops.rails_in_basis:  # as the step's rows (.run._Operators.prepare)
                S = block.to_basis(S)
            for o in np.unique(orders):
                pick = orders == o
                _add(Y, rows[pick], run.sel, np.ascontiguousarray(S[pick] @ x[o][: run.nb]).view(np.complex128))
        rows, loc = self.contact
        if rows.size:
            f = run.F[loc].view(run.cdtype)
            _add(Y, rows, run.sel, f if self.shared is None else f - self.shared * run.R[loc])


def _add(Y: ComplexArray, rows: IntArray, sel: Any, values: ComplexArray) -> None:
    if isinstance(sel, slice):
        Y[rows, sel] += values
    else:
        Y[np.ix_(rows, sel)] += values


__all__ = ["_Outputs"]
