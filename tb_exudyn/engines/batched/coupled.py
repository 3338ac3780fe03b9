"""A coupled bridge block in the batched engine: a component whose bridge coordinates are coupled in M,
K0 or D0 (a track's modes, whose pads' and ballast's damping Phi^T C Phi is not diagonal:
:attr:`tb_exudyn.system.components.Component.coupled`).

The block is constant (the supports are fixed in space; only the contacts move, and they stay the
low-rank part solved by Woodbury in :mod:`.run`). Its step is Delta_b = -P_k q~_b - P_d v~_b - A0_b^-1
S^a(t)^T f with A0_b = beta' M_b + gamma' D0_b + K0_b, P_k = A0_b^-1 K0_b, P_d = A0_b^-1 D0_b. When M_b,
K0_b, D0_b are symmetric (a track's always are), the block is integrated in the basis q_b = T y of the
generalised eigenproblem K0_b t = kappa A0_b t (T^T A0_b T = I, T^T K0_b T = diag(kappa)): there A0_b = I,
P_k = diag(kappa) and P_d = T^T D0_b T, the same step up to round-off with one dense product per step
instead of two; the rail shapes S(t) become S(t) T (tabulated once where the bridge's rail function can:
``_Operators.rails_in_basis``, the track's, with C_b P_d from S(t) T P_d), the generalised forces T^T F and the bridge channels'
station shapes s T. Otherwise (``basis`` False, or a block that is not symmetric) A0_b is inverted once
and both products are dense.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.linalg import eigh

from .kernels import gemm_call, in_precision

FloatArray = NDArray[np.float64]

#: integrate a symmetric coupled block in the basis where P_k is diagonal (module docstring)
DIAGONAL_STIFFNESS_BASIS = True


def _symmetric(X: FloatArray) -> bool:
    return bool(np.all(np.abs(X - X.T) <= 1e-13 * max(float(np.abs(X).max(initial=0.0)), 1e-300)))


def _rows_times(S: FloatArray, X: FloatArray) -> FloatArray:
    """S @ X for a stack of rows S (..., n) as one matrix product (numpy's matmul takes a stack matrix by
    matrix)."""
    return (np.ascontiguousarray(S).reshape(-1, S.shape[-1]) @ X).reshape(*S.shape[:-1], X.shape[1])


class CoupledBridge:
    """The constant operators of a coupled bridge block of ``nb`` coordinates (local rows 0 .. nb - 1 of
    M, K0, D0), in the precision ``dtype`` (module docstring)."""

    def __init__(self, M: FloatArray, K0: FloatArray, D0: FloatArray, nb: int, bp: float, gp: float,
                 dtype: Any, basis: bool | None = None) -> None:
        Mb, Kb, Db = (np.array(X[:nb, :nb], dtype=float) for X in (M, K0, D0))
        A = bp * Mb + gp * Db + Kb
        basis = DIAGONAL_STIFFNESS_BASIS if basis is None else basis
        self.T: FloatArray | None = None
        self.mass = Mb  # M_b in the block's coordinates
        if basis and all(_symmetric(X) for X in (Mb, Kb, Db)):
            kappa, T = eigh(Kb, A)
            self.T, self.mass = T, T.T @ Mb @ T
            self.Pd = T.T @ Db @ T
            self.pk, self.Pk, self.A0b_inv = kappa, None, None
            self.mpk = in_precision(-kappa[:, None], dtype)
        else:
            self.A0b_inv = np.linalg.inv(A)
            self.Pk, self.Pd = self.A0b_inv @ Kb, self.A0b_inv @ Db
            self.pk = None
            self.mPk = in_precision(-self.Pk, dtype)
        self.mPd = in_precision(-self.Pd, dtype)

    def to_basis(self, S: FloatArray) -> FloatArray:
        """Rows over the bridge's coordinates (rail shapes, station shapes: (..., nb)) in the block's basis."""
        return S if self.T is None else _rows_times(S, self.T)

    def force(self, F: FloatArray) -> FloatArray:
        """A generalised force on the bridge (nb, ...) in the block's basis: T^T F."""
        return F if self.T is None else self.T.T @ F

    def solve(self, F: FloatArray) -> FloatArray:
        """A0_b^-1 F for F in the block's basis (where A0_b = I in the eigenbasis)."""
        return F.copy() if self.T is not None else self.A0b_inv @ F

    def row_operators(self, Sa: FloatArray, Sk: FloatArray, Sd: FloatArray, Cb: FloatArray,
                      CbPd: FloatArray | None = None) -> tuple[FloatArray, FloatArray, FloatArray]:
        """(L_q, L_v, S^a A0_b^-T) of the contact rows (..., rows, nb), the shapes in the block's basis:
        L_q = S^k - C_b P_k, L_v = S^d - C_b P_d (C_b = S^k + gamma' S^d); ``CbPd``: C_b P_d given (the
        rails' rows times P_d tabulated once: the engine's ``rails_in_basis``), else the product."""
        Lv = Sd - (_rows_times(Cb, self.Pd) if CbPd is None else CbPd)
        if self.T is not None:
            return Sk - Cb * self.pk, Lv, Sa
        return Sk - _rows_times(Cb, self.Pk), Lv, _rows_times(Sa, self.A0b_inv.T)

    def step_calls(self, QP: FloatArray, VP: FloatArray, DL: FloatArray) -> list[tuple[Any, tuple]]:
        """The bridge's Delta_b = -P_k q~_b - P_d v~_b on the run's bridge rows, prepared
        (:func:`.kernels.run_calls`): a column scaling and a product in the eigenbasis, else two products."""
        if self.T is not None:
            return [(np.multiply, (QP, self.mpk, DL)), gemm_call(DL, self.mPd, VP)]
        return [gemm_call(DL, self.mPk, QP, beta=0.0), gemm_call(DL, self.mPd, VP)]


__all__ = ["DIAGONAL_STIFFNESS_BASIS", "CoupledBridge"]
