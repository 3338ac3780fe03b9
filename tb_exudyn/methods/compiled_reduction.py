"""The PEM reducer's sums at an output time in compiled code (Numba): the kernels of
:class:`~tb_exudyn.methods.pseudo_reduction.PseudoReduction` with ``compiled=True``.

The same sums as the numpy path of that class (its module docstring: sigma^2 by type, lambda_1 and
lambda_2, the PSD map per frequency, the ratios' cross sums, the Sperling inputs' power, the
derivative's sums), formed in one pass per row instead of a numpy pass per sum: each z row is formed
from the engine's outputs (its terms in the plan's order, on the float view: a real coefficient times
a complex output is two real products), then |z|^2 and its sums are taken while the row is in the
cache. Sums are accumulated in another order than numpy's (BLAS for the type sums, pairwise
summation for the others; here reassociation is allowed, so the compiler vectorises them): the
results agree with the numpy path to round-off (tests/methods/test_compiled_reduction.py states the
bound). ``fastmath`` allows only reassociation and contraction (no assumption of finite values: a
non-finite output stays non-finite in every sum).

Arrays are C-contiguous; complex arrays are passed as their float64 views (re, im interleaved).
Import through :func:`tb_exudyn.jit.load` (Numba's cache directory is set there).
"""

from __future__ import annotations

import numba
import numpy as np
from numba import njit

#: cache on disk only in the directory tb_exudyn.jit.load points Numba at (as engines/batched/compiled.py)
CACHE = bool(numba.config.CACHE_DIR)
#: reassociation (vectorised sums) and contraction (fused multiply-add); no finite-math assumption
FAST = {"reassoc", "contract"}


@njit(cache=CACHE, fastmath=FAST)
def form_rows(Y, ptr, idx, coef, Z):  # noqa: ANN001, ANN201
    """Z[r] = sum_k coef[k] Y[idx[k]] over k in ptr[r] .. ptr[r + 1] - 1 (float views of complex rows:
    Y (n_out, 2m), Z (rows, 2m)); the terms in their order, the first one assigned."""
    n2 = Y.shape[1]
    for r in range(ptr.size - 1):
        z = Z[r]
        a, b = ptr[r], ptr[r + 1]
        if b == a:
            z[:] = 0.0
            continue
        y, ck = Y[idx[a]], coef[a]
        for c in range(n2):
            z[c] = ck * y[c]
        for k in range(a + 1, b):
            y, ck = Y[idx[k]], coef[k]
            for c in range(n2):
                z[c] += ck * y[c]


@njit(cache=CACHE, fastmath=FAST)
def weight_rows(Z, rows, W):  # noqa: ANN001, ANN201
    """Z[rows[j]] *= W[j] (complex rows: the frequency weighting of EN 12299's filters)."""
    for j in range(rows.size):
        z, w = Z[rows[j]], W[j]
        for c in range(z.size):
            z[c] *= w[c]


@njit(cache=CACHE, fastmath=FAST)
def pair_sums(Z, a_rows, b_rows, pos_type, w1, w2, inv_df, psd_of, psd, out_type, out_lam, full, wn,
              out_nodes, nodes):  # noqa: ANN001, ANN201
    """For each pair q of rows of Z (float view (rows, 2m)), x = Re(conj(z_a) z_b) per column
    (|z|^2 where a = b) summed over the columns (frequency-major, ``pos_type.size`` columns per
    frequency, pos_type[t] the type of position t): by type into out_type[:, q]; with ``full`` weighted
    by w and w^2 into out_lam[:, q] and per frequency, divided by its width, into psd[psd_of[q]] where
    psd_of[q] >= 0; with ``nodes`` weighted by wn (m,) by type into out_nodes[:, q] (the local grid
    error's node sums). One pass over the columns per pair (up to eight sums at once)."""
    m, pf = Z.shape[1] // 2, pos_type.size
    nf = m // pf
    acc = np.zeros(pf)
    accn = np.zeros(pf)
    for q in range(a_rows.size):
        a, b = Z[a_rows[q]], Z[b_rows[q]]
        k = psd_of[q] if full else -1
        l1, l2 = 0.0, 0.0
        if pf == 3:  # the three irregularity types of a frequency, unrolled
            s0, s1, s2 = 0.0, 0.0, 0.0
            n0, n1, n2 = 0.0, 0.0, 0.0
            for f in range(nf):
                c = 6 * f
                x0 = a[c] * b[c] + a[c + 1] * b[c + 1]
                x1 = a[c + 2] * b[c + 2] + a[c + 3] * b[c + 3]
                x2 = a[c + 4] * b[c + 4] + a[c + 5] * b[c + 5]
                s0 += x0
                s1 += x1
                s2 += x2
                j = 3 * f
                l1 += x0 * w1[j] + x1 * w1[j + 1] + x2 * w1[j + 2]
                l2 += x0 * w2[j] + x1 * w2[j + 1] + x2 * w2[j + 2]
                if k >= 0:
                    psd[k, f] = (x0 + x1 + x2) * inv_df[f]
                if nodes:
                    n0 += x0 * wn[j]
                    n1 += x1 * wn[j + 1]
                    n2 += x2 * wn[j + 2]
            out_type[pos_type[0], q] = s0
            out_type[pos_type[1], q] = s1
            out_type[pos_type[2], q] = s2
            if nodes:
                out_nodes[pos_type[0], q] = n0
                out_nodes[pos_type[1], q] = n1
                out_nodes[pos_type[2], q] = n2
        else:
            acc[:] = 0.0
            accn[:] = 0.0
            for f in range(nf):
                sf = 0.0
                for t in range(pf):
                    c = f * pf + t
                    x = a[2 * c] * b[2 * c] + a[2 * c + 1] * b[2 * c + 1]
                    acc[t] += x
                    sf += x
                    l1 += x * w1[c]
                    l2 += x * w2[c]
                    if nodes:
                        accn[t] += x * wn[c]
                if k >= 0:
                    psd[k, f] = sf * inv_df[f]
            for t in range(pf):
                out_type[pos_type[t], q] = acc[t]
                if nodes:
                    out_nodes[pos_type[t], q] = accn[t]
        if full:
            out_lam[0, q] = l1
            out_lam[1, q] = l2


@njit(cache=CACHE, fastmath=FAST)
def weighted_power(Z, rows, W, out):  # noqa: ANN001, ANN201
    """out[e] = sum over the columns of |z|^2 of row rows[e] of Z (float view) times W[e] (the
    Sperling inputs' power)."""
    m = Z.shape[1] // 2
    for e in range(rows.size):
        z, w = Z[rows[e]], W[e]
        s = 0.0
        for c in range(m):
            s += (z[2 * c] * z[2 * c] + z[2 * c + 1] * z[2 * c + 1]) * w[c]
        out[e] = s


@njit(cache=CACHE, fastmath=FAST)
def _dot(a, b):  # noqa: ANN001, ANN202
    s = 0.0
    for c in range(a.size):
        s += a[c] * b[c]
    return s


@njit(cache=CACHE, fastmath=FAST)
def derivative_sums(z, z_prev, z_next, mode, rot, w, dt, d_rec, d_ps, rat_n, rat_d, dvar, dcov, pairs):  # noqa: ANN001, ANN201
    """The derivative's sums at one time over its rows z (float views (rows, 2m); the first
    d_rec.shape[0] recorded, d_rec their derivatives, the others pseudo): dvar[r] = sum |z'_r|^2,
    dcov[r] = sum Re(conj(z_r) z'_r), and per ratio q the sums (N, D'), (D, N'), (N', D') of
    Re(conj(.) .) into pairs[:, q]. The pseudo rows' derivative, into d_ps: the demodulated difference
    of the neighbouring times plus i w z, (z_next e^{-iw dt} - z_prev e^{iw dt}) / (2 dt) (mode 1),
    (z_next e^{-iw dt} - z) / dt at the first time (mode 0), (z - z_prev e^{iw dt}) / dt at the last
    (mode 2), i w z alone with a single time (mode 3); rot (2m,): e^{-iw dt}, float view."""
    nr, m = d_rec.shape[0], z.shape[1] // 2
    for r in range(nr):
        dvar[r] = _dot(d_rec[r], d_rec[r])
        dcov[r] = _dot(z[r], d_rec[r])
    # coefficients of z_next rot, z_prev rot*, z and the step's divisor by mode (branch-free loop)
    cn = 1.0 if mode <= 1 else 0.0
    cp = -1.0 if mode == 1 or mode == 2 else 0.0
    cz = -1.0 if mode == 0 else (1.0 if mode == 2 else 0.0)
    h = 2.0 * dt if mode == 1 else dt
    for r in range(nr, z.shape[0]):
        y, n, p, o = z[r], z_next[r], z_prev[r], d_ps[r - nr]
        s1, s2 = 0.0, 0.0
        for c in range(m):
            cr, ci = rot[2 * c], rot[2 * c + 1]
            yr, yi, nr_, ni, pr, pi = y[2 * c], y[2 * c + 1], n[2 * c], n[2 * c + 1], p[2 * c], p[2 * c + 1]
            dr = cn * (nr_ * cr - ni * ci) + cp * (pr * cr + pi * ci) + cz * yr
            di = cn * (nr_ * ci + ni * cr) + cp * (pi * cr - pr * ci) + cz * yi
            dr = dr / h - yi * w[c]
            di = di / h + yr * w[c]
            o[2 * c] = dr
            o[2 * c + 1] = di
            s1 += dr * dr + di * di
            s2 += yr * dr + yi * di
        dvar[r] = s1
        dcov[r] = s2
    for q in range(rat_n.size):
        a, b = rat_n[q], rat_d[q]
        da = d_rec[a] if a < nr else d_ps[a - nr]
        db = d_rec[b] if b < nr else d_ps[b - nr]
        pairs[0, q] = _dot(z[a], db)
        pairs[1, q] = _dot(z[b], da)
        pairs[2, q] = _dot(da, db)


@njit(cache=CACHE)
def flush_psd(block, n, psd, i0):  # noqa: ANN001, ANN201
    """psd[k, f, i0 + t] = block[t, k, f] for t < n: a block of output times' PSD rows into the
    (rows, n_freq, n_t) map (each map row's times written together, a cache line at a time)."""
    for k in range(block.shape[1]):
        for f in range(block.shape[2]):
            for t in range(n):
                psd[k, f, i0 + t] = block[t, k, f]


__all__ = ["derivative_sums", "flush_psd", "form_rows", "pair_sums", "weight_rows", "weighted_power"]
