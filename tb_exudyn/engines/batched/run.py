"""One component's integration in the batched engine: its state, its constant operators, its step.

Per step, with A0 = beta' M + gamma' D0 + K0 (constant, block diagonal: inverted once) and the
contact a low-rank term (one row per contact force, B = [S(t), -G]):

    A0 Delta + B^T f = R = -(K0 q~ + D0 v~),    f = f~ + C Delta,    C = (k + gamma' c) B + c v [dS, 0]

where f~ is the contact force at the predictor. So the contact forces come out of the small system
(I + C A0^-1 B^T) f = f~ + C A0^-1 R (Woodbury) and Delta = A0^-1 (R - B^T f). Only the small
contact matrix is factorised per step, over the contact rows of the vehicles with an axle on the
bridge; the wheels' part of every operator is constant and block-sparse per vehicle, and a vehicle off
the bridge (on the rigid track) advances by a constant operator with its contact forces folded in
(computed only when an output is recorded).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ...system.components import Component
from ..alpha import GeneralizedAlpha
from .inputs import run_inputs
from .kernels import _acc, _inv, advance

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]
IntArray = NDArray[np.int64]


@dataclass(frozen=True)
class _Step:
    """What a step's time gives: axle positions x and which are on the bridge, the coupling's rail shapes S and
    slopes dS there (None while no axle is on the bridge: zero rows), the approach taper w, w' of
    every axle (``steady``: w = 1, w' = 0 for all; ``zero``: w = w' = 0 for all)."""

    t: float
    speed: float
    x: FloatArray
    on: NDArray[np.bool_]
    S: FloatArray | None
    dS: FloatArray | None
    w: FloatArray
    dw: FloatArray
    steady: bool
    zero: bool



class _Vehicle:
    """A vehicle's part of a component: its coordinates [v0, v1), its contact rows [r0, r1) and
    the constant operators of both ways to advance it.

    On the bridge (its contact forces part of the Woodbury system): Y0 = -(A0^-1 K0 q~ + A0^-1 D0 v~)
    per dense block, the contact equations' right-hand side J [q~; v~] (g = f~ + C Y0 of the wheels)
    and Delta += A0^-1 G^T f. Off the bridge the rail is rigid, the vehicle's step is constant and
    folded: Delta = T_q q~ + T_v v~ + T_i (k r + c r'), with f = H0^-1 (k r + c r' + J [q~; v~]) only
    when an output is recorded. T_q, T_v keep the blocks of A0 when they have no entries outside them
    (a symmetric car: left and right wheels' cross terms cancel), else one dense block.
    """

    def __init__(self, veh, A0inv: FloatArray, K0: FloatArray, D0: FloatArray, Gl: FloatArray,  # noqa: ANN001
                 k: FloatArray, c: FloatArray, kap: FloatArray, H0: FloatArray) -> None:
        v0, v1, r0, r1 = self.v0, self.v1, self.r0, self.r1 = veh.start, veh.stop, veh.row_start, veh.row_stop
        Ai = A0inv[v0:v1, v0:v1]
        Pk, Pd = Ai @ K0[v0:v1, v0:v1], Ai @ D0[v0:v1, v0:v1]
        self.blocks = [(b0, b1, np.ascontiguousarray(-Pk[b0 - v0:b1 - v0, b0 - v0:b1 - v0]),
                        np.ascontiguousarray(-Pd[b0 - v0:b1 - v0, b0 - v0:b1 - v0])) for b0, b1 in veh.blocks]
        Gv = Gl[r0:r1, v0:v1]
        self.Gi = np.ascontiguousarray(Ai @ Gv.T)
        # wheels' part of g = f~ + C Y0: -k G q~ - c G v~ - kappa G Y0
        self.Jq = np.ascontiguousarray(-k[r0:r1, None] * Gv + kap[r0:r1, None] * (Gv @ Pk))
        self.Jv = np.ascontiguousarray(-c[r0:r1, None] * Gv + kap[r0:r1, None] * (Gv @ Pd))
        H0[r0:r1, r0:r1] += kap[r0:r1, None] * (Gv @ self.Gi)
        self.H0inv = _inv(H0[r0:r1, r0:r1])
        Ti = self.Gi @ self.H0inv
        Tq, Tv = -Pk + Ti @ self.Jq, -Pd + Ti @ self.Jv
        self.Ti = np.ascontiguousarray(Ti)
        inside = np.zeros(Tq.shape, dtype=bool)
        for b0, b1 in veh.blocks:
            inside[b0 - v0:b1 - v0, b0 - v0:b1 - v0] = True
        scale = max(np.abs(Tq).max(initial=0.0), 1e-300), max(np.abs(Tv).max(initial=0.0), 1e-300)
        split = np.all(np.abs(Tq[~inside]) <= 1e-13 * scale[0]) and np.all(np.abs(Tv[~inside]) <= 1e-13 * scale[1])
        spans = veh.blocks if split else ((v0, v1),)
        self.folded = [(b0, b1, np.ascontiguousarray(Tq[b0 - v0:b1 - v0, b0 - v0:b1 - v0]),
                        np.ascontiguousarray(Tv[b0 - v0:b1 - v0, b0 - v0:b1 - v0])) for b0, b1 in spans]

    def delta(self, QP: FloatArray, VP: FloatArray, DL: FloatArray, F: FloatArray) -> None:
        """On the bridge: Delta = Y0 + A0^-1 G^T f (f solved for)."""
        for b0, b1, mPk, mPd in self.blocks:
            np.matmul(mPk, QP[b0:b1], out=DL[b0:b1])
            _acc(DL[b0:b1], mPd, VP[b0:b1])
        _acc(DL[self.v0:self.v1], self.Gi, F[self.r0:self.r1])

    def delta_off(self, QP: FloatArray, VP: FloatArray, DL: FloatArray, G: FloatArray, F: FloatArray,
                  record: bool) -> None:
        """Off the bridge: the folded constant step; ``G`` holds k r + c r' of the rows."""
        for b0, b1, Tq, Tv in self.folded:
            np.matmul(Tq, QP[b0:b1], out=DL[b0:b1])
            _acc(DL[b0:b1], Tv, VP[b0:b1])
        g = G[self.r0:self.r1]
        _acc(DL[self.v0:self.v1], self.Ti, g)
        if record:
            _acc(g, self.Jq, QP[self.v0:self.v1])
            _acc(g, self.Jv, VP[self.v0:self.v1])
            np.matmul(self.H0inv, g, out=F[self.r0:self.r1])


class _Run:
    """State (q~, v~, a~, Delta of the columns on the float64 view) and constant operators of one
    component for one task's columns."""

    def __init__(self, lin: Any, ga: GeneralizedAlpha, comp: Component, cols: IntArray, source: Any) -> None:
        cp = lin.coupling
        self.comp, self.cols = comp, cols
        self.sel: Any = slice(None) if cols.size == source.width else cols
        bp, gp = ga.beta_p, ga.gamma_p
        g = comp.coords
        M, K0, D0 = (X[np.ix_(g, g)] for X in (lin.M, lin.K0, lin.D0))
        self.M = M
        A0 = bp * M + gp * D0 + K0
        nb = self.nb = comp.n_bridge
        self.modes = comp.modes
        self.a0b = np.diag(A0)[:nb].copy()
        self.pk = (np.diag(K0)[:nb] / self.a0b)[:, None]
        self.pd = (np.diag(D0)[:nb] / self.a0b)[:, None]
        A0inv = np.zeros_like(A0)
        for veh in comp.vehicles:
            for b0, b1 in veh.blocks:
                A0inv[b0:b1, b0:b1] = np.linalg.inv(A0[b0:b1, b0:b1])
        rows = self.rows = comp.rows
        self.axle = cp.contacts.axle[rows]
        k, c = lin.k[rows], lin.c[rows]
        kap = k + gp * c
        self.k, self.c, self.kap = k[:, None], c[:, None], kap[:, None]
        # the wheels' part of the gap map in local coordinates: B = [S, -Gl]
        Gl = np.zeros((rows.size, g.size))
        wheel_col = {int(w): j for j, w in enumerate(lin.wheel)}
        for j, gi in enumerate(g):
            if int(gi) in wheel_col:
                Gl[:, j] = lin.G[rows, wheel_col[int(gi)]]
        self.Gl = Gl
        self.H0 = np.eye(rows.size)
        self.vehicles = [_Vehicle(veh, A0inv, K0, D0, Gl, k, c, kap, self.H0) for veh in comp.vehicles]
        if sum(v.r1 - v.r0 for v in self.vehicles) != rows.size:
            raise NotImplementedError("a contact row acting on no vehicle coordinate")
        m = cols.size
        self.input = run_inputs(self, source, cols, cp)  # k r + c r' of the rows, per step
        n = g.size
        self.QP, self.VP, self.AP, self.DL = (np.zeros((n, 2 * m)) for _ in range(4))
        self.tmp = np.zeros((nb, 2 * m))
        self.Gc = np.zeros((rows.size, m), dtype=complex)
        self.G = self.Gc.view(np.float64)
        self.R = np.zeros((rows.size, m), dtype=complex)  # k r + c r' at output steps
        self.F = np.zeros((rows.size, 2 * m))
        self.qdd0 = np.zeros((n, 2 * m))
        self.bridge_moving = False

    def inputs(self, step: "_Step", shared: Any, out: ComplexArray) -> None:
        """k r + c r' of the component's contact rows (``shared``: the column source's ``at(step)``)."""
        if step.zero:
            out.fill(0.0)
        else:
            self.input(step, shared, out)

    def start(self, step: "_Step", shared: Any, ga: GeneralizedAlpha) -> None:
        """Rest; M qdd0 = -B(0)^T (k r + c r'); the first predictor."""
        self.inputs(step, shared, self.Gc)
        B = -self.Gl
        if self.nb and step.S is not None:
            B = B.copy()
            B[:, : self.nb] = step.S[np.ix_(self.rows, self.modes)]
        self.qdd0 = np.linalg.solve(self.M, -(B.T @ self.G))
        self.QP[:], self.VP[:], self.AP[:] = ga.first_predictor(self.qdd0)
        self.bridge_moving = bool(np.any(self.qdd0[: self.nb]))
        self.F[:] = self.G
        self.R[:] = self.Gc

    def solve(self, step: "_Step", shared: Any, record: bool) -> None:
        """Delta (self.DL) and contact forces (self.F; of vehicles off the bridge only when recording)
        of the step ending at step.t."""
        nb, QP, VP, DL, G, F = self.nb, self.QP, self.VP, self.DL, self.G, self.F
        self.inputs(step, shared, self.Gc)  # g = f~ + C Y0 starts with k r + c r'
        if record:
            self.R[:] = self.Gc
        on_rows = np.flatnonzero(step.on[self.axle]) if nb and step.S is not None else ()
        self.bridge_moving |= len(on_rows) > 0  # until the first axle arrives the bridge stays at rest
        if nb and self.bridge_moving:
            np.multiply(QP[:nb], -self.pk, out=DL[:nb])
            np.multiply(VP[:nb], self.pd, out=self.tmp)
            DL[:nb] -= self.tmp
        on_veh: list[_Vehicle] = []
        if len(on_rows):
            # Woodbury on the contact rows of the vehicles with an axle on the bridge
            r0, r1 = int(on_rows[0]), int(on_rows[-1]) + 1
            on_veh = [v for v in self.vehicles if v.r0 < r1 and v.r1 > r0]
            R0, R1 = on_veh[0].r0, on_veh[-1].r1
            rows = self.rows[r0:r1]
            S = step.S[rows][:, self.modes]
            dS = step.dS[rows][:, self.modes]
            k, c = self.k[r0:r1], self.c[r0:r1]
            cvdS = (c * step.speed) * dS
            Cb = self.kap[r0:r1] * S + cvdS
            Lq = np.ascontiguousarray(k * S + cvdS - Cb * self.pk.T)
            Lv = np.ascontiguousarray(c * S - Cb * self.pd.T)
            SaT = np.ascontiguousarray((S / self.a0b).T)
            H = self.H0[R0:R1, R0:R1].copy()
            H[r0 - R0:r1 - R0, r0 - R0:r1 - R0] += Cb @ SaT
            for v in on_veh:
                _acc(G[v.r0:v.r1], v.Jq, QP[v.v0:v.v1])
                _acc(G[v.r0:v.r1], v.Jv, VP[v.v0:v.v1])
            _acc(G[r0:r1], Lq, QP[:nb])
            _acc(G[r0:r1], Lv, VP[:nb])
            np.matmul(_inv(H), G[R0:R1], out=F[R0:R1])
            _acc(DL[:nb], SaT, F[r0:r1], alpha=-1.0)
            for v in on_veh:
                v.delta(QP, VP, DL, F)
        for v in self.vehicles:
            if v not in on_veh:
                v.delta_off(QP, VP, DL, G, F, record)

    def update(self, coef: tuple[float, ...], h: float) -> None:
        """Corrector of this step fused with the predictor of the next, in place."""
        r0 = 0 if self.bridge_moving else self.nb  # the bridge's rows are zero while it is at rest
        advance(coef, h, *(X[r0:].reshape(-1) for X in (self.QP, self.VP, self.AP, self.DL)))




__all__ = ["_Run", "_Step", "_Vehicle"]
