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
e_c from the track centre line: z + e_c rx, + a_c y on coned wheels; lateral contact: y; all at rail
level, zero off the bridge), r_c the irregularity input (``input_map`` times the inputs of :mod:`.excitation`)
and G_c the wheel's matching coordinate combination (e.g. z + e_c rx for a wheel, y + r rx for the
lateral contact point of a wheelset at rail level, r the wheel radius). The contact force, linear, is

    f_c = k_c delta_c + c_c d(delta_c)/dt,
    d(delta_c)/dt = S_c qd_b + v S'_c q_b + rdot_c - G_c qd_w     (S' = d S / dx: convective term)

Sign: f_c is the force the rail exerts on the wheel in +z (vertical: positive = compression, the
rail pushed down by the same amount) or in +y (lateral: to the left). The generalised forces are
Q_w = G^T f on the wheels and Q_b = -S^T f on the bridge, plus -L^T P for the moving point loads P
(downward forces at the track centre line, scaled by ``load_factor``).

With B = [S, -G] the Jacobians of the left-hand side (-Q) of the equations of motion are

    K = B^T diag(k) B + B^T diag(c) [v S', 0],        D = B^T diag(c) B.

General linear rows
-------------------
Rows whose force is not a spring-damper on one gap (e.g. the creep forces of
:mod:`.creep`: the lateral creep force -2 f22 (y'/v - psi) depends on the yaw but acts on y) are
held apart in :class:`LinearRows`. Row g has three maps on u = [q_b; q_w], each a bridge part
built from the rail shapes at its axle and a constant wheel part,

    A_g = [S^a_g(t), -G^a_g],   K_g = [S^k_g(t), -G^k_g],   D_g = [S^d_g(t), -G^d_g],
    S^m_g(t) = sum_j P^m[g, j] shape_j(x_a(g)),   shape_j in (y, z, rx, dy, dz, drx) (:class:`RailShapes` rows),

and its force and generalised forces are

    f_g = K_g u + D_g u' + W^v_g . val(x_a) + W^s_g . slope(x_a),      Q = -A^T f

(val, slope: the rail inputs of :func:`.excitation.rail_inputs`, fixed in space: no rate term). So
K_lin = A^T K, D_lin = A^T D (not symmetric). The bridge parts use the rail's *material* motion
(no convective term): whatever a row needs of the moving contact is in its maps. The penalty rows
above are computed exactly as without general rows (same operations: results bitwise unchanged).
"""

from __future__ import annotations

from contextlib import contextmanager
from dataclasses import dataclass
from typing import Iterator

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..structure.modal import ModalBridge, RailShapes
from .conventions import axle_positions
from .excitation import Excitation, as_excitation, is_zero, rail_inputs

VERTICAL, LATERAL = 0, 1


#: the rail-shape rows a general row's bridge maps combine, in this order (fields of RailShapes)
RAIL_SHAPE_ROWS: tuple[str, ...] = ("y", "z", "rx", "dy", "dz", "drx")


@dataclass(frozen=True)
class LinearRows:
    """General linear contact rows (see the module docstring): f = K u + D u' + f_in, Q = -A^T f.

    Attributes
    ----------
    axle : (n_g,) int, the axle each row travels with
    app_shape, stiff_shape, damp_shape : (n_g, 6) coefficients P^a, P^k, P^d of the rail shapes
        (RAIL_SHAPE_ROWS) in the bridge parts of A, K, D
    app_wheel, stiff_wheel, damp_wheel : (n_g, n_w) the wheel parts G^a, G^k, G^d (entering as -G)
    input_value, input_slope : (n_g, 3) weights of the rail inputs (vertical, alignment, cross-level
        angle) and of their slopes d/dx in f_in
    """

    axle: NDArray[np.int64]
    app_shape: NDArray[np.float64]
    app_wheel: NDArray[np.float64]
    stiff_shape: NDArray[np.float64]
    stiff_wheel: NDArray[np.float64]
    damp_shape: NDArray[np.float64]
    damp_wheel: NDArray[np.float64]
    input_value: NDArray[np.float64]
    input_slope: NDArray[np.float64]

    def __post_init__(self) -> None:
        n = self.axle.shape[0]
        for name in ("app_shape", "stiff_shape", "damp_shape"):
            if getattr(self, name).shape != (n, len(RAIL_SHAPE_ROWS)):
                raise ValueError(f"LinearRows.{name} must have shape ({n}, {len(RAIL_SHAPE_ROWS)})")
        n_w = self.app_wheel.shape[1] if self.app_wheel.ndim == 2 else -1
        for name in ("app_wheel", "stiff_wheel", "damp_wheel"):
            if getattr(self, name).shape != (n, n_w):
                raise ValueError(f"LinearRows.{name} must have shape ({n}, n_w) like app_wheel")
        for name in ("input_value", "input_slope"):
            if getattr(self, name).shape != (n, 3):
                raise ValueError(f"LinearRows.{name} must have shape ({n}, 3)")

    @property
    def n_rows(self) -> int:
        return int(self.axle.shape[0])


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
    linear : general linear rows (e.g. creep) after the n_c penalty rows, or None
    """

    axle: NDArray[np.int64]
    direction: NDArray[np.int64]
    rail_offset: NDArray[np.float64]
    stiffness: NDArray[np.float64]
    damping: NDArray[np.float64]
    wheel_map: NDArray[np.float64]
    input_map: NDArray[np.float64]
    linear: LinearRows | None = None
    rail_lateral: NDArray[np.float64] | float = 0.0  #: (n_c,) a_c: y (dy) in S_c (S'_c) on coned wheels, or 0

    def __post_init__(self) -> None:
        n = self.axle.shape[0]
        for name in ("direction", "rail_offset", "stiffness", "damping"):
            if getattr(self, name).shape != (n,):
                raise ValueError(f"ContactLayout.{name} must have shape ({n},)")
        if self.wheel_map.ndim != 2 or self.wheel_map.shape[0] != n:
            raise ValueError(f"ContactLayout.wheel_map must have {n} rows")
        if self.input_map.shape != (n, 3):
            raise ValueError(f"ContactLayout.input_map must have shape ({n}, 3)")
        if self.linear is not None and self.linear.app_wheel.shape[1] != self.wheel_map.shape[1]:
            raise ValueError("ContactLayout.linear must act on the same wheel coordinates as wheel_map")

    @property
    def n_contacts(self) -> int:
        return int(self.axle.shape[0])

    @property
    def n_wheel(self) -> int:
        return int(self.wheel_map.shape[1])

    @property
    def n_linear(self) -> int:
        """Number of general linear rows (0 without)."""
        return 0 if self.linear is None else self.linear.n_rows


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
    A_lin, K_lin, D_lin : (n_g, n) application, stiffness and damping maps of the general linear
        rows (None without)
    f_lin : (n_g,) their input force W^v . val + W^s . slope [N] (None without)
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
    A_lin: NDArray[np.float64] | None = None
    K_lin: NDArray[np.float64] | None = None
    D_lin: NDArray[np.float64] | None = None
    f_lin: NDArray[np.float64] | None = None


@dataclass(frozen=True)
class RowMaps:
    """Every contact row of a coupling in one linear form, penalty rows first, then the general
    rows (the order of ``contact_forces``): the linear engines' view of the coupling.

    Row r has an application map P_r and force maps on u = [q_b; q_w],

        P_r = [S^a_r(t), -G^a_r],  F^k_r = [S^k_r(t), -G^k_r],  F^d_r = [S^d_r(t), -G^d_r],
        S^m_r(t) = sum_j shape_m[r, j] rail_j(x_a(r)),   rail_j in RAIL_SHAPE_ROWS at the row's axle,

        f_r = F^k_r u + F^d_r u' + f_in_r,    f_in_r = sum_kind value[r, kind] val_kind + slope[r, kind] slope_kind,
        Q = -P^T f

    (val, slope: the tapered rail inputs of :func:`.excitation.rail_inputs` at the row's axle).
    A penalty row f = k (B u + r) + c (B u' + v dS q_b + r') with B = [s . rail, -G] (s: z + e rx or
    y) is P = B, F^k = k B + c v [dS, 0] (the convective term: shape_k = k s + c v s' on the slope
    rows), F^d = c B, value = k W, slope = c v W (r' = v d r / dx); a general row is its
    :class:`LinearRows` as given. So P^T F^k and P^T F^d are the coupling's Jacobians
    (:meth:`WheelRailCoupling.jacobians`) and f_r its contact forces, for the moving train.

    Attributes
    ----------
    axle : (n_r,) the axle of every row
    app_shape, stiff_shape, damp_shape : (n_r, 6) the coefficients of the rail shapes in S^a, S^k, S^d
    app_wheel, stiff_wheel, damp_wheel : (n_r, n_w) G^a, G^k, G^d
    input_value, input_slope : (n_r, 3) weights of the rail inputs and their slopes in f_in
    n_penalty : number of penalty rows (the first rows)
    """

    axle: NDArray[np.int64]
    app_shape: NDArray[np.float64]
    stiff_shape: NDArray[np.float64]
    damp_shape: NDArray[np.float64]
    app_wheel: NDArray[np.float64]
    stiff_wheel: NDArray[np.float64]
    damp_wheel: NDArray[np.float64]
    input_value: NDArray[np.float64]
    input_slope: NDArray[np.float64]
    n_penalty: int

    @property
    def n_rows(self) -> int:
        return int(self.axle.shape[0])

    def bridge_parts(self, rs: RailShapes | None, n_bridge: int) -> tuple[NDArray[np.float64], ...]:
        """S^a, S^k, S^d (n_r, n_b) for the rail shapes ``rs`` at the axles (None: every axle off the
        bridge, zero)."""
        if rs is None:
            zero = np.zeros((self.n_rows, n_bridge))
            return zero, zero, zero
        stack = np.stack([getattr(rs, name)[self.axle] for name in RAIL_SHAPE_ROWS], axis=1)  # (n_r, 6, n_b)
        return tuple(np.einsum("rj,rjb->rb", P, stack) for P in (self.app_shape, self.stiff_shape, self.damp_shape))


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
        # S = select @ [Y; Z; RX] (rows: axles): vertical contact z + e rx (+ a y), lateral contact y
        n_a, rows = self.axle_start.size, np.arange(self.n_contacts)
        vert = self._is_vertical.astype(float)
        self._select = np.zeros((self.n_contacts, 3 * n_a))
        self._select[rows, contacts.axle] = 1.0 - vert + contacts.rail_lateral
        self._select[rows, n_a + contacts.axle] = vert
        self._select[rows, 2 * n_a + contacts.axle] = vert * contacts.rail_offset
        self._zero_S = np.zeros((self.n_contacts, self.n_bridge))
        self._zero_L = np.zeros((self.load_axle.size, self.n_bridge))
        self._B0 = np.zeros((self.n_contacts, self.n))
        self._B0[:, self.n_bridge:] = -self._G
        self._init_linear(contacts.linear, n_a)
        self.set_excitation(excitation)

    def _init_linear(self, lin: LinearRows | None, n_a: int) -> None:
        """Selections of the general rows' bridge parts (shape rows at their axles) and their
        off-bridge maps [0, -G]."""
        self._lin = lin
        self.n_linear = 0 if lin is None else lin.n_rows
        if lin is None:
            return
        rows = np.arange(lin.n_rows)
        self._lin_select = []
        self._lin_off = []
        for P, Gm in ((lin.app_shape, lin.app_wheel), (lin.stiff_shape, lin.stiff_wheel), (lin.damp_shape, lin.damp_wheel)):
            sel = np.zeros((lin.n_rows, len(RAIL_SHAPE_ROWS) * n_a))
            for j in range(len(RAIL_SHAPE_ROWS)):
                sel[rows, j * n_a + lin.axle] = P[:, j]
            self._lin_select.append(sel)
            off = np.zeros((lin.n_rows, self.n))
            off[:, self.n_bridge:] = -Gm
            self._lin_off.append(off)

    def row_maps(self) -> RowMaps:
        """All contact rows in the linear engines' form (:class:`RowMaps`): penalty rows, then the
        general rows."""
        c = self.contacts
        n_c = self.n_contacts
        vert = self._is_vertical.astype(float)
        e = vert * c.rail_offset
        s = np.zeros((n_c, len(RAIL_SHAPE_ROWS)))  # z + e rx (vertical) or y (lateral), and slopes
        s[:, RAIL_SHAPE_ROWS.index("y")] = 1.0 - vert + c.rail_lateral
        s[:, RAIL_SHAPE_ROWS.index("z")] = vert
        s[:, RAIL_SHAPE_ROWS.index("rx")] = e
        ds = np.zeros_like(s)
        ds[:, RAIL_SHAPE_ROWS.index("dy")] = s[:, RAIL_SHAPE_ROWS.index("y")]
        ds[:, RAIL_SHAPE_ROWS.index("dz")] = vert
        ds[:, RAIL_SHAPE_ROWS.index("drx")] = e
        k, cc = self._k[:, None], self._c[:, None]
        parts = dict(
            axle=c.axle.astype(np.int64), app_shape=s, stiff_shape=k * s + (cc * self.speed) * ds, damp_shape=cc * s,
            app_wheel=self._G, stiff_wheel=k * self._G, damp_wheel=cc * self._G,
            input_value=k * c.input_map, input_slope=(cc * self.speed) * c.input_map,
        )
        lin = self._lin
        if lin is not None:
            general = dict(
                axle=lin.axle, app_shape=lin.app_shape, stiff_shape=lin.stiff_shape, damp_shape=lin.damp_shape,
                app_wheel=lin.app_wheel, stiff_wheel=lin.stiff_wheel, damp_wheel=lin.damp_wheel,
                input_value=lin.input_value, input_slope=lin.input_slope,
            )
            parts = {key: np.concatenate((value, np.asarray(general[key]))) for key, value in parts.items()}
        return RowMaps(**parts, n_penalty=n_c)

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
    def _shapes(self, x: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], bool, RailShapes | None]:
        """Contact shape rows S, dS (n_c, n_b), point-load shapes and the rail shapes at the axles
        (None while no axle is on the bridge); zero rows for axles off the bridge (rigid approach
        track), no evaluation at all while every axle is off it."""
        if not np.any(self.bridge.carries(x)):
            return self._zero_S, self._zero_S, self._zero_L, False, None
        rs = self.bridge.rail_shapes(x)  # zero rows off the bridge
        S = self._select @ np.concatenate((rs.y, rs.z, rs.rx))
        dS = self._select @ np.concatenate((rs.dy, rs.dz, rs.drx))
        return S, dS, rs.z[self.load_axle], True, rs

    def _linear_maps(self, rs: RailShapes | None) -> tuple[NDArray[np.float64], ...]:
        """A, K, D (n_g, n) of the general rows for the rail shapes rs at the axles (None: off the bridge)."""
        if rs is None:
            return tuple(self._lin_off)
        stack = np.concatenate([getattr(rs, name) for name in RAIL_SHAPE_ROWS])
        out = []
        for sel, off in zip(self._lin_select, self._lin_off):
            M = off.copy()
            M[:, : self.n_bridge] = sel @ stack
            out.append(M)
        return tuple(out)

    def contact_state(self, t: float) -> ContactState:
        """Shapes at the wheels, their slopes and the inputs at time t (cached per t)."""
        static = self._frozen is not None
        if static:
            t = self._frozen  # type: ignore[assignment]
        key = (float(t), static)
        if self._state_key == key and self._state is not None:
            return self._state
        x = self.positions(t)
        S, dS, L, on_bridge, rs = self._shapes(x)
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
        lin: dict[str, NDArray[np.float64]] = {}
        if self._lin is not None:
            lin["A_lin"], lin["K_lin"], lin["D_lin"] = self._linear_maps(rs)
            if self._zero_input:
                lin["f_lin"] = np.zeros(self.n_linear)
            else:
                a_g = self._lin.axle
                lin["f_lin"] = (np.einsum("ck,kc->c", self._lin.input_value, val[:, a_g])
                                + np.einsum("ck,kc->c", self._lin.input_slope, slo[:, a_g]))
        state = ContactState(
            t=float(t), x=x, speed=0.0 if static else self.speed, S=S, dS=dS, r=r, r_dot=r_dot,
            load_shapes=L, B=B, on_bridge=on_bridge, **lin,
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

    def _linear_force(self, st: ContactState, u: NDArray[np.float64], ud: NDArray[np.float64]) -> NDArray[np.float64]:
        """Forces of the general linear rows, K u + D u' + f_in."""
        return self.linear_law(st, u, ud, st.f_lin)  # type: ignore[arg-type]

    def linear_law(self, st: ContactState, u: NDArray, ud: NDArray, f_in: NDArray) -> NDArray:
        """The general rows' law: f_g = K_g u + D_g u' + f_in at the contact state ``st``, for
        coordinates u, u' (n,) or (n, m) and input forces f_in (n_g,) or (n_g, m) (real or complex;
        e.g. a column source's ``linear_inputs``). The one formula of the general rows' force."""
        return st.K_lin @ u + st.D_lin @ ud + f_in  # type: ignore[operator]

    def _all_forces(self, st: ContactState, u: NDArray[np.float64], ud: NDArray[np.float64]) -> NDArray[np.float64]:
        """Penalty rows' forces, then the general rows' (the same array without general rows)."""
        f = self._force(st, u, ud)
        if self._lin is None:
            return f
        return np.concatenate((f, self._linear_force(st, u, ud)))

    def contact_forces(
        self, t: float, q_b: ArrayLike, qd_b: ArrayLike, q_w: ArrayLike, qd_w: ArrayLike
    ) -> NDArray[np.float64]:
        """Contact forces f_c [N] (rail on wheel: +z compression, +y to the left), the penalty
        rows' followed by the general rows' (forces or moments, by their definition)."""
        u = np.concatenate((np.asarray(q_b, dtype=float).reshape(-1), np.asarray(q_w, dtype=float).reshape(-1)))
        ud = np.concatenate((np.asarray(qd_b, dtype=float).reshape(-1), np.asarray(qd_w, dtype=float).reshape(-1)))
        return self._all_forces(self.contact_state(t), u, ud)

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
        if self._lin is not None:
            Q -= st.A_lin.T @ self._linear_force(st, u, ud)  # type: ignore[union-attr]
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
        if self._lin is not None:
            K += st.A_lin.T @ st.K_lin  # type: ignore[union-attr]
            D += st.A_lin.T @ st.D_lin  # type: ignore[union-attr]
        self._jac_key, self._jac = key, (K, D)
        return K, D

    def unit_input_forces(self, t: float) -> NDArray[np.float64]:
        """(3, n, 2 n_axles) generalised forces Q on u = [q_b; q_w] of a unit input of each kind
        (vertical, alignment, cross-level angle; rows of :func:`.excitation.rail_inputs`) at one
        axle, with the train at its positions of time t: column j < n_axles a unit value at axle j,
        column n_axles + j a unit slope d/dx there (fixed in space: the rate is v times the slope).
        Penalty rows -B^T (k W) and -B^T (c v W), general rows -A^T W^v and -A^T W^s. What an input
        can reach (:func:`.modes.damped_modes`), without its spectrum."""
        st = self.contact_state(t)
        n_a = self.axle_start.size
        out = np.zeros((3, self.n, 2 * n_a))
        one = np.zeros((self.n_contacts, n_a))
        one[np.arange(self.n_contacts), self.contacts.axle] = 1.0
        lin = self._lin
        if lin is not None:
            one_g = np.zeros((lin.n_rows, n_a))
            one_g[np.arange(lin.n_rows), lin.axle] = 1.0
        for k in range(3):
            Wk = self.contacts.input_map[:, k : k + 1] * one
            out[k, :, :n_a] = -(st.B.T @ (self._k[:, None] * Wk))
            out[k, :, n_a:] = -(st.B.T @ ((self.speed * self._c)[:, None] * Wk))
            if lin is not None:
                out[k, :, :n_a] -= st.A_lin.T @ (lin.input_value[:, k : k + 1] * one_g)  # type: ignore[union-attr]
                out[k, :, n_a:] -= st.A_lin.T @ (lin.input_slope[:, k : k + 1] * one_g)  # type: ignore[union-attr]
        return out

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
        out = np.empty((times.size, self.n_contacts + self.n_linear))
        for i, t in enumerate(times):
            out[i] = self._all_forces(self.contact_state(t), u[i], ud[i])
        return out

    def point_load_history(self, times: ArrayLike) -> NDArray[np.float64]:
        """Point loads (n_t, n_l) [N] (downward; constant while ``load_factor`` is)."""
        times = np.asarray(times, dtype=float)
        return np.broadcast_to(self.load_factor * self.load_force, (times.size, self.load_force.size)).copy()
