"""Modal reduction of the bridge finite-element model and the ModalBridge built from it.

:func:`modal_bridge` is the entry point: bridge data (``SimpleBeam`` or ``Frame``) in, a
mass-normalised :class:`~tb_exudyn.structure.modal.ModalBridge` out. In between:

1. :func:`~tb_exudyn.structure.assembly.assemble`: sparse K, M and the rigid-constraint map u = T q;
2. :func:`solve_modes`: the lowest modes of (T^T K T) q = omega^2 (T^T M T) q by shift-invert
   Lanczos (``scipy.sparse.linalg.eigsh``) with a negative shift, so the factorisation exists even
   for a mechanism, which is then reported (a zero-frequency mode, named by where it moves) instead
   of failing inside the solver. Independent parts (e.g. the separate spans of a ``SimpleBeam``) are
   solved one by one, so their (equal) modes stay separate instead of mixing;
3. mode types from modal kinetic-energy fractions, effective masses, damping ratios
   (:func:`rayleigh_damping_ratios` turns Rayleigh coefficients into modal ratios);
4. :class:`RailShapeEvaluator`: rail-level mode shapes anywhere along the track from the element
   interpolation (cubic bending, linear twist), as precomputed per-element polynomial
   coefficients, so an evaluation is one gather and one small product.

Pure numpy/scipy, no Exudyn.
"""

from __future__ import annotations

import math
from collections import OrderedDict
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import scipy.linalg as la
import scipy.sparse as sp
import scipy.sparse.csgraph as csgraph
import scipy.sparse.linalg as sla

from ..scenario.model import Frame, SimpleBeam
from ..scenario.sections import track_lines
from .assembly import (DOF_NAMES, GIRDER, PIER, FEModel, StructureError, assemble, extreme_section_key, mechanism_key,
                       validate_bridge)
from .beam import SIGN_VERTICAL, cubic_coefficients
from .size import check_bridge_size
from .modal import ModalBridge, ModeSet, RailShapes, TrackShapes, track_stations

#: kinetic-energy groups used to name a mode
ENERGY_GROUPS = ("vertical", "lateral", "torsion", "longitudinal", "pier")
#: a mode is named after the group holding at least this fraction of its kinetic energy, else 'mixed'
DOMINANT_FRACTION = 0.5
#: a mode below this frequency [Hz] is a mechanism (a real bridge has none below ~0.1 Hz; round-off
#: puts a true zero at about 1e-5 Hz for these models)
MECHANISM_FREQUENCY = 1e-2
#: eigsh shift [Hz]: the shifted matrix K + (2 pi f)^2 M is positive definite even for a mechanism
_SHIFT_FREQUENCY = 1.0
#: components up to this size are solved densely (faster and more robust than Lanczos)
_DENSE_LIMIT = 400


# ============================================================================================
# modes


@dataclass(frozen=True)
class FEModes(ModeSet):
    """Modes of an assembled model.

    Attributes
    ----------
    model : the assembled model
    frequencies : (n,) [Hz], ascending
    shapes : (n_dof, n) mass-normalised modes on all DOFs (phi^T M phi = I)
    energy_fractions : (n, 5) kinetic-energy fractions per group of :data:`ENERGY_GROUPS`
    mode_types : (n,) 'vertical', 'lateral', 'torsion', 'longitudinal', 'pier' or 'mixed'
    effective_masses : (n, 3) effective modal masses for rigid motion in y, z [kg] and about x [kg m^2]
    total_masses : (3,) r^T M r of the same rigid motions (their sum over all modes)
    """

    model: FEModel = field(repr=False)
    frequencies: np.ndarray
    shapes: np.ndarray = field(repr=False)
    energy_fractions: np.ndarray = field(repr=False)
    mode_types: tuple[str, ...]
    effective_masses: np.ndarray = field(repr=False)
    total_masses: np.ndarray = field(repr=False)


def _eigen_dense(k: sp.spmatrix, m: sp.spmatrix, n_wanted: int) -> tuple[np.ndarray, np.ndarray]:
    lam, vec = la.eigh(k.toarray(), m.toarray(), subset_by_index=(0, min(n_wanted, k.shape[0]) - 1))
    return lam, vec


def _eigen_sparse(k: sp.spmatrix, m: sp.spmatrix, n_wanted: int) -> tuple[np.ndarray, np.ndarray]:
    sigma = -((2.0 * np.pi * _SHIFT_FREQUENCY) ** 2)
    v0 = np.random.default_rng(12345).standard_normal(k.shape[0])  # fixed: reproducible modes
    lam, vec = sla.eigsh(k.tocsc(), k=n_wanted, M=m.tocsc(), sigma=sigma, which="LM", v0=v0)
    order = np.argsort(lam)
    return lam[order], vec[:, order]


def _eigen(k: sp.spmatrix, m: sp.spmatrix, lam_max: float, max_modes: int) -> tuple[np.ndarray, np.ndarray]:
    """Lowest eigenpairs with lambda <= lam_max (at most max_modes if > 0; always the lowest one)."""
    n = k.shape[0]
    if n <= _DENSE_LIMIT:
        lam, vec = _eigen_dense(k, m, n)
    else:
        want = min(n - 2, max_modes if max_modes > 0 else 24)
        while True:
            lam, vec = _eigen_sparse(k, m, want)
            more = lam[-1] <= lam_max and want < n - 2 and (max_modes == 0 or want < max_modes)
            if not more:
                break
            want = min(n - 2, 2 * want if max_modes == 0 else min(2 * want, max_modes))
    keep = max(1, int(np.count_nonzero(lam <= lam_max)))
    if max_modes > 0:
        keep = min(keep, max_modes)
    return lam[:keep], vec[:, :keep]


def _components(k: sp.spmatrix, m: sp.spmatrix) -> list[np.ndarray]:
    """Index sets of the uncoupled parts of (K, M)."""
    pattern = (abs(k) + abs(m)).tocsr()
    count, labels = csgraph.connected_components(pattern, directed=False)
    return [np.flatnonzero(labels == c) for c in range(count)]


def _dominant_motion(model: FEModel, phi_full: np.ndarray) -> tuple[int, int, int]:
    """Where a mode moves most: the (part, member, DOF) with the largest kinetic energy."""
    energy = phi_full * (model.mass @ phi_full)
    keys: dict[tuple[int, int, int], float] = {}
    for dof in np.flatnonzero(np.abs(energy) > 0):
        node, j = divmod(int(dof), 6)
        key = (int(model.node_part[node]), int(model.node_member[node]), j)
        keys[key] = keys.get(key, 0.0) + float(energy[dof])
    return max(keys, key=keys.get)


def _check_mechanism(model: FEModel, lam: np.ndarray, vec_full: np.ndarray) -> None:
    zero = lam < (2.0 * np.pi * MECHANISM_FREQUENCY) ** 2
    if not np.any(zero):
        return
    f0 = math.sqrt(max(float(lam[0]), 0.0)) / (2.0 * np.pi)
    part, member, j = _dominant_motion(model, vec_full[:, 0])
    what = f"the girder of span {member + 1}" if part == GIRDER else f"pier {member + 1}"
    key, value = mechanism_key(model.bridge, part, j, member)
    allowed = ("a stiffness > 0" if key.split(".")[-1].startswith("k_")
               else f"a section stiff enough for its mass in {DOF_NAMES[j]} (every mode >= {MECHANISM_FREQUENCY:g} Hz)")
    raise StructureError(
        f"bridge '{model.name}'", key, value, allowed,
        f"mechanism: {int(zero.sum())} mode(s) below {MECHANISM_FREQUENCY:g} Hz (lowest {f0:.2g} Hz), "
        f"mainly {what} in {DOF_NAMES[j]}",
    )


def _group_masks(model: FEModel) -> np.ndarray:
    """(5, n_dof) boolean masks of :data:`ENERGY_GROUPS`."""
    part = np.repeat(model.node_part, 6)
    j = np.tile(np.arange(6), model.n_nodes)
    g = part == GIRDER
    return np.array([
        g & ((j == 2) | (j == 4)),
        g & ((j == 1) | (j == 5)),
        g & (j == 3),
        g & (j == 0),
        part == PIER,
    ])


def energy_fractions(model: FEModel, shapes: np.ndarray) -> np.ndarray:
    """(n, 5) kinetic-energy fractions phi_g^T M_gg phi_g / sum, per group of :data:`ENERGY_GROUPS`."""
    out = np.empty((shapes.shape[1], len(ENERGY_GROUPS)))
    for i, mask in enumerate(_group_masks(model)):
        p = shapes * mask[:, None]
        out[:, i] = np.einsum("ij,ij->j", p, model.mass @ p)
    total = out.sum(axis=1, keepdims=True)
    return out / np.where(total > 0.0, total, 1.0)


def classify_modes(fractions: np.ndarray, dominant: float = DOMINANT_FRACTION) -> tuple[str, ...]:
    """Name each mode after its dominant energy group (fraction >= ``dominant``), else 'mixed'."""
    best = np.argmax(fractions, axis=1)
    return tuple(
        ENERGY_GROUPS[b] if fractions[i, b] >= dominant else "mixed" for i, b in enumerate(best)
    )


def rigid_motions(model: FEModel) -> np.ndarray:
    """(n_dof, 3) unit rigid motions: translation along y, along z, rotation about the x axis."""
    r = np.zeros((model.n_dof, 3))
    y, z = model.coordinates[:, 1], model.coordinates[:, 2]
    r[1::6, 0] = 1.0
    r[2::6, 1] = 1.0
    r[1::6, 2] = -z
    r[2::6, 2] = y
    r[3::6, 2] = 1.0
    return r


def lumped_masses(model: FEModel) -> np.ndarray:
    """(n_nodes,) translational mass of each node: the row sums M r_x of a unit x translation."""
    r = np.zeros(model.n_dof)
    r[0::6] = 1.0
    return np.asarray(model.mass @ r)[0::6]


def solve_modes(model: FEModel, max_frequency: float, max_modes: int = 0) -> FEModes:
    """The modes of ``model`` up to ``max_frequency`` [Hz] (at most ``max_modes`` if > 0).

    Raises
    ------
    StructureError
        for a mechanism (a mode below :data:`MECHANISM_FREQUENCY`), naming where it moves, or when
        no mode lies below ``max_frequency``.
    """
    if not (max_frequency > 0.0 and math.isfinite(max_frequency)):
        raise StructureError(f"bridge '{model.name}'", "max_frequency", max_frequency, "a finite frequency > 0 [Hz]")
    if max_modes < 0:
        raise StructureError(f"bridge '{model.name}'", "max_modes", max_modes, ">= 0 (0: no limit)")
    with np.errstate(over="ignore", invalid="ignore"):  # huge (finite) element values: refused below
        k_r, m_r = model.reduced()
    if k_r.shape[0] == 0:
        raise StructureError(f"bridge '{model.name}'", "<top level>", model.name, "a bridge with a free DOF",
                             "every DOF is fixed, no mode to compute")
    if not (np.all(np.isfinite(k_r.data)) and np.all(np.isfinite(m_r.data))):
        key, value = extreme_section_key(model.bridge)
        raise StructureError(f"bridge '{model.name}'", key, value, "section values whose stiffness and mass matrices "
                             "are finite numbers", "the finite-element matrices overflow")
    lam_max = (2.0 * np.pi * max_frequency) ** 2
    lams, vecs = [], []
    for idx in _components(k_r, m_r):
        lam, vec = _eigen(k_r[idx][:, idx], m_r[idx][:, idx], lam_max, max_modes)
        full = np.zeros((k_r.shape[0], lam.size))
        full[idx] = vec
        _check_mechanism(model, lam, model.transform @ full)
        lams.append(lam)
        vecs.append(full)
    lam = np.concatenate(lams)
    vec = np.hstack(vecs)
    order = np.argsort(lam, kind="stable")
    lam, vec = lam[order], vec[:, order]
    keep = lam <= lam_max
    if not np.any(keep):
        f0 = math.sqrt(lam[0]) / (2.0 * np.pi)
        raise StructureError(f"bridge '{model.name}'", "max_frequency", max_frequency,
                             f"above the bridge's lowest mode, {f0:.4g} Hz", "no mode below max_frequency")
    lam, vec = lam[keep], vec[:, keep]
    if max_modes > 0:
        lam, vec = lam[:max_modes], vec[:, :max_modes]
    vec = vec / np.sqrt(np.einsum("ij,ij->j", vec, m_r @ vec))
    shapes = model.transform @ vec
    # a reproducible sign: the first entry of at least 10 % of the largest is positive (the largest
    # entry itself is no good: symmetric structures have near-ties of opposite sign)
    mag = np.abs(shapes)
    first = np.argmax(mag >= 0.1 * mag.max(axis=0), axis=0)
    shapes = shapes * np.sign(shapes[first, np.arange(shapes.shape[1])])
    fractions = energy_fractions(model, shapes)
    r = rigid_motions(model)
    mr = model.mass @ r
    gamma = shapes.T @ mr
    return FEModes(
        model=model,
        frequencies=np.sqrt(np.maximum(lam, 0.0)) / (2.0 * np.pi),
        shapes=shapes,
        energy_fractions=fractions,
        mode_types=classify_modes(fractions),
        effective_masses=gamma**2,
        total_masses=np.einsum("ij,ij->j", r, mr),
    )


def static_displacement(model: FEModel, loads: np.ndarray) -> np.ndarray:
    """The direct static solution u (all DOFs) of K u = f for nodal loads f (n_dof,) or (n_dof, k)."""
    k_r, _ = model.reduced()
    t = model.transform
    q = sla.spsolve(k_r.tocsc(), t.T @ loads)
    return t @ q


# ============================================================================================
# damping


def rayleigh_damping_ratios(omega: np.ndarray, alpha: float, beta: float) -> np.ndarray:
    """Modal damping ratios of Rayleigh damping C = alpha M + beta K: zeta = alpha / (2 w) + beta w / 2."""
    w = np.asarray(omega, dtype=float)
    return alpha / (2.0 * w) + 0.5 * beta * w


def rayleigh_coefficients(f1: float, f2: float, zeta: float) -> tuple[float, float]:
    """(alpha, beta) giving damping ratio ``zeta`` at frequencies f1 and f2 [Hz]."""
    w1, w2 = 2.0 * np.pi * f1, 2.0 * np.pi * f2
    beta = 2.0 * zeta / (w1 + w2)
    return beta * w1 * w2, beta


# ============================================================================================
# mode shapes along the track


@dataclass(frozen=True)
class RailShapeEvaluator:
    """Mode shapes at a line parallel to the girder axis, as a callable x -> RailShapes.

    Per girder element e and mode k the displacements (y, z, rx) of the line are cubic
    polynomials in xi = (x - x_start[e]) / length[e]; ``coefficients[e, p, c * n + k]`` is the
    coefficient of xi^p of component c (0: y, 1: z, 2: rx) of mode k. An evaluation finds the
    element of every x (searchsorted), gathers its coefficients and multiplies them by the powers
    of xi (values) and their derivatives (slopes): one gather and one batched product.

    The arrays carry a sentinel element with zero coefficients before x = 0 and after the bridge
    end, so positions off the bridge give zeros without a mask (x = length belongs to the bridge).
    Build it with :func:`line_shape_evaluator`.
    """

    bounds: np.ndarray
    x_start: np.ndarray
    inv_length: np.ndarray
    coefficients: np.ndarray = field(repr=False)
    length: float
    n_modes: int

    def __call__(self, x: np.ndarray) -> RailShapes:
        x = np.asarray(x, dtype=float)
        e = np.searchsorted(self.bounds, x, side="right") - 1
        inv = self.inv_length.take(e)
        xi = (x - self.x_start.take(e)) * inv
        xi2 = xi * xi
        basis = np.empty((x.size, 2, 4))
        basis[:, 0, 0] = 1.0
        basis[:, 0, 1] = xi
        basis[:, 0, 2] = xi2
        basis[:, 0, 3] = xi2 * xi
        basis[:, 1, 0] = 0.0
        basis[:, 1, 1] = inv
        basis[:, 1, 2] = 2.0 * xi * inv
        basis[:, 1, 3] = 3.0 * xi2 * inv
        out = np.matmul(basis, self.coefficients.take(e, axis=0))
        n = self.n_modes
        return RailShapes(
            out[:, 0, :n], out[:, 0, n : 2 * n], out[:, 0, 2 * n :],
            out[:, 1, :n], out[:, 1, n : 2 * n], out[:, 1, 2 * n :],
        )

    def truncated(self, n_modes: int) -> "RailShapeEvaluator":
        """The same evaluator for the lowest ``n_modes`` modes only."""
        n, m = int(n_modes), self.n_modes
        cols = np.concatenate([np.arange(n), m + np.arange(n), 2 * m + np.arange(n)])
        return RailShapeEvaluator(
            self.bounds, self.x_start, self.inv_length,
            np.ascontiguousarray(self.coefficients[:, :, cols]), self.length, n,
        )


def line_shape_evaluator(
    model: FEModel, shapes: np.ndarray, offset: float = 0.0, height: float = 0.0
) -> RailShapeEvaluator:
    """Mode shapes along a line at lateral ``offset`` e and ``height`` h from the girder shear centre.

    The line moves by dy = v - h rx, dz = w + e rx and rotates by rx, with v, w the girder's
    bending interpolation (cubic) and rx its twist (linear) within each element.
    """
    g = model.girder
    n_el, n = g.nodes.shape[0], shapes.shape[1]
    a, b = 6 * g.nodes[:, 0], 6 * g.nodes[:, 1]
    coef = np.zeros((n_el, 4, 3 * n))
    for e in range(n_el):
        c_lat = cubic_coefficients(g.length[e], g.phi_lateral[e])
        c_ver = cubic_coefficients(g.length[e], g.phi_vertical[e])
        v = c_lat @ shapes[[a[e] + 1, a[e] + 5, b[e] + 1, b[e] + 5]]
        w = c_ver @ (shapes[[a[e] + 2, a[e] + 4, b[e] + 2, b[e] + 4]] * SIGN_VERTICAL[:, None])
        t = np.zeros((4, n))
        t[0] = shapes[a[e] + 3]
        t[1] = shapes[b[e] + 3] - shapes[a[e] + 3]
        coef[e, :, :n] = v - height * t
        coef[e, :, n : 2 * n] = w + offset * t
        coef[e, :, 2 * n :] = t
    zero = np.zeros((1, 4, 3 * n))
    return RailShapeEvaluator(
        bounds=np.concatenate([[-np.inf], g.x_start, [np.nextafter(model.length, np.inf)]]),
        x_start=np.concatenate([[0.0], g.x_start, [0.0]]),
        inv_length=np.concatenate([[0.0], 1.0 / g.length, [0.0]]),
        coefficients=np.concatenate([zero, coef, zero]),
        length=model.length,
        n_modes=n,
    )


# ============================================================================================
# stations, report, ModalBridge


def stations(model: FEModel, shapes: np.ndarray, tracks: tuple[TrackShapes, ...] = ()
             ) -> tuple[tuple[str, ...], np.ndarray]:
    """Named output stations and their (y, z, rx) shape rows, array (n_stations, 3, n_modes).

    Quarter points and midspan of every span on the girder axis ('span1.q1', 'span1.mid',
    'span1.q3', ...), pier tops ('pier1.top', ...) and, with two ``tracks`` or more, the span points
    along each track at rail level ('span1.mid.track2', :func:`.modal.track_stations`).
    """
    axis = line_shape_evaluator(model, shapes)
    names, xs = [], []
    for s, (x0, length) in enumerate(zip(model.span_starts, model.span_lengths)):
        for label, frac in (("q1", 0.25), ("mid", 0.5), ("q3", 0.75)):
            names.append(f"span{s + 1}.{label}")
            xs.append(x0 + frac * length)
    rows = []
    if xs:
        r = axis(np.array(xs))
        rows.append(np.stack([r.y, r.z, r.rx], axis=1))
    for i, node in enumerate(model.pier_top_nodes):
        names.append(f"pier{i + 1}.top")
        rows.append(shapes[[6 * node + 1, 6 * node + 2, 6 * node + 3]][None, :, :])
    along, along_rows = track_stations(names[:len(xs)], xs, tracks)
    if along_rows is not None:
        names, rows = names + list(along), rows + [along_rows]
    return tuple(names), np.concatenate(rows, axis=0)


@dataclass(frozen=True)
class ModalReport:
    """Frequencies, effective masses and mode types of a bridge (see :func:`modal_report`)."""

    bridge: str
    frequencies: np.ndarray
    mode_types: tuple[str, ...]
    energy_fractions: np.ndarray
    effective_masses: np.ndarray
    total_masses: np.ndarray

    def table(self, n: int | None = None) -> str:
        """A plain-text table of the first ``n`` modes (all by default)."""
        n = self.frequencies.size if n is None else min(n, self.frequencies.size)
        head = (f"{'mode':>4} {'f [Hz]':>9} {'type':<12} "
                + " ".join(f"{g[:5]:>6}" for g in ENERGY_GROUPS)
                + f" {'meff_y %':>8} {'meff_z %':>8} {'meff_rx %':>9}")
        lines = [f"bridge '{self.bridge}': {self.frequencies.size} modes", head]
        pct = 100.0 * self.effective_masses / np.where(self.total_masses > 0, self.total_masses, 1.0)
        for i in range(n):
            lines.append(
                f"{i + 1:>4} {self.frequencies[i]:>9.3f} {self.mode_types[i]:<12} "
                + " ".join(f"{v:>6.2f}" for v in self.energy_fractions[i])
                + f" {pct[i, 0]:>8.2f} {pct[i, 1]:>8.2f} {pct[i, 2]:>9.2f}"
            )
        return "\n".join(lines)


def modal_report(modes: FEModes) -> ModalReport:
    """The report of computed modes: frequencies, types, energy fractions, effective masses."""
    return ModalReport(
        bridge=modes.model.name, frequencies=modes.frequencies, mode_types=modes.mode_types,
        energy_fractions=modes.energy_fractions, effective_masses=modes.effective_masses,
        total_masses=modes.total_masses,
    )


#: the last bridges' modes by their inputs (bridge data are frozen, hashable values): a speed sweep or
#: a code check solves the same bridge for every speed and train (li_zhu_2011: 0.04 s a solve, one
#: per speed and three in the parent of a sweep); kept with read-only arrays, shared by the callers
_SOLVED: OrderedDict[tuple[Any, float, int], FEModes] = OrderedDict()
_SOLVED_KEPT = 4


def _read_only(modes: FEModes) -> FEModes:
    """``modes`` with every array it holds (its model's included) made read-only, in place."""
    arrays = [modes.frequencies, modes.shapes, modes.energy_fractions, modes.effective_masses, modes.total_masses]
    for value in vars(modes.model).values():
        if isinstance(value, np.ndarray):
            arrays.append(value)
        elif sp.issparse(value):
            arrays += [a for a in (getattr(value, n, None) for n in ("data", "indices", "indptr")) if a is not None]
    for a in arrays:
        a.setflags(write=False)
    return modes


def bridge_modes(bridge: SimpleBeam | Frame, max_frequency: float, max_modes: int = 0) -> FEModes:
    """Assemble ``bridge`` and compute its modes (see :func:`solve_modes`); a bridge whose model would
    not fit the memory available is refused first (:func:`.size.check_bridge_size`). The last few
    results are kept by their inputs (the same bridge data and limits give the same modes, whose
    arrays are read-only)."""
    key = (bridge, float(max_frequency), int(max_modes))
    try:
        hit = _SOLVED.get(key)
    except TypeError:  # bridge data that are not a hashable value: solved every time
        key, hit = None, None
    if hit is not None:
        _SOLVED.move_to_end(key)
        return hit
    validate_bridge(bridge)
    check_bridge_size(bridge, max_frequency, max_modes, solve_modes)
    modes = _read_only(solve_modes(assemble(bridge), max_frequency, max_modes))
    if key is None:
        return modes
    _SOLVED[key] = modes
    while len(_SOLVED) > _SOLVED_KEPT:
        _SOLVED.popitem(last=False)
    return modes


def modal_bridge_from_modes(
    modes: FEModes, damping_ratios: np.ndarray | float | None = None, description: str = ""
) -> ModalBridge:
    """The :class:`ModalBridge` of computed modes (rail line at the model's track offset and height)."""
    model = modes.model
    zeta = model.damping_ratio if damping_ratios is None else damping_ratios
    zeta = np.broadcast_to(np.asarray(zeta, dtype=float), modes.frequencies.shape).copy()
    lines = track_lines(model.bridge) if model.bridge is not None else ((model.track_offset, model.track_height),)
    tracks = tuple(TrackShapes(e, h, line_shape_evaluator(model, modes.shapes, e, h)) for e, h in lines)
    names, rows = stations(model, modes.shapes, tracks)
    node_shapes = modes.shapes.reshape(model.n_nodes, 6, -1)[:, :3, :]
    return ModalBridge(
        frequencies=modes.frequencies,
        damping_ratios=zeta,
        length=model.length,
        mode_types=modes.mode_types,
        station_names=names,
        station_shapes=rows,
        rail_shape_function=tracks[0].shapes,
        effective_masses=modes.effective_masses,
        description=description or f"finite-element modes of bridge '{model.name}'",
        node_positions=model.coordinates.copy(),
        node_shapes=np.ascontiguousarray(node_shapes),
        node_masses=lumped_masses(model),
        tracks=tracks if len(tracks) > 1 else (),
    )


def modal_bridge(
    bridge: SimpleBeam | Frame,
    max_frequency: float,
    max_modes: int = 0,
    rayleigh: tuple[float, float] | None = None,
) -> ModalBridge:
    """The mass-normalised modal model of a bridge from its spatial-beam finite-element model.

    Parameters
    ----------
    bridge : ``SimpleBeam`` or ``Frame`` data; x = 0 at the start of the first span
    max_frequency : keep the modes up to this frequency [Hz]
    max_modes : at most this many modes (0: no limit)
    rayleigh : optional Rayleigh coefficients (alpha [1/s], beta [s]) replacing the bridge's
        damping_ratio by the modal ratios alpha / (2 w) + beta w / 2

    Raises
    ------
    StructureError
        bad bridge data (zero span, negative stiffness, ...), a mechanism or an unsupported part,
        or no mode below ``max_frequency``.
    """
    modes = bridge_modes(bridge, max_frequency, max_modes)
    zeta = None if rayleigh is None else rayleigh_damping_ratios(modes.omega, *rayleigh)
    return modal_bridge_from_modes(modes, zeta)
