"""The static deformation checks of EN 1990 Annex A2 (A2.4.4.2.2 to A2.4.4.2.4) on the bridge's finite elements.

Load models (EN 1991-2:2003): LM71 (6.3.2: four axles of 250 kN at 1.6 m, 80 kN/m on both sides from 0.8 m beyond
the outer axles, unlimited) and SW/0 (6.3.3: 133 kN/m over two lengths of 15 m, 5.3 m apart; continuous decks),
each x alpha (classified loads) x Phi (6.4.5: Phi_2 carefully maintained track, Phi_3 standard), on the centre
line of one track; the nosing force (6.5.2: 100 kN x alpha, no Phi) as a lateral point force at rail level.

Every quantity is a linear functional c . u of the static displacements u (vertical or lateral displacement of
a track line at x, its slope, the twist between the rails over 3 m). By reciprocity the influence line of
c . u for a unit load at s on the loaded track's line is the line's displacement at s under the "load" c:
one sparse factorisation of the reduced stiffness, one solve per functional (many at once), and the
influence lines of every functional on a grid of the loaded line. The load model is then placed at every
grid position (:func:`envelope`): the axles as a group, LM71's distributed load on the parts of the line
where it is adverse (outside 0.8 m of the outer axles), SW/0 whole; the largest value of either sign.

Pure numpy/scipy on :mod:`tb_exudyn.structure`'s assembly; no modes, no Exudyn.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Sequence

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as sla

from ..errors import SettingError
from ..scenario.model import Continuous
from ..scenario.sections import track_lines
from ..structure.assembly import FEModel, assemble
from ..structure.beam import SIGN_VERTICAL, cubic_coefficients
from . import en1991 as code

#: the rails of a standard-gauge track are read this far apart for the twist (EN 1990 A2.4.4.2.2: 1.435 m) [m]
GAUGE = 1.435
#: the twist's base length (A2.4.4.2.2) [m]
TWIST_BASE = 3.0
#: the nosing force of EN 1991-2:2003 6.5.2 [N] (x alpha, not x Phi) [check]
NOSING_FORCE = 100e3


@dataclass(frozen=True)
class LoadModel:
    """A static rail load model: point loads at ``axle_offsets`` behind the first [m] of ``axle_loads`` [N];
    a distributed load ``udl`` [N/m] from ``udl_gap`` beyond the outer axles on both sides, on the parts of the
    influence line where it is adverse (LM71); ``segments`` (start, end, q) [m, m, N/m] behind the first point,
    placed whole (SW/0)."""

    name: str
    axle_offsets: tuple[float, ...] = ()
    axle_loads: tuple[float, ...] = ()
    udl: float = 0.0
    udl_gap: float = 0.0
    segments: tuple[tuple[float, float, float], ...] = ()

    @property
    def extent(self) -> float:
        ends = [*self.axle_offsets, *(e for _, e, _ in self.segments)]
        return max(ends) if ends else 0.0


#: EN 1991-2:2003 6.3.2 Figure 6.1 (characteristic values, before alpha and Phi)
LM71 = LoadModel("LM71", (0.0, 1.6, 3.2, 4.8), (250e3,) * 4, udl=80e3, udl_gap=0.8)
#: EN 1991-2:2003 6.3.3 Table 6.1 (SW/0: q = 133 kN/m, a = 15 m, c = 5.3 m)
SW0 = LoadModel("SW/0", segments=((0.0, 15.0, 133e3), (20.3, 35.3, 133e3)))


def determinant_length(bridge) -> tuple[float, str]:  # noqa: ANN001
    """L_Phi [m] of EN 1991-2:2003 Table 6.2 [check] and its basis: simply supported spans: the shortest span
    (each span's own L, the largest Phi taken); a continuous girder of n spans: k L_mean with k = 1.2, 1.3, 1.4,
    1.5 for n = 2, 3, 4, >= 5, at least the longest span."""
    spans = [float(s) for s in bridge.spans]
    if isinstance(bridge, Continuous) and len(spans) > 1:
        k = {2: 1.2, 3: 1.3, 4: 1.4}.get(len(spans), 1.5)
        lp = max(k * sum(spans) / len(spans), max(spans))
        return lp, f"L_Phi = {lp:.3g} m ({k:g} x mean span, continuous girder, Table 6.2)"
    return min(spans), f"L_Phi = {min(spans):g} m (the shortest simply supported span, Table 6.2)"


def dynamic_factor(bridge, maintenance: str) -> tuple[float, str]:  # noqa: ANN001
    """Phi (Phi_2 for 'careful' maintenance, Phi_3 for 'standard'; EN 1991-2:2003 6.4.5.2) and its basis."""
    lp, basis = determinant_length(bridge)
    if maintenance == "careful":
        return code.dynamic_factor_phi2(lp), f"Phi_2 = {code.dynamic_factor_phi2(lp):.3f} ({basis})"
    if maintenance == "standard":
        return code.dynamic_factor_phi3(lp), f"Phi_3 = {code.dynamic_factor_phi3(lp):.3f} ({basis})"
    raise SettingError("dynamic_factor", "maintenance", maintenance, "careful or standard")


# ============================================================================ functionals of the displacements
def line_operator(model: FEModel, x: Sequence[float] | np.ndarray, offset: float, height: float,
                  component: str = "z", slope: bool = False) -> sp.csr_matrix:
    """(n_x, n_dof): row i maps the displacements u (every DOF) to the ``component`` ('z' vertical, 'y'
    lateral) of the line at ``offset`` e and ``height`` h from the girder's shear centre at x[i] (its slope
    d/dx with ``slope``), as the modes' rail shapes do (structure.fe.line_shape_evaluator: dz = w + e rx,
    dy = v - h rx, bending cubic and twist linear in each element). Zero rows off the bridge. Its transpose
    is the consistent nodal load of a unit force on the line."""
    x = np.atleast_1d(np.asarray(x, dtype=float))
    g = model.girder
    e_idx = np.clip(np.searchsorted(g.x_start, x, side="right") - 1, 0, len(g.x_start) - 1)
    on = (x >= 0.0) & (x <= model.length)
    rows, cols, vals = [], [], []
    cache: dict[int, np.ndarray] = {}
    for i in np.flatnonzero(on):
        e = int(e_idx[i])
        length = float(g.length[e])
        xi = (x[i] - g.x_start[e]) / length
        if slope:
            basis, lin = np.array([0.0, 1.0, 2.0 * xi, 3.0 * xi * xi]) / length, np.array([-1.0, 1.0]) / length
        else:
            basis, lin = np.array([1.0, xi, xi * xi, xi ** 3]), np.array([1.0 - xi, xi])
        key = (e, component)
        if key not in cache:
            cache[key] = cubic_coefficients(length, g.phi_vertical[e] if component == "z" else g.phi_lateral[e])
        w = basis @ cache[key]
        a, b = 6 * int(g.nodes[e, 0]), 6 * int(g.nodes[e, 1])
        if component == "z":
            dofs, coef, twist = [a + 2, a + 4, b + 2, b + 4], w * SIGN_VERTICAL, offset * lin
        else:
            dofs, coef, twist = [a + 1, a + 5, b + 1, b + 5], w, -height * lin
        rows += [i] * 6
        cols += dofs + [a + 3, b + 3]
        vals += [*coef, *twist]
    return sp.csr_matrix((vals, (rows, cols)), shape=(x.size, model.n_dof))


class StaticSolver:
    """One factorisation of a bridge's reduced stiffness; influence lines of functionals."""

    def __init__(self, model: FEModel) -> None:
        self.model = model
        k_r, _ = model.reduced()
        self._lu = sla.splu(k_r.tocsc())

    def influence(self, functionals: sp.spmatrix, s: np.ndarray, offset: float, height: float,
                  component: str = "z") -> np.ndarray:
        """(n_s, k): functional j of the displacements under a unit force (downwards for 'z', towards +y
        for 'y') at s[i] on the line (offset, height)."""
        t = self.model.transform
        rhs = np.asarray((t.T @ functionals.T).todense())
        g = self._lu.solve(rhs)
        sign = -1.0 if component == "z" else 1.0  # z up: a downward unit load is -1 in z
        return sign * np.asarray(line_operator(self.model, s, offset, height, component) @ (t @ g))


def load_grid(model: FEModel, step: float | None = None) -> tuple[np.ndarray, float]:
    """The loaded line's grid: 0 ... bridge length with a step dividing LM71's 0.8 m (at most 0.1 m and 1/50 of
    the shortest span)."""
    if step is None:
        step = min(0.1, float(np.min(model.span_lengths)) / 50.0)
    k = int(math.ceil(0.8 / step - 1e-9))
    ds = 0.8 / k
    n = int(math.floor(model.length / ds + 1e-9))
    return ds * np.arange(n + 1), ds


def envelope(eta: np.ndarray, ds: float, load: LoadModel) -> tuple[np.ndarray, np.ndarray]:
    """(largest, smallest) over every position of ``load`` of the functionals whose influence lines are the
    columns of ``eta`` (on a grid of step ``ds`` from 0; zero beyond it). The axles move as a group on the
    grid (their offsets rounded to it: exact when ds divides them, as for LM71's 1.6 and 0.8 m)."""
    eta = np.atleast_2d(np.asarray(eta, dtype=float))
    n, k = eta.shape
    pad = int(math.ceil((load.extent + load.udl_gap) / ds)) + 2
    z = np.vstack([np.zeros((pad, k)), eta, np.zeros((pad, k))])
    shifts = [int(round(a / ds)) for a in load.axle_offsets]
    top = max(shifts + [int(round(e / ds)) for _, e, _ in load.segments] + [0])
    starts = np.arange(0, z.shape[0] - top)
    points = np.zeros((starts.size, k))
    for sh, p in zip(shifts, load.axle_loads):
        points += p * z[starts + sh]
    cum = np.vstack([np.zeros((1, k)), np.cumsum(0.5 * (z[1:] + z[:-1]) * ds, axis=0)])
    for s0, s1, q in load.segments:
        points += q * (cum[starts + int(round(s1 / ds))] - cum[starts + int(round(s0 / ds))])
    if load.udl <= 0.0:
        return points.max(axis=0), points.min(axis=0)
    gap = int(round(load.udl_gap / ds))
    lo = np.clip(starts - gap, 0, z.shape[0] - 1)
    hi = np.clip(starts + top + gap, 0, z.shape[0] - 1)
    out = []
    for sign in (1.0, -1.0):
        part = np.maximum(sign * z, 0.0)
        c = np.vstack([np.zeros((1, k)), np.cumsum(0.5 * (part[1:] + part[:-1]) * ds, axis=0)])
        udl = load.udl * (c[-1] - (c[hi] - c[lo]))
        out.append((sign * points + udl).max(axis=0))
    return out[0], -out[1]


def largest(eta: np.ndarray, ds: float, loads: Sequence[LoadModel]) -> np.ndarray:
    """(k,): the largest |value| of each functional over the load models and their positions."""
    best = np.zeros(np.atleast_2d(eta).shape[1])
    for load in loads:
        hi, lo = envelope(eta, ds, load)
        best = np.maximum(best, np.maximum(hi, -lo))
    return best


# ============================================================================ the quantities
@dataclass(frozen=True)
class StaticDeformations:
    """Per track (index t): under one track loaded with the load models x 1 (alpha and Phi applied by the
    caller): ``deflection[t]`` (n_spans,) the largest |vertical deflection| of the track line in each span [m]
    and ``deflection_x[t]`` where; ``twist[t]`` the largest twist over 3 m between its rails [m] and
    ``twist_x[t]`` its station (the first rail section); ``end_rotation[t]`` (2,) the slope of the track line
    at the bridge's two ends [rad]; ``joint_rotation[t]`` (n_joints,) the kink between adjacent simply
    supported spans [rad]; lateral, under the nosing force (1 N x NOSING_FORCE): ``lateral[t]`` (n_spans,) the
    largest |lateral deflection| of the track line per span [m], ``horizontal_rotation[t]`` (n_spans, 2) the
    plan slope at each span's ends [rad]. ``loads``: the vertical load models' names."""

    spans: tuple[float, ...]
    loads: tuple[str, ...]
    deflection: tuple[np.ndarray, ...]
    deflection_x: tuple[np.ndarray, ...]
    twist: tuple[float, ...]
    twist_x: tuple[float, ...]
    end_rotation: tuple[np.ndarray, ...]
    joint_rotation: tuple[np.ndarray, ...]
    lateral: tuple[np.ndarray, ...]
    horizontal_rotation: tuple[np.ndarray, ...]


def _stations(starts: np.ndarray, lengths: np.ndarray, n: int = 16) -> tuple[np.ndarray, np.ndarray]:
    xs = np.concatenate([s + l * np.arange(1, n) / n for s, l in zip(starts, lengths)])
    span = np.repeat(np.arange(len(lengths)), n - 1)
    return xs, span


def static_deformations(bridge, vertical_loads: Sequence[LoadModel] | None = None) -> StaticDeformations:  # noqa: ANN001
    """The static quantities of A2.4.4.2.2-4 for every track of ``bridge`` (SimpleBeam, Frame or Continuous),
    each track loaded alone by ``vertical_loads`` (default LM71, plus SW/0 on a continuous girder) at unit
    alpha and Phi, and the nosing force at unit alpha."""
    model = assemble(bridge)
    if vertical_loads is None:
        vertical_loads = (LM71, SW0) if isinstance(bridge, Continuous) else (LM71,)
    solver = StaticSolver(model)
    starts, lengths = model.span_starts, model.span_lengths
    s, ds = load_grid(model)
    xs, span_of = _stations(starts, lengths)
    eps = 1e-9 * float(lengths.min())
    ends = np.array([eps, model.length - eps])
    joints = starts[1:] if not isinstance(bridge, Continuous) else np.array([])
    # the twist's sections: every node of the girder and 3 m before each, from 3 m before the deck to its end
    nodes_x = np.unique(np.concatenate([model.girder.x_start, [model.length]]))
    tw_x = np.unique(np.round(np.concatenate([nodes_x, nodes_x - TWIST_BASE]), 9))
    tw_x = tw_x[(tw_x >= -TWIST_BASE) & (tw_x <= model.length)]
    out: dict[str, list] = {k: [] for k in ("deflection", "deflection_x", "twist", "twist_x", "end_rotation",
                                             "joint_rotation", "lateral", "horizontal_rotation")}
    for e, h in track_lines(bridge):
        op = lambda x, comp="z", slope=False, off=e: line_operator(model, x, off, h, comp, slope)  # noqa: E731
        left, right = e + GAUGE / 2.0, e - GAUGE / 2.0
        twist = ((line_operator(model, tw_x, left, h) - line_operator(model, tw_x, right, h))
                 - (line_operator(model, tw_x + TWIST_BASE, left, h) - line_operator(model, tw_x + TWIST_BASE, right, h)))
        kink = (op(joints + eps, slope=True) - op(joints - eps, slope=True)) if joints.size else None
        blocks = [op(xs), twist, op(ends, slope=True)] + ([kink] if kink is not None else [])
        eta = solver.influence(sp.vstack(blocks).tocsr(), s, e, h)
        val = largest(eta, ds, vertical_loads)
        nd, nt = xs.size, tw_x.size
        d, tw, rot = val[:nd], val[nd:nd + nt], val[nd + nt:nd + nt + 2]
        per_span = [np.flatnonzero(span_of == j) for j in range(len(lengths))]
        out["deflection"].append(np.array([d[i].max() for i in per_span]))
        out["deflection_x"].append(np.array([xs[i][np.argmax(d[i])] for i in per_span]))
        out["twist"].append(float(tw.max()))
        out["twist_x"].append(float(tw_x[np.argmax(tw)]))
        out["end_rotation"].append(rot)
        out["joint_rotation"].append(val[nd + nt + 2:] if kink is not None else np.zeros(0))
        # lateral: the nosing force, a point force at rail level anywhere on the track
        span_ends = np.concatenate([[a + eps, a + l - eps] for a, l in zip(starts, lengths)])
        lat = solver.influence(sp.vstack([op(xs, "y"), op(span_ends, "y", True)]).tocsr(), s, e, h, "y")
        lat_max = NOSING_FORCE * np.abs(lat).max(axis=0)
        out["lateral"].append(np.array([lat_max[:nd][i].max() for i in per_span]))
        out["horizontal_rotation"].append(lat_max[nd:].reshape(-1, 2))
    return StaticDeformations(spans=tuple(float(x) for x in lengths), loads=tuple(m.name for m in vertical_loads),
                              **{k: tuple(v) for k, v in out.items()})


def first_lateral_frequency(frequencies: Sequence[float], mode_types: Sequence[str]) -> float:
    """The lowest frequency of a mode whose kinetic energy is mostly lateral bending (structure.fe's mode
    types); NaN when no such mode was computed."""
    f = [float(x) for x, t in zip(frequencies, mode_types) if t == "lateral"]
    return min(f) if f else math.nan


__all__ = ["GAUGE", "LM71", "LoadModel", "NOSING_FORCE", "SW0", "StaticDeformations", "StaticSolver",
           "determinant_length", "dynamic_factor", "envelope", "first_lateral_frequency", "largest", "line_operator",
           "load_grid", "static_deformations"]
