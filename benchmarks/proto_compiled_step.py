"""Feasibility of a compiled step: the batched engine's step on the reference study's shapes, as
per-step numpy/BLAS calls (like engines/batched/run.py) and as one compiled loop over the steps.

The prototype that led to the compiled step now in the package (engines/batched/compiled.py,
docs/speed.md section 6); kept for its measurements. Not run by the tests:

    OPENBLAS_NUM_THREADS=1 python benchmarks/proto_compiled_step.py 600 480

Problem: one chunk of W real columns (480 = the 240 complex columns of a reference-study task),
52 bridge modes, 4 vehicles of 27 coordinates in dense blocks of 17 and 10, 12 contact rows per
vehicle, every vehicle on the bridge (the costliest step): the products of the Woodbury step (the
vehicles' J_q, J_v, the bridge's L_q, L_v, the contact inverse, S^a / diag A0, the vehicles' blocks
and A0^-1 G^a^T) and the generalized-alpha update. Synthetic operators (random, small, so that the
state stays bounded over T steps); the two versions must agree to round-off (printed). The compiled
loop calls BLAS dgemm through scipy's cython_blas (in place, beta = 1) and fuses the update into one
pass. Prints the median of 5 runs of T steps and the rate of the step's flops.

Measured on the project's 2-core machine (2026-12-02, Numba 0.68.1, load about 1), us per step:

    W      numpy calls     compiled loop    ratio    (compile: 4.8 s per process)
    240    300 (27 GFlop/s)  166 (48 GFlop/s)  1.8
    480    696 (23 GFlop/s)  435 (37 GFlop/s)  1.6
    960   1491 (22 GFlop/s)  921 (35 GFlop/s)  1.6
"""
import ctypes
import sys
import time

import numpy as np
from numba import njit
from numba.extending import get_cython_function_address
from scipy.linalg.blas import daxpy, dgemm, dscal

T = int(sys.argv[1]) if len(sys.argv) > 1 else 600
W = int(sys.argv[2]) if len(sys.argv) > 2 else 480
NB, NV, VSZ, ROWS = 52, 4, 27, 12
BLOCKS = ((0, 17), (17, 27))
N, M = NB + NV * VSZ, NV * ROWS
rng = np.random.default_rng(1)


def op(r, c, s=0.01):
    return np.ascontiguousarray(rng.standard_normal((r, c)) * s)


Lq, Lv, SaS, Hinv = op(M, NB), op(M, NB), op(M, NB), op(M, M, 0.02)
Jq, Jv, Gi = [op(ROWS, VSZ) for _ in range(NV)], [op(ROWS, VSZ) for _ in range(NV)], [op(VSZ, ROWS) for _ in range(NV)]
Pk = [[op(b1 - b0, b1 - b0) for b0, b1 in BLOCKS] for _ in range(NV)]
Pd = [[op(b1 - b0, b1 - b0) for b0, b1 in BLOCKS] for _ in range(NV)]
pk, pd = rng.random(NB)[:, None] * 0.01, rng.random(NB)[:, None] * 0.01
coef = (1e-6, 1.0, 0.5e-3, 1.0, -0.3, 0.5)
h = 1e-3
Fin = op(M, W, 1.0)


def state():
    return [np.ascontiguousarray(rng.standard_normal((N, W)) * 1e-3) for _ in range(4)]


# ------------------------------------------------------------------ (a) numpy, per-step calls
def gemm_acc(out, a, b, alpha=1.0, beta=1.0):
    dgemm(alpha, b.T, a.T, beta, out.T, 0, 0, 1)


def run_numpy(QP, VP, AP, DL, G, F, tmp):
    nu_a, nu_d, rho_a, rho_d, mu_a, mu_d = coef
    n = QP.size
    qf, vf, af, df = (X.reshape(-1) for X in (QP, VP, AP, DL))
    for _ in range(T):
        G[:] = Fin
        np.multiply(QP[:NB], -pk, out=DL[:NB])
        np.multiply(VP[:NB], pd, out=tmp)
        DL[:NB] -= tmp
        for j in range(NV):
            v0, r0 = NB + j * VSZ, j * ROWS
            gemm_acc(G[r0:r0 + ROWS], Jq[j], QP[v0:v0 + VSZ])
            gemm_acc(G[r0:r0 + ROWS], Jv[j], VP[v0:v0 + VSZ])
        gemm_acc(G, Lq, QP[:NB])
        gemm_acc(G, Lv, VP[:NB])
        F.fill(0.0)
        gemm_acc(F, Hinv, G)
        dgemm(-1.0, F.T, SaS.T, 1.0, DL[:NB].T, 0, 1, 1)  # DL_b -= SaS^T F
        for j in range(NV):
            v0, r0 = NB + j * VSZ, j * ROWS
            for (b0, b1), A, B in zip(BLOCKS, Pk[j], Pd[j]):
                gemm_acc(DL[v0 + b0:v0 + b1], A, QP[v0 + b0:v0 + b1], -1.0, 0.0)
                gemm_acc(DL[v0 + b0:v0 + b1], B, VP[v0 + b0:v0 + b1], -1.0)
            gemm_acc(DL[v0:v0 + VSZ], Gi[j], F[r0:r0 + ROWS])
        daxpy(vf, qf, n, h)
        daxpy(af, qf, n, nu_a)
        daxpy(df, qf, n, nu_d)
        daxpy(af, vf, n, rho_a)
        daxpy(df, vf, n, rho_d)
        dscal(mu_a, af)
        daxpy(df, af, n, mu_d)


# ------------------------------------------------------------------ (b) one compiled loop
_p = ctypes.c_void_p
_ftype = ctypes.CFUNCTYPE(None, _p, _p, _p, _p, _p, _p, _p, _p, _p, _p, _p, _p, _p)
_dgemm = _ftype(get_cython_function_address("scipy.linalg.cython_blas", "dgemm"))


@njit(cache=False)
def _gemm(out, a, b, alpha, beta, ta, buf_i, buf_d, cN, cT):
    """out (r x w) = alpha op(a) @ b + beta out, C order: column-major out^T = b^T op(a)^T."""
    r, w = out.shape
    k = b.shape[0]
    buf_i[0] = w
    buf_i[1] = r
    buf_i[2] = k
    buf_i[3] = w  # ldb (b^T: w x k, ld w)
    buf_i[4] = a.shape[1]  # lda of a^T (k x r when ta = 0: a is r x k, ld k; ta = 1: a is k x r, ld r)
    buf_i[5] = w  # ldc
    buf_d[0] = alpha
    buf_d[1] = beta
    _dgemm(cN.ctypes, cT.ctypes if ta else cN.ctypes, buf_i[0:].ctypes, buf_i[1:].ctypes, buf_i[2:].ctypes,
           buf_d[0:].ctypes, b.ctypes, buf_i[3:].ctypes, a.ctypes, buf_i[4:].ctypes, buf_d[1:].ctypes, out.ctypes,
           buf_i[5:].ctypes)


@njit(cache=False)
def run_numba(QP, VP, AP, DL, G, F, Fin, Lq, Lv, SaS, Hinv, Jq, Jv, Gi, Pk, Pd, pk, pd, coef, h, T, buf_i, buf_d, cN, cT):
    nu_a, nu_d, rho_a, rho_d, mu_a, mu_d = coef[0], coef[1], coef[2], coef[3], coef[4], coef[5]
    n, w = QP.shape
    for _ in range(T):
        G[:, :] = Fin
        for i in range(NB):
            for c in range(w):
                DL[i, c] = -pk[i, 0] * QP[i, c] - pd[i, 0] * VP[i, c]
        for j in range(NV):
            v0, r0 = NB + j * VSZ, j * ROWS
            _gemm(G[r0:r0 + ROWS], Jq[j], QP[v0:v0 + VSZ], 1.0, 1.0, 0, buf_i, buf_d, cN, cT)
            _gemm(G[r0:r0 + ROWS], Jv[j], VP[v0:v0 + VSZ], 1.0, 1.0, 0, buf_i, buf_d, cN, cT)
        _gemm(G, Lq, QP[:NB], 1.0, 1.0, 0, buf_i, buf_d, cN, cT)
        _gemm(G, Lv, VP[:NB], 1.0, 1.0, 0, buf_i, buf_d, cN, cT)
        _gemm(F, Hinv, G, 1.0, 0.0, 0, buf_i, buf_d, cN, cT)
        _gemm(DL[:NB], SaS, F, -1.0, 1.0, 1, buf_i, buf_d, cN, cT)
        for j in range(NV):
            v0, r0 = NB + j * VSZ, j * ROWS
            _gemm(DL[v0:v0 + 17], Pk[j][0], QP[v0:v0 + 17], -1.0, 0.0, 0, buf_i, buf_d, cN, cT)
            _gemm(DL[v0:v0 + 17], Pd[j][0], VP[v0:v0 + 17], -1.0, 1.0, 0, buf_i, buf_d, cN, cT)
            _gemm(DL[v0 + 17:v0 + 27], Pk[j][1], QP[v0 + 17:v0 + 27], -1.0, 0.0, 0, buf_i, buf_d, cN, cT)
            _gemm(DL[v0 + 17:v0 + 27], Pd[j][1], VP[v0 + 17:v0 + 27], -1.0, 1.0, 0, buf_i, buf_d, cN, cT)
            _gemm(DL[v0:v0 + VSZ], Gi[j], F[r0:r0 + ROWS], 1.0, 1.0, 0, buf_i, buf_d, cN, cT)
        for i in range(n):  # the corrector and the next predictor, one pass
            for c in range(w):
                q, v, a, d = QP[i, c], VP[i, c], AP[i, c], DL[i, c]
                QP[i, c] = q + h * v + nu_a * a + nu_d * d
                VP[i, c] = v + rho_a * a + rho_d * d
                AP[i, c] = mu_a * a + mu_d * d


def median_time(fn, reps=5):
    ts = []
    for _ in range(reps):
        X = state()
        G, F, tmp = np.zeros((M, W)), np.zeros((M, W)), np.zeros((NB, W))
        t = time.perf_counter()
        fn(*X, G, F, tmp)
        ts.append(time.perf_counter() - t)
    return float(np.median(ts))


if __name__ == "__main__":
    from numba.typed import List
    Jq_t, Jv_t, Gi_t = List(Jq), List(Jv), List(Gi)
    Pk_t = List([List(p) for p in Pk])
    Pd_t = List([List(p) for p in Pd])
    buf_i, buf_d = np.zeros(8, dtype=np.int32), np.zeros(4)
    cN, cT = np.frombuffer(b"N\0", dtype=np.uint8).copy(), np.frombuffer(b"T\0", dtype=np.uint8).copy()
    carr = np.array(coef)

    def nb(QP, VP, AP, DL, G, F, tmp):
        run_numba(QP, VP, AP, DL, G, F, Fin, Lq, Lv, SaS, Hinv, Jq_t, Jv_t, Gi_t, Pk_t, Pd_t, pk, pd, carr, h, T,
                  buf_i, buf_d, cN, cT)

    t = time.perf_counter()
    X = state()
    nb(*X, np.zeros((M, W)), np.zeros((M, W)), np.zeros((NB, W)))
    print(f"numba compile + first run: {time.perf_counter() - t:.2f} s")
    # the same result from both (a check that the compiled step is the numpy one)
    X1, X2 = state(), None
    X2 = [x.copy() for x in X1]
    G1, F1, G2, F2 = np.zeros((M, W)), np.zeros((M, W)), np.zeros((M, W)), np.zeros((M, W))
    run_numpy(*X1, G1, F1, np.zeros((NB, W)))
    nb(*X2, G2, F2, None)
    err = max(float(np.abs(a - b).max() / max(np.abs(a).max(), 1e-300)) for a, b in zip(X1, X2))
    print(f"max relative difference numpy vs numba after {T} steps: {err:.2e}")
    flops = 2 * W * (2 * NV * ROWS * VSZ * 2 / 2 + 2 * M * NB + M * M + NB * M
                     + NV * (2 * (17 * 17 + 10 * 10) + VSZ * ROWS)) * T
    for name, fn in (("numpy per-step calls", run_numpy), ("numba one loop", nb)):
        s = median_time(fn)
        print(f"{name:22s}: {s:.3f} s for {T} steps = {1e6 * s / T:.0f} us/step, {flops / s / 1e9:.1f} GFlop/s")
