"""The structural model of a continuous girder (bridge kind ``continuous``, issue 29).

One girder through all spans, a node shared at every intermediate support, each span with its own
section if given (``girders``); one bearing line at each support: the abutments on rigid ground, an
intermediate support on its pier's top ('pier') or on rigid ground ('rigid'); k_x_fixed at the
fixed support, k_x_sliding at the others, k_y, k_z, k_rx at all, rotations about y and z free;
bearings ``height`` below the shear centre, joined to it by a rigid link (as a frame's, see
:mod:`.assembly`). Registered in :data:`.assembly.KINDS`, so :func:`.assembly.assemble`,
``validate_bridge`` and the error keys of a mechanism or of overflowing matrices take it.
"""

from __future__ import annotations

import math

import numpy as np

from ..scenario.model import BeamSection, Continuous
from .assembly import (GIRDER, KINDS, BridgeKind, FEModel, GirderMesh, _add_pier, _bearing, _BEARING_OF_DOF, _Builder,
                       _check_added_mass, _check_pier, _check_section, _check_stiffness, _fail, _girder_section_mass,
                       _section_key,
                       validate_bridge)


def validate_continuous(bridge: Continuous) -> None:
    """What the assembly of a continuous girder needs (the loader's rules, for one built in Python too)."""
    name, n = bridge.name, len(bridge.spans)
    if n < 2:
        raise _fail(name, "spans", list(bridge.spans), "at least two span lengths > 0 (one span: kind 'frame' or "
                    "'simple_beam')", "a continuous girder of fewer than two spans")
    if bridge.girders and len(bridge.girders) != n:
        raise _fail(name, "girders", f"{len(bridge.girders)} sections", f"{n} sections, one per span")
    for s, section in enumerate(bridge.sections):
        if not isinstance(section, BeamSection):
            raise _fail(name, bridge.section_key(s), section, "a girder section (BeamSection)", "no girder section")
        _check_section(name, bridge.section_key(s), section)
    if len(bridge.supports) != n - 1 or any(k not in ("pier", "rigid") for k in bridge.supports):
        entries = f"{n - 1} {'entry' if n == 2 else 'entries'}"
        reason = ("a continuous girder without supports" if not bridge.supports else
                  "not one support per span joint" if len(bridge.supports) != n - 1 else "unknown support kind")
        raise _fail(name, "supports", list(bridge.supports), f"{entries} 'pier' or 'rigid', one per intermediate "
                    "support", reason)
    if "pier" in bridge.supports:
        if bridge.pier is None:
            raise _fail(name, "pier", None, "a pier table (supports include 'pier')", "no pier data")
        if int(bridge.elements_per_pier) < 1:
            raise _fail(name, "elements_per_pier", bridge.elements_per_pier, ">= 1")
        _check_pier(name, bridge.pier)
    b = bridge.bearings
    for key in ("k_x_fixed", "k_x_sliding", "k_y", "k_z", "k_rx"):
        _check_stiffness(name, f"bearings.{key}", getattr(b, key))
    if not (isinstance(b.fixed_support, int) and 0 <= b.fixed_support <= n):
        raise _fail(name, "bearings.fixed_support", b.fixed_support, f"0 ... {n} (0: the start abutment, {n}: the end "
                    "abutment)", "no such support")
    if not (math.isfinite(b.height) and b.height >= 0.0):
        raise _fail(name, "bearings.height", b.height, "a finite number >= 0")
    _check_added_mass(name, bridge.added_mass)


def mechanism_key(bridge: Continuous, part: int, j: int, member: int) -> tuple[str, object]:
    """The key of the data that lets the girder (span ``member``) or a pier move freely in DOF ``j``: a
    bearing free in that direction at every support, a pier's footing spring, else the section."""
    b, p = bridge.bearings, bridge.pier if "pier" in bridge.supports else None
    if part == GIRDER:
        free = (b.k_x_fixed == 0.0 and b.k_x_sliding == 0.0) if j == 0 else getattr(b, _BEARING_OF_DOF[j]) == 0.0
        if free:
            return f"bearings.{_BEARING_OF_DOF[j]}", 0.0
    if p is not None and p.footing == "springs":
        for key in ("k_translation", "k_rotation") if j < 3 else ("k_rotation", "k_translation"):
            if getattr(p, key) == 0.0:
                return f"pier.{key}", 0.0
    if part == GIRDER:
        s = min(max(int(member), 0), len(bridge.spans) - 1)
        return _section_key(bridge.section_key(s), bridge.sections[s], j)
    return _section_key("pier.section", p.section, j) if p is not None else ("<top level>", None)


def _add_continuous_girder(b: _Builder, bridge: Continuous) -> tuple[GirderMesh, list[int], np.ndarray]:
    """The girder through all spans, a node shared at each intermediate support; returns its mesh, the
    girder node at each support line (n_spans + 1) and the span starts."""
    spans = tuple(float(x) for x in bridge.spans)
    n_el = int(bridge.elements_per_span)
    starts = np.concatenate([[0.0], np.cumsum(spans)[:-1]])
    el_nodes, el_x, el_len, el_span, phis = [], [], [], [], []
    supports = [b.node((0.0, 0.0, 0.0), GIRDER, 0)]
    for s, (x0, length) in enumerate(zip(starts, spans)):
        section = bridge.sections[s]
        smass = _girder_section_mass(section, bridge.added_mass)
        xs = x0 + np.linspace(0.0, length, n_el + 1)
        xs[-1] = x0 + length
        nodes = [supports[-1]] + [b.node((x, 0.0, 0.0), GIRDER, s) for x in xs[1:]]
        for i in range(n_el):
            phis.append(b.element(nodes[i], nodes[i + 1], section, smass, bridge.section_key(s)))
            el_nodes.append((nodes[i], nodes[i + 1]))
            el_x.append(xs[i])
            el_len.append(xs[i + 1] - xs[i])
            el_span.append(s)
        supports.append(nodes[-1])
    phis_a = np.array(phis)
    mesh = GirderMesh(
        nodes=np.array(el_nodes, dtype=int), x_start=np.array(el_x), length=np.array(el_len),
        span=np.array(el_span, dtype=int), phi_lateral=phis_a[:, 0], phi_vertical=phis_a[:, 1],
    )
    return mesh, supports, starts


def assemble_continuous(bridge: Continuous) -> FEModel:
    """One girder continuous over its spans, on a bearing line at every support: the abutments on rigid
    ground, each intermediate support on its pier ('pier') or on rigid ground ('rigid')."""
    validate_bridge(bridge)
    b = _Builder(bridge.name)
    mesh, support_nodes, starts = _add_continuous_girder(b, bridge)
    br = bridge.bearings
    top_z = -float(br.height)
    grounds: list[int | None] = [None] * len(support_nodes)
    tops = []
    for i, kind in enumerate(bridge.supports):
        if kind == "pier":
            grounds[i + 1] = _add_pier(b, bridge.pier, float(starts[i + 1]), top_z, int(bridge.elements_per_pier),
                                       len(tops))
            tops.append(grounds[i + 1])
    for i, (node, ground) in enumerate(zip(support_nodes, grounds)):
        k_x = br.k_x_fixed if i == br.fixed_support else br.k_x_sliding
        _bearing(b, node, ground, br.height, k_x, br.k_y, br.k_z, br.k_rx)
    return b.finish(
        girder=mesh, span_starts=starts, span_lengths=np.array([float(x) for x in bridge.spans]),
        pier_top_nodes=tuple(tops), track_offset=float(bridge.track_offset),
        track_height=float(bridge.track_height), damping_ratio=float(bridge.damping_ratio), bridge=bridge,
    )


def sections(bridge: Continuous) -> list[tuple[str, BeamSection]]:
    """(key, section) of every section of the bridge: each span's girder, the pier's if a support is one."""
    found = [(bridge.section_key(s), g) for s, g in enumerate(bridge.sections)]
    if "pier" in bridge.supports:
        found.append(("pier.section", bridge.pier.section))
    return found


KINDS[Continuous] = BridgeKind(validate=validate_continuous, assemble=assemble_continuous, mechanism_key=mechanism_key,
                               sections=sections)

__all__ = ["assemble_continuous", "mechanism_key", "sections", "validate_continuous"]
