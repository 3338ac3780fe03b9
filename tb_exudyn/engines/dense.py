"""The dense engine: the linear model and Exudyn's generalized-alpha step on full matrices.

A small reference for the batched engine (the same model and step, none of its structure: no
components, no Woodbury, no folded off-bridge operators) and the naive baseline of the speed
benchmark. Per step it assembles the full system matrix

    A(t) = beta' M + gamma' (D0 + Dc(t)) + K0 + Kc(t)

with the coupling's own Jacobians Kc, Dc (:meth:`~tb_exudyn.system.coupling.WheelRailCoupling.jacobians`),
solves A Delta = -(K(t) q~ + D(t) v~ + B^T (k r + c r') + A^T f_in) for every column at once
(complex right-hand sides, one LU per step), and evaluates the contact forces with the coupling's
contact laws (penalty rows: ``contact_law``; general linear rows such as creep: ``linear_law``, their
Jacobians are in the coupling's) and the inputs with the column source's ``contact_inputs`` and
``linear_inputs``. Cost: one dense LU of the whole system
per step, so it is meant for small models (tests) and for measuring what the batched engine saves.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from scipy.linalg import lu_factor, lu_solve

from ..builder import linear_system
from ..execution.threads import single_threaded_blas
from ..system.conventions import scenario_steps
from .alpha import GeneralizedAlpha
from .base import Engine


class DenseEngine(Engine):
    """The linear model's columns on full matrices (no options)."""

    name = "dense"
    full_model = False
    linear_rows = True

    def __init__(self, scenario: Any, options: Any = None, wheel_forces: bool = False) -> None:
        super().__init__(scenario, options, wheel_forces)
        self.lin = linear_system(self.model, scenario.analysis.linearization)
        steps = scenario_steps(scenario)
        self.n_steps, self.ratio = steps.n_steps, steps.ratio
        self.alpha = GeneralizedAlpha(float(scenario.analysis.spectral_radius), steps.h)
        self.ci = np.concatenate((self.lin.bridge, self.lin.wheel))

    def describe(self) -> dict[str, Any]:
        return {"engine": self.name, "linearization": self.lin.linearization, "coordinates": self.lin.n}

    def _matrices(self, t: float) -> tuple[Any, np.ndarray, np.ndarray, Any]:
        """K(t), D(t) of the whole system and the contact state at t."""
        lin, ci = self.lin, self.ci
        cp = lin.coupling
        st = cp.contact_state(t)
        Kc, Dc = cp.jacobians(t)
        K, D = lin.K0.copy(), lin.D0.copy()
        K[np.ix_(ci, ci)] += Kc
        D[np.ix_(ci, ci)] += Dc
        return st, K, D, cp

    def _outputs(self, x: tuple[np.ndarray, np.ndarray, np.ndarray], f: np.ndarray) -> np.ndarray:
        """The outputs (n_outputs, m) from (q, v, qdd) and the contact forces."""
        om, lin = self.outputs, self.lin
        Y = np.zeros((len(om.names), f.shape[1]), dtype=complex)
        for i, g, order in om.node:
            Y[i] = x[order][g]
        for i, shape, order in om.bridge:
            Y[i] = shape @ x[order][lin.bridge]
        for i, row in om.contact:
            Y[i] = f[row]
        return Y  # moving point loads: zero without gravity

    def integrate(self, source: Any, reducer: Any) -> dict[str, np.ndarray]:
        with single_threaded_blas():
            return self._integrate(source, reducer)

    def _integrate(self, source: Any, reducer: Any) -> dict[str, np.ndarray]:
        lin, ga, ci = self.lin, self.alpha, self.ci
        n, m, h = lin.n, source.width, ga.h
        bp, gp = ga.beta_p, ga.gamma_p
        c1 = (1.0 - ga.alpha_f) / (1.0 - ga.alpha_m)
        ext = np.arange(len(self.outputs.names))

        general = lin.coupling.n_linear > 0

        def forcing(t: float) -> tuple[Any, np.ndarray, np.ndarray, tuple[np.ndarray, ...], np.ndarray]:
            st, K, D, cp = self._matrices(t)
            r, r_dot = source.contact_inputs(cp, t)
            kr = lin.k[:, None] * r + lin.c[:, None] * r_dot
            F = np.zeros((n, m), dtype=complex)
            F[ci] = -(st.B.T @ kr)  # the generalised input forces -B^T (k r + c r')
            if not general:
                return st, K, D, (r, r_dot), F
            f_in = source.linear_inputs(cp, t)
            F[ci] -= st.A_lin.T @ f_in  # and the general rows' -A^T f_in
            return st, K, D, (r, r_dot, f_in), F

        def forces(st: Any, q: np.ndarray, v: np.ndarray, inputs: tuple[np.ndarray, ...]) -> np.ndarray:
            f = lin.coupling.contact_law(st, q[ci], v[ci], inputs[0], inputs[1])
            if not general:
                return f
            return np.concatenate((f, lin.coupling.linear_law(st, q[ci], v[ci], inputs[2])))

        # start at rest: M qdd0 = -B(0)^T (k r + c r')
        st, K, D, inputs, F = forcing(0.0)
        zero = np.zeros((n, m), dtype=complex)
        qdd0 = np.linalg.solve(lin.M, F)
        reducer.record(0, self._outputs((zero, zero, qdd0), forces(st, zero, zero, inputs)), ext)
        a = qdd0.copy()
        qt = h * h * (0.5 - ga.beta) * qdd0 + h * h * ga.beta * ((ga.alpha_f - ga.alpha_m) / (1.0 - ga.alpha_m) * qdd0)
        at = (ga.alpha_f - ga.alpha_m) / (1.0 - ga.alpha_m) * qdd0
        vt = h * (1.0 - ga.gamma) * qdd0 + h * ga.gamma * at
        for step in range(1, self.n_steps + 1):
            t = step * h
            st, K, D, inputs, F = forcing(t)
            A = bp * lin.M + gp * D + K
            delta = lu_solve(lu_factor(A), F - K @ qt - D @ vt)
            q, v, qdd = qt + delta, vt + gp * delta, bp * delta
            a = at + c1 * qdd
            if step % self.ratio == 0:
                reducer.record(step // self.ratio, self._outputs((q, v, qdd), forces(st, q, v, inputs)), ext)
            at = (ga.alpha_f * qdd - ga.alpha_m * a) / (1.0 - ga.alpha_m)
            qt = q + h * v + h * h * (0.5 - ga.beta) * a + h * h * ga.beta * at
            vt = v + h * (1.0 - ga.gamma) * a + h * ga.gamma * at
        return reducer.result()


__all__ = ["DenseEngine"]
