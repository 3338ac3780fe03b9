"""The wheel-rail coupling in plain numpy: contact kinematics, forces and their Jacobians.

No Exudyn here: the Exudyn user functions of the built model call this object, and any other
integrator (e.g. a batched pseudo-excitation engine) can use the same physics.

Coordinates
-----------
The coupling acts on the local vector u = [q_b; q_w]: the bridge's modal coordinates q_b
(n_b, mass-normalised modes) followed by the coordinates q_w of the nodes carrying the wheels
(n_w; e.g. the six coordinates x, y, z, rx, ry, rz of every wheelset node).

Contacts
--------
Every contact c is one scalar force component travelling with axle a(c) at x_a(t) = x0_a + v t
(x = 0 at the bridge start). Its gap variable is

    delta_c = S_c(t) q_b + r_c(t) - G_c q_w        (rail minus wheel, [m])

where S_c is the rail's mode-shape row at the wheel (vertical contact on the rail at lateral offset
e_c from the track centre line: z + e_c rx; lateral contact: y; all at rail level, zero off the
bridge), r_c the irregularity input (``input_map`` times the inputs of :mod:`.excitation`) and G_c
the wheel's matching coordinate combination (e.g. z + e_c rx for a wheel, y + r rx for the lateral
contact point of a wheelset at rail level, r the wheel radius). The contact force, linear, is

    f_c = k_c delta_c + c_c d(delta_c)/dt,
    d(delta_c)/dt = S_c qd_b + v S'_c q_b + rdot_c - G_c qd_w     (S' = d S / dx: convective term)

Sign: f_c is the force the rail exerts on the wheel in +z (vertical: positive = compression, the
rail pushed down by the same amount) or in +y (lateral: to the left). The generalised forces are
Q_w = G^T f on the wheels and Q_b = -S^T f on the bridge, plus -L^T P for the moving point loads P
(downward forces at the track centre line, scaled by ``load_factor``).

With B = [S, -G] the Jacobians of the left-hand side (-Q) of the equations of motion are

    K = B^T diag(k) B + B^T diag(c) [v S', 0],        D = B^T diag(c) B.
"""

from __future__ import annotations

from contextlib import contextmanager
from dataclasses import dataclass, field
from typing import Iterator

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..structure.modal import ModalBridge
from .conventions import axle_positions
from .excitation import Excitation, as_excitation, is_zero, rail_inputs

VERTICAL, LATERAL = 0, 1


@dataclass(frozen=True)
class ContactLayout:
    """The contacts of a train: one row per scalar contact force.

    Attributes
    ----------
    axle : (n_c,) int, index of the axle (in ``axle_start``) the contact travels with
    direction : (n_c,) int, VERTICAL (0) or LATERAL (1)
    rail_offset : (n_c,) lateral position of the contacted rail from the track centre line [m]
        (+y left; used by vertical contacts: +b left rail, -b right rail, 0 a single wheel)
    stiffness : (n_c,) contact stiffness [N/m]
    damping : (n_c,) contact damping [N s/m]
    wheel_map : (n_c, n_w) G, the wheel-side contact coordinate as a combination of q_w
    input_map : (n_c, 3) weights of the inputs (vertical, alignment, cross-level angle) in r_c
    """

    axle: NDArray[np.int64]
    direction: NDArray[np.int64]
    rail_offset: NDArray[np.float64]
    stiffness: NDArray[np.float64]
    damping: NDArray[np.float64]
    wheel_map: NDArray[np.float64]
    input_map: NDArray[np.float64]

    def __post_init__(self) -> None:
        n = self.axle.shape[0]
        for name in ("direction", "rail_offset", "stiffness", "damping"):
            if getattr(self, name).shape != (n,):
                raise ValueError(f"ContactLayout.{name} must have shape ({n},)")
        if self.wheel_map.ndim != 2 or self.wheel_map.shape[0] != n:
            raise ValueError(f"ContactLayout.wheel_map must have {n} rows")
        if self.input_map.shape != (n, 3):
            raise ValueError(f"ContactLayout.input_map must have shape ({n}, 3)")

    @property
    def n_contacts(self) -> int:
        return int(self.axle.shape[0])

    @property
    def n_wheel(self) -> int:
        return int(self.wheel_map.shape[1])


@dataclass(frozen=True)
class ContactState:
    """The time-varying, low-rank coupling at one time t (everything a solver needs).

    Attributes
    ----------
    t : time [s]
    x : (n_axles,) axle positions along the track [m]
    speed : the speed entering the convective term (0 in a frozen static state) [m/s]
    S : (n_c, n_b) rail mode shapes at the contacts
    dS : (n_c, n_b) their derivatives along x [1/m]
    r, r_dot : (n_c,) irregularity input [m] and its time derivative [m/s]
    load_shapes : (n_l, n_b) vertical track-centre-line shapes under the point loads
    B : (n_c, n) the gap map [S, -G] on u = [q_b; q_w]
    on_bridge : whether any axle is on the bridge
    """

    t: float
    x: NDArray[np.float64]
    speed: float
    S: NDArray[np.float64]
    dS: NDArray[np.float64]
    r: NDArray[np.float64]
    r_dot: NDArray[np.float64]
    load_shapes: NDArray[np.float64]
    B: NDArray[np.float64]
    on_bridge: bool


class WheelRailCoupling:
    """Wheel-rail contact forces of a whole train on a modal bridge (vectorised numpy).

    Parameters
    ----------
    bridge : the modal bridge (rail shapes at x, zero off the bridge: rigid approach track)
    axle_start : (n_axles,) position of every axle at t = 0 [m]
    speed : train speed v [m/s]
    contacts : the contact rows
    load_axle : (n_l,) axle index of every moving point load
    load_force : (n_l,) downward force of every point load at ``load_factor`` = 1 [N]
    half_gauge : b [m]
    excitation : the irregularity input (None: smooth track)
    taper_length : length of the irregularity's taper after the first axle's start [m]
    """

    def __init__(
        self,
        bridge: ModalBridge,
        axle_start: ArrayLike,
        speed: float,
        contacts: ContactLayout,
        load_axle: ArrayLike = (),
        load_force: ArrayLike = (),
        half_gauge: float = 0.75,
        excitation: Excitation | None = None,
        taper_length: float = 0.0,
    ) -> None:
        self.bridge = bridge
        self.axle_start = np.asarray(axle_start, dtype=float)
        self.speed = float(speed)
        self.contacts = contacts
        self.load_axle = np.asarray(load_axle, dtype=np.int64).reshape(-1)
        self.load_force = np.asarray(load_force, dtype=float).reshape(-1)
        if self.load_axle.shape != self.load_force.shape:
            raise ValueError("load_axle and load_force must have the same length")
        self.half_gauge = float(half_gauge)
        self.taper_length = float(taper_length)
        self.n_bridge = bridge.n_modes
        self.n_wheel = contacts.n_wheel
        self.n = self.n_bridge + self.n_wheel
        self.n_contacts = contacts.n_contacts
        #: scale of the point loads (1 with gravity, 0 without)
        self.load_factor = 1.0
        self._x_ref = float(self.axle_start[0]) if self.axle_start.size else 0.0
        self._is_vertical = contacts.direction == VERTICAL
        self._k = contacts.stiffness
        self._c = contacts.damping
        self._damped = bool(np.any(self._c != 0.0))
        self._G = contacts.wheel_map
        self._frozen: float | None = None
        # S = select @ [Y; Z; RX] (rows: axles): vertical contact z + e rx, lateral contact y
        n_a, rows = self.axle_start.size, np.arange(self.n_contacts)
        vert = self._is_vertical.astype(float)
        self._select = np.zeros((self.n_contacts, 3 * n_a))
        self._select[rows, contacts.axle] = 1.0 - vert
        self._select[rows, n_a + contacts.axle] = vert
        self._select[rows, 2 * n_a + contacts.axle] = vert * contacts.rail_offset
        self._zero_S = np.zeros((self.n_contacts, self.n_bridge))
        self._zero_L = np.zeros((self.load_axle.size, self.n_bridge))
        self._B0 = np.zeros((self.n_contacts, self.n))
        self._B0[:, self.n_bridge:] = -self._G
        self.set_excitation(excitation)

    # ------------------------------------------------------------------ excitation, time
    def set_excitation(self, excitation: Excitation | None) -> None:
        """Replace the irregularity input (no rebuild needed); clears the caches."""
        self.excitation = as_excitation(excitation)
        self._zero_input = is_zero(self.excitation)
        self._clear_cache()

    def _clear_cache(self) -> None:
        self._state_key: tuple[float, bool] | None = None
        self._state: ContactState | None = None
        self._jac_key: tuple[float, bool] | None = None
        self._jac: tuple[NDArray[np.float64], NDArray[np.float64]] | None = None

    @contextmanager
    def frozen(self, t: float) -> Iterator[None]:
        """Within the block every time argument is replaced by ``t`` and the train stands still:
        no convective term, no input rate (for static solutions and linearisations at t)."""
        old = self._frozen
        self._frozen = float(t)
        self._clear_cache()
        try:
            yield
        finally:
            self._frozen = old
            self._clear_cache()

    def positions(self, t: float) -> NDArray[np.float64]:
        """Axle positions x_j(t) = x0_j + v t [m] (:func:`~.conventions.axle_positions`)."""
        return axle_positions(self.axle_start, self.speed, t)

    # ------------------------------------------------------------------ contact description
    def _shapes(self, x: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], bool]:
        """Contact shape rows S, dS (n_c, n_b) and point-load shapes; zero rows for axles off the
        bridge (rigid approach track), no evaluation at all while every axle is off it."""
        if not np.any((x >= 0.0) & (x <= self.bridge.length)):
            return self._zero_S, self._zero_S, self._zero_L, False
        rs = self.bridge.rail_shapes(x)  # zero rows off the bridge
        S = self._select @ np.concatenate((rs.y, rs.z, rs.rx))
        dS = self._select @ np.concatenate((rs.dy, rs.dz, rs.drx))
        return S, dS, rs.z[self.load_axle], True

    def contact_state(self, t: float) -> ContactState:
        """Shapes at the wheels, their slopes and the inputs at time t (cached per t)."""
        static = self._frozen is not None
        if static:
            t = self._frozen  # type: ignore[assignment]
        key = (float(t), static)
        if self._state_key == key and self._state is not None:
            return self._state
        x = self.positions(t)
        S, dS, L, on_bridge = self._shapes(x)
        n_c = self.n_contacts
        if self._zero_input:
            r, r_dot = np.zeros(n_c), np.zeros(n_c)
        else:
            a = self.contacts.axle
            val, slo = rail_inputs(self.excitation, x, self._x_ref, self.half_gauge, self.taper_length)
            W = self.contacts.input_map
            r = np.einsum("ck,kc->c", W, val[:, a])
            r_dot = np.zeros(n_c) if static else self.speed * np.einsum("ck,kc->c", W, slo[:, a])
        if on_bridge:
            B = self._B0.copy()
            B[:, : self.n_bridge] = S
        else:
            B = self._B0
        state = ContactState(
            t=float(t), x=x, speed=0.0 if static else self.speed, S=S, dS=dS, r=r, r_dot=r_dot,
            load_shapes=L, B=B, on_bridge=on_bridge,
        )
        self._state_key, self._state = key, state
        return state

    # ------------------------------------------------------------------ forces
    def _force(self, st: ContactState, u: NDArray[np.float64], ud: NDArray[np.float64]) -> NDArray[np.float64]:
        return self.contact_law(st, u, ud, st.r, st.r_dot)

    def contact_law(self, st: ContactState, u: NDArray, ud: NDArray, r: NDArray, r_dot: NDArray) -> NDArray:
        """The contact law: f = k (B u + r) + c (B u' + v dS q_b + r') at the contact state ``st``,
        for coordinates u, u' (n,) or (n, m) (m columns; then r, r' are (n_c, m), real or complex).
        The one formula of the contact force: the Exudyn user functions and every engine use it."""
        k = self._k if u.ndim == 1 else self._k[:, None]
        gap = st.B @ u + r
        if not self._damped:
            return k * gap
        c = self._c if u.ndim == 1 else self._c[:, None]
        rate = st.B @ ud + r_dot
        if st.on_bridge and st.speed != 0.0:
            rate += st.speed * (st.dS @ u[: self.n_bridge])
        return k * gap + c * rate

    def contact_forces(
        self, t: float, q_b: ArrayLike, qd_b: ArrayLike, q_w: ArrayLike, qd_w: ArrayLike
    ) -> NDArray[np.float64]:
        """Contact forces f_c [N] (rail on wheel: +z compression, +y to the left)."""
        u = np.concatenate((np.asarray(q_b, dtype=float).reshape(-1), np.asarray(q_w, dtype=float).reshape(-1)))
        ud = np.concatenate((np.asarray(qd_b, dtype=float).reshape(-1), np.asarray(qd_w, dtype=float).reshape(-1)))
        return self._force(self.contact_state(t), u, ud)

    def generalized_forces(
        self, t: float, q_b: ArrayLike, qd_b: ArrayLike, q_w: ArrayLike, qd_w: ArrayLike
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Generalised forces (Q_b on the modal coordinates, Q_w on the wheel coordinates)."""
        u = np.concatenate((np.asarray(q_b, dtype=float).reshape(-1), np.asarray(q_w, dtype=float).reshape(-1)))
        ud = np.concatenate((np.asarray(qd_b, dtype=float).reshape(-1), np.asarray(qd_w, dtype=float).reshape(-1)))
        Q = self.forces(t, u, ud)
        return Q[: self.n_bridge], Q[self.n_bridge:]

    def forces(self, t: float, u: ArrayLike, ud: ArrayLike) -> NDArray[np.float64]:
        """Generalised force vector Q = -B^T f (- L^T P) on u = [q_b; q_w] (right-hand side)."""
        st = self.contact_state(t)
        u = np.asarray(u, dtype=float)
        ud = np.asarray(ud, dtype=float)
        Q = -(st.B.T @ self._force(st, u, ud))
        if st.on_bridge and self.load_axle.size and self.load_factor != 0.0:
            Q[: self.n_bridge] -= st.load_shapes.T @ (self.load_factor * self.load_force)
        return Q

    def jacobians(self, t: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Stiffness and damping Jacobians (n, n) of -Q (the left-hand side); independent of u."""
        static = self._frozen is not None
        key = (float(self._frozen if static else t), static)
        if self._jac_key == key and self._jac is not None:
            return self._jac
        st = self.contact_state(t)
        B = st.B
        cB = self._c[:, None] * B
        K = B.T @ (self._k[:, None] * B)
        if st.on_bridge and st.speed != 0.0 and self._damped:
            K[:, : self.n_bridge] += st.speed * (cB.T @ st.dS)
        D = B.T @ cB
        self._jac_key, self._jac = key, (K, D)
        return K, D

    def static_force(self, t: float) -> NDArray[np.float64]:
        """Q at u = 0 with the train standing at its positions of time t (inputs and point loads)."""
        with self.frozen(t):
            return self.forces(t, np.zeros(self.n), np.zeros(self.n))

    def contact_force_history(
        self, times: ArrayLike, q_b: ArrayLike, qd_b: ArrayLike, q_w: ArrayLike, qd_w: ArrayLike
    ) -> NDArray[np.float64]:
        """Contact forces (n_t, n_c) along recorded histories (rows = times)."""
        times = np.asarray(times, dtype=float)
        u = np.hstack((np.asarray(q_b, dtype=float), np.asarray(q_w, dtype=float)))
        ud = np.hstack((np.asarray(qd_b, dtype=float), np.asarray(qd_w, dtype=float)))
        out = np.empty((times.size, self.n_contacts))
        for i, t in enumerate(times):
            out[i] = self._force(self.contact_state(t), u[i], ud[i])
        return out

    def point_load_history(self, times: ArrayLike) -> NDArray[np.float64]:
        """Point loads (n_t, n_l) [N] (downward; constant while ``load_factor`` is)."""
        times = np.asarray(times, dtype=float)
        return np.broadcast_to(self.load_factor * self.load_force, (times.size, self.load_force.size)).copy()


@dataclass
class ContactRows:
    """Builder helper: contact rows collected vehicle by vehicle, then frozen into a layout."""

    axle: list[int] = field(default_factory=list)
    direction: list[int] = field(default_factory=list)
    rail_offset: list[float] = field(default_factory=list)
    stiffness: list[float] = field(default_factory=list)
    damping: list[float] = field(default_factory=list)
    wheel_terms: list[dict[tuple[int, int], float]] = field(default_factory=list)
    inputs: list[tuple[float, float, float]] = field(default_factory=list)
    names: list[str] = field(default_factory=list)

    def add(
        self, *, name: str, axle: int, direction: int, rail_offset: float, stiffness: float, damping: float,
        wheel_terms: dict[tuple[int, int], float], inputs: tuple[float, float, float],
    ) -> None:
        """Add one contact; ``wheel_terms`` maps (node number, node coordinate) -> coefficient."""
        self.names.append(name)
        self.axle.append(int(axle))
        self.direction.append(int(direction))
        self.rail_offset.append(float(rail_offset))
        self.stiffness.append(float(stiffness))
        self.damping.append(float(damping))
        self.wheel_terms.append(dict(wheel_terms))
        self.inputs.append(tuple(float(v) for v in inputs))  # type: ignore[arg-type]

    def layout(self, node_offsets: dict[int, int], n_wheel: int) -> ContactLayout:
        """Freeze into a :class:`ContactLayout`; ``node_offsets`` maps node -> first index in q_w."""
        n = len(self.axle)
        G = np.zeros((n, n_wheel))
        for i, terms in enumerate(self.wheel_terms):
            for (node, coord), coef in terms.items():
                G[i, node_offsets[node] + coord] += coef
        return ContactLayout(
            axle=np.array(self.axle, dtype=np.int64).reshape(n),
            direction=np.array(self.direction, dtype=np.int64).reshape(n),
            rail_offset=np.array(self.rail_offset, dtype=float).reshape(n),
            stiffness=np.array(self.stiffness, dtype=float).reshape(n),
            damping=np.array(self.damping, dtype=float).reshape(n),
            wheel_map=G,
            input_map=np.array(self.inputs, dtype=float).reshape(n, 3),
        )
