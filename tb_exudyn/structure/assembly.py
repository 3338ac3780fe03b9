"""Assembly of the bridge finite-element model: girders, piers, bearings, supports.

Global axes: x along the track (x = 0 at the start of the first span), y lateral to the left,
z up; the girder shear centre lies on the x axis (y = z = 0). Every node has six DOFs
(ux, uy, uz, rx, ry, rz), node i owning DOFs 6 i ... 6 i + 5.

- Girders: every span is its own girder (simply supported spans) of its own section (``sections``),
  ``elements_per_span`` beam elements; adjacent spans have separate end nodes at the same x.
- Piers (``Frame``): one between each pair of spans, a vertical beam of ``elements_per_pier`` elements from
  the footing up to the pier top at z = -bearings.height. Footing clamped or on springs (per translation /
  rotation; inf = rigid, 0 = free). Optional lumped cap mass at the top.
- Bearings: each girder end rests on the pier top (or on a rigid abutment at the bridge ends) with per-direction
  stiffness between the girder's bearing point (bearings.height below the shear centre, joined to it by a rigid
  link) and the support: longitudinal (k_x_fixed at the span's fixed end, k_x_sliding at the other), lateral
  k_y, vertical k_z, torsional k_rx; rotations about y and z are free. For a rigid link of height h_b the
  girder's bearing point moves by (ux - h_b ry, uy + h_b rx, uz).
- Stiffness inf is imposed exactly by eliminating the girder DOF (master-slave: u = T q), not by a penalty, so
  a rigid bearing adds no spurious stiff mode and no round-off; stiffness 0 adds nothing.
- ``SimpleBeam``: the same girders on ideal supports at the shear centre (uy, uz, rx at both ends,
  ux at the start of each span).
- Other kinds (``Continuous``, :mod:`.continuous`) register their validation, assembly and the keys of their
  errors in :data:`KINDS`.

Sparse matrices (scipy.sparse) throughout. No Exudyn.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Callable

import numpy as np
import scipy.sparse as sp

from ..errors import ScenarioError
from ..scenario.model import AddedMass, BeamSection, Bearings, Frame, Pier, SimpleBeam
from ..scenario.schema import source_file
from .beam import element_mass, element_stiffness, rotation, section_mass, shear_parameter, to_global

DOF_NAMES = ("ux", "uy", "uz", "rx", "ry", "rz")
GIRDER, PIER = 0, 1
#: physical bounds of a span [m]: a shorter one is no beam (its modes lie far above any analysed band: a
#: 1 m span of the reference girder has its first mode near 5 kHz; 1e-6 m gives 1e9 Hz), a longer one is
#: longer than any bridge span built (the longest, 2023 m, is a suspension bridge's main span)
SPAN_RANGE = (1.0, 2500.0)


class StructureError(ScenarioError):
    """Bridge data that cannot give a structural model (zero span, negative stiffness, a mechanism,
    a degenerate section): a user error (one line, exit 2 on the command line) naming the bridge
    (``file``: ``bridge 'NAME'``), the key of the bridge data to change (``girder.E``, ``spans[0]``,
    ``bearings.k_z``; ``max_frequency`` and ``max_modes`` for the modes asked for), the value and
    what is allowed. :func:`located` puts it in the scenario's file, with the key path from there."""

    def __init__(self, file: str | None, key: str, value: object, allowed: str, reason: str = "") -> None:
        super().__init__(file, key, value, allowed, reason)


#: the keys of the modes asked for (modal_bridge's arguments) -> the scenario keys that set them
ANALYSIS_KEYS = {"max_frequency": "analysis.mode_max_frequency", "max_modes": "analysis.max_modes"}


def located(exc: StructureError, scenario: object) -> StructureError:
    """``exc`` raised for a scenario's bridge, located where the user can change it: the bridge's own
    file (a bridge read from ``models/bridges``) with the key inside it, or the scenario's file with
    ``bridge.KEY``; the keys of the modes asked for become ``analysis.mode_max_frequency`` and
    ``analysis.max_modes`` of the scenario. The bridge's name stays in the message."""
    where = getattr(scenario, "where", None) or "<scenario>"
    bridge_file = source_file(getattr(scenario, "bridge", None))
    if exc.key in ANALYSIS_KEYS:
        file, key = where, ANALYSIS_KEYS[exc.key]
    elif bridge_file is not None:
        file, key = bridge_file, exc.key
    else:
        file, key = where, "bridge" if exc.key == "<top level>" else f"bridge.{exc.key}"
    reason = f"{exc.file}: {exc.reason}" if exc.reason else exc.file
    return type(exc)(file, key, exc.value, exc.allowed, reason)


@dataclass(frozen=True)
class GirderMesh:
    """The girder elements along the track, in order of x (for mode shapes along the track).

    ``nodes`` (n_el, 2) node numbers of each element; ``x_start`` and ``length`` (n_el,) its start
    and length along x; ``span`` (n_el,) its span index; ``phi_lateral`` and ``phi_vertical`` (n_el,)
    the shear parameters of lateral (I_z) and vertical (I_y) bending (0: Euler-Bernoulli).
    """

    nodes: np.ndarray
    x_start: np.ndarray
    length: np.ndarray
    span: np.ndarray
    phi_lateral: np.ndarray
    phi_vertical: np.ndarray


@dataclass(frozen=True)
class FEModel:
    """An assembled bridge model: full sparse K and M, and the constraint map u = T q.

    Attributes
    ----------
    name : the bridge's name (for messages)
    coordinates : (n_nodes, 3) node positions [m]
    node_part : (n_nodes,) GIRDER (0) or PIER (1)
    node_member : (n_nodes,) span index of a girder node, pier index of a pier node
    stiffness, mass : (n_dof, n_dof) sparse symmetric matrices of all DOFs (before constraints)
    transform : (n_dof, n_free) sparse T: all DOFs u = T q from the free coordinates q
    girder : the girder elements along x
    span_starts, span_lengths : (n_spans,) [m]
    pier_top_nodes : node number of each pier's top
    track_offset, track_height : rail line position relative to the shear centre [m]
    damping_ratio : modal damping ratio of the bridge data
    bridge : the bridge data it was assembled from (None: a pier alone), to name the key of an error
    """

    name: str
    coordinates: np.ndarray
    node_part: np.ndarray
    node_member: np.ndarray
    stiffness: sp.csr_matrix = field(repr=False)
    mass: sp.csr_matrix = field(repr=False)
    transform: sp.csr_matrix = field(repr=False)
    girder: GirderMesh = field(repr=False)
    span_starts: np.ndarray
    span_lengths: np.ndarray
    pier_top_nodes: tuple[int, ...]
    track_offset: float = 0.0
    track_height: float = 0.0
    damping_ratio: float = 0.0
    bridge: SimpleBeam | Frame | None = field(default=None, repr=False, compare=False)

    @property
    def n_nodes(self) -> int:
        return int(self.coordinates.shape[0])

    @property
    def n_dof(self) -> int:
        return 6 * self.n_nodes

    @property
    def n_free(self) -> int:
        return int(self.transform.shape[1])

    @property
    def length(self) -> float:
        """Length of the bridge along the track [m]."""
        return float(self.span_starts[-1] + self.span_lengths[-1]) if self.span_lengths.size else 0.0

    def reduced(self) -> tuple[sp.csr_matrix, sp.csr_matrix]:
        """(K_r, M_r) = (T^T K T, T^T M T) on the free coordinates."""
        t = self.transform
        return (t.T @ self.stiffness @ t).tocsr(), (t.T @ self.mass @ t).tocsr()

    def dof(self, node: int, name: str) -> int:
        """Global DOF number of ``name`` ('ux', 'uy', 'uz', 'rx', 'ry', 'rz') at ``node``."""
        return 6 * int(node) + DOF_NAMES.index(name)

    def describe_dof(self, dof: int) -> str:
        """A readable location of a DOF, e.g. 'girder of span 2 at x = 16 m, uy'."""
        node, j = divmod(int(dof), 6)
        x, _, z = self.coordinates[node]
        if self.node_part[node] == GIRDER:
            where = f"girder of span {self.node_member[node] + 1} at x = {x:g} m"
        else:
            where = f"pier {self.node_member[node] + 1} at z = {z:g} m"
        return f"{where}, {DOF_NAMES[j]}"


@dataclass(frozen=True)
class BridgeKind:
    """How a bridge kind defined in another module is modelled (its module registers it in :data:`KINDS`):
    ``validate(bridge)`` raises StructureError for its own keys (after the checks every kind shares:
    spans, track, damping, elements_per_span); ``assemble(bridge)`` -> FEModel;
    ``mechanism_key(bridge, part, dof, member)`` and ``sections(bridge)`` -> [(key, BeamSection)] name
    the data of a mechanism and of overflowing element matrices."""

    validate: Callable[[Any], None]
    assemble: Callable[[Any], FEModel]
    mechanism_key: Callable[[Any, int, int, int], tuple[str, object]]
    sections: Callable[[Any], list[tuple[str, BeamSection]]]


#: bridge classes modelled by other modules of this package (tb_exudyn.structure.continuous)
KINDS: dict[type, BridgeKind] = {}


# ============================================================================================
# validation


def _fail(bridge_name: str, key: str, value: object, allowed: str, reason: str = "") -> StructureError:
    return StructureError(f"bridge '{bridge_name}'", key, value, allowed, reason)


def _check_positive(name: str, label: str, value: float) -> None:
    if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0.0):
        raise _fail(name, label, value, "a finite number > 0")


def _check_stiffness(name: str, label: str, value: float) -> None:
    if not isinstance(value, (int, float)) or math.isnan(value) or value < 0.0 or value == -math.inf:
        raise _fail(name, label, value, ">= 0 (inf = rigid, 0 = free)", "a stiffness must be >= 0")


def _check_section(name: str, label: str, s: BeamSection) -> None:
    for key in ("E", "G", "area", "I_y", "I_z", "J", "mass_per_length", "rot_mass_per_length"):
        _check_positive(name, f"{label}.{key}", getattr(s, key))
    if not (0.0 <= s.shear_area_factor <= 1.0):
        raise _fail(name, f"{label}.shear_area_factor", s.shear_area_factor, "0 <= shear_area_factor <= 1")


def _check_pier(name: str, p: Pier) -> None:  # a frame's and a continuous girder's
    _check_positive(name, "pier.height", p.height)
    _check_section(name, "pier.section", p.section)
    if p.footing not in ("fixed", "springs"):
        raise _fail(name, "pier.footing", p.footing, "'fixed' or 'springs'")
    _check_stiffness(name, "pier.k_translation", p.k_translation)
    _check_stiffness(name, "pier.k_rotation", p.k_rotation)
    if not (math.isfinite(p.cap_mass) and p.cap_mass >= 0.0):
        raise _fail(name, "pier.cap_mass", p.cap_mass, "a finite number >= 0")


def _check_added_mass(name: str, a: AddedMass) -> None:
    """The added mass on a girder (a frame's and a continuous girder's)."""
    for key, low in (("mass_per_length", 0.0), ("rot_mass_per_length", 0.0), ("offset", -math.inf), ("height", -math.inf)):
        v = getattr(a, key)
        if not (math.isfinite(v) and v >= low):
            raise _fail(name, f"added_mass.{key}", v, "a finite number" + (" >= 0" if low == 0.0 else ""))


def validate_bridge(bridge: SimpleBeam | Frame) -> None:
    """Raise :class:`StructureError` for bridge data no structural model can be built from.

    Checks what the scenario loader checks (so a dataclass built in Python is safe too) plus the
    consistency the assembly needs and the spans' physical bounds (:data:`SPAN_RANGE`). Mechanisms
    (e.g. every bearing free in one direction) are found later from the stiffness matrix, see
    ``tb_exudyn.structure.fe``.
    """
    kind = KINDS.get(type(bridge))
    if not isinstance(bridge, (SimpleBeam, Frame)) and kind is None:
        raise _not_a_bridge(bridge)
    name = bridge.name
    if len(bridge.spans) == 0:
        raise _fail(name, "spans", [], "at least one span length > 0", "no spans")
    for i, span in enumerate(bridge.spans):
        _check_positive(name, f"spans[{i}]", span)
        if not SPAN_RANGE[0] <= span <= SPAN_RANGE[1]:
            raise _fail(name, f"spans[{i}]", span, f"{SPAN_RANGE[0]:g} m <= span <= {SPAN_RANGE[1]:g} m",
                        "no bridge span")
    if kind is not None:
        kind.validate(bridge)
    else:
        for i, section in enumerate(bridge.sections):
            _check_section(name, bridge.section_key(i), section)
    for key in ("track_offset", "track_height"):
        if not math.isfinite(getattr(bridge, key)):
            raise _fail(name, key, getattr(bridge, key), "a finite number")
    if not (0.0 <= bridge.damping_ratio < 1.0):
        raise _fail(name, "damping_ratio", bridge.damping_ratio, "0 <= damping_ratio < 1")
    if int(bridge.elements_per_span) < 1:
        raise _fail(name, "elements_per_span", bridge.elements_per_span, ">= 1")
    if isinstance(bridge, Frame):
        if int(bridge.elements_per_pier) < 1:
            raise _fail(name, "elements_per_pier", bridge.elements_per_pier, ">= 1")
        b = bridge.bearings
        _check_pier(name, bridge.pier)
        for key in ("k_x_fixed", "k_x_sliding", "k_y", "k_z", "k_rx"):
            _check_stiffness(name, f"bearings.{key}", getattr(b, key))
        if b.fixed_end not in ("start", "end"):
            raise _fail(name, "bearings.fixed_end", b.fixed_end, "'start' or 'end'")
        if not (math.isfinite(b.height) and b.height >= 0.0):
            raise _fail(name, "bearings.height", b.height, "a finite number >= 0")
        _check_added_mass(name, bridge.added_mass)


#: a Young's or shear modulus below this [N/m^2] is no structural material (timber ~1e10, concrete
#: ~3e10, steel ~2e11): a mechanism of a section with such a modulus names the modulus, else the geometry
MIN_MODULUS = 1e9
#: DOF (ux, uy, uz, rx, ry, rz) -> the section value whose product with the modulus resists it, and the bearing key
_SECTION_OF_DOF = ("area", "I_z", "I_y", "J", "I_y", "I_z")
_BEARING_OF_DOF = ("k_x_fixed", "k_y", "k_z", "k_rx", "k_z", "k_y")


def _section_key(label: str, s: BeamSection, j: int) -> tuple[str, float]:
    modulus = "G" if j == 3 else "E"
    if getattr(s, modulus) < MIN_MODULUS:
        return f"{label}.{modulus}", getattr(s, modulus)
    return f"{label}.{_SECTION_OF_DOF[j]}", getattr(s, _SECTION_OF_DOF[j])


def mechanism_key(bridge: SimpleBeam | Frame | None, part: int, j: int, member: int = 0) -> tuple[str, object]:
    """The key (and its value) of the bridge data that lets a part move freely in DOF ``j``: a free
    bearing (Frame, stiffness 0 in that direction) or footing spring, else the section too soft for
    its mass (its modulus below :data:`MIN_MODULUS`, else its area, second moment or torsion constant).
    ``member``: the span (girder) or pier that moves (a continuous girder's section of that span)."""
    if bridge is None:
        return "<top level>", None
    if type(bridge) in KINDS:
        return KINDS[type(bridge)].mechanism_key(bridge, part, j, member)
    if not isinstance(bridge, Frame):
        return _section_key(bridge.section_key(member), bridge.sections[member], j) if part == GIRDER else ("<top level>", None)
    if part == GIRDER and getattr(bridge.bearings, _BEARING_OF_DOF[j]) == 0.0:
        return f"bearings.{_BEARING_OF_DOF[j]}", 0.0
    p = bridge.pier
    if p.footing == "springs" and len(bridge.spans) > 1:  # a girder on piers free on their footing moves with them
        for key in ("k_translation", "k_rotation") if j < 3 else ("k_rotation", "k_translation"):
            if getattr(p, key) == 0.0:
                return f"pier.{key}", 0.0
    girder = _section_key(bridge.section_key(member), bridge.sections[member], j)
    return girder if part == GIRDER else _section_key("pier.section", p.section, j)


def _extreme_value(label: str, s: BeamSection) -> tuple[str, float]:
    """The section value farthest from 1 in orders of magnitude (what makes the matrices overflow)."""
    items = [(f"{label}.{k}", getattr(s, k)) for k in ("E", "G", "area", "I_y", "I_z", "J", "mass_per_length",
                                                        "rot_mass_per_length")]
    return max(items, key=lambda kv: abs(math.log10(kv[1])) if kv[1] > 0 else math.inf)


def extreme_section_key(bridge: SimpleBeam | Frame | None) -> tuple[str, object]:
    """The section value of the bridge farthest from 1 in orders of magnitude (girder or pier)."""
    if bridge is None:
        return "<top level>", None
    if type(bridge) in KINDS:
        found = [_extreme_value(label, section) for label, section in KINDS[type(bridge)].sections(bridge)]
        return max(found, key=lambda kv: abs(math.log10(kv[1])) if kv[1] > 0 else math.inf)
    found = [_extreme_value(bridge.section_key(i), g) for i, g in enumerate(bridge.sections)]
    if isinstance(bridge, Frame):
        found.append(_extreme_value("pier.section", bridge.pier.section))
    return max(found, key=lambda kv: abs(math.log10(kv[1])) if kv[1] > 0 else math.inf)


# ============================================================================================
# the builder (internal, mutable while assembling)


class _Builder:
    """Collects nodes, element triplets, springs and constraints; :meth:`finish` makes the model."""

    def __init__(self, name: str):
        self.name = name
        self.coords: list[tuple[float, float, float]] = []
        self.part: list[int] = []
        self.member: list[int] = []
        self.rows: list[np.ndarray] = []
        self.cols: list[np.ndarray] = []
        self.k_vals: list[np.ndarray] = []
        self.m_vals: list[np.ndarray] = []
        self.constraints: dict[int, dict[int, float]] = {}

    def node(self, xyz: tuple[float, float, float], part: int, member: int) -> int:
        self.coords.append(tuple(float(c) for c in xyz))
        self.part.append(part)
        self.member.append(member)
        return len(self.coords) - 1

    def _add(self, dofs: np.ndarray, k: np.ndarray | None, m: np.ndarray | None) -> None:
        n = dofs.size
        self.rows.append(np.repeat(dofs, n))
        self.cols.append(np.tile(dofs, n))
        self.k_vals.append(np.zeros(n * n) if k is None else np.asarray(k, dtype=float).ravel())
        self.m_vals.append(np.zeros(n * n) if m is None else np.asarray(m, dtype=float).ravel())

    def element(self, n1: int, n2: int, section: BeamSection, smass: np.ndarray,
                label: str = "girder") -> tuple[float, float]:
        """A beam element between nodes n1 and n2; returns its shear parameters (lateral, vertical).
        Section values whose element matrices overflow raise a StructureError naming the extreme one."""
        p1, p2 = np.array(self.coords[n1]), np.array(self.coords[n2])
        rot = rotation(p1, p2)
        length = float(np.linalg.norm(p2 - p1))
        a_s = section.shear_area_factor * section.area
        phi_y = shear_parameter(section.E, section.I_z, section.G, a_s, length)
        phi_z = shear_parameter(section.E, section.I_y, section.G, a_s, length)
        with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
            k = element_stiffness(length, section.E, section.G, section.area, section.I_y, section.I_z, section.J, a_s)
            m = element_mass(length, smass, phi_y, phi_z)
            k, m = to_global(k, rot), to_global(m, rot)
        if not (np.all(np.isfinite(k)) and np.all(np.isfinite(m))):
            key, value = _extreme_value(label, section)
            raise _fail(self.name, key, value, "section values whose element stiffness and mass are finite numbers",
                        "the finite-element matrices overflow")
        dofs = np.concatenate([np.arange(6 * n1, 6 * n1 + 6), np.arange(6 * n2, 6 * n2 + 6)])
        self._add(dofs, k, m)
        return phi_y, phi_z

    def lumped_mass(self, node: int, mass: float) -> None:
        if mass > 0.0:
            dofs = np.arange(6 * node, 6 * node + 3)
            self._add(dofs, None, mass * np.eye(3))

    def link(self, coeffs: dict[int, float], stiffness: float) -> None:
        """Restrain the relative displacement d = sum c_j u_j: a spring k d^2 / 2, or d = 0 if k = inf.

        For k = inf the first DOF of ``coeffs`` (coefficient 1) is eliminated: u_0 = -sum_j c_j u_j.
        """
        if stiffness == 0.0:
            return
        dofs = np.array(list(coeffs), dtype=int)
        c = np.array([coeffs[d] for d in dofs])
        if math.isinf(stiffness):
            slave = int(dofs[0])
            if slave in self.constraints:
                raise RuntimeError(f"bridge '{self.name}': DOF {slave} constrained twice (internal error)")
            self.constraints[slave] = {int(d): -float(v) for d, v in zip(dofs[1:], c[1:])}
        else:
            self._add(dofs, stiffness * np.outer(c, c), None)

    def finish(self, **kwargs) -> FEModel:
        n_dof = 6 * len(self.coords)
        rows, cols = np.concatenate(self.rows), np.concatenate(self.cols)
        k = sp.coo_matrix((np.concatenate(self.k_vals), (rows, cols)), shape=(n_dof, n_dof)).tocsr()
        m = sp.coo_matrix((np.concatenate(self.m_vals), (rows, cols)), shape=(n_dof, n_dof)).tocsr()
        k.eliminate_zeros()
        m.eliminate_zeros()
        return FEModel(
            name=self.name,
            coordinates=np.array(self.coords),
            node_part=np.array(self.part, dtype=int),
            node_member=np.array(self.member, dtype=int),
            stiffness=k,
            mass=m,
            transform=master_slave_transform(n_dof, self.constraints, self.name),
            **kwargs,
        )


def master_slave_transform(n_dof: int, constraints: dict[int, dict[int, float]], name: str = "") -> sp.csr_matrix:
    """The map u = T q eliminating constrained DOFs.

    ``constraints[s] = {j: a_j}`` means u_s = sum_j a_j u_j (empty: u_s = 0). A master that is
    itself constrained is substituted until only free DOFs remain; a cycle raises StructureError.
    """
    resolved: dict[int, dict[int, float]] = {}

    def resolve(s: int, stack: tuple[int, ...]) -> dict[int, float]:
        if s in resolved:
            return resolved[s]
        if s in stack:
            raise RuntimeError(f"bridge '{name}': circular rigid constraints through DOF {s} (internal error)")
        out: dict[int, float] = {}
        for j, a in constraints[s].items():
            terms = resolve(j, stack + (s,)) if j in constraints else {j: 1.0}
            for jj, aa in terms.items():
                out[jj] = out.get(jj, 0.0) + a * aa
        resolved[s] = out
        return out

    for s in constraints:
        resolve(s, ())
    free = np.array([d for d in range(n_dof) if d not in constraints], dtype=int)
    column = -np.ones(n_dof, dtype=int)
    column[free] = np.arange(free.size)
    rows, cols, vals = list(free), list(range(free.size)), [1.0] * free.size
    for s, terms in resolved.items():
        for j, a in terms.items():
            if a != 0.0:
                rows.append(s)
                cols.append(int(column[j]))
                vals.append(a)
    return sp.coo_matrix((vals, (rows, cols)), shape=(n_dof, free.size)).tocsr()


# ============================================================================================
# bridges


def _girder_section_mass(girder: BeamSection, added: AddedMass | None) -> np.ndarray:
    s = section_mass(girder.mass_per_length, girder.rot_mass_per_length)
    if added is not None and (added.mass_per_length > 0.0 or added.rot_mass_per_length > 0.0):
        s = s + section_mass(added.mass_per_length, added.rot_mass_per_length, added.offset, added.height)
    return s


def _add_girders(b: _Builder, spans: tuple[float, ...], bridge: SimpleBeam | Frame, added: AddedMass | None,
                 n_el: int) -> tuple[GirderMesh, list[tuple[int, int]], np.ndarray]:
    starts = np.concatenate([[0.0], np.cumsum(spans)[:-1]])
    el_nodes, el_x, el_len, el_span, phis = [], [], [], [], []
    ends = []
    for s, (x0, length) in enumerate(zip(starts, spans)):
        girder, key = bridge.sections[s], bridge.section_key(s)
        smass = _girder_section_mass(girder, added)
        xs = x0 + np.linspace(0.0, length, n_el + 1)
        nodes = [b.node((x, 0.0, 0.0), GIRDER, s) for x in xs]
        for i in range(n_el):
            phis.append(b.element(nodes[i], nodes[i + 1], girder, smass, key))
            el_nodes.append((nodes[i], nodes[i + 1]))
            el_x.append(xs[i])
            el_len.append(xs[i + 1] - xs[i])
            el_span.append(s)
        ends.append((nodes[0], nodes[-1]))
    phis_a = np.array(phis)
    mesh = GirderMesh(
        nodes=np.array(el_nodes, dtype=int), x_start=np.array(el_x), length=np.array(el_len),
        span=np.array(el_span, dtype=int), phi_lateral=phis_a[:, 0], phi_vertical=phis_a[:, 1],
    )
    return mesh, ends, starts


def _bearing(b: _Builder, girder_node: int, support_node: int | None, height: float,
             k_x: float, k_y: float, k_z: float, k_rx: float) -> None:
    """Bearing between a girder end (shear centre) and a pier top node (None: rigid ground)."""
    g = 6 * girder_node
    p = None if support_node is None else 6 * support_node
    directions = (
        (k_rx, {g + 3: 1.0}, 3),
        (k_x, {g + 0: 1.0, g + 4: -height}, 0),
        (k_y, {g + 1: 1.0, g + 3: height}, 1),
        (k_z, {g + 2: 1.0}, 2),
    )
    for k, coeffs, j in directions:
        coeffs = {d: c for d, c in coeffs.items() if c != 0.0}
        if p is not None:
            coeffs[p + j] = -1.0
        b.link(coeffs, k)


def assemble_simple_beam(bridge: SimpleBeam) -> FEModel:
    """Independent spans on ideal supports at the shear centre (uy, uz, rx both ends, ux at the start)."""
    validate_bridge(bridge)
    b = _Builder(bridge.name)
    spans = tuple(float(s) for s in bridge.spans)
    mesh, ends, starts = _add_girders(b, spans, bridge, None, int(bridge.elements_per_span))
    for start, end in ends:
        _bearing(b, start, None, 0.0, math.inf, math.inf, math.inf, math.inf)
        _bearing(b, end, None, 0.0, 0.0, math.inf, math.inf, math.inf)
    return b.finish(girder=mesh, span_starts=starts, span_lengths=np.array(spans), pier_top_nodes=(),
                    track_offset=float(bridge.track_offset), track_height=float(bridge.track_height),
                    damping_ratio=float(bridge.damping_ratio), bridge=bridge)


def _add_pier(b: _Builder, pier: Pier, x: float, top_z: float, n_el: int, index: int) -> int:
    """A vertical pier at x from its footing up to ``top_z``; returns the top node."""
    smass = section_mass(pier.section.mass_per_length, pier.section.rot_mass_per_length)
    zs = top_z - pier.height + np.linspace(0.0, pier.height, n_el + 1)
    nodes = [b.node((x, 0.0, z), PIER, index) for z in zs]
    for i in range(n_el):
        b.element(nodes[i], nodes[i + 1], pier.section, smass, "pier.section")
    base = 6 * nodes[0]
    if pier.footing == "fixed":
        springs = (math.inf,) * 6
    else:
        springs = (pier.k_translation,) * 3 + (pier.k_rotation,) * 3
    for j, k in enumerate(springs):
        b.link({base + j: 1.0}, k)
    b.lumped_mass(nodes[-1], pier.cap_mass)
    return nodes[-1]


def assemble_frame(bridge: Frame) -> FEModel:
    """Girders on bearings, on piers between the spans and rigid abutments at both bridge ends."""
    validate_bridge(bridge)
    b = _Builder(bridge.name)
    spans = tuple(float(s) for s in bridge.spans)
    mesh, ends, starts = _add_girders(b, spans, bridge, bridge.added_mass, int(bridge.elements_per_span))
    br: Bearings = bridge.bearings
    top_z = -float(br.height)
    tops = tuple(
        _add_pier(b, bridge.pier, float(starts[i + 1]), top_z, int(bridge.elements_per_pier), i)
        for i in range(len(spans) - 1)
    )
    k_start, k_end = (br.k_x_fixed, br.k_x_sliding) if br.fixed_end == "start" else (br.k_x_sliding, br.k_x_fixed)
    for s, (start, end) in enumerate(ends):
        support_start = None if s == 0 else tops[s - 1]
        support_end = None if s == len(spans) - 1 else tops[s]
        _bearing(b, start, support_start, br.height, k_start, br.k_y, br.k_z, br.k_rx)
        _bearing(b, end, support_end, br.height, k_end, br.k_y, br.k_z, br.k_rx)
    return b.finish(girder=mesh, span_starts=starts, span_lengths=np.array(spans), pier_top_nodes=tops,
                    track_offset=float(bridge.track_offset), track_height=float(bridge.track_height),
                    damping_ratio=float(bridge.damping_ratio), bridge=bridge)


def assemble_pier(pier: Pier, n_elements: int = 8, name: str = "pier") -> FEModel:
    """A pier alone on its footing, free at the top (for checks and calibration)."""
    _check_positive(name, "pier.height", pier.height)
    _check_section(name, "pier.section", pier.section)
    b = _Builder(name)
    top = _add_pier(b, pier, 0.0, pier.height, int(n_elements), 0)
    empty = GirderMesh(*(np.zeros((0, 2), dtype=int),) + tuple(np.zeros(0) for _ in range(5)))
    return b.finish(girder=empty, span_starts=np.zeros(0), span_lengths=np.zeros(0), pier_top_nodes=(top,))


def assemble(bridge: SimpleBeam | Frame) -> FEModel:
    """The finite-element model of a ``SimpleBeam`` or ``Frame`` bridge, or of a kind of :data:`KINDS`."""
    if type(bridge) in KINDS:
        return KINDS[type(bridge)].assemble(bridge)
    if isinstance(bridge, Frame):
        return assemble_frame(bridge)
    if isinstance(bridge, SimpleBeam):
        return assemble_simple_beam(bridge)
    raise _not_a_bridge(bridge)


def _not_a_bridge(bridge: object) -> StructureError:
    return StructureError("bridge", "<top level>", type(bridge).__name__, "a SimpleBeam, a Frame or a Continuous",
                          "not a bridge")
