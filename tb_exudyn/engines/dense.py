"""The dense engine: the linear model and Exudyn's generalized-alpha step on full matrices.

A small reference for the batched engine (the same model and step, none of its structure: no
components, no Woodbury, no folded off-bridge operators, no row maps) and the naive baseline of the
speed benchmark. Per step it assembles the full system matrix

    A(t) = beta' M + gamma' (D0 + Dc(t)) + K0 + Kc(t)

with the coupling's own Jacobians Kc, Dc (:meth:`~tb_exudyn.system.coupling.WheelRailCoupling.jacobians`,
general linear rows included), solves A Delta = -(K(t) q~ + D(t) v~) + F_in(t) for every column at
once (complex right-hand sides, one LU per step) and evaluates the contact forces with the
coupling's contact law (penalty rows) and its general rows' maps K_lin u + D_lin u' (general rows),
plus the input forces of the column source. The input forces: F_in = -B^T (k r + c r') of the
penalty rows (the source's ``contact_inputs``) and -A_lin^T f_in of the general rows, f_in =
W^v . val + W^s . slope of the source's ``rail_values``. Cost: one dense LU of the whole system per
step, so it is meant for small models (tests) and for measuring what the batched engine saves.

Its mean (option ``mean = "linear"``, :class:`DenseOptions`) is the same linear model about the
static state under the dead loads, integrated on full matrices: M d'' + D(t) d' + K(t) d = W(t) -
K(t) u_s from rest, u = u_s + d (the reference of the batched engine's gravity column).
"""

from __future__ import annotations

import time as _time
from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.linalg import lu_factor, lu_solve

from ..errors import SettingError
from ..execution.threads import single_threaded_blas
from ..system.channels import rail_rows
from ..system.columns import linear_row_inputs
from .base import Engine, exudyn_side, init_linear, on_linear_system, typed_options

MEANS: tuple[str, ...] = ("exudyn", "linear")


@dataclass(frozen=True)
class DenseOptions:
    """Options of the dense engine: ``mean`` "exudyn" (default: Exudyn's deterministic run) or
    "linear" (the linear model about the static state under the dead loads, on full matrices)."""

    mean: str = "exudyn"

    def __post_init__(self) -> None:
        if self.mean not in MEANS:
            raise SettingError("DenseOptions", "mean", self.mean, " or ".join(map(repr, MEANS)))


class DenseEngine(Engine):
    """The linear model's columns on full matrices (options: :class:`DenseOptions`)."""

    name = "dense"
    full_model = False
    linear_rows = True  # general linear rows (creep) through the coupling's RowMaps
    options_type = DenseOptions

    def __init__(self, scenario: Any, options: Any = None, wheel_forces: bool = False, system: Any = None) -> None:
        super().__init__(scenario, options, wheel_forces, system)
        self.options = _options(options)
        init_linear(self)
        self.ci = np.concatenate((self.lin.bridge, self.lin.wheel))

    @classmethod
    def on_system(cls, lin: Any, steps: Any, spectral_radius: float, outputs: Any, options: Any = None) -> "DenseEngine":
        """The engine on a linear system built by hand (:func:`~tb_exudyn.engines.base.on_linear_system`)."""
        engine = on_linear_system(cls, lin, steps, spectral_radius, outputs, _options(options))
        engine.ci = np.concatenate((lin.bridge, lin.wheel))
        return engine


    @classmethod
    def describe_options(cls, options: Any) -> dict[str, Any]:
        return {"mean": _options(options).mean}

    def describe(self) -> dict[str, Any]:
        return {"engine": self.name, "linearization": self.lin.linearization, "coordinates": self.lin.n}

    def _matrices(self, lin: Any, t: float) -> tuple[Any, np.ndarray, np.ndarray]:
        """The contact state at t and K(t), D(t) of the whole system."""
        ci = self.ci
        cp = lin.coupling
        st = cp.contact_state(t)
        Kc, Dc = cp.jacobians(t)
        K, D = lin.K0.copy(), lin.D0.copy()
        K[np.ix_(ci, ci)] += Kc
        D[np.ix_(ci, ci)] += Dc
        return st, K, D

    def _outputs(self, x: tuple[np.ndarray, np.ndarray, np.ndarray], f: np.ndarray, S: Any) -> np.ndarray:
        """The outputs (n_outputs, m) from (q, v, qdd), the contact forces (penalty rows, then
        general rows) and the rail under each contact (n_c, n_b) at the output time (rail channels:
        :func:`~tb_exudyn.system.channels.rail_rows`; None without)."""
        om, lin = self.outputs, self.lin
        Y = np.zeros((len(om.names), f.shape[1]), dtype=complex)
        for i, g, order in om.node:
            Y[i] = x[order][g]
        for i, shape, order in om.bridge:
            Y[i] = shape @ x[order][lin.bridge]
        for i, row in om.contact:
            Y[i] = f[row]
        for i, row, order in om.rail:
            Y[i] = S[row] @ x[order][lin.bridge]
        return Y  # moving point loads: zero without gravity

    def integrate(self, source: Any, reducer: Any) -> dict[str, np.ndarray]:
        with single_threaded_blas():
            return self._integrate(source, reducer)

    def _inputs(self, source: Any, t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(r, r') of the penalty rows and f_in of the general rows of ``source`` at t."""
        cp = self.lin.coupling
        r, r_dot = source.contact_inputs(cp, t)
        if not cp.n_linear:
            return r, r_dot, np.zeros((0, source.width), dtype=complex)
        return r, r_dot, linear_row_inputs(source, cp, t)

    def _integrate(self, source: Any, reducer: Any) -> dict[str, np.ndarray]:
        lin, ci = self.lin, self.ci
        cp = lin.coupling
        n, m = lin.n, source.width
        ext = np.arange(len(self.outputs.names))

        def forcing(t: float) -> tuple[Any, np.ndarray, np.ndarray, tuple, np.ndarray]:
            st, K, D = self._matrices(lin, t)
            r, r_dot, f_lin = self._inputs(source, t)
            kr = lin.k[:, None] * r + lin.c[:, None] * r_dot
            F = np.zeros((n, m), dtype=complex)
            F[ci] = -(st.B.T @ kr)  # the generalised input forces -B^T (k r + c r') - A_lin^T f_in
            if cp.n_linear:
                F[ci] -= st.A_lin.T @ f_lin
            return st, K, D, (r, r_dot, f_lin), F

        def forces(st: Any, q: np.ndarray, v: np.ndarray, inputs: tuple) -> np.ndarray:
            r, r_dot, f_lin = inputs
            f = cp.contact_law(st, q[ci], v[ci], r, r_dot)
            if cp.n_linear:
                f = np.concatenate((f, st.K_lin @ q[ci] + st.D_lin @ v[ci] + f_lin))
            return f

        return self._run(forcing, forces, np.zeros((n, m), dtype=complex), reducer, ext, lin)

    def _run(self, forcing: Any, forces: Any, zero: np.ndarray, reducer: Any, ext: np.ndarray, lin: Any,
             offset: np.ndarray | None = None) -> dict[str, np.ndarray]:
        """Exudyn's generalized-alpha step from rest on the full matrices of ``lin``; ``offset``
        (n,) is added to the displacements of every output (the linear mean's static state)."""
        ga = self.alpha
        h = ga.h
        bp, gp = ga.beta_p, ga.gamma_p
        c1 = (1.0 - ga.alpha_f) / (1.0 - ga.alpha_m)
        shift = 0.0 if offset is None else offset[:, None]

        def record(i: int, q: np.ndarray, v: np.ndarray, qdd: np.ndarray, st: Any, inputs: tuple) -> None:
            rails = rail_rows(lin.coupling, st.t) if self.outputs.rail else None
            reducer.record(i, self._outputs((q + shift, v, qdd), forces(st, q + shift, v, inputs), rails), ext)

        st, K, D, inputs, F = forcing(0.0)
        qdd0 = np.linalg.solve(lin.M, F)  # at rest: M qdd0 = F(0)
        record(0, zero, zero, qdd0, st, inputs)
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
                record(step // self.ratio, q, v, qdd, st, inputs)
            at = (ga.alpha_f * qdd - ga.alpha_m * a) / (1.0 - ga.alpha_m)
            qt = q + h * v + h * h * (0.5 - ga.beta) * a + h * h * ga.beta * at
            vt = v + h * (1.0 - ga.gamma) * a + h * ga.gamma * at
        return reducer.result()

    def mean(self) -> dict[str, np.ndarray]:
        if self.options.mean == "exudyn":
            return super().mean()
        with single_threaded_blas():
            return self._linear_mean()

    def _linear_mean(self) -> dict[str, np.ndarray]:
        """The linear model about the static state under the dead loads (see the module docstring)."""
        start = _time.perf_counter()
        model = self.model
        model.set_excitation(None)
        model.set_gravity(True)
        u_s = model.static_state(0.0)
        lin = exudyn_side().linear_system(model, "static")  # leaves gravity off
        cp, ci, om = lin.coupling, self.ci, self.outputs
        zero_in = (np.zeros((cp.n_contacts, 1)), np.zeros((cp.n_contacts, 1)), np.zeros((cp.n_linear, 1)))

        def forcing(t: float) -> tuple[Any, np.ndarray, np.ndarray, tuple, np.ndarray]:
            st, K, D = self._matrices(lin, t)
            return st, K, D, zero_in, (model.dead_load(t) - K @ u_s)[:, None].astype(complex)

        def forces(st: Any, q: np.ndarray, v: np.ndarray, inputs: tuple) -> np.ndarray:
            f = cp.contact_law(st, q[ci], v[ci], zero_in[0], zero_in[1])
            if cp.n_linear:
                f = np.concatenate((f, st.K_lin @ q[ci] + st.D_lin @ v[ci]))
            return f

        values = np.zeros((len(om.names), self.steps.n_outputs))

        class _Recorder:  # a protocols.Reducer: the mean column's outputs
            def record(self, i: int, Y: np.ndarray, ext: np.ndarray) -> None:
                values[:, i] = Y[:, 0].real

            def result(self) -> dict[str, np.ndarray]:
                return {}

        model.set_gravity(True)  # the dead loads of every step
        try:
            self._run(forcing, forces, np.zeros((lin.n, 1), dtype=complex), _Recorder(), np.arange(len(om.names)),
                      lin, offset=u_s)
        finally:
            model.set_gravity(False)
        provenance = {"engine": "dense", "mean_engine": "dense (linear model about the static state)",
                      "linearization": "static", "gravity": True, "initial_state": "static", "excitation": "none",
                      "warnings": list(model.warnings)}
        return self.linear_mean_arrays(values, provenance, start)


def _options(options: Any) -> DenseOptions:
    return typed_options(options, DenseOptions)


__all__ = ["DenseEngine", "DenseOptions"]
