"""Contact rows collected while building, vehicle by vehicle, then frozen into a
:class:`~.coupling.ContactLayout` (the builder's helper; penalty rows and general linear rows)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .coupling import RAIL_SHAPE_ROWS, ContactLayout, LinearRows


def rail_motion_maps(coefficients: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """The rail's motion at a contact in the coordinates (y_r, theta_r, psi_r) of
    :mod:`.creep` (lateral displacement at rail level, roll of the rail plane, yaw of the rail
    line), as the rail shapes and rail inputs a general row combines.

        y_r = S_y q_b + alignment,   theta_r = S_rx q_b + cross-level angle,
        psi_r = S_dy q_b + d(alignment)/dx

    (S_y, S_rx, S_dy: the rail shapes ``y``, ``rx``, ``dy`` at the axle). A row coefficient c on
    (y_r, theta_r, psi_r) becomes coefficients on RAIL_SHAPE_ROWS, on the input values and on the
    input slopes (vertical, alignment, cross-level). The material rates of the rail (theirs at a
    fixed x) are the same shapes times q_b' (the irregularity has none).
    """
    c = np.asarray(coefficients, dtype=float).reshape(3)
    shape = np.zeros(len(RAIL_SHAPE_ROWS))
    shape[RAIL_SHAPE_ROWS.index("y")] = c[0]
    shape[RAIL_SHAPE_ROWS.index("rx")] = c[1]
    shape[RAIL_SHAPE_ROWS.index("dy")] = c[2]
    value = np.array([0.0, c[0], c[1]])
    slope = np.array([0.0, c[2], 0.0])
    return shape, value, slope


@dataclass
class _LinearRowData:
    name: str
    axle: int
    wheel: tuple[dict[tuple[int, int], float], dict[tuple[int, int], float], dict[tuple[int, int], float]]
    rail: tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]


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
    rail_lateral: list[float] = field(default_factory=list)
    names: list[str] = field(default_factory=list)
    linear: list[_LinearRowData] = field(default_factory=list)

    def add(
        self, *, name: str, axle: int, direction: int, rail_offset: float, stiffness: float, damping: float,
        wheel_terms: dict[tuple[int, int], float], inputs: tuple[float, float, float], rail_lateral: float = 0.0,
    ) -> None:
        """Add one contact; ``wheel_terms`` maps (node number, node coordinate) -> coefficient;
        ``rail_lateral``: the coefficient of the rail's lateral shape in its rail part
        (:class:`~.coupling.ContactLayout`)."""
        self.names.append(name)
        self.axle.append(int(axle))
        self.direction.append(int(direction))
        self.rail_offset.append(float(rail_offset))
        self.stiffness.append(float(stiffness))
        self.damping.append(float(damping))
        self.wheel_terms.append(dict(wheel_terms))
        self.inputs.append(tuple(float(v) for v in inputs))  # type: ignore[arg-type]
        self.rail_lateral.append(float(rail_lateral))

    def add_linear(
        self, *, name: str, axle: int,
        wheel_application: dict[tuple[int, int], float], wheel_stiffness: dict[tuple[int, int], float],
        wheel_damping: dict[tuple[int, int], float],
        rail_application: ArrayLike, rail_stiffness: ArrayLike, rail_damping: ArrayLike,
    ) -> None:
        """Add one general linear row (e.g. one row of :class:`.creep.CreepRows`):

            f = -(sum wheel_stiffness q + sum wheel_damping q') + rail_stiffness . rho + rail_damping . rho'_mat,
            Q_w = wheel_application^T f,  Q_rho = -rail_application^T f,

        the wheel terms keyed by (node number, node coordinate), the rail terms on the rail motion
        rho = (y_r, theta_r, psi_r) at the axle (:func:`rail_motion_maps`)."""
        self.linear.append(_LinearRowData(
            name=name, axle=int(axle),
            wheel=(dict(wheel_application), dict(wheel_stiffness), dict(wheel_damping)),
            rail=tuple(np.asarray(v, dtype=float).reshape(3) for v in (rail_application, rail_stiffness, rail_damping)),  # type: ignore[arg-type]
        ))

    @property
    def all_names(self) -> list[str]:
        """Names of the penalty rows, then of the general rows (the order of ``contact_forces``)."""
        return self.names + [row.name for row in self.linear]

    def _linear_layout(self, node_offsets: dict[int, int], n_wheel: int) -> LinearRows | None:
        if not self.linear:
            return None
        n = len(self.linear)
        wheel = [np.zeros((n, n_wheel)) for _ in range(3)]
        shape = [np.zeros((n, len(RAIL_SHAPE_ROWS))) for _ in range(3)]
        value, slope = np.zeros((n, 3)), np.zeros((n, 3))
        for i, row in enumerate(self.linear):
            for m in range(3):
                for (node, coord), coef in row.wheel[m].items():
                    wheel[m][i, node_offsets[node] + coord] += coef
                shape[m][i], val_m, slo_m = rail_motion_maps(row.rail[m])
                if m == 1:  # only the stiffness row carries the inputs (they are fixed in space)
                    value[i], slope[i] = val_m, slo_m
        return LinearRows(
            axle=np.array([row.axle for row in self.linear], dtype=np.int64),
            app_shape=shape[0], app_wheel=wheel[0], stiff_shape=shape[1], stiff_wheel=wheel[1],
            damp_shape=shape[2], damp_wheel=wheel[2], input_value=value, input_slope=slope,
        )

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
            linear=self._linear_layout(node_offsets, n_wheel),
            rail_lateral=np.array(self.rail_lateral, dtype=float).reshape(n) if any(self.rail_lateral) else 0.0,
        )


__all__ = ["ContactRows", "rail_motion_maps"]
