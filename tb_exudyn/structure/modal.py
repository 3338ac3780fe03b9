"""The modal bridge: what the train-bridge model needs to know about the structure.

A :class:`ModalBridge` holds mass-normalised modes (modal mass = identity), their frequencies and
damping ratios, and evaluates, for any position x along the track on the bridge, the rail-level
motion of every mode. Two sources fill it: the closed form of uniform simply supported spans
(:func:`simply_supported_modes`, for checks and as a fallback) and the spatial-beam finite-element
model (``tb_exudyn.structure.fe``). Pure numpy, no Exudyn.

Sign conventions (x along the track, y left, z up): a modal coordinate q_k moves the girder's shear
centre by (v_k, w_k) and rotates it by theta_k about x; a point of the cross-section at lateral
offset e and height h above the shear centre moves by dy = v - h theta, dz = w + e theta.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable

import numpy as np


@dataclass(frozen=True)
class RailShapes:
    """Mode shapes at rail level on the track centre line, each array of shape (n_x, n_modes).

    ``y``, ``z``: lateral and vertical displacement per unit modal coordinate [m];
    ``rx``: rotation about x (track cant from the deck's torsion) [rad];
    ``dy``, ``dz``, ``drx``: their derivatives along x [1/m] (for the convective rail velocity
    v * d(phi)/dx * q of a moving wheel). Zero for x off the bridge.
    """

    y: np.ndarray
    z: np.ndarray
    rx: np.ndarray
    dy: np.ndarray
    dz: np.ndarray
    drx: np.ndarray


@dataclass(frozen=True)
class ModalBridge:
    """Mass-normalised modal model of a bridge.

    Attributes
    ----------
    frequencies : (n,) natural frequencies [Hz], ascending
    damping_ratios : (n,) modal damping ratios [-]
    length : length of track on the bridge [m]; x = 0 at the bridge start
    mode_types : (n,) labels, e.g. 'vertical', 'lateral', 'torsion', 'longitudinal', 'pier', 'mixed'
    station_names : names of output stations, e.g. 'span1.mid', 'span1.q1', 'pier1.top'
    station_shapes : (n_stations, 3, n) shape rows (y, z, rx) of the girder axis / pier top
    rail_shape_function : callable x -> RailShapes (vectorised over x)
    effective_masses : (n, 3) effective modal masses in y, z, rx directions, if known
    node_positions : (n_nodes, 3) positions of the finite-element nodes [m], if known (mesh for
        visualisation and for the FFRF body)
    node_shapes : (n_nodes, 3, n) translations (x, y, z) of those nodes per mode, if known
    node_masses : (n_nodes,) lumped translational mass of those nodes [kg], if known
    """

    frequencies: np.ndarray
    damping_ratios: np.ndarray
    length: float
    mode_types: tuple[str, ...]
    station_names: tuple[str, ...]
    station_shapes: np.ndarray
    rail_shape_function: Callable[[np.ndarray], RailShapes] = field(repr=False)
    effective_masses: np.ndarray | None = None
    description: str = ""
    node_positions: np.ndarray | None = field(default=None, repr=False)
    node_shapes: np.ndarray | None = field(default=None, repr=False)
    node_masses: np.ndarray | None = field(default=None, repr=False)

    @property
    def n_modes(self) -> int:
        return int(self.frequencies.size)

    @property
    def omega(self) -> np.ndarray:
        """Circular frequencies [rad/s]."""
        return 2.0 * np.pi * self.frequencies

    @property
    def mass_matrix(self) -> np.ndarray:
        return np.eye(self.n_modes)

    @property
    def stiffness_matrix(self) -> np.ndarray:
        return np.diag(self.omega**2)

    @property
    def damping_matrix(self) -> np.ndarray:
        return np.diag(2.0 * self.damping_ratios * self.omega)

    def rail_shapes(self, x: np.ndarray) -> RailShapes:
        """Rail-level mode shapes on the track centre line at positions x [m] (zero off the bridge)."""
        return self.rail_shape_function(np.atleast_1d(np.asarray(x, dtype=float)))

    def truncated(self, n_modes: int) -> "ModalBridge":
        """The same bridge with only its lowest ``n_modes`` modes."""
        n = int(n_modes)
        full = self.rail_shape_function
        own = getattr(full, "truncated", None)  # an evaluator that can drop modes itself (faster)
        if callable(own):
            shapes = own(n)
        else:

            def shapes(x: np.ndarray) -> RailShapes:
                s = full(x)
                return RailShapes(*(a[:, :n] for a in (s.y, s.z, s.rx, s.dy, s.dz, s.drx)))

        return ModalBridge(
            self.frequencies[:n], self.damping_ratios[:n], self.length, self.mode_types[:n],
            self.station_names, self.station_shapes[:, :, :n], shapes,
            None if self.effective_masses is None else self.effective_masses[:n], self.description,
            self.node_positions, None if self.node_shapes is None else self.node_shapes[:, :, :n],
            self.node_masses,
        )


def simply_supported_modes(
    spans: tuple[float, ...] | list[float],
    EI_vertical: float,
    EI_lateral: float,
    GJ: float,
    mass_per_length: float,
    rot_mass_per_length: float,
    damping_ratio: float,
    max_frequency: float,
    track_offset: float = 0.0,
    track_height: float = 0.0,
    max_modes: int = 0,
) -> ModalBridge:
    """Closed-form modes of independent uniform simply supported spans (Euler-Bernoulli, St-Venant torsion).

    Vertical and lateral bending: omega_j = (j pi / L)^2 sqrt(EI / m), shape sin(j pi x / L);
    torsion: omega_j = (j pi / L) sqrt(G J / I_p), same shape. Mass-normalised over the span:
    shape amplitude sqrt(2 / (m L)) (bending) and sqrt(2 / (I_p L)) (torsion). Bending and torsion
    are uncoupled (shear centre = mass centre). Modes up to ``max_frequency`` [Hz] (and at most
    ``max_modes`` if > 0), sorted by frequency.
    """
    spans = tuple(float(s) for s in spans)
    starts = np.concatenate([[0.0], np.cumsum(spans)[:-1]])
    rows = []  # (freq, span index, j, type, amplitude)
    for s, L in enumerate(spans):
        for kind, stiff, inertia in (("vertical", EI_vertical, mass_per_length), ("lateral", EI_lateral, mass_per_length)):
            j = 1
            while True:
                f = (j * np.pi / L) ** 2 * np.sqrt(stiff / inertia) / (2 * np.pi)
                if f > max_frequency:
                    break
                rows.append((f, s, j, kind, np.sqrt(2.0 / (inertia * L))))
                j += 1
        j = 1
        while True:
            f = (j * np.pi / L) * np.sqrt(GJ / rot_mass_per_length) / (2 * np.pi)
            if f > max_frequency:
                break
            rows.append((f, s, j, "torsion", np.sqrt(2.0 / (rot_mass_per_length * L))))
            j += 1
    rows.sort(key=lambda r: r[0])
    if max_modes > 0:
        rows = rows[:max_modes]
    if not rows:
        raise ValueError(f"no bridge mode below max_frequency = {max_frequency:g} Hz")
    freq = np.array([r[0] for r in rows])
    span_idx = np.array([r[1] for r in rows])
    j_idx = np.array([r[2] for r in rows], dtype=float)
    kinds = tuple(r[3] for r in rows)
    amp = np.array([r[4] for r in rows])
    is_v = np.array([k == "vertical" for k in kinds], dtype=float)
    is_l = np.array([k == "lateral" for k in kinds], dtype=float)
    is_t = np.array([k == "torsion" for k in kinds], dtype=float)
    L_mode = np.array(spans)[span_idx]
    x0_mode = starts[span_idx]
    e, h = float(track_offset), float(track_height)

    def shapes(x: np.ndarray) -> RailShapes:
        xi = x[:, None] - x0_mode[None, :]
        inside = (xi >= 0.0) & (xi <= L_mode[None, :])
        k = j_idx * np.pi / L_mode
        s = np.where(inside, amp * np.sin(k * xi), 0.0)
        ds = np.where(inside, amp * k * np.cos(k * xi), 0.0)
        y = s * (is_l - h * is_t)
        z = s * (is_v + e * is_t)
        rx = s * is_t
        return RailShapes(y, z, rx, ds * (is_l - h * is_t), ds * (is_v + e * is_t), ds * is_t)

    names, rows_st = [], []
    for s, L in enumerate(spans):
        for label, frac in (("q1", 0.25), ("mid", 0.5), ("q3", 0.75)):
            xs = starts[s] + frac * L
            names.append(f"span{s + 1}.{label}")
            inside = span_idx == s
            val = np.where(inside, amp * np.sin(j_idx * np.pi * frac), 0.0)
            rows_st.append(np.stack([val * is_l, val * is_v, val * is_t]))
    return ModalBridge(
        frequencies=freq,
        damping_ratios=np.full(freq.size, float(damping_ratio)),
        length=float(sum(spans)),
        mode_types=kinds,
        station_names=tuple(names),
        station_shapes=np.array(rows_st),
        rail_shape_function=shapes,
        description="closed-form simply supported spans",
    )
