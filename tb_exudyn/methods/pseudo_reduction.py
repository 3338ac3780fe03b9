"""PEM's sums over a task's columns at every output time (:class:`PseudoReduction`).

What is summed is described in :mod:`tb_exudyn.methods.reduction` (the module docstring: sigma^2 by
type, the PSD map, lambda_1 and lambda_2, the derivative's sums for the Rice rate, the ratios' cross
sums, the Sperling inputs' power); :func:`~tb_exudyn.methods.reduction.finish_pem_task` turns the raw
sums into per-channel arrays.

How, per output time (measured on the reference study, 240 columns, 551 z rows: 3.2 ms before, see
docs/speed.md section 4): the z rows are formed in an internal order (the rows with a recorded
derivative, then those with a pseudo-derivative, then the rest) straight from the engine's outputs in
its own row order (the plan's maps with their columns permuted once per row order: no gathered copy
of the outputs), and the last three times' z rows are kept by reference (no copies); |z|^2 is formed
in preallocated buffers. sigma^2, the PSD maps and the ratios' sums are the plain formulas' on
``L @ y[ext]``, bitwise; the derivative's sums are bitwise the same for any row order of the engine,
and within 1.3e-15 of each channel's max of those before this module (which divided the complex
derivative by a real step with numpy's complex division instead of on the float view).

By default the sums are taken in compiled code (:mod:`.compiled_reduction`, issue 28): the z rows are
formed into a ring of three preallocated times (no new arrays), every row's sums by type, weighted,
per frequency (the PSD map) and the Sperling inputs' power come from one pass over its columns, the
derivative's sums from one pass over the neighbouring times, and the PSD rows of 16 output times are
written into the map together. The same sums to round-off of their order (1e-13 of each quantity's
largest value, tests/methods/test_compiled_reduction.py); measured on the reference study's 240-column
task in the integration: 4.0 -> 1.15 s (docs/speed.md section 7). ``compiled=False`` keeps the numpy
passes below, the reference.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from .. import jit
from ..system.comfort import sperling_power_weights, weighting_response

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]
IntArray = NDArray[np.int64]

#: precision of a task's PSD map on its way to the parent (see tb_exudyn.methods.pem.PSD_TRANSPORT)
PSD_TRANSPORT = np.float32
#: output times whose PSD rows the compiled path gathers before it writes them into the (rows, n_freq,
#: n_t) map (a map row's 16 float32 times are one 64-byte cache line)
PSD_BLOCK = 16


def permuted_columns(A: sp.csr_matrix, rows: IntArray, ext: IntArray) -> sp.csr_matrix:
    """The rows ``rows`` of ``A`` acting on y in the engine's row order: B @ y == A[rows] @ y[ext],
    with every row's terms in their order in ``A`` (the same sums in the same order: bitwise)."""
    sub = A[rows]  # y[ext][k] = y[ext[k]]: column k of A is column ext[k] of B
    return sp.csr_matrix((sub.data, np.asarray(ext, dtype=sub.indices.dtype)[sub.indices], sub.indptr),
                         shape=(sub.shape[0], int(ext.size)))


def copy_rows(A: sp.csr_matrix) -> NDArray[np.bool_]:
    """Rows of ``A`` that copy one entry of y (one term, coefficient 1)."""
    one = np.diff(A.indptr) == 1
    one[one] = A.data[A.indptr[:-1][one]] == 1.0
    return one


class RowMap:
    """z = A[rows] @ y[ext] as a new array: one gather of y's rows (fancy indexing) for the rows that
    copy an entry of y, the sparse product over the runs of the other rows (bitwise the same values:
    0 + 1.0 y = y). Measured on the reference study's 551 rows x 240 columns: 0.15 ms against the
    sparse product's 0.32 ms (np.take with ``out`` was slower than either, 0.2 ms for half the rows)."""

    def __init__(self, A: sp.csr_matrix, rows: IntArray, ext: IntArray) -> None:
        B = permuted_columns(A, rows, ext)
        copy = copy_rows(B)
        self.src = np.zeros(copy.size, dtype=np.intp)
        self.src[copy] = B.indices[B.indptr[:-1][copy]]
        edges = np.flatnonzero(np.diff(copy.astype(np.int8))) + 1
        self.runs = [(int(a), int(b), B[int(a):int(b)]) for a, b in zip(np.concatenate(([0], edges)),
                                                                         np.concatenate((edges, [copy.size])))
                     if b > a and not copy[a]]

    def __call__(self, Y: ComplexArray) -> ComplexArray:
        out = Y[self.src]
        for a, b, how in self.runs:
            out[a:b] = how @ Y
        return out


class PseudoReduction:
    """PEM's sums over a task's columns at every output time (module docstring), a
    :class:`~tb_exudyn.engines.protocols.Reducer` (``record(i, Y, ext)``, ``result()``); ``result()`` returns
    the raw sums, which :func:`~tb_exudyn.methods.reduction.finish_pem_task` turns into per-channel arrays.
    f_col : (m,) excitation frequency [Hz] of each column; type_index : (m,) its irregularity type;
    n_types : types of the scenario; n_freq : frequencies of the task (columns frequency-major, all
    types of a frequency side by side); df : (n_freq,) their widths [Hz]; dt : output step [s];
    psd_z : the z rows whose PSD maps are kept (pem.psd_z_rows; None: all);
    variance_only : only what sigma^2 needs (sigma^2 by type and the ratios' cross sums by type: the
    grid error's midpoint sweep); the other sums stay zero. On the reference study this takes the
    reduction of an output time from 4.7 to 1.9 ms (300 columns).
    node_weight : (m,) or None: per column the factor of the local grid-error estimate's node sums
    (its trapezoid weight over the column's own, 0 for the other columns): sigma^2 by type and the
    ratios' cross sums by type weighted by it ("var_nodes_z", "nd_nodes"), the sums T of
    :func:`~tb_exudyn.methods.grid.locally_refined_variance` from the grid's own columns.
    compiled : the sums in compiled code (:mod:`.compiled_reduction`, one pass per row; the default),
    or by the numpy passes below (the reference the compiled path is tested against). The compiled
    path needs the columns frequency-major with the same types in the same order at every frequency
    (what :func:`~tb_exudyn.methods.pem.harmonic_columns` makes) and real maps; other layouts take the
    numpy path.
    """

    def __init__(self, plan: Any, f_col: FloatArray, type_index: IntArray, n_types: int, n_freq: int,
                 df: FloatArray, n_t: int, dt: float, keep_psd: bool, psd_z: IntArray | None = None,
                 variance_only: bool = False, compiled: bool = True, node_weight: FloatArray | None = None) -> None:
        m = f_col.size
        self.variance_only = bool(variance_only)
        self.plan, self.n_t, self.dt, self.n_f, self.m = plan, n_t, float(dt), n_freq, m
        self.per_freq = m // n_freq if n_freq else 1
        self.type_sum = np.zeros((m, n_types))
        self.type_sum[np.arange(m), type_index] = 1.0
        w = 2.0 * np.pi * np.asarray(f_col, dtype=float)
        self.omega = w
        self.w12 = np.stack([w, w * w], axis=1)  # (m, 2)
        self.rot = np.exp(-1j * w * self.dt)  # e^{-i w dt}: one output step of demodulation
        self.rot_c = self.rot.conj()
        self.inv_df = 1.0 / np.asarray(df, dtype=float)
        nz = plan.n_z
        # internal row order: recorded derivative, pseudo-derivative, the rest; `at` maps z -> internal
        self.d_rows = np.concatenate((plan.recorded, plan.pseudo)).astype(np.int64)
        nd, nr = self.d_rows.size, int(plan.recorded.size)
        self.n_rec, self.n_d = nr, nd
        # within each group the rows that copy an output come first (gathered in runs: RowMap)
        lcopy, dcopy = copy_rows(plan.L.tocsr()), np.zeros(nz, dtype=bool)
        if nr:
            dcopy[plan.recorded] = copy_rows(plan.Ld[plan.recorded].tocsr())
        groups = (plan.recorded, plan.pseudo, np.setdiff1d(np.arange(nz), self.d_rows))
        self.order = np.concatenate([np.asarray(g, dtype=np.int64)[np.lexsort((~dcopy[g], ~lcopy[g]))] for g in groups])
        at = self.at = np.empty(nz, dtype=np.int64)
        at[self.order] = np.arange(nz)
        w_rows = np.array([z for z, x in enumerate(plan.weighting) if x], dtype=np.int64)
        self.w_at = at[w_rows]
        self.W = np.array([weighting_response(plan.weighting[z], f_col) for z in w_rows]).reshape(-1, m)  # type: ignore[arg-type]
        self.w_rec = [(j, int(np.flatnonzero(w_rows == z)[0])) for j, z in enumerate(self.order[:nr]) if plan.weighting[z]]
        self.var = np.zeros((n_t, n_types, nz))  # internal row order; result() gives z order
        self.lam = np.zeros((n_t, 2, nz))
        self.psd_z = None if psd_z is None else np.asarray(psd_z, dtype=np.int64)  # z rows of the kept maps (None: all)
        self.psd_at = at if self.psd_z is None else at[self.psd_z]
        self.psd = np.zeros((nz if psd_z is None else self.psd_z.size, n_freq, n_t), dtype=PSD_TRANSPORT) if keep_psd else None
        self.maps: tuple[Any, Any, Any] | None = None  # (ext, L, Ld) for the engine's row order ext
        self.ring: list[Any] = [None, None, None]  # z (internal order) of the last 3 times: references
        self.ring_d: list[Any] = [None, None, None]  # recorded derivatives of the last 3 times
        self.sq, self.P = np.empty((nz, m)), np.empty((nz, m))  # im^2, |z|^2
        self.d_buf = (np.empty((nd - nr, m), dtype=complex), np.empty((nd - nr, m), dtype=complex))
        self.iw = 1j * w
        self.dvar, self.dcov = np.zeros((n_t, nd)), np.zeros((n_t, nd))
        self.ratio_n, self.ratio_d = (at[np.array([r[k] for r in plan.ratios], dtype=np.int64)] for k in (1, 2))
        self.ratio_nd, self.ratio_dd = self.ratio_n, self.ratio_d  # internal rows start with the derivative rows
        nr_ = len(plan.ratios)
        self.nd_type = np.zeros((n_t, n_types, nr_))
        self.nd_lam = np.zeros((n_t, 2, nr_))
        self.nd_psd = np.zeros((nr_, n_freq, n_t), dtype=PSD_TRANSPORT) if keep_psd and nr_ else None
        self.nd_pairs = np.zeros((n_t, 3, nr_))  # (N, D'), (D, N'), (N', D')
        self.sp_rows = at[np.array([s[1] for s in plan.sperling], dtype=np.int64)]
        self.sp_w = np.array([sperling_power_weights(f_col, s[2]) for s in plan.sperling]).reshape(-1, m)  # type: ignore[arg-type]
        self.sp = np.zeros((n_t, len(plan.sperling)))
        nodes = node_weight is not None and bool(np.any(node_weight)) and not self.variance_only
        self.node_sum = self.type_sum * np.asarray(node_weight, dtype=float)[:, None] if nodes else None
        self.var_nodes = np.zeros((n_t, n_types, nz)) if nodes else np.zeros((1, n_types, 0))
        self.nd_nodes = np.zeros((n_t, n_types, nr_)) if nodes else np.zeros((1, n_types, 0))
        self.kernels = self._compiled_setup(np.asarray(type_index)) if compiled else None

    def _freq_sum(self, p: FloatArray) -> FloatArray:
        """(rows, m) -> (rows, n_freq) summed over the types of each frequency, per Hz."""
        return p.reshape(p.shape[0], self.n_f, self.per_freq).sum(axis=2) * self.inv_df

    def _maps(self, ext: IntArray) -> tuple[Any, Any]:
        """The plan's maps in the internal row order acting on the engine's rows (``ext``: the
        engine's row of each output), built once per row order."""
        if self.maps is None or not (self.maps[0] is ext or np.array_equal(self.maps[0], ext)):
            plan, nr = self.plan, self.n_rec
            L = RowMap(plan.L.tocsr(), self.order, ext)
            Ld = RowMap(plan.Ld.tocsr(), self.order[:nr], ext) if nr else None
            self.maps = (ext, L, Ld)
        return self.maps[1], self.maps[2]

    def record(self, i: int, Y: ComplexArray, ext: IntArray) -> None:
        if self.kernels is not None:
            self._record_compiled(i, Y, ext)
            return
        L, Ld = self._maps(ext)
        Z = L(Y)
        if self.w_at.size:
            Z[self.w_at] *= self.W
        P, sq = self.P, self.sq
        np.multiply(Z.real, Z.real, out=P)  # |z|^2 = re^2 + im^2, no temporaries
        np.multiply(Z.imag, Z.imag, out=sq)
        P += sq
        self.var[i] = (P @ self.type_sum).T
        if self.node_sum is not None:
            self.var_nodes[i] = (P @ self.node_sum).T
        if self.variance_only:
            if self.ratio_n.size:
                self.nd_type[i] = ((Z[self.ratio_n].conj() * Z[self.ratio_d]).real @ self.type_sum).T
            return
        self.lam[i] = (P @ self.w12).T
        if self.psd is not None:
            self.psd[:, :, i] = self._freq_sum(P[self.psd_at])  # the kept z rows, in their order
        if self.ratio_n.size:
            X = (Z[self.ratio_n].conj() * Z[self.ratio_d]).real
            self.nd_type[i] = (X @ self.type_sum).T
            if self.node_sum is not None:
                self.nd_nodes[i] = (X @ self.node_sum).T
            self.nd_lam[i] = (X @ self.w12).T
            if self.nd_psd is not None:
                self.nd_psd[:, :, i] = self._freq_sum(X)
        if self.sp_rows.size:
            self.sp[i] = np.einsum("ij,ij->i", P[self.sp_rows], self.sp_w)
        if not self.n_d:
            return
        self.ring[i % 3] = Z  # a new array every time: kept by reference
        if self.n_rec:
            Zd = Ld(Y)
            for j, wj in self.w_rec:
                Zd[j] *= self.W[wj]
            self.ring_d[i % 3] = Zd
        if i >= 1:
            self._derivative(i - 1, i)
        if i == self.n_t - 1:
            self._derivative(i, i)

    def _derivative(self, j: int, latest: int) -> None:
        """Derivative statistics at time j (latest: the newest time recorded)."""
        z_j, nr, nd = self.ring[j % 3], self.n_rec, self.n_d
        d, buf = self.d_buf  # the pseudo rows' derivative: the formula's operations in its order
        if nd > nr:  # (z_next rot - z_prev rot*) / (2 dt) + i w y; one-sided at the ends
            y = z_j[nr:nd]
            if j > 0:
                np.multiply(self.ring[(j - 1) % 3][nr:nd], self.rot_c, out=buf)
            if j == 0 or j < latest:
                np.multiply(self.ring[(j + 1) % 3][nr:nd], self.rot, out=d)
                d -= y if j == 0 else buf
            else:
                np.subtract(y, buf, out=d)
            # on the float view: complex / real would be a complex division (Smith's rule gives a / c
            # for a real divisor c: the same values, at a third of the time)
            d.view(np.float64).__itruediv__(self.dt if j == 0 or j == latest else 2 * self.dt)
            np.multiply(y, self.iw, out=buf)
            d += buf
        # Re(conj(a) b) summed over the columns = the dot product of the float views (one pass, no temporaries)
        zf = z_j.view(np.float64)
        parts = ((0, nr, self.ring_d[j % 3]), (nr, nd, d))
        for a, b, dd in parts:
            if b > a:
                df = dd.view(np.float64)
                np.einsum("ij,ij->i", df, df, out=self.dvar[j, a:b])
                np.einsum("ij,ij->i", zf[a:b], df, out=self.dcov[j, a:b])
        if self.ratio_n.size:
            dn, dd_ = (self._d_rows(r, self.ring_d[j % 3], d) for r in (self.ratio_nd, self.ratio_dd))
            for k, (a, b) in enumerate(((zf[self.ratio_nd], dd_), (zf[self.ratio_dd], dn), (dn, dd_))):
                np.einsum("ij,ij->i", a, b, out=self.nd_pairs[j, k])

    def _d_rows(self, rows: IntArray, recorded: ComplexArray | None, pseudo: ComplexArray) -> FloatArray:
        """The derivative of the internal rows ``rows`` (< n_d) from the recorded and the pseudo rows, float view."""
        nr = self.n_rec
        out = np.empty((rows.size, 2 * self.m))
        rec = rows < nr
        if rec.any():
            out[rec] = recorded.view(np.float64)[rows[rec]]  # type: ignore[union-attr]
        if (~rec).any():
            out[~rec] = pseudo.view(np.float64)[rows[~rec] - nr]
        return out

    # ------------------------------------------------------------------ the compiled path
    def _compiled_setup(self, type_index: IntArray) -> Any:
        """The compiled path's tables and buffers, or None where it does not apply (the class
        docstring): the type of each column position of a frequency, the weighted rows, the Sperling
        entries by row, a ring of the last three times' z rows, the PSD rows of PSD_BLOCK times."""
        m, n_f, plan = self.m, self.n_f, self.plan
        if not n_f or m % n_f or np.iscomplexobj(plan.L.data) or np.iscomplexobj(plan.Ld.data):
            return None
        pos = type_index.reshape(n_f, m // n_f)
        if not (pos == pos[:1]).all() or np.unique(pos[0]).size != pos.shape[1]:
            return None
        k = jit.load("tb_exudyn.methods.compiled_reduction")
        nz, nr = plan.n_z, self.n_rec
        self.c_pos = np.ascontiguousarray(pos[0], dtype=np.int64)
        self.c_w1, self.c_w2 = self.omega.copy(), self.omega * self.omega
        self.c_wn = np.zeros(m) if self.node_sum is None else self.node_sum.sum(axis=1)
        self.c_Wz = np.ascontiguousarray(self.W, dtype=complex)
        self.c_wd = np.array([j for j, _ in self.w_rec], dtype=np.int64)
        self.c_Wd = np.ascontiguousarray(self.W[[wj for _, wj in self.w_rec]], dtype=complex).reshape(-1, m)
        self.c_psd_of = -np.ones(nz, dtype=np.int64)  # the PSD map row of each internal row (-1: none)
        if self.psd is not None:
            self.c_psd_of[self.psd_at] = np.arange(self.psd_at.size)
        self.c_rows = np.arange(nz, dtype=np.int64)
        self.c_sp_w = np.ascontiguousarray(self.sp_w, dtype=float).reshape(-1, m)
        self.c_nd_of = (np.arange(self.ratio_n.size) if self.nd_psd is not None else -np.ones(self.ratio_n.size)).astype(np.int64)
        self.c_ring = np.zeros((3, nz, m), dtype=complex)  # z (internal order) of the last three times
        self.c_ring_d = np.zeros((3, nr, m), dtype=complex)  # their recorded derivatives
        self.c_d = np.zeros((self.n_d - nr, m), dtype=complex)  # the pseudo-derivative at one time
        self.c_rot = np.ascontiguousarray(self.rot).view(np.float64)
        n_psd = 0 if self.psd is None else self.psd.shape[0]
        self.c_block = (np.zeros((PSD_BLOCK, n_psd, n_f), dtype=PSD_TRANSPORT),
                        np.zeros((PSD_BLOCK, 0 if self.nd_psd is None else self.nd_psd.shape[0], n_f), dtype=PSD_TRANSPORT))
        self.c_blocked = [0, 0]  # first time and count of the times in the block
        self.c_maps: tuple[Any, ...] | None = None
        return k

    def _compiled_maps(self, ext: IntArray) -> tuple[Any, ...]:
        """(ptr, idx, coef) of L and Ld in the internal row order on the engine's rows, once per ext."""
        if self.c_maps is None or not (self.c_maps[0] is ext or np.array_equal(self.c_maps[0], ext)):
            out: list[Any] = [ext]
            for A, rows in ((self.plan.L, self.order), (self.plan.Ld, self.order[:self.n_rec])):
                B = permuted_columns(A.tocsr(), rows, ext)
                out.append((B.indptr.astype(np.int64), B.indices.astype(np.int64), B.data.astype(np.float64)))
            self.c_maps = tuple(out)
        return self.c_maps[1:]

    def _record_compiled(self, i: int, Y: ComplexArray, ext: IntArray) -> None:
        k, full = self.kernels, not self.variance_only
        (ptr, idx, coef), (dptr, didx, dcoef) = self._compiled_maps(ext)
        Yf = np.ascontiguousarray(Y, dtype=np.complex128).view(np.float64)
        Z, Zf = self.c_ring[i % 3], self.c_ring[i % 3].view(np.float64)
        k.form_rows(Yf, ptr, idx, coef, Zf)
        if self.w_at.size:
            k.weight_rows(Z, self.w_at, self.c_Wz)
        b0, bn = self.c_blocked
        if bn and i != b0 + bn:  # not the next time: the block so far goes first
            self._flush()
        if not self.c_blocked[1]:
            self.c_blocked[0] = i
        t, pos, w1, w2, inv_df = self.c_blocked[1], self.c_pos, self.c_w1, self.c_w2, self.inv_df
        nodes = self.node_sum is not None
        k.pair_sums(Zf, self.c_rows, self.c_rows, pos, w1, w2, inv_df, self.c_psd_of, self.c_block[0][t],
                    self.var[i], self.lam[i], full, self.c_wn, self.var_nodes[i if nodes else 0], nodes)
        if self.ratio_n.size:
            k.pair_sums(Zf, self.ratio_n, self.ratio_d, pos, w1, w2, inv_df, self.c_nd_of, self.c_block[1][t],
                        self.nd_type[i], self.nd_lam[i], full, self.c_wn, self.nd_nodes[i if nodes else 0], nodes)
        if full and self.sp_rows.size:
            k.weighted_power(Zf, self.sp_rows, self.c_sp_w, self.sp[i])
        self.c_blocked[1] += 1
        if self.c_blocked[1] == PSD_BLOCK or i == self.n_t - 1:
            self._flush()
        if not full or not self.n_d:
            return
        if self.n_rec:
            k.form_rows(Yf, dptr, didx, dcoef, self.c_ring_d[i % 3].view(np.float64))
            if self.c_wd.size:
                k.weight_rows(self.c_ring_d[i % 3], self.c_wd, self.c_Wd)
        if i >= 1:
            self._derivative_compiled(i - 1, i)
        if i == self.n_t - 1:
            self._derivative_compiled(i, i)

    def _derivative_compiled(self, j: int, latest: int) -> None:
        """The derivative's sums at time j (latest: the newest time recorded), compiled."""
        k, nr, nd = self.kernels, self.n_rec, self.n_d
        mode = (0 if j < latest else 3) if j == 0 else (1 if j < latest else 2)
        ring = self.c_ring.view(np.float64)
        k.derivative_sums(ring[j % 3, :nd], ring[(j - 1) % 3, :nd], ring[(j + 1) % 3, :nd], mode, self.c_rot,
                          self.omega, self.dt, self.c_ring_d[j % 3].view(np.float64), self.c_d.view(np.float64),
                          self.ratio_nd, self.ratio_dd, self.dvar[j], self.dcov[j], self.nd_pairs[j])

    def _flush(self) -> None:
        """The block's PSD rows into the maps (times c_blocked[0] ..)."""
        i0, n = self.c_blocked
        for block, out in zip(self.c_block, (self.psd, self.nd_psd)):
            if n and out is not None and not self.variance_only:
                self.kernels.flush_psd(block, n, out, i0)
        self.c_blocked[1] = 0

    def result(self) -> dict[str, np.ndarray]:
        if self.kernels is not None and self.c_blocked[1]:
            self._flush()
        at = self.at
        dz = at[self.d_rows]  # the plan's order of the derivative rows (recorded, pseudo)
        out = {"var_z": self.var[:, :, at], "lam_z": self.lam[:, :, at], "dvar_z": self.dvar[:, dz], "dcov_z": self.dcov[:, dz],
               "nd_type": self.nd_type, "nd_lam": self.nd_lam, "nd_pairs": self.nd_pairs, "sperling_power": self.sp}
        if self.psd is not None:
            out["psd_z"] = self.psd
            out["psd_z_rows"] = np.arange(self.plan.n_z) if self.psd_z is None else self.psd_z
        if self.nd_psd is not None:
            out["nd_psd"] = self.nd_psd
        if self.node_sum is not None:
            out["var_nodes_z"], out["nd_nodes"] = self.var_nodes[:, :, at], self.nd_nodes
        return out


def reducer_column_bytes(plan: Any, n_out: int) -> int:
    """Bytes per complex column of :class:`PseudoReduction` at an output time: the z rows of the last
    three times and the one being formed (complex), the squares of their float view and |z|^2, the
    pseudo-derivative and its buffer (complex), the recorded derivatives of the last three times and
    the one being formed (the numpy path; the compiled path holds less: three times of z rows and of
    the recorded derivatives, one pseudo-derivative, and the kept PSD rows of 16 output times per
    frequency in float32, less than the numpy path's squares). ``n_out``, the engine's outputs, are the engine's (counted there)."""
    n_z, n_rec = plan.n_z, plan.recorded.size
    n_ps = plan.pseudo.size
    return 16 * 4 * n_z + 16 * n_z + 8 * n_z + 16 * 2 * n_ps + 16 * 4 * n_rec


__all__ = ["PSD_TRANSPORT", "PseudoReduction", "RowMap", "copy_rows", "permuted_columns", "reducer_column_bytes"]
