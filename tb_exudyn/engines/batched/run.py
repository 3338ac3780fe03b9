"""One component's integration in the batched engine: its state, its constant operators, its step.

Every contact row, penalty or general (:class:`~tb_exudyn.system.coupling.RowMaps`), has an
application map P = [S^a(t), -G^a] and force maps F^k = [S^k(t), -G^k], F^d = [S^d(t), -G^d]:
f = F^k u + F^d u' + f_in, Q = -P^T f (a penalty row: P = B, F^k = k B + c v [dS, 0], F^d = c B).
Per step, with A0 = beta' M + gamma' D0 + K0 (constant, block diagonal: inverted once),

    A0 Delta + P^T f = R = -(K0 q~ + D0 v~),    f = f~ + C Delta,    C = F^k + gamma' F^d,
    f~ = F^k q~ + F^d v~ + f_in,

so the contact forces come out of the small system (I + C A0^-1 P^T) f = f~ + C A0^-1 R (Woodbury)
and Delta = A0^-1 (R - P^T f) (docs/creep_design.md, section 4). Only the small contact matrix is
factorised per step, over the rows of the vehicles with an axle on the bridge; the wheels' part of
every operator is constant and block-sparse per vehicle, and a vehicle off the bridge (on the rigid
track) advances by a constant operator with its contact forces folded in (computed only when an
output is recorded). The bridge parts of the per-step operators are computed for a block of steps
at once (:meth:`_Run.prepare`, from :mod:`.steps`), so that a step is only products with the columns.

A column source may carry a constant generalised force per column (the gravity load of the linear
mean, :class:`tb_exudyn.system.columns.StaticLoadColumns`): y_c = A0^-1 F_c is added to Delta and
C y_c to the contact equations' right-hand side.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from ...system.components import Component
from ..alpha import GeneralizedAlpha
from .coupled import CoupledBridge
from .inputs import _HarmonicInputs, _StaticInputs, run_inputs
from ...jit import blas_scratch
from .kernels import PRECISIONS, _inv, advance_calls, gemm_call, in_precision, run_calls
from .steps import StepBlock, mode_shapes

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]
IntArray = NDArray[np.int64]


class _Vehicle:
    """A vehicle's part of a component: its coordinates [v0, v1), its contact rows [r0, r1) and
    the constant operators of both ways to advance it.

    On the bridge (its contact forces part of the Woodbury system): Y0 = -(A0^-1 K0 q~ + A0^-1 D0 v~)
    per dense block, the contact equations' right-hand side J [q~; v~] (its wheel part
    -G^k q~ - G^d v~ - C_w Y0, C_w = G^k + gamma' G^d) and Delta += A0^-1 G^a^T f. Off the bridge the
    rail is rigid, the vehicle's step is constant and folded: Delta = T_q q~ + T_v v~ + T_i f_in, with
    f = H0^-1 (f_in + J [q~; v~]) only when an output is recorded. T_q, T_v keep the blocks of A0
    when they have no entries outside them (a symmetric car: left and right wheels' cross terms
    cancel), else one dense block.
    """

    def __init__(self, veh, A0inv: FloatArray, K0: FloatArray, D0: FloatArray, Ga: FloatArray,  # noqa: ANN001
                 Gk: FloatArray, Gd: FloatArray, Cw: FloatArray, H0: FloatArray, dtype: Any) -> None:
        v0, v1, r0, r1 = self.v0, self.v1, self.r0, self.r1 = veh.start, veh.stop, veh.row_start, veh.row_stop
        Ai = A0inv[v0:v1, v0:v1]
        Pk, Pd = Ai @ K0[v0:v1, v0:v1], Ai @ D0[v0:v1, v0:v1]

        def c(X: FloatArray) -> FloatArray:
            return in_precision(X, dtype)

        self.blocks = [(b0, b1, c(-Pk[b0 - v0:b1 - v0, b0 - v0:b1 - v0]), c(-Pd[b0 - v0:b1 - v0, b0 - v0:b1 - v0]))
                       for b0, b1 in veh.blocks]
        Gav, Gkv, Gdv, Cwv = (X[r0:r1, v0:v1] for X in (Ga, Gk, Gd, Cw))
        Gi = Ai @ Gav.T
        self.Ai, self.Cw = Ai, Cwv
        # wheels' part of g = f~ + C Y0: -G^k q~ - G^d v~ - C_w Y0
        Jq = -Gkv + Cwv @ Pk
        Jv = -Gdv + Cwv @ Pd
        H0[r0:r1, r0:r1] += Cwv @ Gi
        H0inv = _inv(H0[r0:r1, r0:r1])
        Ti = Gi @ H0inv
        Tq, Tv = -Pk + Ti @ Jq, -Pd + Ti @ Jv
        self.Gi, self.Jq, self.Jv, self.H0inv, self.Ti = c(Gi), c(Jq), c(Jv), c(H0inv), c(Ti)
        inside = np.zeros(Tq.shape, dtype=bool)
        for b0, b1 in veh.blocks:
            inside[b0 - v0:b1 - v0, b0 - v0:b1 - v0] = True
        scale = max(np.abs(Tq).max(initial=0.0), 1e-300), max(np.abs(Tv).max(initial=0.0), 1e-300)
        split = np.all(np.abs(Tq[~inside]) <= 1e-13 * scale[0]) and np.all(np.abs(Tv[~inside]) <= 1e-13 * scale[1])
        spans = veh.blocks if split else ((v0, v1),)
        self.folded = [(b0, b1, c(Tq[b0 - v0:b1 - v0, b0 - v0:b1 - v0]), c(Tv[b0 - v0:b1 - v0, b0 - v0:b1 - v0]))
                       for b0, b1 in spans]

    def calls(self, QP: FloatArray, VP: FloatArray, DL: FloatArray, G: FloatArray, F: FloatArray
              ) -> tuple[list[Any], list[Any], list[Any], list[Any]]:
        """The vehicle's products for a run's arrays, prepared (:func:`.kernels.gemm_call`):

        - on the bridge, before the contact solve: g += J_q q~ + J_v v~ (``G`` holds f_in);
        - on the bridge, after it: Delta = Y0 + A0^-1 G^a^T f;
        - off the bridge: the folded step Delta = T_q q~ + T_v v~ + T_i f_in;
        - off the bridge, at an output time: f = H0^-1 (f_in + J [q~; v~])."""
        v0, v1, r0, r1 = self.v0, self.v1, self.r0, self.r1
        g, f = G[r0:r1], F[r0:r1]
        rhs = [gemm_call(g, self.Jq, QP[v0:v1]), gemm_call(g, self.Jv, VP[v0:v1])]
        on = [c for b0, b1, mPk, mPd in self.blocks
              for c in (gemm_call(DL[b0:b1], mPk, QP[b0:b1], beta=0.0), gemm_call(DL[b0:b1], mPd, VP[b0:b1]))]
        on.append(gemm_call(DL[v0:v1], self.Gi, f))
        off = [c for b0, b1, Tq, Tv in self.folded
               for c in (gemm_call(DL[b0:b1], Tq, QP[b0:b1], beta=0.0), gemm_call(DL[b0:b1], Tv, VP[b0:b1]))]
        off.append(gemm_call(DL[v0:v1], self.Ti, g))
        forces = rhs + [gemm_call(f, self.H0inv, g, beta=0.0)]
        return rhs, on, off, forces


class _Operators:
    """The constant operators of one component and, per block of steps, the bridge parts of its
    per-step operators (:meth:`prepare`): shared by the runs (column chunks) of the component."""

    def __init__(self, lin: Any, ga: GeneralizedAlpha, comp: Component, precision: str = "float64") -> None:
        cp = lin.coupling
        maps = self.maps = cp.row_maps()
        self.dtype, self.cdtype = PRECISIONS[precision]
        self.comp = comp
        bp, gp = self.bp, self.gp = ga.beta_p, ga.gamma_p
        g = comp.coords
        M, K0, D0 = (X[np.ix_(g, g)] for X in (lin.M, lin.K0, lin.D0))
        self.M = M
        A0 = bp * M + gp * D0 + K0
        nb = self.nb = comp.n_bridge
        self.modes = comp.modes
        self.a0b = np.diag(A0)[:nb].copy()
        self.pk = np.diag(K0)[:nb] / self.a0b
        self.pd = np.diag(D0)[:nb] / self.a0b
        self.pk_c = in_precision(self.pk[:, None], self.dtype)
        self.pd_c = in_precision(self.pd[:, None], self.dtype)
        A0inv = np.zeros_like(A0)
        self.coupled = comp.coupled  # the bridge block dense (a track's modes): its operators in .coupled
        self.bridge_block: CoupledBridge | None = None
        if self.coupled:
            self.bridge_block = CoupledBridge(M, K0, D0, nb, bp, gp, self.dtype)
            self.M = M.copy()  # its mass block in the block's basis (the first accelerations)
            self.M[:nb, :nb] = self.bridge_block.mass
        # the rail shapes the step reads: the modes' own, or (a coupled block in its eigenbasis, a rail function
        # that can: the track's) directly in the block's basis, S(x) T tabulated once (.steps.basis_shapes)
        self.shape_key: tuple[Any, ...] = tuple(int(i) for i in self.modes)
        self.rails_in_basis = bool(self.bridge_block is not None and self.bridge_block.T is not None
                                   and hasattr(lin.coupling.bridge.rail_shape_function, "in_basis"))
        if self.rails_in_basis:
            self.shape_key = ("basis", *self.shape_key)
        #: with rails_in_basis, the rail shapes times P_d as well (C_b P_d of L_v interpolated, not a product)
        self.damped_key = ("basis P_d", *self.shape_key[1:]) if self.rails_in_basis else None
        for veh in comp.vehicles:
            for b0, b1 in veh.blocks:
                A0inv[b0:b1, b0:b1] = np.linalg.inv(A0[b0:b1, b0:b1])
        self.A0inv = A0inv
        rows = self.rows = comp.rows
        self.axle = maps.axle[rows]
        # the wheels' parts of the row maps in local coordinates: P = [S^a, -Ga], F^k = [S^k, -Gk], ...
        wheel_col = {int(w): j for j, w in enumerate(lin.wheel)}
        loc = [(j, wheel_col[int(gi)]) for j, gi in enumerate(g) if int(gi) in wheel_col]
        Ga, Gk, Gd = (np.zeros((rows.size, g.size)) for _ in range(3))
        for X, W in ((Ga, maps.app_wheel), (Gk, maps.stiff_wheel), (Gd, maps.damp_wheel)):
            for j, wc in loc:
                X[:, j] = W[rows, wc]
        self.Ga, self.Cw = Ga, Gk + gp * Gd
        # (n_r, 3, 6): the coefficients of the rail shapes (RAIL_SHAPE_ROWS) in S^a, S^k, S^d of each row
        self.shape_maps = np.ascontiguousarray(
            np.stack([P[rows] for P in (maps.app_shape, maps.stiff_shape, maps.damp_shape)], axis=1))
        self.H0 = np.eye(rows.size)
        self.vehicles = [_Vehicle(veh, A0inv, K0, D0, Ga, Gk, Gd, self.Cw, self.H0, self.dtype) for veh in comp.vehicles]
        if sum(v.r1 - v.r0 for v in self.vehicles) != rows.size:
            raise NotImplementedError("a contact row acting on no vehicle coordinate")
        self.row_vehicle = np.zeros(rows.size, dtype=np.int64)
        for i, v in enumerate(self.vehicles):
            self.row_vehicle[v.r0:v.r1] = i
        self.block: dict[str, Any] | None = None
        self.compiled = False  # whether prepare() packs the block for the compiled step (_kernels)
        self._kernels: Any = None
        self._kinv: tuple[Any, ...] | None = None
        self.kblock: tuple[Any, ...] | None = None
        self._ktables: tuple[Any, ...] | None = None

    def rail_shapes(self, bridge: Any) -> dict[Any, Any]:
        """key -> x -> the rail shapes this component's step reads (:func:`.steps.mode_shapes`): of its bridge
        modes, or with ``rails_in_basis`` in the coupled block's basis, S(x) T, and S(x) T P_d
        (``damped_key``)."""
        if not self.rails_in_basis:
            return {self.shape_key: mode_shapes(bridge, self.modes)}
        X = np.zeros((bridge.n_modes, self.nb))
        X[self.modes] = self.bridge_block.T
        fn = bridge.rail_shape_function
        return {self.shape_key: fn.in_basis(X), self.damped_key: fn.in_basis(X @ self.bridge_block.Pd)}

    def vehicle_tables(self) -> tuple[Any, ...]:
        """The vehicles' operators for the compiled step (:mod:`.compiled`): (vt, vo, bl, fo, vbuf),
        vt[j] = v0, v1, r0, r1; vo[j] = the offsets of J_q, J_v, A0^-1 G^a^T, T_i and H0^-1 in vbuf;
        bl / fo rows = vehicle, b0, b1 and the offsets of a dense block's -A0^-1 K0, -A0^-1 D0 / T_q, T_v."""
        parts: list[np.ndarray] = []
        size = 0

        def put(X: np.ndarray) -> int:
            nonlocal size
            parts.append(np.ascontiguousarray(X, dtype=self.dtype).reshape(-1))
            size += X.size
            return size - X.size

        vt = [[v.v0, v.v1, v.r0, v.r1] for v in self.vehicles]
        vo = [[put(v.Jq), put(v.Jv), put(v.Gi), put(v.Ti), put(v.H0inv)] for v in self.vehicles]
        bl = [[j, b0, b1, put(mPk), put(mPd)] for j, v in enumerate(self.vehicles) for b0, b1, mPk, mPd in v.blocks]
        fo = [[j, b0, b1, put(Tq), put(Tv)] for j, v in enumerate(self.vehicles) for b0, b1, Tq, Tv in v.folded]

        def table(rows: list[list[int]], width: int) -> IntArray:
            return np.array(rows, dtype=np.int64).reshape(len(rows), width)

        vbuf = np.concatenate(parts) if parts else np.zeros(1, dtype=self.dtype)
        return table(vt, 4), table(vo, 5), table(bl, 5), table(fo, 5), vbuf

    def _pack(self, block: StepBlock, steps: IntArray | None = None, on: Any = None, Cb: Any = None,
              SaS: Any = None, a0: int = 0) -> None:
        """The block's per-step operators for the compiled step (``self.kblock``): st[k] = has, i, r0, r1,
        R0, R1, j0, j1, L_q, L_v, S^a / diag(A0) (k, rows, n_b), the inverses of the contact matrices one
        after another (hbuf, offsets hoff), formed by :func:`.compiled.contact_inverses` (no step with
        an axle on the bridge: ``steps`` None)."""
        T = block.size
        st = np.zeros((T, 8), dtype=np.int64)
        hoff = np.zeros(T, dtype=np.int64)
        if steps is None:
            empty = np.zeros((1, 1, max(self.nb, 1)), dtype=self.dtype)
            self.kblock = (st, empty, empty, empty, np.zeros(1, dtype=self.dtype), hoff, 0)
            return
        if self._kinv is None:
            self._kinv = (*blas_scratch(np.dtype(np.float64)), np.ascontiguousarray(self.row_vehicle),
                          np.array([[v.r0, v.r1] for v in self.vehicles], dtype=np.int64).reshape(-1, 2))
        n_r = self.rows.size
        hbuf = np.zeros(steps.size * n_r * n_r, dtype=np.float64)  # float64 in every precision: one
        tiny = float(np.finfo(self.dtype).tiny) if self.dtype != np.float64 else 0.0  # compiled kernel
        try:
            self._kernels.contact_inverses(*self._kinv, steps, np.ascontiguousarray(on), self.H0,
                                           np.ascontiguousarray(Cb), np.ascontiguousarray(SaS), a0,
                                           st, hbuf, hoff, tiny)
        except np.linalg.LinAlgError:
            raise np.linalg.LinAlgError("singular contact matrix in the batched engine") from None
        # rounded to nearest as the kernel's store did (zeros where no inverse is stored: an unset float64
        # of np.empty would overflow float32 in the cast and say so on the terminal)
        hbuf = hbuf.astype(self.dtype, copy=False)
        blk = self.block
        self.kblock = (st, blk["Lq"], blk["Lv"], blk["SaS"], hbuf, hoff, a0)

    def prepare(self, block: StepBlock) -> None:
        """The bridge parts of the operators at every step of ``block`` with an axle of this
        component on the bridge: L_q = S^k - C_b p_k^T, L_v = S^d - C_b p_d^T (C_b = S^k + gamma' S^d,
        p = diag(K0 or D0) / diag(A0) of the modes), S^a / diag(A0) and the inverse of the contact
        matrix H = H0 + C_b (S^a / diag(A0))^T over the rows of the vehicles with an axle on the
        bridge, and which rows and vehicles take part. Only the rows whose axle is on the bridge at
        some step of the block are evaluated."""
        nb = self.nb
        self.block = None
        rails = block.rails.get(self.shape_key) if nb else None
        on = None if rails is None else block.on[:, self.axle]  # (T, n_r)
        steps = None if on is None else np.flatnonzero(on.any(axis=1))
        if steps is None or not steps.size:
            if self.compiled:
                self._pack(block)
            return
        used = np.flatnonzero(on[steps].any(axis=0))
        a0, a1 = int(used[0]), int(used[-1]) + 1  # rows evaluated: [a0, a1)
        # S^m[r] = sum_j shape_m[r, j] rail_j(x_a(r)): one (3 x 6) @ (6 x n_b) product per row and step
        S = np.matmul(self.shape_maps[a0:a1], rails[steps][:, self.axle[a0:a1]])  # (k, rows, 3, n_b)
        if self.bridge_block is not None and not self.rails_in_basis:  # the shapes in the coupled block's basis
            S = self.bridge_block.to_basis(S)
        Sa, Sk, Sd = S[:, :, 0], S[:, :, 1], S[:, :, 2]
        Cb = Sk + self.gp * Sd
        if self.damped_key is not None:  # C_b P_d from the rails times P_d (.coupled.CoupledBridge.row_operators)
            SP = np.matmul(self.shape_maps[a0:a1, 1:], block.rails[self.damped_key][steps][:, self.axle[a0:a1]])
            Lq, Lv, SaS = self.bridge_block.row_operators(Sa, Sk, Sd, Cb, SP[:, :, 0] + self.gp * SP[:, :, 1])
        elif self.bridge_block is not None:  # its dense P_d (and P_k, A0_b^-1 outside its eigenbasis)
            Lq, Lv, SaS = self.bridge_block.row_operators(Sa, Sk, Sd, Cb)
        else:
            Lq = Sk - Cb * self.pk
            Lv = Sd - Cb * self.pd
            SaS = Sa / self.a0b
        dt = self.dtype
        if self.compiled:  # the per-step contact matrices and their inverses in compiled code
            self.block = {"per_step": None, "a0": a0, "Lq": in_precision(Lq, dt), "Lv": in_precision(Lv, dt),
                          "SaS": in_precision(SaS, dt), "Cb": Cb}
            self._pack(block, steps, on, Cb, SaS, a0)
            return
        per_step: list[Any] = [None] * block.size
        H0 = self.H0
        for i, k in enumerate(steps):
            idx = np.flatnonzero(on[k])
            r0, r1 = int(idx[0]), int(idx[-1]) + 1
            vs = range(int(self.row_vehicle[r0]), int(self.row_vehicle[r1 - 1]) + 1)
            on_veh = [self.vehicles[j] for j in vs]
            R0, R1 = on_veh[0].r0, on_veh[-1].r1
            # the contact matrix of the vehicles on the bridge
            H = H0[R0:R1, R0:R1].copy()
            H[r0 - R0:r1 - R0, r0 - R0:r1 - R0] += Cb[i, r0 - a0:r1 - a0] @ SaS[i, r0 - a0:r1 - a0].T
            per_step[k] = (i, r0, r1, R0, R1, on_veh, vs, in_precision(_inv(H), self.dtype))
        self.block = {"per_step": per_step, "a0": a0, "Lq": in_precision(Lq, dt), "Lv": in_precision(Lv, dt),
                      "SaS": in_precision(SaS, dt), "Cb": Cb}


class _Run:
    """State (q~, v~, a~, Delta of the columns on the real view) of one component for a chunk of a
    task's columns (``cols``, indices into the source's columns; ``sel`` the same as a slice when
    contiguous), in the operators' precision (:data:`.kernels.PRECISIONS`)."""

    def __init__(self, ops: _Operators, cols: IntArray, source: Any, coupling: Any) -> None:
        self.ops = ops
        self.comp, self.cols = ops.comp, cols
        self.rows, self.axle, self.modes, self.nb = ops.rows, ops.axle, ops.modes, ops.nb
        self.dtype, self.cdtype = ops.dtype, ops.cdtype
        contiguous = cols.size and np.array_equal(cols, np.arange(cols[0], cols[0] + cols.size))
        self.sel: Any = slice(int(cols[0]), int(cols[0]) + cols.size) if contiguous else cols
        nb, rows = ops.nb, ops.rows
        m = cols.size
        self.input = run_inputs(self, source, cols, coupling, ops.maps, self.cdtype)  # f_in of the rows, per step
        n = ops.comp.size
        dt = self.dtype
        self.QP, self.VP, self.AP, self.DL = (np.zeros((n, 2 * m), dtype=dt) for _ in range(4))
        self.tmp = np.zeros((nb, 2 * m), dtype=dt)
        self.Gc = np.zeros((rows.size, m), dtype=self.cdtype)
        self.G = self.Gc.view(dt)
        self.R = np.zeros((rows.size, m), dtype=self.cdtype)  # f_in at output steps
        self.F = np.zeros((rows.size, 2 * m), dtype=dt)
        self.qdd0 = np.zeros((n, 2 * m))
        self.bridge_moving = False
        self.kernel: Any = None  # the compiled step, when compile() applies
        # the vehicles' products, prepared on this run's arrays
        self.calls_rhs, self.calls_on, self.calls_off, self.calls_forces = zip(
            *(v.calls(self.QP, self.VP, self.DL, self.G, self.F) for v in ops.vehicles)) if ops.vehicles else ((),) * 4
        self._advance: dict[tuple[int, int], list[Any]] = {}
        self._gemm = gemm_call(self.F, self.F, self.F)[0]  # the gemm of the run's precision
        self._bridge_views = (self.QP[:nb], self.VP[:nb], self.DL[:nb])
        # a coupled bridge block: Delta_b = -P_k q~_b - P_d v~_b (.coupled.CoupledBridge.step_calls)
        self.calls_bridge = (ops.bridge_block.step_calls(self.QP[:nb], self.VP[:nb], self.DL[:nb])
                             if ops.bridge_block is not None and nb else None)
        # vehicles still at rest (no input yet, off the bridge: their state is exactly zero) are not
        # stepped; they are the trailing ones, so the active vehicles are a leading range
        self.n_active = 0
        self.rows_end = nb  # the local rows that are stepped: [0 or nb, rows_end)
        # a constant generalised force per column (the linear mean's gravity load)
        force = getattr(source, "constant_force", None)
        self.force_delta = None
        if force is not None:
            g = ops.comp.coords
            Fc = force(g)[:, cols]  # (n, m) complex, local coordinates
            yc = np.zeros_like(Fc)
            yc[nb:] = ops.A0inv[nb:, nb:] @ Fc[nb:]
            if ops.bridge_block is not None:  # in the coupled block's basis
                Fc[:nb] = ops.bridge_block.force(Fc[:nb])
                yc[:nb] = ops.bridge_block.solve(Fc[:nb])
            else:
                yc[:nb] = Fc[:nb] / ops.a0b[:, None]
            self.constant_force = Fc
            self.force_delta = np.ascontiguousarray(yc).view(np.float64).astype(dt)  # added to Delta every step
            self.force_rows = (-(ops.Cw[:, nb:] @ yc[nb:])).astype(self.cdtype)  # wheel part of C y_c
            self.force_bridge = np.ascontiguousarray(yc[:nb]).view(np.float64).astype(dt)  # C_b y_c per step

    def inputs(self, k: int, block: StepBlock, shared: Any, out: ComplexArray) -> None:
        """f_in of the component's contact rows at step k of ``block`` (``shared``: see
        :func:`.inputs.shared_inputs`)."""
        if block.zero[k] and self.force_delta is None:
            out.fill(0.0)
        else:
            self.input(k, block, shared, out)

    def _activate(self, k: int, block: StepBlock) -> None:
        """Count in the vehicles that leave rest at step k (an input at one of their axles, an axle
        on the bridge, or a constant force)."""
        ops = self.ops
        vehicles = ops.vehicles
        while self.n_active < len(vehicles):
            v = vehicles[self.n_active]
            a = self.axle[v.r0:v.r1]
            if not (self.force_delta is not None or np.any(block.w[k, a]) or np.any(block.dw[k, a])
                    or np.any(block.on[k, a]) or np.any(self.qdd0[v.v0:v.v1])):
                break
            self.n_active += 1
            self.rows_end = v.v1
        if self.n_active == len(vehicles):
            self.rows_end = self.comp.size

    def start(self, block0: StepBlock, shared: Any, ga: GeneralizedAlpha) -> None:
        """Rest; M qdd0 = F_c - P(0)^T f_in; the first predictor (``block0``: the block of step 0)."""
        ops = self.ops
        self.inputs(0, block0, shared, self.Gc)
        P = -ops.Ga
        if self.nb and ops.shape_key in block0.rails:
            P = P.copy()
            P[:, : self.nb] = np.matmul(ops.shape_maps[:, :1], block0.rails[ops.shape_key][0][self.axle])[:, 0]
            if ops.bridge_block is not None and not ops.rails_in_basis:
                P[:, : self.nb] = ops.bridge_block.to_basis(P[:, : self.nb])
        rhs = -(P.T @ self.Gc.astype(np.complex128))
        if self.force_delta is not None:
            rhs += self.constant_force
        self.qdd0 = np.ascontiguousarray(np.linalg.solve(ops.M, rhs)).view(np.float64)
        qp, vp, ap = ga.first_predictor(self.qdd0)
        self.QP[:], self.VP[:], self.AP[:] = qp, vp, ap
        self.bridge_moving = bool(np.any(self.qdd0[: self.nb]))
        self.F[:] = self.G
        self.R[:] = self.Gc
        self._activate(0, block0)

    def solve(self, k: int, block: StepBlock, shared: Any, record: bool) -> None:
        """Delta (self.DL) and contact forces (self.F; of vehicles off the bridge only when recording)
        of step k of ``block``."""
        ops = self.ops
        nb, QP, VP, DL, G, F = self.nb, self.QP, self.VP, self.DL, self.G, self.F
        self.inputs(k, block, shared, self.Gc)  # g = f~ + C Y0 starts with f_in
        if record:
            self.R[:] = self.Gc
        if self.force_delta is not None:
            self.Gc += self.force_rows
        self._activate(k, block)
        step = None if ops.block is None else ops.block["per_step"][k]
        self.bridge_moving |= step is not None  # until the first axle arrives the bridge stays at rest
        if nb and self.bridge_moving and self.calls_bridge is not None:
            run_calls(self.calls_bridge)
        elif nb and self.bridge_moving:
            np.multiply(QP[:nb], -ops.pk_c, out=DL[:nb])
            np.multiply(VP[:nb], ops.pd_c, out=self.tmp)
            DL[:nb] -= self.tmp
        on: Any = ()
        if step is not None:
            # Woodbury on the contact rows of the vehicles with an axle on the bridge
            i, r0, r1, R0, R1, on_veh, on, Hinv = step
            blk = ops.block
            a = blk["a0"]
            if self.force_delta is not None:  # C_b y_c of the constant force's bridge part
                G[r0:r1] += blk["Cb"][i, r0 - a:r1 - a] @ self.force_bridge
            for j in on:
                run_calls(self.calls_rhs[j])
            gemm = self._gemm
            qb, vb, db = self._bridge_views
            g = G[r0:r1]
            gemm(1.0, qb.T, blk["Lq"][i, r0 - a:r1 - a].T, 1.0, g.T, 0, 0, 1)
            gemm(1.0, vb.T, blk["Lv"][i, r0 - a:r1 - a].T, 1.0, g.T, 0, 0, 1)
            fr = F[R0:R1]
            fr.fill(0.0)  # then beta = 1: OpenBLAS takes a slower path for beta = 0 at this size
            gemm(1.0, G[R0:R1].T, Hinv.T, 1.0, fr.T, 0, 0, 1)
            gemm(-1.0, F[r0:r1].T, blk["SaS"][i, r0 - a:r1 - a].T, 1.0, db.T, 0, 1, 1)
            for j in on:
                run_calls(self.calls_on[j])
        for j in range(self.n_active):
            if j not in on:
                run_calls(self.calls_off[j])
                if record:
                    run_calls(self.calls_forces[j])
        if self.force_delta is not None:
            DL += self.force_delta

    def compile(self, module: Any, coef: tuple[float, ...], h: float) -> bool:
        """Use the compiled step (:mod:`.compiled`, ``module``) for this run: harmonic (PEM) columns
        without a constant force, or the gravity column (a constant input and a constant force on the
        wheels only, as the linear mean's always is: every axle on the approach at t = 0, so the
        bridge rows' C_b y_c of :meth:`solve` is zero; a force with a bridge part keeps the numpy step).
        Returns whether it applies."""
        if self.ops.coupled:  # the compiled step's bridge is diagonal: a coupled one keeps the numpy step
            return False
        harmonic = isinstance(self.input, _HarmonicInputs) and self.force_delta is None
        constant = (isinstance(self.input, _StaticInputs) and self.force_delta is not None
                    and not np.any(self.force_bridge))
        if not (harmonic or constant):
            return False
        dt, cdt = np.dtype(self.dtype), np.dtype(self.cdtype)
        if constant:  # (constant, f_s, the wheels' C y_c, y_c); the harmonic inputs unused
            self._kconstant = (True, np.array(np.broadcast_to(self.input.value, self.Gc.shape), dtype=cdt, order="C"),
                               np.ascontiguousarray(self.force_rows, dtype=cdt),
                               np.ascontiguousarray(self.force_delta, dtype=dt))
            self._kinputs = (np.zeros((1, 1), dtype=cdt), np.zeros((1, 1), dtype=cdt), np.zeros((1, 1), dtype=cdt))
        else:
            self._kconstant = (False, np.zeros((1, 1), dtype=cdt), np.zeros((1, 1), dtype=cdt),
                               np.zeros((1, 1), dtype=dt))
        self.kernel, self.kwrite = module.run_steps, module.write_outputs
        self.ops.compiled, self.ops._kernels = True, module
        if self.ops._ktables is None:
            self.ops._ktables = self.ops.vehicle_tables()
        self._kconst = blas_scratch(np.dtype(self.dtype))
        self._kstate = (self.QP, self.VP, self.AP, self.DL, self.Gc, self.G, self.F, self.R)
        self._kcoef = np.array([*coef, h], dtype=np.float64)
        self._kpk = np.ascontiguousarray(self.ops.pk_c.reshape(-1))
        self._kpd = np.ascontiguousarray(self.ops.pd_c.reshape(-1))
        self._kcols = np.ascontiguousarray(self.cols, dtype=np.int64)
        return True

    def run_block(self, block: StepBlock, z: ComplexArray, buffers: dict[int, Any], out: Any, ga: GeneralizedAlpha) -> None:
        """Every step of ``block`` by the compiled step (after :meth:`compile`); the outputs of the
        block's output steps (``buffers``: step -> channel buffer) written by ``out``."""
        T = block.size
        n_active, moving, rows_end = (np.zeros(T, dtype=np.int64), np.zeros(T, dtype=np.bool_),
                                      np.zeros(T, dtype=np.int64))
        has_step = self.ops.kblock[0][:, 0]
        if self.n_active == len(self.ops.vehicles) and self.bridge_moving:  # nothing left to start
            n_active[:], moving[:], rows_end[:] = self.n_active, True, self.rows_end
        else:
            for k in range(T):  # the same order of activation as solve()
                self._activate(k, block)
                self.bridge_moving |= bool(has_step[k])
                n_active[k], moving[k], rows_end[k] = self.n_active, self.bridge_moving, self.rows_end
        rec = np.zeros(T, dtype=np.bool_)
        rec[list(buffers)] = True
        qss, qd, z = self._kinputs if self._kconstant[0] else (self.input.Qss, self.input.Qd, z)
        inputs = (qss, qd, z, self._kcols, np.ascontiguousarray(block.w), np.ascontiguousarray(block.dw),
                  block.steady, block.zero, np.ascontiguousarray(self.axle))
        st, Lq, Lv, SaS, hbuf, hoff, a0 = self.ops.kblock
        bridge = (self._kpk, self._kpd, st, Lq, Lv, SaS, hbuf, hoff, a0)
        schedule = (n_active, moving, rows_end)
        blas, ib, sb, ch = self._kconst
        k, pending = 0, False
        while True:
            k = self.kernel(k, T, pending, rec, blas, ib, sb, ch, self._kstate, inputs, self._kconstant, bridge,
                            schedule, self.ops._ktables, self._kcoef)
            if k >= T:
                return
            out.write_compiled(self, buffers[k], ga)
            k, pending = k + 1, True

    def update(self, coef: tuple[float, ...], h: float) -> None:
        """Corrector of this step fused with the predictor of the next, in place (only the rows
        that move: the bridge once an axle has reached it, the vehicles that have left rest)."""
        r0 = 0 if self.bridge_moving else self.nb  # the bridge's rows are zero while it is at rest
        r1 = self.rows_end
        if r1 > r0:
            calls = self._advance.get((r0, r1))
            if calls is None:
                calls = self._advance[(r0, r1)] = advance_calls(
                    coef, h, *(X[r0:r1].reshape(-1) for X in (self.QP, self.VP, self.AP, self.DL)))
            run_calls(calls)


__all__ = ["_Operators", "_Run", "_Vehicle"]
