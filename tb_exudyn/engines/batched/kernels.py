"""BLAS kernels of the batched engine: in-place products, small inverses, the fused step update.

Complex columns are computed on their float64 view (real BLAS); products accumulate in place
(dgemm with beta = 1, no temporaries); the corrector of a step and the predictor of the next are
seven in-place BLAS level-1 updates of (q~, v~, a~) by Delta."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy.linalg import lapack
from scipy.linalg.blas import daxpy, dgemm, dscal

FloatArray = NDArray[np.float64]


def _acc(out: FloatArray, a: FloatArray, b: FloatArray, alpha: float = 1.0) -> None:
    """out += alpha a @ b in place: dgemm with beta = 1 on the transposed (Fortran-ordered) views,
    no temporary. ``out`` and ``b`` are C-contiguous row blocks, ``a`` is C-contiguous."""
    if out.size and a.shape[1]:
        dgemm(alpha, b.T, a.T, beta=1.0, c=out.T, overwrite_c=1)


def _inv(H: FloatArray) -> FloatArray:
    """Inverse of a small general matrix (LAPACK getrf/getri)."""
    lu, piv, info = lapack.dgetrf(H)
    if info == 0:
        inv, info = lapack.dgetri(lu, piv)
    if info != 0:
        raise np.linalg.LinAlgError("singular contact matrix in the batched engine")
    return np.ascontiguousarray(inv)


def advance(coef: tuple[float, ...], h: float, qp: FloatArray, vp: FloatArray, ap: FloatArray, dl: FloatArray) -> None:
    """Corrector of a step fused with the predictor of the next, in place on flat views (see
    :meth:`~tb_exudyn.engines.alpha.GeneralizedAlpha.update_coefficients`)."""
    nu_a, nu_d, rho_a, rho_d, mu_a, mu_d = coef
    daxpy(vp, qp, a=h)
    daxpy(ap, qp, a=nu_a)
    daxpy(dl, qp, a=nu_d)
    daxpy(ap, vp, a=rho_a)
    daxpy(dl, vp, a=rho_d)
    dscal(mu_a, ap)
    daxpy(dl, ap, a=mu_d)


__all__ = ["_acc", "_inv", "advance"]
