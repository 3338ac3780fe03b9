"""The batched pseudo-excitation engine: the whole PEM sweep in one time integration.

The train-bridge model is linear and every pseudo-run shares its time-varying matrices; only the
excitation differs. So all pseudo-excitations (one complex column per irregularity type and
frequency: real part the cosine run, imaginary part the sine run) are integrated together, with
exactly Exudyn's generalized-alpha step, on the very model the Exudyn runs use
(:mod:`.batched_model`: M, K0, D0 from ``ComputeLinearizedSystem``, the contact from the
``WheelRailCoupling``). The Exudyn engine stays the reference; the mean (the deterministic run
with gravity) is Exudyn's, as in the Exudyn engine.

Generalized-alpha as Exudyn does it (``CSolverImplicitSecondOrderTimeInt``, Arnold & Bruls'
algorithm 1; docs/RST/ImplicitTrapezoidalRulebasedNewmarkAndGeneralizedalphaSolver.rst): with
spectral radius rho, alpha_m = (2 rho - 1) / (rho + 1), alpha_f = rho / (rho + 1),
gamma = 1/2 + alpha_f - alpha_m, beta = (gamma + 1/2)^2 / 4, a step of size h from (q, v, qdd, a)
predicts

    a~ = (alpha_f qdd - alpha_m a) / (1 - alpha_m)
    q~ = q + h v + h^2 (1/2 - beta) a + h^2 beta a~,    v~ = v + h (1 - gamma) a + h gamma a~

and Newton solves M qdd + f(q, v, t_{n+1}) = 0 for the increment Delta of q = q~ + Delta,
v = v~ + gamma' Delta, qdd = beta' Delta, with beta' = (1 - alpha_m) / (h^2 beta (1 - alpha_f)) and
gamma' = gamma / (h beta); then a = a~ + (1 - alpha_f) / (1 - alpha_m) qdd. The model being
linear, the batched engine solves that equation exactly (Exudyn to its Newton tolerance). Initial
accelerations from M qdd0 = f(q0, v0, 0) and a0 = qdd0 (Exudyn's computeInitialAccelerations);
the step h = end_time / n_steps and the output grid are the Exudyn engine's.

Per step, with A0 = beta' M + gamma' D0 + K0 (constant, block diagonal: inverted once) and the
contact a low-rank term (one row per contact force, B = [S(t), -G]):

    A0 Delta + B^T f = R = -(K0 q~ + D0 v~),    f = f~ + C Delta,    C = (k + gamma' c) B + c v [dS, 0]

where f~ is the contact force at the predictor. So the contact forces come out of the small system
(I + C A0^-1 B^T) f = f~ + C A0^-1 R (Woodbury) and Delta = A0^-1 (R - B^T f). What makes it fast:

- only the small contact matrix is factorised per step, over the contact rows of the vehicles with
  an axle on the bridge; the wheels' part of every operator is constant and block-sparse per
  vehicle, and a vehicle off the bridge (on the rigid track) advances by a constant operator with
  its contact forces folded in (computed only when an output is recorded);
- independent components (e.g. the vertical in-plane and lateral out-of-plane motion of a symmetric
  car on a symmetric track) each integrate only the columns that excite them, and coordinates no
  input reaches (longitudinal, wheelset spin and yaw, pier modes) are not integrated at all;
- complex columns are stored as complex and computed on their float64 view (real BLAS);
- the corrector of a step and the predictor of the next are seven in-place BLAS level-1 updates of
  (q~, v~, a~) by Delta: no temporaries; products accumulate in place (dgemm with beta = 1);
- single-threaded BLAS, one process per core, each owning large slices of the columns (tasks); the
  mean (Exudyn's deterministic run, exactly the Exudyn engine's) is a task too, so that no core
  runs two things at once (a third thread made every process 20-30 % slower);
- outputs are reduced at every output step (|y~|^2 into the PSD map and sigma^2), never stored as
  histories; a task's PSD map travels to the parent in float32 (relative rounding 6e-8, far below
  the engines' agreement; sigma^2 is float64 throughout), which halves the largest messages.
"""

from __future__ import annotations

import json
import math
import os
import time as _time
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Sequence

import numpy as np
from numpy.typing import NDArray
from scipy.linalg import lapack
from scipy.linalg.blas import daxpy, dgemm, dscal

from ..system.excitation import taper
from ..results.random_response import RandomResponse
from ..results.storage import json_default
from ..scenario import Scenario, ScenarioError
from .batched_model import (
    CHECK_TOLERANCE,
    LINEARIZATIONS,
    Component,
    LinearTrainBridge,
    find_components,
    kind_scale,
    output_times,
    spectral_radius_alphas,
)
from .grid import band_mask
from .pem import PemTask, kind_and_unit, pem_tasks, prepare_sweep
from .tasks import Task, run_tasks
from .threads import single_threaded_blas

FloatArray = NDArray[np.float64]
#: precision in which a task's PSD map travels to the parent (sigma^2 is float64 throughout):
#: float32's relative rounding of 6e-8 is far below the engines' agreement of 1e-6 and halves the
#: largest messages (the reference study's map is 420 MB in float64)
PSD_TRANSPORT = np.float32
#: output times written to a task's PSD map at once (contiguous runs of the time axis)
PSD_BLOCK = 16
ComplexArray = NDArray[np.complex128]
IntArray = NDArray[np.int64]
KIND_INDEX = {"vertical": 0, "alignment": 1, "cross_level": 2}


# ============================================================================ generalized-alpha
@dataclass(frozen=True)
class GeneralizedAlpha:
    """Exudyn's generalized-alpha coefficients for spectral radius ``rho`` and step ``h``."""

    rho: float
    h: float
    alpha_m: float = field(init=False)
    alpha_f: float = field(init=False)
    gamma: float = field(init=False)
    beta: float = field(init=False)

    def __post_init__(self) -> None:
        for name, value in zip(("alpha_m", "alpha_f", "gamma", "beta"), spectral_radius_alphas(self.rho)):
            object.__setattr__(self, name, value)

    @property
    def beta_p(self) -> float:
        """d qdd / d Delta = (1 - alpha_m) / (h^2 beta (1 - alpha_f))."""
        return (1.0 - self.alpha_m) / (self.h**2 * self.beta * (1.0 - self.alpha_f))

    @property
    def gamma_p(self) -> float:
        """d v / d Delta = gamma / (h beta)."""
        return self.gamma / (self.h * self.beta)

    def first_predictor(self, qdd0: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        """(q~, v~, a~) of the first step from rest with accelerations qdd0 (a0 = qdd0)."""
        h, g, b, am, af = self.h, self.gamma, self.beta, self.alpha_m, self.alpha_f
        ap = (af - am) / (1.0 - am) * qdd0
        return h * h * (0.5 - b) * qdd0 + h * h * b * ap, h * (1.0 - g) * qdd0 + h * g * ap, ap

    def update_coefficients(self) -> tuple[float, float, float, float, float, float]:
        """(nu_a, nu_d, rho_a, rho_d, mu_a, mu_d) of the corrector fused with the next predictor:
        q~' = q~ + h v~ + nu_a a~ + nu_d D,  v~' = v~ + rho_a a~ + rho_d D,  a~' = mu_a a~ + mu_d D."""
        h, g, b, am, af = self.h, self.gamma, self.beta, self.alpha_m, self.alpha_f
        bp, gp = self.beta_p, self.gamma_p
        c1 = (1.0 - af) / (1.0 - am)
        mu_a = -am / (1.0 - am)
        mu_d = bp * (af - am * c1) / (1.0 - am)
        return (h * h * (0.5 - b) + h * h * b * mu_a, 1.0 + h * gp + h * h * (0.5 - b) * c1 * bp + h * h * b * mu_d,
                h * (1.0 - g) + h * g * mu_a, gp + h * (1.0 - g) * c1 * bp + h * g * mu_d, mu_a, mu_d)


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


# ====================================================================================== columns
@dataclass(frozen=True)
class Columns:
    """Complex pseudo-excitation columns, frequency-major (the types of a frequency side by side).

    Attributes
    ----------
    kinds : (m,) input kind per column (0 vertical, 1 alignment, 2 cross-level angle)
    omega : (m,) spatial circular frequency [rad/m]
    scale : (m,) input amplitude sqrt(S_hz df) (over 2 b for a cross-level given as a height)
    freq_index, df : (n_f,) grid indices of the frequencies and their widths [Hz]
    n_types : number of irregularity types (columns per frequency)
    """

    kinds: IntArray
    omega: FloatArray
    scale: FloatArray
    freq_index: IntArray
    df: FloatArray
    n_types: int

    # the column-source interface of the integrator (see SampleColumns in .batched_mc for the other)
    @property
    def width(self) -> int:
        """Number of complex columns."""
        return int(self.kinds.size)

    def columns_for(self, kinds: Sequence[int]) -> IntArray:
        """The columns a component excited by ``kinds`` integrates: those of its kinds."""
        return np.flatnonzero(np.isin(self.kinds, kinds))

    def at(self, step: "_Step", speed: float) -> ComplexArray:
        """What every column's input needs at a step: exp(i Omega v t)."""
        return np.exp(1j * (self.omega * speed) * step.t)

    def run_inputs(self, run: "_Run", cols: IntArray, coupling) -> "_HarmonicInputs":  # noqa: ANN001
        return _HarmonicInputs(run, self, cols, coupling)


def task_columns(ptasks: Sequence[PemTask], scenario: Scenario) -> Columns:
    """Order (type, frequency) pairs frequency-major; every frequency must carry every type."""
    types = scenario.track.irregularities
    freqs = sorted({p.freq_index for p in ptasks})
    by = {(p.freq_index, p.type_index): p for p in ptasks}
    if len(by) != len(ptasks) or len(by) != len(freqs) * len(types):
        raise ValueError("a batched task must hold every irregularity type of each of its frequencies, once")
    kinds, omega, scale = [], [], []
    for k in freqs:
        for ti, name in enumerate(types):
            p = by[(k, ti)]
            kind, unit = kind_and_unit(name)
            kinds.append(KIND_INDEX[kind])
            omega.append(2.0 * math.pi * p.f / scenario.speed)
            scale.append(p.amplitude * kind_scale(kind, unit, scenario.track.half_gauge))
    return Columns(np.array(kinds, dtype=np.int64), np.array(omega), np.array(scale),
                   np.array(freqs, dtype=np.int64), np.array([by[(k, 0)].df for k in freqs]), len(types))


# ===================================================================================== the setup
@dataclass(frozen=True)
class ChannelMap:
    """Sources of the output channels (in ``names`` order): (channel, global coordinate, order) of
    node channels, (channel, station shape row over the modes, order) of bridge channels,
    (channel, contact row) of contact forces; moving point loads are zero without gravity."""

    names: tuple[str, ...]
    units: tuple[str, ...]
    node: tuple[tuple[int, int, int], ...]
    bridge: tuple[tuple[int, FloatArray, int], ...]
    contact: tuple[tuple[int, int], ...]


class BatchedModel:
    """What a worker builds once: the Exudyn model and its linear form, the components, the
    generalized-alpha coefficients, the step grid and the channel map; and the once-only checks of
    the contact description (``check``: largest relative differences, must be round-off)."""

    def __init__(self, scenario: Scenario, spectral_radius: float | None = None, wheel_forces: bool = False,
                 linearization: str = "rest") -> None:
        """``wheel_forces``: also output every vertical wheel-rail force (``*.force_z``) the scenario's
        channels leave out, after the selected channels (the Monte Carlo loss-of-contact check).
        ``linearization``: "rest" or "static" (:mod:`.batched_model`)."""
        from ..builder import build_model

        self.scenario = scenario
        self.wheel_forces = wheel_forces
        with single_threaded_blas():
            self.model = build_model(scenario, warn=False)
            self.lin = LinearTrainBridge(self.model, linearization)
            cp = self.lin.coupling
            self.n_steps, self.ratio, h = output_times(scenario)
            rho = scenario.analysis.spectral_radius if spectral_radius is None else spectral_radius
            self.alpha = GeneralizedAlpha(float(rho), h)
            self.output_time = np.arange(self.n_steps // self.ratio + 1) * (h * self.ratio)
            self.components = find_components(self.lin, self.output_time)
            t_mid = _most_axles_on_bridge(cp, self.output_time)
            t_taper = 0.5 * cp.taper_length / cp.speed if cp.taper_length > 0 else t_mid
            self.check = {
                "coupling": self.lin.check_coupling(t_mid),
                "inputs": max(self.lin.check_inputs(t, kind, 0.7, 1.0) for t in (t_taper, t_mid) for kind in range(3)),
            }
        if max(self.check.values()) > CHECK_TOLERANCE:
            raise RuntimeError(f"the batched engine's contact description disagrees with the coupling: {self.check}")
        self.channels = self._channel_map()

    @property
    def n_selected(self) -> int:
        """Number of the scenario's channels (the first of ``channels.names``)."""
        return len(self.model.selected)

    @property
    def force_channels(self) -> list[Any]:
        """The vertical wheel-rail force channels (``*.force_z``) of the channel map."""
        return [c for c in self._outputs if c.name.endswith(".force_z")]

    def _channel_map(self) -> ChannelMap:
        model = self.model
        node, bridge, contact = [], [], []
        shapes = model.bridge.station_shapes
        self._outputs = list(model.selected)
        if self.wheel_forces:
            self._outputs += [c for c in model.channels if c.name.endswith(".force_z") and c not in model.selected]
        for i, ch in enumerate(self._outputs):
            if ch.source == "node":
                node.append((i, int(model.node_indices(ch.index)[ch.coordinate]), ch.order))
            elif ch.source == "bridge":
                bridge.append((i, shapes[ch.index, ch.coordinate], ch.order))
            elif ch.source == "contact":
                contact.append((i, ch.index))
        return ChannelMap(tuple(c.name for c in self._outputs), tuple(c.unit for c in self._outputs),
                          tuple(node), tuple(bridge), tuple(contact))

    def describe(self) -> dict[str, Any]:
        """Provenance: components, generalized-alpha parameters, checks."""
        ga = self.alpha
        return {
            "linearization": self.lin.linearization,
            "generalized_alpha": {"spectral_radius": ga.rho, "alpha_m": ga.alpha_m, "alpha_f": ga.alpha_f,
                                  "gamma": ga.gamma, "beta": ga.beta, "time_step_s": ga.h, "steps": self.n_steps},
            "components": [{"coordinates": c.size, "bridge_modes": c.n_bridge, "contacts": int(c.rows.size),
                            "kinds": [("vertical", "alignment", "cross_level")[k] for k in c.kinds]}
                           for c in self.components],
            "coordinates": self.lin.n,
            "contact_check": self.check,
        }


def _most_axles_on_bridge(coupling, times: FloatArray) -> float:  # noqa: ANN001
    counts = [np.count_nonzero((x >= 0) & (x <= coupling.bridge.length)) for x in map(coupling.positions, times)]
    return float(times[int(np.argmax(counts))])


# =============================================================================== one component
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

    def __init__(self, bm: BatchedModel, comp: Component, cols: IntArray, source: Any) -> None:
        lin, ga = bm.lin, bm.alpha
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
        self.input = source.run_inputs(self, cols, cp)  # k r + c r' of the rows, per step
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
        nu_a, nu_d, rho_a, rho_d, mu_a, mu_d = coef
        r0 = 0 if self.bridge_moving else self.nb  # the bridge's rows are zero while it is at rest
        qp, vp, ap, dl = (X[r0:].reshape(-1) for X in (self.QP, self.VP, self.AP, self.DL))
        daxpy(vp, qp, a=h)
        daxpy(ap, qp, a=nu_a)
        daxpy(dl, qp, a=nu_d)
        daxpy(ap, vp, a=rho_a)
        daxpy(dl, vp, a=rho_d)
        dscal(mu_a, ap)
        daxpy(dl, ap, a=mu_d)


class _HarmonicInputs:
    """k r + c r' of a run's contact rows for harmonic (PEM) columns: r_c = P0 exp(i Omega v t) w(x_c),
    so k r + c r' = w Qss z + c v w' P0 z with z = exp(i Omega v t) (``Columns.at``)."""

    def __init__(self, run: _Run, columns: Columns, cols: IntArray, coupling) -> None:  # noqa: ANN001
        self.sel, self.axle = run.sel, run.axle
        omega = columns.omega[cols]
        x0 = coupling.positions(0.0)[run.axle] - float(coupling.axle_start[0])
        W = coupling.contacts.input_map[np.ix_(run.rows, columns.kinds[cols])] * columns.scale[cols][None, :]
        self.P0 = W * np.exp(1j * np.outer(x0, omega))
        self.cv = run.c[:, 0] * coupling.speed
        self.Qss = self.P0 * (run.k + 1j * self.cv[:, None] * omega[None, :])

    def __call__(self, step: "_Step", z_all: ComplexArray, out: ComplexArray) -> None:
        z = z_all[self.sel]
        np.multiply(self.Qss, z, out=out)
        if step.steady:
            return
        out *= step.w[self.axle][:, None]
        dwr = step.dw[self.axle]
        idx = np.flatnonzero(dwr)
        if idx.size:
            out[idx] += (self.cv[idx] * dwr[idx])[:, None] * (self.P0[idx] * z)


class _Outputs:
    """Where a component's state goes at an output time, in an internal channel order that makes
    its node channels of one order a contiguous block of rows (written without scatter): row
    gathers of (q, v, qdd), station-shape products over its modes (bridge channels, summed over
    components) and its contact forces. With components sharing a contact row, each one's force
    f_I = k (B_I u_I + r) + c (...) carries the input k r + c r' once: the true force is
    sum_I f_I - (n - 1) (k r + c r') for n components integrating that column."""

    def __init__(self, bm: BatchedModel, run: _Run, overlap: NDArray[np.int64], order: list[int],
                 bridge_rows: dict[int, int], contact_rows: dict[int, int]) -> None:
        cm = bm.channels
        local = {int(gi): j for j, gi in enumerate(run.comp.coords)}
        self.node = []
        for o in range(3):
            pairs = [(i, local[g]) for i, g, oo in cm.node if oo == o and g in local]
            start = len(order)
            order.extend(i for i, _ in pairs)
            self.node.append((start, len(order), np.array([j for _, j in pairs], dtype=np.int64)))
        self.bridge = []
        for o in range(3):
            items = [(bridge_rows[i], s[run.modes]) for i, s, oo in cm.bridge if oo == o and np.any(s[run.modes] != 0)]
            self.bridge.append((np.array([r for r, _ in items], dtype=np.int64),
                                np.array([s for _, s in items]).reshape(len(items), run.nb)))
        rowpos = {int(r): j for j, r in enumerate(run.rows)}
        pairs = [(contact_rows[i], rowpos[r]) for i, r in cm.contact if r in rowpos]
        self.contact = (np.array([i for i, _ in pairs], dtype=np.int64),
                        np.array([j for _, j in pairs], dtype=np.int64))
        n = overlap[np.ix_(run.rows[self.contact[1]], run.cols)].astype(float)
        self.shared = (n - 1.0) / np.maximum(n, 1.0) if np.any(n > 1) else None
        self.x = np.zeros((3, *run.QP.shape))

    def write(self, run: _Run, Y: ComplexArray, ga: GeneralizedAlpha, first: bool) -> None:
        """Write (node channels) or add (bridge, contact) the component's part at this output time."""
        Yf = Y.view(np.float64)
        x = self.x  # (q, v, qdd) of the component: q~ + D, v~ + gamma' D, beta' D
        if first:
            x[:2] = 0.0
            x[2] = run.qdd0
        else:
            np.add(run.QP, run.DL, out=x[0])
            np.multiply(run.DL, ga.gamma_p, out=x[1])
            x[1] += run.VP
            np.multiply(run.DL, ga.beta_p, out=x[2])
        all_cols = isinstance(run.sel, slice)
        for o, (s, e, loc) in enumerate(self.node):
            if e > s:
                if all_cols:
                    np.take(x[o], loc, axis=0, out=Yf[s:e])
                else:
                    Y[s:e, run.sel] = x[o][loc].view(complex)
        for o, (rows, shp) in enumerate(self.bridge):
            if rows.size:
                _add(Y, rows, run.sel, (shp @ x[o][: run.nb]).view(complex))
        rows, loc = self.contact
        if rows.size:
            f = run.F[loc].view(complex)
            _add(Y, rows, run.sel, f if self.shared is None else f - self.shared * run.R[loc])


def _add(Y: ComplexArray, rows: IntArray, sel: Any, values: ComplexArray) -> None:
    if isinstance(sel, slice):
        Y[rows] += values
    else:
        Y[np.ix_(rows, sel)] += values


# ============================================================================= the integration
def integrate_columns(bm: BatchedModel, columns: Columns, keep_psd: bool = True) -> dict[str, np.ndarray]:
    """Integrate pseudo-excitation columns over the crossing and reduce them at every output time.

    Returns
    -------
    dict: ``var_t`` (n_t, n_types, n_ch) sum over the columns' frequencies of |y~|^2 per type;
    ``psd`` (n_ch, n_f, n_t) sum over types of |y~|^2 / df (with keep_psd), in ``PSD_TRANSPORT``
    precision; ``freq_index`` (n_f,).
    """
    with single_threaded_blas():
        reducer = PsdReducer(columns, len(bm.channels.names), bm.output_time.size, keep_psd)
        return integrate(bm, columns, reducer)


class PsdReducer:
    """PEM's reduction at an output time: |y~|^2 summed per type (sigma^2) and, with ``keep_psd``,
    summed over types and divided by df (the PSD map, gathered in blocks of output times)."""

    def __init__(self, columns: Columns, n_ch: int, n_t: int, keep_psd: bool) -> None:
        m, n_f, nty = columns.width, columns.freq_index.size, columns.n_types
        self.columns = columns
        self.var = np.zeros((n_t, nty, n_ch))
        self.psd = np.zeros((n_ch, n_f, n_t), dtype=PSD_TRANSPORT) if keep_psd else None
        self.per_freq = np.zeros((n_ch, n_f))
        self.block = np.zeros((n_ch, n_f, PSD_BLOCK), dtype=PSD_TRANSPORT)  # output times gathered before a write
        self.P2, self.power = np.zeros((n_ch, 2 * m)), np.zeros((n_ch, m))
        self.type_sum = np.zeros((m, nty))  # (m, n_types): which type each column is
        self.type_sum[np.arange(m), np.arange(m) % nty] = 1.0
        self.by_type = np.zeros((n_ch, nty))
        self.inv_df = 1.0 / columns.df
        self.n_t = n_t

    def record(self, i: int, Y: ComplexArray, ext: IntArray) -> None:
        """Reduce the columns' outputs Y (internal channel order; ``ext``: internal row of each channel)."""
        P2, power, nty = self.P2, self.power, self.columns.n_types
        np.multiply(Y.view(np.float64), Y.view(np.float64), out=P2)
        np.add(P2[:, 0::2], P2[:, 1::2], out=power)  # |y~|^2 (no reductions over short axes: slow)
        np.matmul(power, self.type_sum, out=self.by_type)
        self.var[i] = self.by_type[ext].T
        if self.psd is not None:
            per_freq = self.per_freq
            p3 = power.reshape(power.shape[0], -1, nty)
            per_freq[:] = p3[:, :, 0]
            for ti in range(1, nty):
                np.add(per_freq, p3[:, :, ti], out=per_freq)
            np.multiply(per_freq, self.inv_df, out=per_freq)
            self.block[:, :, i % PSD_BLOCK] = per_freq[ext]
            if i % PSD_BLOCK == PSD_BLOCK - 1 or i == self.n_t - 1:  # a strided write per time: 3x slower
                i0 = i - i % PSD_BLOCK
                self.psd[:, :, i0:i + 1] = self.block[:, :, : i + 1 - i0]

    def result(self) -> dict[str, np.ndarray]:
        out = {"var_t": self.var, "freq_index": self.columns.freq_index}
        if self.psd is not None:
            out["psd"] = self.psd
        return out


def integrate(bm: BatchedModel, source: Any, reducer: Any) -> dict[str, np.ndarray]:
    """Integrate the columns of ``source`` over the crossing, handing the outputs of every output
    time to ``reducer.record(i, Y, ext)``; returns ``reducer.result()`` and the run's provenance.

    ``source`` is a column source: ``width`` (number of complex columns), ``columns_for(kinds)``
    (the columns a component excited by those kinds integrates), ``at(step, speed)`` (what the
    inputs of every column need at a step, computed once per step) and ``run_inputs(run, cols,
    coupling)`` (a callable filling k r + c r' of a run's contact rows). PEM's :class:`Columns`
    (harmonic) and :class:`~.batched_mc.SampleColumns` (sampled profiles) are the two.
    """
    lin, ga, cm = bm.lin, bm.alpha, bm.channels
    cp = lin.coupling
    n_ch, m = len(cm.names), source.width
    runs = [_Run(bm, comp, cols, source) for comp in bm.components if (cols := source.columns_for(comp.kinds)).size]
    overlap = np.zeros((lin.k.size, m), dtype=np.int64)  # components integrating (contact row, column)
    for run in runs:
        overlap[np.ix_(run.rows, run.cols)] += 1
    # internal channel order: node channels per component and order, bridge, contacts, the rest
    bridge_ch = [i for o in range(3) for i, _, oo in cm.bridge if oo == o]
    contact_ch = [i for i, _ in cm.contact]
    integrated = {int(g) for r in runs for g in r.comp.coords}
    shared0 = sum(1 for _, g, _ in cm.node if g in integrated)  # node channels come first
    bridge_rows = {i: shared0 + j for j, i in enumerate(bridge_ch)}
    contact_rows = {i: shared0 + len(bridge_ch) + j for j, i in enumerate(contact_ch)}
    order: list[int] = []
    outs = [_Outputs(bm, r, overlap, order, bridge_rows, contact_rows) for r in runs]
    order += bridge_ch + contact_ch
    order += sorted(set(range(n_ch)) - set(order))  # moving loads and channels no input reaches: zero
    ext = np.argsort(np.array(order, dtype=np.int64))  # internal row of each channel
    shared_rows = slice(shared0, n_ch)  # summed over components: cleared at every output time
    Y = np.zeros((n_ch, m), dtype=complex)

    def record(i: int, first: bool) -> None:
        Y[shared_rows] = 0.0
        for run, out in zip(runs, outs):
            out.write(run, Y, ga, first)
        reducer.record(i, Y, ext)

    coef = ga.update_coefficients()
    h = ga.h
    x_ref, length = float(cp.axle_start[0]), cp.bridge.length

    taper_end = (x_ref + cp.taper_length - float(cp.positions(0.0).min())) / cp.speed
    ones, zeros = np.ones(cp.axle_start.size), np.zeros(cp.axle_start.size)

    def step_at(t: float) -> _Step:
        x = cp.positions(t)
        on = (x >= 0.0) & (x <= length)
        st = cp.contact_state(t) if on.any() else None  # off the bridge the rail shapes are zero
        if t >= taper_end:
            w, dw = ones, zeros
        else:
            w, dw = taper(x, x_ref, cp.taper_length)
        return _Step(t, cp.speed, x, on, None if st is None else st.S, None if st is None else st.dS,
                     w, dw, t >= taper_end, not (w.any() or dw.any()))

    step = step_at(0.0)
    shared = source.at(step, cp.speed)
    for run in runs:
        run.start(step, shared, ga)
    record(0, True)
    for n in range(1, bm.n_steps + 1):
        step = step_at(n * h)
        shared = source.at(step, cp.speed)
        rec = n % bm.ratio == 0
        for run in runs:
            run.solve(step, shared, rec)
        if rec:
            record(n // bm.ratio, False)
        for run in runs:
            run.update(coef, h)
    return {
        **reducer.result(),
        "contact_check": np.array([bm.check["coupling"], bm.check["inputs"]]),
        "components": np.array([[c.size, c.n_bridge, c.rows.size, sum(1 << k for k in c.kinds)] for c in bm.components],
                               dtype=np.int64).reshape(-1, 4),
        "alpha": np.array([ga.rho, ga.alpha_m, ga.alpha_f, ga.gamma, ga.beta, ga.h]),
    }


# =================================================================================== the driver
@dataclass(frozen=True)
class BatchedTask:
    """A slice of the sweep's columns (every type of a set of frequencies), integrated together."""

    columns: tuple[PemTask, ...]
    keep_psd: bool


@dataclass(frozen=True)
class MeanTask:
    """The mean: Exudyn's deterministic run (gravity, static start, no irregularity) on the worker's
    built model, the very run of the Exudyn engine."""


def _setup(scenario: Scenario, linearization: str = "rest") -> BatchedModel:
    return BatchedModel(scenario, linearization=linearization)


def _work(bm: BatchedModel, task: Task) -> dict[str, np.ndarray]:
    if isinstance(task.data, MeanTask):
        return _mean(bm)
    data: BatchedTask = task.data
    return integrate_columns(bm, task_columns(data.columns, bm.scenario), data.keep_psd)


def _mean(bm: BatchedModel) -> dict[str, np.ndarray]:
    """The deterministic run as plain arrays (checkpointable): values, time, names, units, the run's
    provenance (JSON) and the scenario's warnings."""
    from .deterministic import run_deterministic

    from ..system.channels import evaluate

    start = _time.perf_counter()
    th = run_deterministic(bm.scenario, model=bm.model)
    forces = bm.force_channels if bm.wheel_forces else []
    if forces:  # the wheel forces of the run, selected or not (Monte Carlo's loss-of-contact check)
        values = evaluate(forces, bm.model.recording(), bm.model.bridge.station_shapes)
        force_mean = np.stack([values[c.name] for c in forces])
    else:
        force_mean = np.zeros((0, th.time.size))
    bm.model.set_gravity(False)  # back to the sweep's state (the batched engine reads only the coupling)
    bm.model.set_excitation(None)
    return {
        "force_mean": force_mean,
        "mean": np.stack([th.channels[c] for c in th.names]), "time": th.time,
        "names": np.array(th.names, dtype=str), "units": np.array([th.units[c] for c in th.names], dtype=str),
        "provenance": np.array(json.dumps(th.provenance, default=json_default)),
        "warnings": np.array(bm.model.warnings, dtype=str).reshape(-1),
        "seconds": np.array(_time.perf_counter() - start),
    }


def column_slices(ptasks: Sequence[PemTask], weights: Sequence[float], keep_psd: bool) -> list[Task]:
    """The sweep's (type, frequency) pairs cut into tasks of contiguous frequencies (all types of a
    frequency in the same task) with numbers of frequencies in proportion to ``weights``."""
    freqs = np.array(sorted({p.freq_index for p in ptasks}))
    w = np.asarray(weights, dtype=float)[: freqs.size]
    edges = np.unique(np.round(np.concatenate(([0.0], np.cumsum(w) / w.sum())) * freqs.size).astype(int))
    out = []
    for a, b in zip(edges[:-1], edges[1:]):
        chosen = set(freqs[a:b].tolist())
        cols = tuple(p for p in ptasks if p.freq_index in chosen)
        out.append(Task(f"pemb-{freqs[a]:05d}-{freqs[b - 1]:05d}", BatchedTask(cols, keep_psd)))
    return out


def default_slices(cores: int) -> list[float]:
    """Slice weights: one per core and a half one. With the mean as the first task, on as many workers
    as cores the worker that runs the mean takes a full slice after it and another the half slice:
    the work evens out without oversubscribing the cores (the mean costs about half a slice's
    share: one Exudyn run against the batched columns)."""
    return [1.0] * max(1, cores) + [0.5]


def run_pem_batched(
    scenario: Scenario,
    workers: int | None = None,
    executor: Any = None,
    out: str | Path | None = None,
    resume: bool = False,
    progress: bool = True,
    keep_psd: bool = True,
    slices: Sequence[float] | None = None,
    linearization: str = "rest",
) -> RandomResponse:
    """The PEM sweep with the batched engine; arguments and result as :func:`~.pem.run_pem`.

    The tasks are the mean (Exudyn's deterministic run, as in the Exudyn engine) and slices of the
    columns, each integrating all its columns at once.

    Parameters
    ----------
    slices : relative sizes of the column slices (default :func:`default_slices` of the number of
        cores). Results depend on the slicing only at round-off level, and the slicing not on
        ``workers`` or ``executor``: a result is bitwise the same for any number of workers, any
        executor and after a resume. Give more slices for an executor with more workers.
    linearization : "rest" (default: the Exudyn engine's model) or "static" (about the static
        equilibrium under gravity, with the suspensions' preload stiffness: see :mod:`.batched_model`)
    """
    t0 = _time.perf_counter()
    check_linearization(linearization)
    key = {"method": "pem", "engine": "batched"} | ({} if linearization == "rest" else {"linearization": linearization})
    grid, spectra, out, checkpoint = prepare_sweep(scenario, out, resume, key)
    ptasks = [t.data for t in pem_tasks(scenario, grid)]
    tasks = [Task("pemb-mean", MeanTask())]
    tasks += column_slices(ptasks, default_slices(_cores()) if slices is None else slices, keep_psd)
    n_types = len(spectra)
    state: dict[str, Any] = {"check": 0.0}

    def allocate(n_ch: int, n_t: int) -> None:
        """The result arrays, touched once: the kernel maps and zeroes the PSD map's pages (0.5 s
        for the reference study's 420 MB) when the mean arrives, while the workers still compute."""
        if "var" not in state:
            state["var"] = np.zeros((n_types, n_ch, n_t))
            state["psd"] = np.zeros((n_ch, grid.f.size, n_t)) if keep_psd else None
            if keep_psd:
                state["psd"].fill(0.0)

    def reduce(i: int, task: Task, result: dict[str, np.ndarray]) -> None:
        if isinstance(task.data, MeanTask):
            state["mean"] = result
            allocate(result["mean"].shape[0], result["mean"].shape[1])
            for message in result["warnings"]:
                warnings.warn(str(message), stacklevel=4)
            return
        var_t = result["var_t"]
        var = state["var"]
        if var_t.shape != (var.shape[2], n_types, var.shape[1]):
            raise RuntimeError(f"task {task.key}: result shape {var_t.shape} does not fit the mean's {var.shape[1:]}")
        var += var_t.transpose(1, 2, 0)
        state["check"] = max(state["check"], float(np.max(result["contact_check"])))
        state["components"] = [
            {"coordinates": int(n), "bridge_modes": int(b), "contacts": int(c),
             "kinds": [kind for j, kind in enumerate(("vertical", "alignment", "cross_level")) if mask >> j & 1]}
            for n, b, c, mask in result["components"]
        ]
        state["alpha"] = dict(zip(("spectral_radius", "alpha_m", "alpha_f", "gamma", "beta", "time_step_s"),
                                  map(float, result["alpha"])))
        if state["psd"] is not None:  # the slices partition the frequencies: each is written once
            k = result["freq_index"]
            if k.size and np.array_equal(k, np.arange(k[0], k[0] + k.size)):
                state["psd"][:, k[0]:k[0] + k.size, :] = result["psd"]  # into a view: no temporary
            else:
                state["psd"][:, k, :] = result["psd"]

    stats = run_tasks(
        tasks, setup=_setup, setup_args=(scenario, linearization), work=_work, reduce=reduce, workers=workers,
        executor=executor, checkpoint=checkpoint, progress=progress, desc="PEM (batched)",
    )
    mean = state["mean"]
    channels = tuple(str(c) for c in mean["names"])
    provenance = {
        **json.loads(str(mean["provenance"])),
        "engine": "batched",
        "mean_engine": "exudyn",
        "method": "pem",
        "linearization": linearization,
        "seconds": _time.perf_counter() - t0,
        "mean_seconds": float(mean["seconds"]),
        "n_frequencies": int(grid.f.size),
        "n_frequencies_in_band": int(band_mask(grid, scenario).sum()),
        "quadrature": grid.rule,
        "columns": len(ptasks),
        "contact_check": state["check"],
        "components": state.get("components", []),
        "generalized_alpha": state.get("alpha", {}),
        **stats,
    }
    var_by_type, psd = state["var"], state["psd"]
    result = RandomResponse(
        method="pem", time=mean["time"], channels=channels, units=tuple(str(u) for u in mean["units"]),
        mean=mean["mean"], std=np.sqrt(var_by_type.sum(axis=0)), band=grid.band, scenario=scenario,
        freq=grid.f, df=grid.df, psd=psd, var_by_type=var_by_type, types=tuple(spectra), provenance=provenance,
    )
    if out is not None:
        result.save(Path(out) / "pem")
    return result


def check_linearization(linearization: str) -> None:
    """ScenarioError (a user error: exit 2 in the CLI) for an unknown linearization point."""
    if linearization not in LINEARIZATIONS:
        raise ScenarioError(None, "linearization", linearization, " or ".join(LINEARIZATIONS),
                            "unknown linearization point of the batched engine")


def _cores() -> int:
    return os.cpu_count() or 1
