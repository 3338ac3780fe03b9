"""BLAS kernels of the batched engine: in-place products, small inverses, the fused step update.

Complex columns are computed on their real view (real BLAS) in the run's precision (float64, or
float32 with the engine's ``precision`` option: :data:`PRECISIONS`); products accumulate in place
(gemm with beta = 1 on the transposed, Fortran-ordered views: no temporaries); the corrector of a
step and the predictor of the next are seven in-place BLAS level-1 updates of (q~, v~, a~) by Delta.
"""

from __future__ import annotations

import numpy as np
from typing import Any

from numpy.typing import NDArray
from scipy.linalg import lapack
from scipy.linalg.blas import daxpy, dgemm, dscal, saxpy, sgemm, sscal

FloatArray = NDArray[np.floating]

#: the precisions of a run's state and products: name -> (real dtype, complex dtype)
PRECISIONS: dict[str, tuple[type, type]] = {"float64": (np.float64, np.complex128), "float32": (np.float32, np.complex64)}

_GEMM = {np.dtype(np.float64): dgemm, np.dtype(np.float32): sgemm}
_AXPY = {np.dtype(np.float64): daxpy, np.dtype(np.float32): saxpy}
_SCAL = {np.dtype(np.float64): dscal, np.dtype(np.float32): sscal}


def in_precision(X: np.ndarray, dtype: Any) -> np.ndarray:
    """``X`` as a C-contiguous array of ``dtype`` with the entries that would be subnormal in it set
    to zero: round-off remainders of exact zeros (e.g. 1e-40 in an inverse's block structure)
    become subnormal in float32, and every product with a subnormal operand takes a slow path in
    the CPU (about 2x slower gemm on the reference study)."""
    out = np.ascontiguousarray(X, dtype=dtype)
    if out.real.dtype == np.float64:  # remainders such as 1e-40 are normal in float64: nothing to clear, no pass
        return out
    tiny = np.finfo(out.real.dtype).tiny
    if out.size and np.any((np.abs(out) < tiny) & (out != 0)):
        out = out.copy() if out is X else out
        out[np.abs(out) < tiny] = 0
    return out


def _acc(out: FloatArray, a: FloatArray, b: FloatArray, alpha: float = 1.0) -> None:
    """out += alpha a @ b in place: gemm with beta = 1 on the transposed (Fortran-ordered) views, no
    temporary. ``out`` and ``b`` are C-contiguous row blocks, ``a`` is C-contiguous; all of one dtype."""
    if out.size and a.shape[1]:
        _GEMM[out.dtype](alpha, b.T, a.T, beta=1.0, c=out.T, overwrite_c=1)


def _acc_t(out: FloatArray, a: FloatArray, b: FloatArray, alpha: float = 1.0) -> None:
    """out += alpha a^T @ b in place (``a`` C-contiguous (k, n_out), ``b`` and ``out`` C-contiguous row
    blocks)."""
    if out.size and a.shape[0]:
        _GEMM[out.dtype](alpha, b.T, a.T, beta=1.0, c=out.T, trans_b=1, overwrite_c=1)


def gemm_call(out: FloatArray, a: FloatArray, b: FloatArray, alpha: float = 1.0, beta: float = 1.0,
              trans_a: bool = False) -> tuple[Any, tuple]:
    """The product out = alpha op(a) @ b + beta out (op(a) = a or a^T), prepared once for arrays that
    stay in place: (gemm, positional arguments), called as ``f(*args)`` at every step (a gemm call
    with prepared positional arguments costs a third of one with keywords). ``out`` and ``b`` are
    C-contiguous row blocks, ``a`` C-contiguous; all of one dtype."""
    return _GEMM[out.dtype], (alpha, b.T, a.T, beta, out.T, 0, 1 if trans_a else 0, 1)


def run_calls(calls: list[tuple[Any, tuple]]) -> None:
    """Call every prepared (function, arguments) in order."""
    for f, args in calls:
        f(*args)


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
    axpy, scal = _AXPY[qp.dtype], _SCAL[qp.dtype]
    axpy(vp, qp, a=h)
    axpy(ap, qp, a=nu_a)
    axpy(dl, qp, a=nu_d)
    axpy(ap, vp, a=rho_a)
    axpy(dl, vp, a=rho_d)
    scal(mu_a, ap)
    axpy(dl, ap, a=mu_d)


def advance_calls(coef: tuple[float, ...], h: float, qp: FloatArray, vp: FloatArray, ap: FloatArray, dl: FloatArray
                  ) -> list[tuple[Any, tuple]]:
    """:func:`advance` prepared as calls (:func:`run_calls`) on flat views that stay in place."""
    nu_a, nu_d, rho_a, rho_d, mu_a, mu_d = coef
    axpy, scal = _AXPY[qp.dtype], _SCAL[qp.dtype]
    n = qp.size
    return [(axpy, (vp, qp, n, h)), (axpy, (ap, qp, n, nu_a)), (axpy, (dl, qp, n, nu_d)), (axpy, (ap, vp, n, rho_a)),
            (axpy, (dl, vp, n, rho_d)), (scal, (mu_a, ap)), (axpy, (dl, ap, n, mu_d))]


__all__ = ["PRECISIONS", "in_precision", "_acc", "_acc_t", "_inv", "advance", "advance_calls", "gemm_call", "run_calls"]
