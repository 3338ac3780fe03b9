"""Damped modal analysis of the linear train-bridge system, mode labels and the damping guard.

Pure numpy/scipy, no Exudyn. The builder supplies M, K, D of the linearised system and a
:class:`Dof` description of every global coordinate (:mod:`tb_exudyn.builder.system_modes`).

Eigenproblem. M q'' + D q' + K q = 0 in first-order form, with x = [q; q'] (K and D need not be
symmetric: creep forces): for M positive definite the standard problem in mass-normalised
coordinates (:func:`_first_order`), else ``[[0, I], [-K, -D]] x = lambda [[I, 0], [0, M]] x``
(``scipy.linalg.eig``, generalised; infinite eigenvalues of a singular M are dropped). For an eigenvalue
lambda = -zeta omega_n + i omega_n sqrt(1 - zeta^2):

- undamped natural frequency f_n = |lambda| / 2 pi [Hz] (:attr:`ModeTable.frequency`; the
  frequency the tables report first, the one a half-power band and a frequency grid refer to),
- damped frequency f_d = Im lambda / 2 pi [Hz] (:attr:`ModeTable.damped_frequency`),
- damping ratio zeta = -Re lambda / |lambda|,
- decay time tau = 1 / (zeta omega_n) = -1 / Re lambda [s]: the free vibration's amplitude falls by
  1/e in tau; its energy and the variance of a randomly excited response settle with 2 / tau.

A complex-conjugate pair is one mode (Im lambda > 0 is kept). A real eigenvalue (an overdamped,
non-oscillating motion, e.g. a critically damped weak spring) is its own row with f_d = 0,
f_n = |lambda| / 2 pi and zeta = 1 (-lambda / |lambda|), so its decay time is 1 / |lambda|. A
rigid-body (near-zero) eigenvalue, |lambda| / 2 pi below :data:`RIGID_FREQUENCY`, has f = 0 and
zeta = nan; an unstable one (Re lambda > 0) a negative zeta.

Round-off. What only round-off decides is fixed, so that a table has the same rows, order and
labels on every machine (numpy's OpenBLAS picks a kernel per CPU, OPENBLAS_CORETYPE): imaginary
and real parts within round-off are zero (:func:`~tb_exudyn.system.mode_roundoff.snap_round_off`: a double real root gives two
real rows whether LAPACK returns it as two reals or as a pair lambda +- i d; an undamped mode has
zeta = 0, not +-1e-16), rows equal within :data:`DEGENERATE_RTOL` are ordered by label
(:func:`~tb_exudyn.system.mode_roundoff.table_order`) and equal energy shares are named together (:data:`SHARE_TIE`).
tests/system/test_modes_blas_kernels.py compares the tables under four kernels.

Labels. Each mode's kinetic energy is split over the coordinates: the share of coordinate i is
Re(conj(phi_i) (M phi)_i) / phi^H M phi (phi: the displacement part of the eigenvector; for the
diagonal M the builder makes, m_ii |phi_i|^2 / sum). Kinetic, not kinetic plus strain energy: K
couples coordinates, so strain energy has no per-coordinate split, while for a diagonal M every
kinetic share is >= 0 and they add up to 1. The label names the groups (the bridge, car k) holding
at least :data:`LABEL_SHARE` of the energy, in each the parts (body, leading bogie, axle 2, a bridge
mode) and in each part its components (lateral, roll, yaw, ...), e.g. "car 2 (ice_trailer),
leading bogie, yaw" or "bridge, lateral 1".

Splitting and degenerate modes. Coordinates that no matrix entry connects form independent parts
(the bridge and each car on rigid track, a car's longitudinal coordinates); each part is solved on
its own, so equal modes of identical cars stay apart instead of mixing. Inside a part, equal
eigenvalues (a symmetric car's two bogie yaw modes) span a space in which every vector is a mode;
that space is rotated to the basis that localises the energy on single parts (the eigenvectors of
a mass-weighted part-index operator), so the labels are "leading bogie" and "trailing bogie" and
not an arbitrary mixture.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Literal, Mapping, Sequence

import numpy as np
import scipy.linalg as la
from numpy.typing import NDArray
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import connected_components

from .mode_roundoff import DEGENERATE_RTOL, REAL_SNAP, RIGID_FREQUENCY, ROUND_OFF, snap_round_off, table_order

#: a group, part or component is named in a label if it holds at least this share of the energy
#: (of the mode, of its group, of its part); the largest one always is
LABEL_SHARE = 0.2
#: matrix entries below this fraction of the matrix's largest entry do not connect coordinates
COUPLING_ZERO = 1e-14
#: a mode whose reach (:func:`damped_modes`) by every input of a group is below this is not reached
#: by the group: zero by symmetry up to round-off. Measured on an ICE creep car at 220 km/h: the
#: wheelsets' antisymmetric longitudinal/spin modes 6e-17 to 2e-16; the least reached modes 1.3e-8
#: (the wheelsets' slow spin roots, "rigid") and 2.7e-8 (the train's surge on the weak springs,
#: through the bogies' pitch), 2e-5 (car body bounce by the vertical profile), 1.5e-5 (body roll by
#: cross-level)
REACH_ZERO = 1e-10

Role = Literal["bridge", "vehicle", "wheelset"]
#: the kinds of mode: what holds most of its energy (see :func:`mode_kind`)
KINDS: tuple[str, ...] = ("bridge", "vehicle", "contact", "decoupled", "rigid")
DIRECTIONS: tuple[str, ...] = ("vertical", "lateral", "torsion")

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class Dof:
    """What one global coordinate of the linear system is (supplied by the builder).

    Attributes
    ----------
    group : the structure it belongs to, as labels name it: "bridge", "car 2 (ice_trailer)"
    part : the body within the group: "body", "leading bogie", "axle 3"; for a bridge modal
        coordinate its type and number, "vertical 1", "lateral 2", "torsion 1", "pier 1"
    component : what the coordinate moves, in words: "lateral", "bounce", "roll", "pitch", "yaw",
        "longitudinal", "spin"; for a bridge mode its type ("vertical", "lateral", ...)
    channel : the channel prefix of the part ("car2.bogie1", "bridge")
    role : "bridge" (a bridge modal coordinate), "vehicle" (car body, bogie, sprung mass) or
        "wheelset" (a body in wheel-rail contact)
    decoupled : a coordinate held only by the builder's weak springs (body x, wheelset spin and
        yaw): no irregularity and no coupled mode reaches it
    """

    group: str
    part: str
    component: str
    channel: str
    role: Role = "vehicle"
    decoupled: bool = False


# ============================================================================================
# the eigenproblem


@dataclass(frozen=True)
class Eigenmodes:
    """Raw result of :func:`damped_modes`: one entry per mode (conjugate pairs once), unsorted.

    eigenvalues : (n_modes,) complex [1/s]; shares : (n_modes, n_dof) kinetic-energy shares;
    reach : (n_modes, n_groups) how strongly each group of inputs reaches each mode (None: no inputs
    given; see :func:`damped_modes`).
    """

    eigenvalues: NDArray[np.complex128]
    shares: FloatArray
    reach: FloatArray | None = None


def independent_parts(*matrices: FloatArray, zero: float = COUPLING_ZERO) -> list[NDArray[np.int64]]:
    """Index sets of the coordinates no entry of the matrices connects (graph components);
    an entry counts if |a_ij| > ``zero`` x max |a| of its matrix."""
    n = matrices[0].shape[0]
    pattern = np.zeros((n, n), dtype=bool)
    for a in matrices:
        a = np.abs(np.asarray(a, dtype=float))
        top = a.max(initial=0.0)
        if top > 0.0:
            pattern |= a > zero * top
    count, labels = connected_components(csr_matrix(pattern), directed=False)
    return [np.flatnonzero(labels == c) for c in range(count)]


def _kinetic_shares(phi: NDArray[np.complex128], M: FloatArray) -> FloatArray:
    """(n, m) shares of each column's kinetic energy per coordinate (>= 0, columns sum to 1)."""
    e = np.real(np.conj(phi) * (M @ phi))
    e = np.clip(e, 0.0, None)
    total = e.sum(axis=0)
    return e / np.where(total > 0.0, total, 1.0)


def _localise(phi: NDArray[np.complex128], M: FloatArray, part_index: NDArray[np.int64]
              ) -> tuple[NDArray[np.complex128], NDArray[np.complex128]]:
    """A basis phi c of span(phi) (equal eigenvalues) whose vectors are localised on parts: the
    eigenvectors of the operator W (part index + 1 on the diagonal) in the M inner product;
    returns (phi c, c)."""
    B = phi.conj().T @ M @ phi
    A = phi.conj().T @ ((part_index + 1.0)[:, None] * (M @ phi))
    B, A = 0.5 * (B + B.conj().T), 0.5 * (A + A.conj().T)
    w = np.linalg.eigvalsh(B)
    if w[0] <= 1e-10 * w[-1]:  # (nearly) dependent vectors: a defective eigenvalue; keep as is
        return phi, np.eye(phi.shape[1], dtype=complex)
    _, c = la.eigh(A, B)
    return phi @ c, c


def _first_order(M: FloatArray, K: FloatArray, D: FloatArray
                 ) -> tuple[FloatArray, FloatArray | None, FloatArray | None]:
    """The first-order pencil (A, B) of M q'' + D q' + K q = 0 and the Cholesky factor L of M.

    M positive definite (every coordinate carries mass, as the builder makes it): the standard
    problem (B None) in mass-normalised coordinates p = L^T q, A = [[0, I], [-L^-1 K L^-T,
    -L^-1 D L^-T]], which LAPACK balances: its left eigenvectors are accurate to round-off of the
    mode's own scale (on a train with 2e9 N/m contacts the generalised pencil's left vectors carry
    1e-12 of noise, the standard form's 1e-16). Otherwise the generalised pencil
    [[0, I], [-K, -D]] x = lambda [[I, 0], [0, M]] x (infinite eigenvalues of a singular M dropped
    later) and L None."""
    n = M.shape[0]
    eye, zero = np.eye(n), np.zeros((n, n))
    try:
        L = np.linalg.cholesky(M)
    except np.linalg.LinAlgError:
        return np.block([[zero, eye], [-K, -D]]), np.block([[eye, zero], [zero, M]]), None
    Li = la.solve_triangular(L, eye, lower=True)
    return np.block([[zero, eye], [-(Li @ K @ Li.T), -(Li @ D @ Li.T)]]), None, L


def _part_modes(
    M: FloatArray, K: FloatArray, D: FloatArray, part_index: NDArray[np.int64],
    inputs: Sequence[FloatArray] | None = None,
) -> tuple[NDArray[np.complex128], NDArray[np.complex128], FloatArray | None]:
    """Eigenvalues (Im >= 0, finite), displacement eigenvectors of one independent part and (with
    ``inputs``) each mode's reach by each group of inputs (:func:`_reach`; inside a degenerate set
    the left vectors are rotated with the right ones, Y^H B X = I on the set before and after)."""
    n = M.shape[0]
    A, B, L = _first_order(M, K, D)
    if inputs is not None:
        lam, vl, vec = la.eig(A, B, left=True, right=True)
    else:
        lam, vec = la.eig(A, B)
        vl = None
    lam = snap_round_off(lam, A, B)
    keep = np.isfinite(lam) & (lam.imag >= 0.0)
    # complex whatever eig gave (real vectors when every root is real): the rotation of a degenerate
    # set below is complex in general
    lam, x = lam[keep], vec[:, keep].astype(np.complex128)
    y = None if vl is None else vl[:, keep].astype(np.complex128)
    if L is not None:  # back to the coordinates q (both halves of x)
        x = np.vstack([la.solve_triangular(L.T, x[:n], lower=False), la.solve_triangular(L.T, x[n:], lower=False)])
    # a rigid mode's displacement part carries it; an oscillating mode's phi = x[:n] as well
    norms = np.linalg.norm(x[:n], axis=0)
    x = x / np.where(norms > 0.0, norms, 1.0)
    # degenerate sets: rotate to localised vectors
    order = np.argsort(np.abs(lam))
    lam, x = lam[order], x[:, order]
    y = None if y is None else y[:, order]
    Bq = np.block([[np.eye(n), np.zeros((n, n))], [np.zeros((n, n)), M]])
    i = 0
    while i < lam.size:
        j = i + 1
        scale = max(abs(lam[i]), 2 * math.pi * RIGID_FREQUENCY)
        while j < lam.size and abs(lam[j] - lam[i]) <= DEGENERATE_RTOL * scale:
            j += 1
        if j - i > 1:
            _, c = _localise(x[:n, i:j], M, part_index)
            if y is not None:  # y in the pencil's coordinates: x there is [L^T q; L^T q'] (or q)
                xs = x[:, i:j] if L is None else np.vstack([L.T @ x[:n, i:j], L.T @ x[n:, i:j]])
                G = y[:, i:j].conj().T @ (xs if B is None else Bq @ xs)
                try:
                    y[:, i:j] = y[:, i:j] @ np.linalg.inv(G).conj().T @ np.linalg.inv(c).conj().T
                except np.linalg.LinAlgError:  # a defective set: keep the vectors eig gave
                    pass
            x[:, i:j] = x[:, i:j] @ c
        i = j
    reach = None if y is None or inputs is None else _reach(y[n:], L, inputs)
    return lam, x[:n], reach


def _reach(y_v: NDArray[np.complex128], L: FloatArray | None, inputs: Sequence[FloatArray]) -> FloatArray:
    """(n_modes, n_groups): the largest over a group's columns f of the cosine between f and the
    velocity half y_v of a mode's left eigenvector, both in mass-normalised coordinates (y_v as
    :func:`_first_order` gives it there; f -> L^-1 f; their product, the modal input, is that of
    the original coordinates). Mass normalisation puts translations and rotations on one (energy)
    scale. Without L (singular M): in the original coordinates."""
    yt = y_v / np.where(np.linalg.norm(y_v, axis=0) > 0.0, np.linalg.norm(y_v, axis=0), 1.0)
    out = np.zeros((y_v.shape[1], len(inputs)))
    for g, F in enumerate(inputs):
        Ft = F if L is None else la.solve_triangular(L, F, lower=True)
        fn = np.linalg.norm(Ft, axis=0)
        keep = fn > 0.0
        if keep.any():
            out[:, g] = np.abs(yt.conj().T @ (Ft[:, keep] / fn[keep])).max(axis=1)
    return out


def _without_round_off(F: FloatArray) -> FloatArray:
    """Input columns with the entries below :data:`COUPLING_ZERO` of their column's largest set to
    zero, as :func:`independent_parts` treats the matrices: the reach is a cosine on each part's
    coordinates, so a round-off entry (the left and right wheels' opposite creep inputs cancelling
    on a wheelset's spin to 1e-18 of the column) would otherwise look like a full input of that
    part."""
    top = np.abs(F).max(axis=0, initial=0.0)
    return np.where(np.abs(F) > COUPLING_ZERO * top, F, 0.0)


def damped_modes(
    M: FloatArray, K: FloatArray, D: FloatArray, part_index: Sequence[int] | None = None,
    inputs: Sequence[FloatArray] | None = None,
) -> Eigenmodes:
    """Damped modes of M q'' + D q' + K q = 0 (module docstring): each independent part solved
    on its own, conjugate pairs once, degenerate sets localised on the parts given by
    ``part_index`` (an integer per coordinate naming its body; default: every coordinate its own).
    K and D need not be symmetric (creep forces): the eigenproblem is the general one.

    ``inputs``: groups of input force vectors (each (n, k): generalised forces per unit input, e.g.
    one group per irregularity kind, a column per axle and value or slope). Then ``reach[i, g]`` is
    the largest over the group's columns f of the cosine between f and the velocity half of mode
    i's left eigenvector y_i in the first-order form B x' = A x + [0; f] u, in mass-normalised
    coordinates (:func:`_reach`; y_i^H [0; f] is the mode's modal input: Hautus' test). A mode no input of a group reaches (the wheelsets' antisymmetric
    longitudinal/spin mode of a symmetric bogie: no input pushes along x, and that mode moves
    nothing else) has reach zero up to round-off (below :data:`REACH_ZERO`); the coordinates' graph cannot
    see that when the coordinates are connected (a bogie's pitch moves its axle boxes along x).
    """
    M, K, D = (np.asarray(a, dtype=float) for a in (M, K, D))
    n = M.shape[0]
    if M.shape != (n, n) or K.shape != (n, n) or D.shape != (n, n):
        raise ValueError(f"M, K, D must be square and of one size, got {M.shape}, {K.shape}, {D.shape}")
    pidx = np.arange(n) if part_index is None else np.asarray(part_index, dtype=np.int64)
    groups = None if inputs is None else [_without_round_off(np.asarray(F, dtype=float).reshape(n, -1)) for F in inputs]
    lams, shares, reach = [], [], []
    for idx in independent_parts(M, K, D):
        sub = np.ix_(idx, idx)
        lam, phi, r = _part_modes(M[sub], K[sub], D[sub], pidx[idx], None if groups is None else [F[idx] for F in groups])
        s = np.zeros((lam.size, n))
        s[:, idx] = _kinetic_shares(phi, M[sub]).T
        lams.append(lam)
        shares.append(s)
        if r is not None:
            reach.append(r)
    return Eigenmodes(np.concatenate(lams), np.vstack(shares), np.vstack(reach) if groups is not None else None)


# ============================================================================================
# labels


#: shares within this fraction of the total are equal (:func:`_named`): the two bogies of a
#: symmetric car hold 0.1701 each of its longitudinal mode, and round-off, different on each BLAS
#: kernel, would otherwise decide which one the label names
SHARE_TIE = 1e-9


def _named(shares: dict[str, float], threshold: float) -> list[str]:
    """Keys holding at least ``threshold`` of the total, and the largest always (every key that
    ties with it, within :data:`SHARE_TIE` of the total), largest first; equal shares in the order
    of ``shares``."""
    total = sum(shares.values())
    tol = SHARE_TIE * total
    items = list(shares.items())
    by_size = sorted(range(len(items)), key=lambda i: -items[i][1])
    ranked: list[tuple[str, float]] = []
    i = 0
    while i < len(by_size):  # runs of equal shares in their given order
        j = i + 1
        while j < len(by_size) and items[by_size[i]][1] - items[by_size[j]][1] <= tol:
            j += 1
        ranked.extend(items[k] for k in sorted(by_size[i:j]))
        i = j
    if not ranked:
        return []
    top = ranked[0][1]
    return [k for k, v in ranked if v >= top - tol or (total > 0 and v >= threshold * total - tol)]


def _sum_by(keys: Sequence[str], shares: FloatArray, members: Sequence[int]) -> dict[str, float]:
    out: dict[str, float] = {}
    for i in members:
        out[keys[i]] = out.get(keys[i], 0.0) + float(shares[i])
    return out


def mode_label(shares: FloatArray, dofs: Sequence[Dof], threshold: float = LABEL_SHARE) -> str:
    """What moves in a mode, from its kinetic-energy shares per coordinate (``dofs`` in the same
    order): "car 2 (ice_trailer), leading bogie, yaw"; "car 1 (ice_motor), body, lateral + roll;
    leading bogie, lateral"; "bridge, lateral 1"; several groups joined by " & ". A decoupled
    coordinate's component is marked "(decoupled)"."""
    shares = np.asarray(shares, dtype=float)
    groups = [d.group for d in dofs]
    parts = [d.part for d in dofs]
    comps = [d.component + (" (decoupled)" if d.decoupled else "") for d in dofs]
    all_idx = range(len(dofs))
    out = []
    for g in _named(_sum_by(groups, shares, all_idx), threshold):
        members = [i for i in all_idx if groups[i] == g]
        named = _named(_sum_by(parts, shares, members), threshold)
        if dofs[members[0]].role == "bridge":
            out.append(f"{g}, " + " + ".join(named))
            continue
        # parts moving in the same components are named together, in coordinate order
        what: dict[str, list[str]] = {}
        for p in named:
            in_part = [i for i in members if parts[i] == p]
            what.setdefault(" + ".join(_named(_sum_by(comps, shares, in_part), threshold)), []).append(p)
        first = {p: parts.index(p) for p in named}
        texts = [" + ".join(sorted(ps, key=first.__getitem__)) + f", {c}" for c, ps in what.items()]
        out.append(f"{g}, " + "; ".join(texts))
    return " & ".join(out)


def mode_kind(shares: FloatArray, dofs: Sequence[Dof], frequency: float) -> str:
    """"rigid" (frequency below :data:`RIGID_FREQUENCY`), else what holds the largest share of
    the energy: "decoupled" (weak-spring coordinates), "bridge", "vehicle" (car bodies, bogies,
    sprung masses) or "contact" (wheelsets: on the stiff wheel-rail contact, and a creep car's
    wheelsets in their creep-guided lateral, yaw and longitudinal motion)."""
    if frequency < RIGID_FREQUENCY:
        return "rigid"
    shares = np.asarray(shares, dtype=float)
    by = {"decoupled": 0.0, "bridge": 0.0, "vehicle": 0.0, "contact": 0.0}
    for s, d in zip(shares, dofs):
        key = "decoupled" if d.decoupled else {"bridge": "bridge", "vehicle": "vehicle", "wheelset": "contact"}[d.role]
        by[key] += float(s)
    return max(by, key=lambda k: by[k])


# ============================================================================================
# the table


def _fmt_time(tau: float) -> str:
    return "inf" if not math.isfinite(tau) else f"{tau:.3g}"


@dataclass(frozen=True)
class ModeTable:
    """Modes of a linear system, sorted by undamped frequency.

    Attributes
    ----------
    eigenvalues : (n,) complex eigenvalues lambda [1/s] (Im >= 0)
    frequency : (n,) undamped natural frequency |lambda| / 2 pi [Hz] (0 for rigid modes)
    damped_frequency : (n,) Im lambda / 2 pi [Hz] (0 for real, overdamped modes)
    damping_ratio : (n,) -Re lambda / |lambda| (1 for a real eigenvalue, nan for a rigid mode)
    kind : (n,) "bridge", "vehicle", "contact", "decoupled" or "rigid" (:func:`mode_kind`)
    label : (n,) what moves (:func:`mode_label`)
    shares : (n, n_dof) kinetic-energy shares per coordinate (rows sum to 1)
    dofs : the coordinates' descriptions
    description : what system this is (e.g. which train position)
    reach : (n, n_groups) how strongly each group of inputs reaches each mode (:func:`damped_modes`),
        or None when the table was computed without inputs
    input_groups : the names of the groups (e.g. the irregularity kinds)
    """

    eigenvalues: NDArray[np.complex128]
    frequency: FloatArray
    damped_frequency: FloatArray
    damping_ratio: FloatArray
    kind: tuple[str, ...]
    label: tuple[str, ...]
    shares: FloatArray = field(repr=False)
    dofs: tuple[Dof, ...] = field(repr=False)
    description: str = ""
    reach: FloatArray | None = field(default=None, repr=False)
    input_groups: tuple[str, ...] = ()

    def __len__(self) -> int:
        return int(self.frequency.size)

    @property
    def overdamped(self) -> NDArray[np.bool_]:
        """Real, non-oscillating modes (not rigid)."""
        return (self.eigenvalues.imag == 0.0) & (self.frequency >= RIGID_FREQUENCY)

    @property
    def decay_time(self) -> FloatArray:
        """1 / (zeta omega_n) = -1 / Re lambda [s] (inf for undamped, rigid and unstable modes)."""
        re = -self.eigenvalues.real
        with np.errstate(divide="ignore"):
            return np.where(re > 0.0, 1.0 / np.where(re > 0.0, re, 1.0), np.inf)

    def select(self, mask: NDArray[np.bool_] | Sequence[bool]) -> "ModeTable":
        """The modes where ``mask`` is true."""
        m = np.asarray(mask, dtype=bool)
        return ModeTable(
            self.eigenvalues[m], self.frequency[m], self.damped_frequency[m], self.damping_ratio[m],
            tuple(k for k, keep in zip(self.kind, m) if keep), tuple(s for s, keep in zip(self.label, m) if keep),
            self.shares[m], self.dofs, self.description, None if self.reach is None else self.reach[m],
            self.input_groups,
        )

    def reached(self, groups: Sequence[str] | None = None) -> NDArray[np.bool_]:
        """Whether an input of the named groups (default: every group) reaches each mode (reach above
        :data:`REACH_ZERO`); all True for a table computed without inputs."""
        if self.reach is None:
            return np.ones(len(self), dtype=bool)
        names = self.input_groups if groups is None else tuple(groups)
        unknown = set(names) - set(self.input_groups)
        if unknown:
            raise ValueError(f"unknown input group(s) {sorted(unknown)}; the table has {', '.join(self.input_groups)}")
        cols = [self.input_groups.index(g) for g in names]
        return (self.reach[:, cols] > REACH_ZERO).any(axis=1) if cols else np.zeros(len(self), dtype=bool)

    def in_band(self, f_min: float, f_max: float) -> "ModeTable":
        """Modes with f_min <= undamped frequency <= f_max [Hz]."""
        return self.select((self.frequency >= f_min) & (self.frequency <= f_max))

    def of_kind(self, *kinds: str) -> "ModeTable":
        """Modes of the given kinds (:data:`KINDS`); e.g. ``of_kind("vehicle", "contact")``."""
        unknown = set(kinds) - set(KINDS)
        if unknown:
            raise ValueError(f"unknown mode kind(s) {sorted(unknown)}; allowed: {', '.join(KINDS)}")
        return self.select([k in kinds for k in self.kind])

    def bridge_frequency(self, direction: str, n: int = 1) -> float:
        """Undamped frequency [Hz] of the n-th (1-based) bridge mode whose largest bridge share is
        in a modal coordinate of type ``direction`` ("vertical", "lateral", "torsion", ...); nan if
        there are fewer. For f1 and f3 of EN 1990 A2.4.4.2.1 use n = 1 and 3."""
        hits = []
        bridge = np.array([d.role == "bridge" for d in self.dofs])
        if not bridge.any():
            return math.nan
        for i, k in enumerate(self.kind):
            if k != "bridge":
                continue
            s = np.where(bridge, self.shares[i], -1.0)
            if self.dofs[int(np.argmax(s))].component == direction:
                hits.append(self.frequency[i])
        hits.sort()
        return float(hits[n - 1]) if len(hits) >= n else math.nan

    def affected_channels(self, i: int, threshold: float = 0.1) -> tuple[str, ...]:
        """Channel patterns of the groups holding at least ``threshold`` of mode i's energy:
        "car2.*" for a mode of car 2 (its bodies, bogies and wheel forces), "bridge.*" for a
        bridge mode; both for a coupled mode."""
        by: dict[str, float] = {}
        for s, d in zip(self.shares[i], self.dofs):
            key = d.channel.split(".")[0]
            by[key] = by.get(key, 0.0) + float(s)
        return tuple(f"{k}.*" for k in _named(by, threshold))

    def text(self, title: bool = True) -> str:
        """The table: undamped and damped frequency [Hz], damping ratio, decay time [s], kind, label."""
        lines = [self.description] if title and self.description else []
        lines.append(f"{'#':>4} {'f_n [Hz]':>10} {'f_d [Hz]':>10} {'zeta':>9} {'decay [s]':>9} {'kind':<9} label")
        tau = self.decay_time
        over = self.overdamped
        reached = self.reached()
        for i in range(len(self)):
            z = self.damping_ratio[i]
            zs = ">= 1" if over[i] else ("nan" if not math.isfinite(z) else f"{z:.3g}")
            fd = "-" if over[i] else f"{self.damped_frequency[i]:.4f}"
            lines.append(
                f"{i + 1:>4} {self.frequency[i]:>10.4f} {fd:>10} {zs:>9} "
                f"{_fmt_time(tau[i]):>9} {self.kind[i]:<9} {self.label[i]}"
                + ("" if reached[i] else " (not excited here: no track input reaches it)")
            )
        lines.append("(f_n = |lambda| / 2 pi undamped, f_d = Im lambda / 2 pi damped; decay = 1 / (zeta omega_n); "
                     "zeta >= 1: a real eigenvalue lambda, a non-oscillating motion decaying as exp(lambda t), "
                     "listed at f_n = |lambda| / 2 pi)")
        return "\n".join(lines)


def mode_table(
    M: FloatArray, K: FloatArray, D: FloatArray, dofs: Sequence[Dof], description: str = "",
    inputs: Mapping[str, FloatArray] | None = None,
) -> ModeTable:
    """The :class:`ModeTable` of M q'' + D q' + K q = 0 with coordinates described by ``dofs``;
    ``inputs`` (group name -> (n, k) input forces, e.g. per irregularity kind) gives each mode its
    reach (:func:`damped_modes`, :meth:`ModeTable.reached`)."""
    dofs = tuple(dofs)
    if len(dofs) != np.asarray(M).shape[0]:
        raise ValueError(f"{len(dofs)} coordinate descriptions for a system of {np.asarray(M).shape[0]} coordinates")
    keys = {}
    part_index = [keys.setdefault((d.group, d.part), len(keys)) for d in dofs]
    groups = tuple(inputs) if inputs is not None else ()
    raw = damped_modes(M, K, D, part_index, None if inputs is None else [inputs[g] for g in groups])
    lam = raw.eigenvalues
    mod = np.abs(lam)
    freq = mod / (2.0 * math.pi)
    rigid = freq < RIGID_FREQUENCY
    freq = np.where(rigid, 0.0, freq)
    with np.errstate(invalid="ignore", divide="ignore"):
        zeta = np.where(rigid, np.nan, -lam.real / np.where(mod > 0.0, mod, 1.0))
    labels = [mode_label(s, dofs) for s in raw.shares]
    order = table_order(freq, zeta, labels)
    lam, freq, zeta, shares = lam[order], freq[order], zeta[order], raw.shares[order]
    return ModeTable(
        eigenvalues=lam, frequency=freq, damped_frequency=np.where(rigid[order], 0.0, lam.imag / (2.0 * math.pi)),
        damping_ratio=zeta,
        kind=tuple(mode_kind(s, dofs, f) for s, f in zip(shares, freq)),
        label=tuple(labels[i] for i in order),
        shares=shares, dofs=dofs, description=description,
        reach=None if raw.reach is None else raw.reach[order], input_groups=groups,
    )


def nth_frequency(frequencies: Sequence[float], types: Sequence[str], direction: str, n: int = 1) -> float:
    """The n-th (1-based) frequency [Hz] among those of type ``direction`` (e.g. a ModalBridge's
    ``frequencies`` and ``mode_types``), nan if there are fewer."""
    hits = sorted(float(f) for f, t in zip(frequencies, types) if t == direction)
    return hits[n - 1] if len(hits) >= n else math.nan
