"""Where a component's state goes at an output time (the batched engine's channel evaluation).

The channels come from the engine's :class:`~tb_exudyn.system.channels.OutputMap` (the same map of
node coordinates, bridge station shapes and contact rows that defines the channels of an Exudyn
recording).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..alpha import GeneralizedAlpha

ComplexArray = NDArray[np.complex128]
IntArray = NDArray[np.int64]


class _Outputs:
    """Where a component's state goes at an output time, in an internal channel order that makes
    its node channels of one order a contiguous block of rows (written without scatter): row
    gathers of (q, v, qdd), station-shape products over its modes (bridge channels, summed over
    components) and its contact forces. With components sharing a contact row, each one's force
    f_I = k (B_I u_I + r) + c (...) carries the input k r + c r' once: the true force is
    sum_I f_I - (n - 1) (k r + c r') for n components integrating that column."""

    def __init__(self, cm: Any, run: Any, overlap: NDArray[np.int64], order: list[int],
                 bridge_rows: dict[int, int], contact_rows: dict[int, int]) -> None:
        local = {int(gi): j for j, gi in enumerate(run.comp.coords)}
        self.node = []
        for o in range(3):
            pairs = [(i, local[g]) for i, g, oo in cm.node if oo == o and g in local]
            start = len(order)
            order.extend(i for i, _ in pairs)
            self.node.append((start, len(order), np.array([j for _, j in pairs], dtype=np.int64)))
        self.bridge = []
        for o in range(3):
            items = [(bridge_rows[i], s[run.modes]) for i, s, oo in cm.bridge if oo == o and np.any(s[run.modes] != 0)]
            self.bridge.append((np.array([r for r, _ in items], dtype=np.int64),
                                np.array([s for _, s in items]).reshape(len(items), run.nb)))
        rowpos = {int(r): j for j, r in enumerate(run.rows)}
        pairs = [(contact_rows[i], rowpos[r]) for i, r in cm.contact if r in rowpos]
        self.contact = (np.array([i for i, _ in pairs], dtype=np.int64),
                        np.array([j for _, j in pairs], dtype=np.int64))
        n = overlap[np.ix_(run.rows[self.contact[1]], run.cols)].astype(float)
        self.shared = (n - 1.0) / np.maximum(n, 1.0) if np.any(n > 1) else None
        self.x = np.zeros((3, *run.QP.shape))

    def write(self, run: Any, Y: ComplexArray, ga: GeneralizedAlpha, first: bool) -> None:
        """Write (node channels) or add (bridge, contact) the component's part at this output time."""
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
        all_cols = isinstance(run.sel, slice)
        for o, (s, e, loc) in enumerate(self.node):
            if e > s:
                if all_cols:
                    np.take(x[o], loc, axis=0, out=Yf[s:e])
                else:
                    Y[s:e, run.sel] = x[o][loc].view(complex)
        for o, (rows, shp) in enumerate(self.bridge):
            if rows.size:
                _add(Y, rows, run.sel, (shp @ x[o][: run.nb]).view(complex))
        rows, loc = self.contact
        if rows.size:
            f = run.F[loc].view(complex)
            _add(Y, rows, run.sel, f if self.shared is None else f - self.shared * run.R[loc])


def _add(Y: ComplexArray, rows: IntArray, sel: Any, values: ComplexArray) -> None:
    if isinstance(sel, slice):
        Y[rows] += values
    else:
        Y[np.ix_(rows, sel)] += values
