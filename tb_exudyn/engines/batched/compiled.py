"""The compiled step of the batched engine (Numba): a run's steps of a block in one call.

The same step as :meth:`.run._Run.solve` and :meth:`.run._Run.update` for harmonic (PEM) columns and
the linear mean's gravity column (a constant input and generalised force): the inputs f_in, the
bridge's diagonal terms, the Woodbury products and the contact solve, the vehicles' products on and
off the bridge (their forces at output steps) and the generalized-alpha update, but
without a Python call per product: every product is the same BLAS gemm (scipy's BLAS through its address,
:func:`tb_exudyn.jit.blas_pointers`) on the same arrays in the same order, and the update the numpy step's
seven axpy / scal passes fused into one loop, so the state it leaves is the numpy step's to round-off
(the inputs' complex products are formed in compiled code; tests/engines/test_compiled_step.py). A call runs the steps k0 .. k1 - 1 of the block
and returns at the first output step (before its update, so that the outputs see that step's Delta),
or k1.

Arrays are C-contiguous; a matrix's place is an offset into a flat array and its leading dimension
(the operator tables of :class:`.run._Operators`). Import through :func:`tb_exudyn.jit.load` (Numba's cache
directory is set there).
"""

from __future__ import annotations

import numba
import numpy as np
from llvmlite import ir
from numba import njit, types
from numba.extending import intrinsic

#: cache on disk only in the directory tb_exudyn.jit.load points Numba at (never next to this file: with
#: no directory set, or one that cannot be written, the functions are compiled in memory)
CACHE = bool(numba.config.CACHE_DIR)


def _pointer_call(n: int):  # noqa: ANN202
    """Code generation of a call of the C function whose address is the first argument with ``n``
    pointer arguments given as integers (Fortran BLAS takes every argument by reference)."""

    def codegen(context, builder, signature, args):  # noqa: ANN001, ANN202
        i8p = ir.IntType(8).as_pointer()
        f = builder.inttoptr(args[0], ir.FunctionType(ir.VoidType(), [i8p] * n).as_pointer())
        builder.call(f, [builder.inttoptr(a, i8p) for a in args[1:]])
        return context.get_dummy_value()

    return codegen


@intrinsic
def _call13(typingctx, fn, a1, a2, a3, a4, a5, a6, a7, a8, a9, a10, a11, a12, a13):  # noqa: ANN001, ANN202
    """fn(a1, ..., a13) with pointer arguments (BLAS gemm)."""
    return types.void(fn, a1, a2, a3, a4, a5, a6, a7, a8, a9, a10, a11, a12, a13), _pointer_call(13)


@njit(cache=CACHE)
def _addr(a, offset):  # noqa: ANN001, ANN202
    """The address of element ``offset`` of the flat array ``a``."""
    return np.int64(a.ctypes.data) + offset * a.itemsize


@njit(cache=CACHE)
def _flags():  # noqa: ANN202
    """gemm's transposition flags ('N': 0, 'T': 1, added to the address of the characters N, T) and a
    zero offset, as int64 values: constants passed as arguments are typed as literals, and each literal
    would compile its own copy of _mm, _gemm and _addr (docs/speed.md section 13)."""
    return np.int64(0), np.int64(1), np.int64(0)


@njit(cache=CACHE)
def _mm(blas, ib, sb, ch, c, ci, a, ai, lda, b, bi, r, k, w, alpha, beta, ta):  # noqa: ANN001, ANN202
    """out (r x w) = alpha op(A) @ B + beta out for row-major (C) arrays: ``out`` starts at flat
    element ``ci`` of ``c``, B (k x w) at ``bi`` of ``b`` (both of leading dimension w), A at ``ai``
    of ``a`` with leading dimension ``lda`` (r x k, or k x r when ``ta`` is 1). As column-major BLAS:
    out^T = B^T op(A)^T (gemm('N', ta ? 'T' : 'N', w, r, k, alpha, B, w, A, lda, beta, out, w)),
    the call :func:`.kernels.gemm_call` prepares."""
    if r == 0 or w == 0:
        return
    if k == 0:
        if beta == 0.0:
            c.reshape(-1)[ci:ci + r * w] = 0.0
        return
    _gemm(blas, ib, sb, ch, _flags()[0], ta, w, r, k, alpha, _addr(b.reshape(-1), bi), w, _addr(a, ai), lda, beta,
          _addr(c.reshape(-1), ci), w)


@njit(cache=CACHE)
def _gemm(blas, ib, sb, ch, ta, tb, m, n, k, alpha, pa, lda, pb, ldb, beta, pc, ldc):  # noqa: ANN001, ANN202
    """Column-major BLAS gemm: C (m x n) = alpha op(A) op(B) + beta C at the addresses pa, pb, pc
    (``ib``, ``sb``: scratch for the arguments passed by reference; ``ch``: the characters N, T;
    ``ta``, ``tb``: 0 for 'N', 1 for 'T', :func:`_flags`)."""
    ib[0] = m
    ib[1] = n
    ib[2] = k
    ib[3] = lda
    ib[4] = ldb
    ib[5] = ldc
    sb[0] = alpha
    sb[1] = beta
    p, s, c = np.int64(ib.ctypes.data), np.int64(sb.ctypes.data), np.int64(ch.ctypes.data)
    _call13(blas[0], c + ta, c + tb, p, p + 4, p + 8, s, pa, p + 12, pb, p + 16,
            s + sb.itemsize, pc, p + 20)


@njit(cache=CACHE, fastmath={"contract"})
def _update(QP, VP, AP, DL, r0, r1, coef):  # noqa: ANN001, ANN202
    """Corrector of a step fused with the predictor of the next on the rows [r0, r1), in one pass over
    the four arrays: the seven BLAS calls of :func:`.kernels.advance` (axpy by h, nu_a, nu_d into q~,
    by rho_a, rho_d into v~, scal by mu_a and axpy by mu_d into a~), in their order per element, each
    product and sum contractible to a fused multiply-add as BLAS' axpy kernels do. The passes read
    and write the state 21 times where this loop does 7: the seven calls cost 138 us against 45 us
    on a 160 x 480 state (2.5 MB, docs/speed.md section 9)."""
    if r1 <= r0:
        return
    i0, i1 = r0 * QP.shape[1], r1 * QP.shape[1]
    # slices indexed from 0: Numba then knows no index is negative and the loop is vectorised
    q, v, a, d = QP.reshape(-1)[i0:i1], VP.reshape(-1)[i0:i1], AP.reshape(-1)[i0:i1], DL.reshape(-1)[i0:i1]
    nu_a, nu_d, rho_a, rho_d, mu_a, mu_d, h = coef[0], coef[1], coef[2], coef[3], coef[4], coef[5], coef[6]
    for i in range(q.size):
        vi, ai, di = v[i], a[i], d[i]
        q[i] = ((q[i] + h * vi) + nu_a * ai) + nu_d * di
        v[i] = (vi + rho_a * ai) + rho_d * di
        a[i] = mu_a * ai + mu_d * di


@njit(cache=CACHE)
def _inputs(k, Gc, Qss, Qd, z, cols, w, dw, steady, zero, axle, zk):  # noqa: ANN001, ANN202
    """f_in of the harmonic columns at step k (:class:`.inputs._HarmonicInputs`):
    (Qss z) w + w' (Qd z) at each row's axle. ``zk``: scratch for the step's z of the columns (gathered
    once, so that the rows' products run over contiguous arrays: 12.8 -> 5.1 us per step at 48 rows x
    230 columns, the same products)."""
    nr, m = Gc.shape
    if zero[k]:
        Gc[:, :] = 0.0
        return
    for j in range(m):
        zk[j] = z[k, cols[j]]
    for r in range(nr):
        for j in range(m):
            Gc[r, j] = Qss[r, j] * zk[j]
    if steady[k]:
        return
    for r in range(nr):
        wr = w[k, axle[r]]
        d = dw[k, axle[r]]
        for j in range(m):
            x = Gc[r, j] * wr
            if d != 0.0:
                x += d * (Qd[r, j] * zk[j])
            Gc[r, j] = x


@njit(cache=CACHE)
def _on_bridge(k, blas, ib, sb, ch, QP, VP, DL, G, F, st, Lq, Lv, SaS, hbuf, hoff, a0, vt, vo, bl, vbuf):  # noqa: ANN001, ANN202
    """The Woodbury step of the vehicles with an axle on the bridge (:meth:`.run._Run.solve`)."""
    keep, trans, origin = _flags()
    w = QP.shape[1]
    nb = Lq.shape[2]
    nrow = Lq.shape[1]
    i, r0, r1, R0, R1, j0, j1 = st[k, 1], st[k, 2], st[k, 3], st[k, 4], st[k, 5], st[k, 6], st[k, 7]
    for j in range(j0, j1):  # g += J_q q~ + J_v v~ of the vehicles
        v0, v1, s0, s1 = vt[j, 0], vt[j, 1], vt[j, 2], vt[j, 3]
        _mm(blas, ib, sb, ch, G, s0 * w, vbuf, vo[j, 0], v1 - v0, QP, v0 * w, s1 - s0, v1 - v0, w, 1.0, 1.0, keep)
        _mm(blas, ib, sb, ch, G, s0 * w, vbuf, vo[j, 1], v1 - v0, VP, v0 * w, s1 - s0, v1 - v0, w, 1.0, 1.0, keep)
    at = (i * nrow + r0 - a0) * nb
    _mm(blas, ib, sb, ch, G, r0 * w, Lq.reshape(-1), at, nb, QP, origin, r1 - r0, nb, w, 1.0, 1.0, keep)
    _mm(blas, ib, sb, ch, G, r0 * w, Lv.reshape(-1), at, nb, VP, origin, r1 - r0, nb, w, 1.0, 1.0, keep)
    F[R0:R1, :] = 0.0  # then beta = 1, as the numpy step
    _mm(blas, ib, sb, ch, F, R0 * w, hbuf, hoff[k], R1 - R0, G, R0 * w, R1 - R0, R1 - R0, w, 1.0, 1.0, keep)
    _mm(blas, ib, sb, ch, DL, origin, SaS.reshape(-1), at, nb, F, r0 * w, nb, r1 - r0, w, -1.0, 1.0, trans)
    for j in range(j0, j1):  # Delta = Y0 + A0^-1 G^a^T f of the vehicles
        for e in range(bl.shape[0]):
            if bl[e, 0] == j:
                b0, b1 = bl[e, 1], bl[e, 2]
                _mm(blas, ib, sb, ch, DL, b0 * w, vbuf, bl[e, 3], b1 - b0, QP, b0 * w, b1 - b0, b1 - b0, w, 1.0, 0.0, keep)
                _mm(blas, ib, sb, ch, DL, b0 * w, vbuf, bl[e, 4], b1 - b0, VP, b0 * w, b1 - b0, b1 - b0, w, 1.0, 1.0, keep)
        v0, v1, s0, s1 = vt[j, 0], vt[j, 1], vt[j, 2], vt[j, 3]
        _mm(blas, ib, sb, ch, DL, v0 * w, vbuf, vo[j, 2], s1 - s0, F, s0 * w, v1 - v0, s1 - s0, w, 1.0, 1.0, keep)


@njit(cache=CACHE)
def _off_bridge(j, record, blas, ib, sb, ch, QP, VP, DL, G, F, vt, vo, fo, vbuf):  # noqa: ANN001, ANN202
    """The folded step of vehicle j off the bridge, and its contact forces when recording."""
    keep, trans, origin = _flags()
    w = QP.shape[1]
    v0, v1, s0, s1 = vt[j, 0], vt[j, 1], vt[j, 2], vt[j, 3]
    for e in range(fo.shape[0]):
        if fo[e, 0] == j:
            b0, b1 = fo[e, 1], fo[e, 2]
            _mm(blas, ib, sb, ch, DL, b0 * w, vbuf, fo[e, 3], b1 - b0, QP, b0 * w, b1 - b0, b1 - b0, w, 1.0, 0.0, keep)
            _mm(blas, ib, sb, ch, DL, b0 * w, vbuf, fo[e, 4], b1 - b0, VP, b0 * w, b1 - b0, b1 - b0, w, 1.0, 1.0, keep)
    _mm(blas, ib, sb, ch, DL, v0 * w, vbuf, vo[j, 3], s1 - s0, G, s0 * w, v1 - v0, s1 - s0, w, 1.0, 1.0, keep)
    if record:
        _mm(blas, ib, sb, ch, G, s0 * w, vbuf, vo[j, 0], v1 - v0, QP, v0 * w, s1 - s0, v1 - v0, w, 1.0, 1.0, keep)
        _mm(blas, ib, sb, ch, G, s0 * w, vbuf, vo[j, 1], v1 - v0, VP, v0 * w, s1 - s0, v1 - v0, w, 1.0, 1.0, keep)
        _mm(blas, ib, sb, ch, F, s0 * w, vbuf, vo[j, 4], s1 - s0, G, s0 * w, s1 - s0, s1 - s0, w, 1.0, 0.0, keep)


@njit(cache=CACHE)
def run_steps(k0, k1, update_first, rec, blas, ib, sb, ch, state, inputs, const, bridge, schedule, vehicles, coef):  # noqa: ANN001, ANN201
    """Steps k0 .. k1 - 1 of a block for one run; returns the first output step (after its solve,
    before its update) or k1. ``update_first``: the update of step k0 - 1 is still to do.

    state = (QP, VP, AP, DL, Gc, G, F, R): the run's arrays (G, the real view of Gc, the contact
    right-hand sides; R, f_in at output steps); inputs = (Qss, Qd, z, cols, w, dw, steady, zero,
    axle); const = (constant, Gs, Gf, Dc): a column source with a constant generalised force on the
    wheels (the linear mean's gravity column, :class:`.run._Run`'s ``force_delta``) instead of harmonic
    inputs where ``constant``: f_in = Gs at every step (no taper), then + Gf (the wheels' part of
    C y_c) and Delta += Dc (y_c) after the vehicles;
    bridge = (pk, pd, st, Lq, Lv, SaS, hbuf, hoff, a0): the bridge's diagonal terms and the
    block's per-step operators (st[k] = has, i, r0, r1, R0, R1, j0, j1); schedule = (n_active,
    moving, rows_end) per step; vehicles = (vt, vo, bl, fo, vbuf); coef = the update's six
    coefficients and h."""
    QP, VP, AP, DL, Gc, G, F, R = state
    Qss, Qd, z, cols, w, dw, steady, zero, axle = inputs
    constant, Gs, Gf, Dc = const
    pk, pd, st, Lq, Lv, SaS, hbuf, hoff, a0 = bridge
    n_active, moving, rows_end = schedule
    vt, vo, bl, fo, vbuf = vehicles
    nb = pk.shape[0]
    zk = np.empty(Gc.shape[1], dtype=z.dtype)
    if update_first:
        _update(QP, VP, AP, DL, 0 if moving[k0 - 1] else nb, rows_end[k0 - 1], coef)
    for k in range(k0, k1):
        if constant:  # element by element: an array assigned to a slice compiles Numba's formatted
            for r in range(Gc.shape[0]):  # shape-mismatch error, seconds of a first run (docs/speed.md section 13)
                for c in range(Gc.shape[1]):
                    Gc[r, c] = Gs[r, c]
        else:
            _inputs(k, Gc, Qss, Qd, z, cols, w, dw, steady, zero, axle, zk)
        if rec[k]:
            for r in range(Gc.shape[0]):
                for c in range(Gc.shape[1]):
                    R[r, c] = Gc[r, c]
        if constant:
            for r in range(Gc.shape[0]):
                for c in range(Gc.shape[1]):
                    Gc[r, c] += Gf[r, c]
        if nb and moving[k]:
            for r in range(nb):
                for c in range(QP.shape[1]):
                    DL[r, c] = QP[r, c] * (-pk[r])
                    DL[r, c] -= VP[r, c] * pd[r]
        j0, j1 = 0, 0
        if st[k, 0]:
            j0, j1 = st[k, 6], st[k, 7]
            _on_bridge(k, blas, ib, sb, ch, QP, VP, DL, G, F, st, Lq, Lv, SaS, hbuf, hoff, a0, vt, vo, bl, vbuf)
        for j in range(n_active[k]):
            if j < j0 or j >= j1:
                _off_bridge(j, rec[k], blas, ib, sb, ch, QP, VP, DL, G, F, vt, vo, fo, vbuf)
        if constant:
            for r in range(DL.shape[0]):
                for c in range(DL.shape[1]):
                    DL[r, c] += Dc[r, c]
        if rec[k]:
            return k
        _update(QP, VP, AP, DL, 0 if moving[k] else nb, rows_end[k], coef)
    return k1





@njit(cache=CACHE)
def _state_value(o, QP, VP, DL, gp, bp, r, j):  # noqa: ANN001, ANN202
    """(q, v, qdd)[o] = (q~ + Delta, v~ + gamma' Delta, beta' Delta) at row r, column j, in the state's
    precision (``gp``, ``bp``: (1,) arrays of the state's dtype)."""
    if o == 0:
        return QP[r, j] + DL[r, j]
    if o == 1:
        return DL[r, j] * gp[0] + VP[r, j]
    return DL[r, j] * bp[0]


@njit(cache=CACHE)
def write_outputs(blas64, ib, sb64, ch, QP, VP, DL, F, R, gp, bp, Yf, c0, nodes, btab, brows, bbuf,
                  crows, cloc, shared, has_shared, xb, tb):  # noqa: ANN001, ANN201
    """A run's part of the outputs at an output step (:meth:`.outputs._Outputs.write` for a run whose
    columns are contiguous, from column c0 of Y's float view ``Yf``): node channels written
    (nodes[i] = order, Y row, local row), bridge channels added (per order o: btab[o] = offset of
    its station shapes in bbuf, their number, offset of their Y rows in brows; the product by gemm
    on the float64 rows of the modes, xb), contact forces added (minus the shared input's repeats)."""
    keep, trans, origin = _flags()
    w = QP.shape[1]
    nb = xb.shape[0]
    for i in range(nodes.shape[0]):
        o, row, r = nodes[i, 0], nodes[i, 1], nodes[i, 2]
        for j in range(w):
            Yf[row, c0 + j] = _state_value(o, QP, VP, DL, gp, bp, r, j)
    for o in range(3):
        n = btab[o, 1]
        if n == 0:
            continue
        for r in range(nb):
            for j in range(w):
                xb[r, j] = _state_value(o, QP, VP, DL, gp, bp, r, j)
        _mm(blas64, ib, sb64, ch, tb, origin, bbuf, btab[o, 0], nb, xb, origin, n, nb, w, 1.0, 0.0, keep)
        for i in range(n):
            row = brows[btab[o, 2] + i]
            for j in range(w):
                Yf[row, c0 + j] += tb[i, j]
    m = w // 2
    for i in range(crows.shape[0]):
        row, r = crows[i], cloc[i]
        for j in range(m):
            re, im = np.float64(F[r, 2 * j]), np.float64(F[r, 2 * j + 1])
            if has_shared:
                re -= shared[i, j] * np.float64(R[r, j].real)
                im -= shared[i, j] * np.float64(R[r, j].imag)
            Yf[row, c0 + 2 * j] += re
            Yf[row, c0 + 2 * j + 1] += im



@njit(cache=CACHE)
def contact_inverses(blas64, ib, sb64, ch, row_vehicle, vrows, steps, on, H0, Cb, SaS, a0, st, hbuf, hoff, tiny):  # noqa: ANN001, ANN201
    """Per step k of ``steps`` (the block's steps with an axle on the bridge): the rows on the bridge
    [r0, r1), the vehicles they belong to [j0, j1) and their rows [R0, R1), and the inverse of the
    contact matrix H = H0[R0:R1, R0:R1] + C_b S^a^T / diag(A0) on [r0, r1) (:meth:`.run._Operators.prepare`),
    written into ``hbuf`` from hoff[k] (entries below ``tiny`` in magnitude set to zero: float32's
    subnormals, :func:`.kernels.in_precision`); st[k] = 1, i, r0, r1, R0, R1, j0, j1."""
    keep, trans, origin = _flags()
    nrow, nb = Cb.shape[1], Cb.shape[2]
    size = 0
    for i in range(steps.shape[0]):
        k = steps[i]
        r0, r1 = -1, -1
        for r in range(on.shape[1]):
            if on[k, r]:
                if r0 < 0:
                    r0 = r
                r1 = r + 1
        j0, j1 = row_vehicle[r0], row_vehicle[r1 - 1] + 1
        R0, R1 = vrows[j0, 0], vrows[j1 - 1, 1]
        n, nr = R1 - R0, r1 - r0
        T = np.zeros((nr, nr))
        # T = C_b S^T (row-major) = column-major gemm('T', 'N', nr, nr, nb, 1, S, nb, C_b, nb, 0, T, nr)
        at = (i * nrow + r0 - a0) * nb
        _gemm(blas64, ib, sb64, ch, trans, keep, nr, nr, nb, 1.0, _addr(SaS.reshape(-1), at), nb,
              _addr(Cb.reshape(-1), at), nb, 0.0, _addr(T.reshape(-1), origin), nr)
        H = np.empty((n, n))
        for a in range(n):  # element by element (no slice assigned from an array: run_steps)
            for b in range(n):
                H[a, b] = H0[R0 + a, R0 + b]
        for a in range(nr):
            for b in range(nr):
                H[r0 - R0 + a, r0 - R0 + b] += T[a, b]
        Hi = np.linalg.inv(H)
        for a in range(n):
            for b in range(n):
                v = Hi[a, b]
                hbuf[size + a * n + b] = 0.0 if abs(v) < tiny else v
        st[k, 0], st[k, 1], st[k, 2], st[k, 3] = 1, i, r0, r1
        st[k, 4], st[k, 5], st[k, 6], st[k, 7] = R0, R1, j0, j1
        hoff[k] = size
        size += n * n
    return size


__all__ = ["contact_inverses", "run_steps", "write_outputs"]
