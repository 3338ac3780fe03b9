"""What every component's step needs from the time alone, for a block of steps at once.

The axle positions, which axles are on the bridge, the approach taper w, w' and the rail shapes of
every axle (:class:`~tb_exudyn.structure.modal.RailShapes` rows in the order of
:data:`~tb_exudyn.system.coupling.RAIL_SHAPE_ROWS`) are evaluated for ``BLOCK_STEPS`` steps in
one vectorised call each, instead of once per step: per step only the products with the columns
remain (:mod:`.run`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable

import numpy as np
from numpy.typing import NDArray

from ...structure.fe import RailShapeEvaluator
from ...structure.modal import RailShapes
from ...system.coupling import RAIL_SHAPE_ROWS
from ...system.excitation import taper

FloatArray = NDArray[np.float64]

#: steps whose time-only data are evaluated at once (bounds the block's arrays to about 1 MB)
BLOCK_STEPS = 16


@dataclass(frozen=True)
class StepBlock:
    """Steps n0 .. n0 + T - 1 (times t = n h).

    Attributes
    ----------
    n0 : the first step's number
    t : (T,) times [s]
    x : (T, n_axles) axle positions [m]
    on : (T, n_axles) whether each axle is on the bridge (on the body's rail: ``bridge.carries``)
    w, dw : (T, n_axles) the approach taper and its slope along x [1/m]
    steady : (T,) w = 1 and w' = 0 at every axle;  zero : (T,) w = w' = 0 at every axle
    rails : per set of modes (a key of :func:`step_block`'s ``shapes``), (T, n_axles, 6, n_modes):
        the rail shapes (rows RAIL_SHAPE_ROWS) at the axles, zero off the bridge; empty when no axle
        is on the bridge during the block
    """

    n0: int
    t: FloatArray
    x: FloatArray
    on: NDArray[np.bool_]
    w: FloatArray
    dw: FloatArray
    steady: NDArray[np.bool_]
    zero: NDArray[np.bool_]
    rails: dict[Any, FloatArray]

    @property
    def size(self) -> int:
        return int(self.t.size)


def mode_shapes(bridge: Any, modes: NDArray[np.int64]) -> Callable[[FloatArray], RailShapes]:
    """The bridge's rail shapes of the modes ``modes`` only, as a callable x -> RailShapes: the
    finite-element evaluator restricted to those modes' coefficients, else the full evaluation."""
    modes = np.asarray(modes, dtype=np.int64)
    fn = bridge.rail_shape_function
    if np.array_equal(modes, np.arange(bridge.n_modes)):
        return bridge.rail_shapes
    if isinstance(fn, RailShapeEvaluator):
        n = fn.n_modes
        cols = np.concatenate([c * n + modes for c in range(3)])
        sub = RailShapeEvaluator(fn.bounds, fn.x_start, fn.inv_length, np.ascontiguousarray(fn.coefficients[:, :, cols]),
                                 fn.length, int(modes.size))
        return lambda x: sub(np.atleast_1d(np.asarray(x, dtype=float)))

    def shapes(x: FloatArray) -> RailShapes:
        rs = bridge.rail_shapes(x)
        return RailShapes(*(getattr(rs, name)[:, modes] for name in ("y", "z", "rx", "dy", "dz", "drx")))

    return shapes


def step_block(coupling: Any, n0: int, n1: int, h: float, shapes: dict[Any, Callable[[FloatArray], RailShapes]]
               ) -> StepBlock:
    """The time-only data of steps n0 <= n < n1 (t = n h) for ``coupling``; the rail shapes by each
    of ``shapes`` (key -> callable x -> RailShapes, :func:`mode_shapes`)."""
    t = np.arange(n0, n1) * h
    x = np.stack([coupling.positions(float(tk)) for tk in t])  # the coupling's one convention for x(t)
    on = coupling.bridge.carries(x)  # the bridge, or the track's whole extent (ModalBridge.rail_extent)
    w, dw = taper(x, float(coupling.axle_start[0]), coupling.taper_length)
    rails: dict[Any, FloatArray] = {}
    if on.any():
        xs = x[on]  # only where an axle is on the bridge: zero elsewhere
        for key, fn in shapes.items():
            rs = fn(xs)
            n_m = rs.y.shape[1]
            r = np.zeros((t.size, x.shape[1], len(RAIL_SHAPE_ROWS), n_m))
            flat = r.reshape(-1, len(RAIL_SHAPE_ROWS), n_m)
            where = np.flatnonzero(on.reshape(-1))
            for j, name in enumerate(RAIL_SHAPE_ROWS):
                flat[where, j] = getattr(rs, name)
            rails[key] = r
    steady = np.all((w == 1.0) & (dw == 0.0), axis=1)
    zero = ~np.any((w != 0.0) | (dw != 0.0), axis=1)
    return StepBlock(n0, t, x, on, w, dw, steady, zero, rails)


__all__ = ["BLOCK_STEPS", "StepBlock", "mode_shapes", "step_block"]
