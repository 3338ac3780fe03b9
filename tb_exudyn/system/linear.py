"""The linear train-bridge system every linear engine integrates (plain numpy data).

M q'' + D0 q' + K0 q = -B(t)^T f,   f = k (B(t) u + r) + c (B(t) u' + v dS(t) q_b + r'),
u = [q_b; q_w] the coupling's coordinates (bridge modes, wheel coordinates).

M, K0 and D0 are the model without the wheel-rail contact, at the linearization point; the contact
is the coupling's (:class:`~.coupling.WheelRailCoupling`: rail shapes S(t) and slopes dS(t) at the
wheels, gap map B = [S, -G], stiffness k and damping c per contact row), the same object the Exudyn
user functions call. The builder makes it from a built Exudyn model
(:func:`tb_exudyn.builder.linear_system`: Exudyn's ``ComputeLinearizedSystem`` minus the coupling's
own Jacobians at t = 0, when every axle stands on the rigid approach).

Linearization points (``LINEARIZATIONS``): ``"rest"``, the unloaded reference configuration, the
state of the Exudyn engine's pseudo-runs (gravity off, from rest), so that both PEM engines
integrate the same model; ``"static"``, the static equilibrium under gravity on the approach, where K
also holds the geometric stiffness of the suspensions' preload (the car body's weight acting above
its springs lowers its roll stiffness by m g h). The Exudyn model with gravity has that stiffness, so
the Exudyn Monte Carlo agrees with "static".
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

#: linearization points of the linear model (see the module docstring)
LINEARIZATIONS: tuple[str, ...] = ("rest", "static")

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]


@dataclass(frozen=True, eq=False)
class LinearSystem:
    """M, K0, D0 (contact left out) and the contact of a train-bridge model.

    Attributes
    ----------
    M, K0, D0 : (n, n) global matrices without the contact, at the linearization point
    bridge : (n_b,) global indices of the bridge's modal coordinates (the coupling's q_b)
    wheel : (n_w,) global indices of the coupling's wheel coordinates (its q_w)
    k, c : (n_c,) contact stiffness and damping; G (n_c, n_w) the wheel map
    coupling : the wheel-rail coupling (S(t), dS(t), the axle positions and the input map)
    linearization : "rest" or "static"
    """

    M: FloatArray
    K0: FloatArray
    D0: FloatArray
    bridge: IntArray
    wheel: IntArray
    k: FloatArray
    c: FloatArray
    G: FloatArray
    coupling: Any
    linearization: str

    @property
    def n(self) -> int:
        return int(self.M.shape[0])


def without_block(A: FloatArray, Ac: FloatArray, ci: IntArray) -> FloatArray:
    """A with the block Ac removed on the indices ci; round-off of the subtraction (below 1e-13 of
    the entries involved) set to exact zero."""
    out = np.array(A, dtype=float, copy=True)
    block = out[np.ix_(ci, ci)] - Ac
    noise = 1e-13 * (np.abs(out[np.ix_(ci, ci)]) + np.abs(Ac))
    block[np.abs(block) <= noise] = 0.0
    out[np.ix_(ci, ci)] = block
    return out


__all__ = ["LINEARIZATIONS", "LinearSystem", "without_block"]
