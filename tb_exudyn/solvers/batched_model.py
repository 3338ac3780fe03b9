"""The linear train-bridge model of the batched engine, taken from the built Exudyn system.

One physics, two integrators: the batched engine reads the very objects the Exudyn runs use.

- M, K0, D0: ``TrainBridgeModel.linearized_system(0)`` (Exudyn's ``ComputeLinearizedSystem``) at
  t = 0, when every axle stands on the rigid approach track, minus the coupling's own Jacobians at
  that time (``WheelRailCoupling.jacobians`` in ``frozen(0)``): the vehicles, the bridge's modal
  matrices and the weak springs, without the wheel-rail contact. For the models the builder makes,
  M is diagonal, the bridge block diagonal and every vehicle an independent block.
- The linearization point (``LINEARIZATIONS``): ``"rest"`` (default), the unloaded reference
  configuration, the state of the Exudyn engine's pseudo-runs (gravity off, from rest), so that
  both PEM engines integrate the same model; or ``"static"``, the static equilibrium under gravity
  on the approach (``static_state(0)``), where K also holds the geometric stiffness of the
  suspensions' preload (the car body's weight acting above its springs lowers its roll stiffness,
  m g h). The Exudyn model with gravity has that stiffness, so the Exudyn Monte Carlo (samples run
  with gravity) agrees with "static"; the Exudyn PEM engine cannot linearise there.
- The contact at time t: ``WheelRailCoupling.contact_state(t)`` (S, dS, B) with the layout's
  stiffness k, damping c and wheel map G, i.e. the contact forces f = k (B u + r) + c (B u' +
  v dS q_b + r') and generalised forces -B^T f of the Exudyn user functions.
  :meth:`LinearTrainBridge.check_coupling` compares this description once with the coupling's
  ``forces`` and ``jacobians``; :meth:`LinearTrainBridge.check_inputs` the pseudo-inputs with
  :func:`~tb_exudyn.system.excitation.rail_inputs`.

Independent components: the graph of the nonzero entries of M, K0, D0 and of the coupling's
Jacobians (including the convective term, at every output time: :func:`coupling_pattern`) splits
the coordinates into independent parts; for a symmetric car on a symmetric track, the vertical in-plane and the
lateral out-of-plane motions (the left and right wheel contacts' cross terms cancel). A part no
irregularity kind reaches (longitudinal coordinates, wheelset spin and yaw, pier modes without
rail motion) stays at rest and is not integrated at all. Entries below 1e-12 of the largest
coupling entry are taken as zero (round-off of cancelling terms; a coupling that small changes no
response by more than 1e-12 relative).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import connected_components

from ..system.excitation import KINDS, HarmonicExcitation, rail_inputs, taper

#: linearization points of the batched engine (see the module docstring)
LINEARIZATIONS: tuple[str, ...] = ("rest", "static")
#: entries of the coupling below this fraction of its largest entry count as zero (round-off)
COUPLING_ZERO = 1e-12
#: largest relative difference the one-time checks of the contact description against the coupling
#: object accept (the same formulas: round-off, measured below 1e-15)
CHECK_TOLERANCE = 1e-9

IntArray = NDArray[np.int64]
FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class VehiclePart:
    """A vehicle's coordinates inside a component: a contiguous local range, its dense diagonal
    blocks (local ranges) and its contact rows (a contiguous range of the component's rows)."""

    start: int
    stop: int
    blocks: tuple[tuple[int, int], ...]
    row_start: int
    row_stop: int


@dataclass(frozen=True)
class Component:
    """An independent part of the system.

    Attributes
    ----------
    coords : (n,) global ODE2 indices in local order: bridge modes first, then the vehicles
    n_bridge : number of bridge modes (local 0 .. n_bridge-1)
    modes : (n_bridge,) their indices among the bridge's modes
    vehicles : the vehicle parts (local coordinate ranges and contact rows)
    rows : (n_rows,) the contact rows (layout indices) acting on the component, in layout order
    kinds : indices into ``KINDS`` of the irregularity kinds that excite the component
    """

    coords: IntArray
    n_bridge: int
    modes: IntArray
    vehicles: tuple[VehiclePart, ...]
    rows: IntArray
    kinds: tuple[int, ...]

    @property
    def size(self) -> int:
        return int(self.coords.size)


class LinearTrainBridge:
    """M, K0, D0 (coupling left out) and the coupling of a built :class:`TrainBridgeModel`.

    The model is switched to no excitation and no gravity (the pseudo-excitation runs' state).

    Attributes
    ----------
    model : the built model; ``coupling`` its wheel-rail coupling
    M, K0, D0 : (n, n) global matrices without the contact, at the linearization point
    bridge : (n_b,) global indices of the bridge's modal coordinates
    wheel : (n_w,) global indices of the coupling's wheel coordinates
    k, c : (n_c,) contact stiffness and damping; G (n_c, n_w) the wheel map
    """

    def __init__(self, model, linearization: str = "rest") -> None:  # noqa: ANN001 - TrainBridgeModel (Exudyn)
        if linearization not in LINEARIZATIONS:
            raise ValueError(f"linearization must be one of {', '.join(map(repr, LINEARIZATIONS))}, got {linearization!r}")
        self.model = model
        self.linearization = linearization
        cp = model.coupling
        self.coupling = cp
        model.set_excitation(None)
        if cp.contact_state(0.0).on_bridge:
            raise ValueError("an axle stands on the bridge at t = 0: the batched engine needs a lead-in")
        state = None
        if linearization == "static":
            model.set_gravity(True)
            state = model.static_state(0.0)
        model.set_gravity(False)
        M, K, D = model.linearized_system(0.0, state)
        with cp.frozen(0.0):
            Kc, Dc = cp.jacobians(0.0)
        ci = model.coupling_indices()
        self.M = M
        self.K0 = _without(K, Kc, ci)
        self.D0 = _without(D, Dc, ci)
        self.n = int(M.shape[0])
        self.bridge = ci[: cp.n_bridge]
        self.wheel = ci[cp.n_bridge:]
        self.k = cp.contacts.stiffness
        self.c = cp.contacts.damping
        self.G = cp.contacts.wheel_map
        model.reset("rest")

    # ------------------------------------------------------------------ one-time checks
    def check_coupling(self, t: float) -> float:
        """Largest relative difference between the contact description used by the batched engine
        (f = k (B u + r) + c (B u' + v dS q_b + r'), Q = -B^T f; K = B^T (k B + c v [dS, 0]),
        D = B^T c B) and the coupling's ``forces`` and ``jacobians`` at time t, for random u, u'."""
        cp = self.coupling
        st = cp.contact_state(t)
        rng = np.random.default_rng(0)
        u, ud = rng.standard_normal(cp.n) * 1e-3, rng.standard_normal(cp.n) * 1e-2
        nb = cp.n_bridge
        B = np.hstack((st.S, -self.G))
        f = self.k * (B @ u + st.r) + self.c * (B @ ud + st.speed * (st.dS @ u[:nb]) + st.r_dot)
        Kc, Dc = cp.jacobians(t)
        K = B.T @ (self.k[:, None] * B)
        K[:, :nb] += st.speed * (B.T @ (self.c[:, None] * st.dS))
        D = B.T @ (self.c[:, None] * B)
        Q = cp.forces(t, u, ud)
        return max(_rel(-(B.T @ f), Q), _rel(K, Kc), _rel(D, Dc))

    def check_inputs(self, t: float, kind: int, omega: float, scale: float) -> float:
        """Largest relative difference between the complex pseudo-input of :func:`pseudo_inputs`
        and the real and imaginary harmonic runs' inputs ``rail_inputs`` (via the coupling)."""
        cp = self.coupling
        r, r_dot = pseudo_inputs(cp, t, np.array([kind]), np.array([omega]), np.array([scale]))
        err = 0.0
        for part, pick in (("real", np.real), ("imag", np.imag)):
            exc = HarmonicExcitation(kind=KINDS[kind], spatial_frequency=omega, amplitude=1.0, part=part)
            x = cp.positions(t)
            val, slo = rail_inputs(exc, x, float(cp.axle_start[0]), cp.half_gauge, cp.taper_length)
            W = cp.contacts.input_map
            a = cp.contacts.axle
            ref = scale * np.einsum("ck,kc->c", W, val[:, a])
            ref_dot = scale * cp.speed * np.einsum("ck,kc->c", W, slo[:, a])
            err = max(err, _rel(pick(r[:, 0]), ref), _rel(pick(r_dot[:, 0]), ref_dot))
        return err


def _without(A: FloatArray, Ac: FloatArray, ci: IntArray) -> FloatArray:
    """A with the coupling's block Ac removed on the coupling indices; round-off of the
    subtraction (below 1e-13 of the entries involved) set to exact zero."""
    out = np.array(A, dtype=float, copy=True)
    block = out[np.ix_(ci, ci)] - Ac
    noise = 1e-13 * (np.abs(out[np.ix_(ci, ci)]) + np.abs(Ac))
    block[np.abs(block) <= noise] = 0.0
    out[np.ix_(ci, ci)] = block
    return out


def _rel(a: FloatArray, b: FloatArray) -> float:
    scale = max(float(np.max(np.abs(b), initial=0.0)), 1e-300)
    return float(np.max(np.abs(np.asarray(a) - np.asarray(b)), initial=0.0)) / scale


# ====================================================================================== inputs
def pseudo_inputs(
    coupling, t: float, kinds: IntArray, omegas: FloatArray, scales: FloatArray  # noqa: ANN001
) -> tuple[NDArray[np.complex128], NDArray[np.complex128]]:
    """Complex pseudo-inputs r, r' (n_c, m) of m harmonic columns at time t.

    Column j is the input of kind ``kinds[j]`` (index into KINDS) of unit amplitude times
    ``scales[j]`` (e.g. the pseudo-amplitude, divided by 2 b for a cross-level height):
    r_c = W[c, kind] s w(x_c) exp(i Omega (x_c - x_ref)), the real part being the cosine run's input
    and the imaginary part the sine run's; r'_c = v W s (w' + i Omega w) exp(...). x_c is the
    position of contact c's axle, x_ref the first axle's start and w the approach taper
    (:func:`~tb_exudyn.system.excitation.taper`).
    """
    x = coupling.positions(t)
    w, dw = taper(x, float(coupling.axle_start[0]), coupling.taper_length)
    a = coupling.contacts.axle
    W = coupling.contacts.input_map[:, kinds] * scales[None, :]
    phase = np.exp(1j * omegas[None, :] * (x[a] - float(coupling.axle_start[0]))[:, None])
    r = W * w[a, None] * phase
    r_dot = coupling.speed * W * (dw[a, None] + 1j * omegas[None, :] * w[a, None]) * phase
    return r, r_dot


# ================================================================================== components
def coupling_pattern(lin: LinearTrainBridge, times: FloatArray) -> tuple[NDArray[np.bool_], NDArray[np.bool_]]:
    """Nonzero pattern of the coupling's Jacobians (n_loc, n_loc) over the given times, and of the
    contact rows' gap maps B (n_c, n_loc).

    The Jacobians' pattern is that of sum_t rho_t J(t) for two draws of random weights rho_t in
    [1, 2] (a stacked product instead of one Jacobian per time): an entry cancels across times only
    with probability zero, while the exact cancellations within a time (left and right wheel) stay
    at round-off, below the threshold.
    """
    cp = lin.coupling
    nb = cp.n_bridge
    rng = np.random.default_rng(2)
    K = np.zeros((2, cp.n, cp.n))
    D = np.zeros((2, cp.n, cp.n))
    rows = np.zeros((cp.n_contacts, cp.n))
    for chunk in np.array_split(np.asarray(times, dtype=float), max(1, len(times) // 128)):
        states = [cp.contact_state(float(t)) for t in chunk]
        Bs = np.concatenate([st.B for st in states])
        dSs = np.concatenate([st.speed * st.dS for st in states])
        rows += sum(np.abs(st.B) + np.abs(np.hstack((st.dS, np.zeros_like(lin.G)))) for st in states)
        for d in range(2):
            rho = np.repeat(1.0 + rng.random(len(states)), cp.n_contacts)
            kw = (rho * np.tile(lin.k, len(states)))[:, None]
            cw = (rho * np.tile(lin.c, len(states)))[:, None]
            K[d] += Bs.T @ (kw * Bs)
            K[d][:, :nb] += Bs.T @ (cw * dSs)
            D[d] += Bs.T @ (cw * Bs)
    pattern = np.zeros((cp.n, cp.n), dtype=bool)
    for X in (*K, *D):
        pattern |= np.abs(X) > COUPLING_ZERO * np.abs(X).max(initial=0.0)
    return pattern | pattern.T, rows > COUPLING_ZERO * rows.max(initial=0.0)


def excited_coordinates(lin: LinearTrainBridge, times: FloatArray) -> NDArray[np.bool_]:
    """(3, n) whether an input of each kind reaches each global coordinate at any of the times:
    the generalised input forces B^T (k r) and B^T (c r) with the same random value of r at all
    contacts of an axle (which sit at the same x)."""
    cp = lin.coupling
    rng = np.random.default_rng(1)
    xi = 1.0 + rng.random(cp.axle_start.size)
    W = cp.contacts.input_map * xi[cp.contacts.axle][:, None]
    reach = np.zeros((len(KINDS), cp.n))
    for t in times:
        B = cp.contact_state(float(t)).B
        for coef in (lin.k, lin.c):
            np.maximum(reach, np.abs(B.T @ (coef[:, None] * W)).T, out=reach)
    out = np.zeros((len(KINDS), lin.n), dtype=bool)
    ci = np.concatenate((lin.bridge, lin.wheel))
    out[:, ci] = reach > COUPLING_ZERO * reach.max(axis=1, keepdims=True).clip(min=1e-300)
    return out


def find_components(lin: LinearTrainBridge, times: FloatArray) -> list[Component]:
    """The independent, excited components of the system (see the module docstring).

    Raises NotImplementedError when a bridge coordinate is not diagonal in M, K0, D0 or a vehicle's
    contact rows are not contiguous (neither happens for the models the builder makes).
    """
    n = lin.n
    base = (lin.M != 0) | (lin.K0 != 0) | (lin.D0 != 0)
    base = base | base.T
    ci = np.concatenate((lin.bridge, lin.wheel))
    coup, rows_pattern = coupling_pattern(lin, times)
    full = base.copy()
    full[np.ix_(ci, ci)] |= coup
    n_comp, label = connected_components(csr_matrix(full), directed=False)
    excited = excited_coordinates(lin, times)
    is_bridge = np.zeros(n, dtype=bool)
    is_bridge[lin.bridge] = True
    offdiag = base.copy()
    np.fill_diagonal(offdiag, False)
    if offdiag[lin.bridge].any():
        raise NotImplementedError("bridge coordinates coupled to others in M, K0 or D0: not a modal bridge body")
    # vehicles: blocks of M, K0, D0 joined by their wheels' contact rows
    veh_graph = base.copy()
    G_glob = np.zeros((lin.G.shape[0], n), dtype=bool)
    G_glob[:, lin.wheel] = lin.G != 0
    for r in G_glob:
        idx = np.flatnonzero(r)
        veh_graph[np.ix_(idx, idx)] = True
    _, vehicle_label = connected_components(csr_matrix(veh_graph), directed=False)
    _, block_label = connected_components(csr_matrix(base), directed=False)
    # which global coordinates each contact row touches (wheel map and, over time, bridge shapes)
    row_touch = np.zeros((lin.G.shape[0], n), dtype=bool)
    row_touch[:, ci] = rows_pattern
    out: list[Component] = []
    for lab in range(n_comp):
        members = np.flatnonzero(label == lab)
        kinds = tuple(int(k) for k in range(len(KINDS)) if excited[k, members].any())
        if not kinds:
            continue  # never excited: stays at rest
        bridge = members[is_bridge[members]]
        modes = np.searchsorted(lin.bridge, bridge)
        rows = np.flatnonzero(row_touch[:, members].any(axis=1))
        coords = [bridge]
        vehicles = []
        local = bridge.size
        veh_of_row = np.full(rows.size, -1)
        for j, row in enumerate(rows):
            wheels = np.flatnonzero(G_glob[row] & (label == lab))
            if wheels.size:
                veh_of_row[j] = vehicle_label[wheels[0]]
        vehicle_ids = list(dict.fromkeys(vehicle_label[m] for m in members if not is_bridge[m]))
        vehicle_ids.sort(key=lambda v: (np.flatnonzero(veh_of_row == v)[:1].tolist() or [rows.size])[0])
        for v in vehicle_ids:
            vm = members[(vehicle_label[members] == v) & ~is_bridge[members]]
            blocks = []
            start = local
            for b in dict.fromkeys(block_label[vm]):
                bm = vm[block_label[vm] == b]
                blocks.append((local, local + bm.size))
                coords.append(bm)
                local += bm.size
            vrows = np.flatnonzero(veh_of_row == v)
            if vrows.size and np.any(np.diff(vrows) != 1):
                raise NotImplementedError("a vehicle's contact rows are not contiguous")
            r0, r1 = (int(vrows[0]), int(vrows[-1]) + 1) if vrows.size else (0, 0)
            vehicles.append(VehiclePart(start, local, tuple(blocks), r0, r1))
        out.append(Component(coords=np.concatenate(coords).astype(np.int64), n_bridge=int(bridge.size),
                             modes=modes.astype(np.int64), vehicles=tuple(vehicles),
                             rows=rows.astype(np.int64), kinds=kinds))
    return out


def output_times(scenario) -> tuple[int, int, float]:  # noqa: ANN001
    """(number of steps, steps per output step, step size) exactly as the Exudyn engine runs:
    whole output steps covering the crossing, Exudyn's step end_time / n_steps."""
    from .settings import number_of_steps

    an = scenario.analysis
    ratio = int(round(an.output_step / an.time_step))
    n_steps = ratio * number_of_steps(scenario.duration, an.output_step)
    end_time = n_steps * an.time_step
    return n_steps, ratio, end_time / n_steps


def kind_scale(kind: str, unit: str, half_gauge: float) -> float:
    """Factor of a spectrum's values in the coupling's input (a cross-level height h is the angle
    h / (2 b))."""
    return 1.0 / (2.0 * half_gauge) if kind == "cross_level" and unit == "height" else 1.0


def spectral_radius_alphas(rho: float) -> tuple[float, float, float, float]:
    """Exudyn's generalized-alpha parameters (alpha_m, alpha_f, gamma, beta) for spectral radius rho
    (CSolverImplicitSecondOrderTimeInt::PreInitializeSolverSpecific)."""
    alpha_m = (2.0 * rho - 1.0) / (rho + 1.0)
    alpha_f = rho / (rho + 1.0)
    gamma = 0.5 + alpha_f - alpha_m
    beta = 0.25 * (gamma + 0.5) ** 2
    return alpha_m, alpha_f, gamma, beta


__all__ = [
    "CHECK_TOLERANCE", "Component", "LinearTrainBridge", "VehiclePart", "excited_coordinates", "find_components", "kind_scale",
    "output_times", "pseudo_inputs", "spectral_radius_alphas",
]
