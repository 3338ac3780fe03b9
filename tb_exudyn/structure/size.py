"""How large a bridge's finite-element and modal model will be, before it is assembled.

The sizes a user types (the number of spans, ``elements_per_span``, ``elements_per_pier``,
``mode_max_frequency``, ``max_modes``) set the model's DOFs exactly and its number of modes below the
cut-off; the modal model holds its mode shapes on every DOF (n_dof x n_modes, several copies while
they are solved, normalised and reduced to the rail and the stations), which is what fills the
memory (1000 spans of 32 m: 102 000 DOFs x 10 000 modes). :func:`check_bridge_size` refuses a bridge
whose estimate exceeds the memory available (:class:`BridgeSizeError`, naming the key to change)
before anything is assembled.

The number of modes is estimated, not guessed: a ``SimpleBeam``'s spans are independent, so it is the
sum of each span's count (every distinct span length solved alone, as :func:`~.fe.solve_modes` solves
it: exact); a ``Frame``'s girders are coupled through the bearings and piers, so it is the count of one
girder span on the abutments per span plus that of one pier on its footing per pier, times
:data:`FRAME_MARGIN` (for the reference frame repeated to 3, 9 and 30 spans the parts' count equals
the coupled count, 56, 182 and 623 modes below 100 Hz; the margin is for frames whose coupling
through soft bearings or piers lowers more modes below the cut-off).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Any, Callable

from ..errors import ResourceError
from ..execution.resources import available_memory, format_bytes
from ..scenario.model import Continuous, Frame, SimpleBeam
from .assembly import StructureError, assemble, assemble_pier

#: bytes per entry of the n_dof x n_modes mode shapes at the peak of the modal solve: 8-byte floats in
#: up to 12 copies (measured 5.7 to 10 copies: 100 spans of the quick girder, 10 and 30 spans of the
#: reference frame; full eigenvectors, the shapes on all DOFs, their station and rail reductions)
BYTES_PER_SHAPE_ENTRY = 12 * 8
#: bytes per beam element while assembling (its 12 x 12 stiffness and mass triplets, values and
#: indices, with their sparse conversions and the reduced matrices): measured 13.9 kB (20 000 elements)
BYTES_PER_ELEMENT = 20_000
#: below this estimate with n_dof modes (an upper bound) no count is made: no solve is spent on it
SMALL_BYTES = 64 * 10**6
#: coupled frame: the estimate from its parts times this margin
FRAME_MARGIN = 1.5
#: at most this many distinct span lengths are solved alone; beyond, the longest stands for all (an
#: upper estimate: a longer span has more modes below the cut-off)
MAX_SPAN_SOLVES = 8


class BridgeSizeError(StructureError, ResourceError):
    """A bridge model estimated to need more memory than this machine has available (a StructureError,
    located like one, and a ResourceError)."""


@dataclass(frozen=True)
class BridgeSize:
    """The estimated size of a bridge's model: DOFs (exact), beam elements (exact), modes (estimated;
    ``upper``: no count made, the upper bound n_dof or max_modes of a model small enough with it)."""

    n_dof: int
    n_elements: int
    n_modes: int
    upper: bool = False

    @property
    def bytes(self) -> int:
        return BYTES_PER_SHAPE_ENTRY * self.n_dof * self.n_modes + BYTES_PER_ELEMENT * self.n_elements


def _counts(bridge: SimpleBeam | Frame) -> tuple[int, int]:
    """(n_dof, n_elements) of the assembled model: every node has 6 DOFs; each span has its own
    ``elements_per_span + 1`` girder nodes, each pier ``elements_per_pier + 1`` nodes."""
    n_spans = len(bridge.spans)
    eps = int(bridge.elements_per_span)
    nodes, elements = n_spans * (eps + 1), n_spans * eps
    if isinstance(bridge, Frame):
        epp = int(bridge.elements_per_pier)
        nodes += (n_spans - 1) * (epp + 1)
        elements += (n_spans - 1) * epp
    if isinstance(bridge, Continuous):  # one node at each span joint; a pier at each support 'pier'
        piers, epp = list(bridge.supports).count("pier"), int(bridge.elements_per_pier)
        nodes += piers * (epp + 1) - (n_spans - 1)
        elements += piers * epp
    return 6 * nodes, elements


#: solve_modes(model, max_frequency, max_modes) -> FEModes (tb_exudyn.structure.fe, which imports this module)
Solver = Callable[[Any, float, int], Any]


def _modes_below(solve: Solver, model: Any, max_frequency: float, whole: bool) -> int:
    """The modes of a small model below the cut-off (none: 0). A part that is a mechanism alone raises
    that error when the whole is one too (``whole``: a span on its supports, which every span of the
    bridge rests on alike); a pier alone (its top free, held by the bearings in the bridge) that is
    one counts its free DOFs."""
    try:
        return solve(model, max_frequency, 0).n_modes
    except StructureError as exc:
        if exc.key == "max_frequency":  # no mode below the cut-off
            return 0
        if whole:
            raise
        return model.n_free


def estimate_modes(bridge: SimpleBeam | Frame, max_frequency: float, max_modes: int, solve: Solver) -> int:
    """The number of modes of ``bridge`` below ``max_frequency`` (at most ``max_modes`` if > 0), from
    its parts solved alone by ``solve`` (module docstring)."""
    if isinstance(bridge, Continuous):
        return _estimate_continuous(bridge, max_frequency, max_modes, solve)
    spans = list(zip((float(s) for s in bridge.spans), bridge.sections))  # each span and its section
    parts = sorted(set(spans), key=lambda p: p[0])
    if len(parts) > MAX_SPAN_SOLVES:
        parts = parts[-1:]
    single = {}
    for length, section in parts:
        part = dataclasses.replace(bridge, spans=(length,), girder=section, girders=())
        # a span of its own section alone: its errors would name 'girder', so the whole model names the key
        single[(length, section)] = _modes_below(solve, assemble(part), max_frequency, not bridge.girders)
    count = sum(single.get(p, single[parts[-1]]) for p in spans)
    if isinstance(bridge, Frame) and len(bridge.spans) > 1:
        pier = assemble_pier(bridge.pier, int(bridge.elements_per_pier), bridge.name)
        per_pier = _modes_below(solve, pier, max_frequency, False)
        count = math.ceil(FRAME_MARGIN * (count + (len(bridge.spans) - 1) * per_pier))
    return min(count, max_modes) if max_modes > 0 else count


def _estimate_continuous(bridge: Continuous, max_frequency: float, max_modes: int, solve: Solver) -> int:
    """A continuous girder: each span as a simple span of its section on ideal supports (each distinct
    span solved alone, at most :data:`MAX_SPAN_SOLVES`), plus each pier alone, times :data:`FRAME_MARGIN`."""
    parts = sorted({(float(x), g) for x, g in zip(bridge.spans, bridge.sections)}, key=lambda p: p[0])
    if len(parts) > MAX_SPAN_SOLVES:
        parts = parts[-1:]
    single = {}
    for length, section in parts:
        span = SimpleBeam(name=bridge.name, spans=(length,), girder=section,
                          elements_per_span=bridge.elements_per_span)
        single[(length, section)] = _modes_below(solve, assemble(span), max_frequency, False)
    count = sum(single.get((float(x), g), single[parts[-1]]) for x, g in zip(bridge.spans, bridge.sections))
    piers = list(bridge.supports).count("pier")
    if piers:
        pier = assemble_pier(bridge.pier, int(bridge.elements_per_pier), bridge.name)
        count += piers * _modes_below(solve, pier, max_frequency, False)
    count = math.ceil(FRAME_MARGIN * count)
    return min(count, max_modes) if max_modes > 0 else count


def bridge_size(bridge: SimpleBeam | Frame, max_frequency: float, max_modes: int, solve: Solver) -> BridgeSize:
    """The size of ``bridge``'s model with the modes up to ``max_frequency`` (at most ``max_modes``)."""
    n_dof, n_el = _counts(bridge)
    upper = BridgeSize(n_dof, n_el, n_dof if max_modes <= 0 else min(n_dof, int(max_modes)), upper=True)
    if upper.bytes <= SMALL_BYTES:
        return upper
    return BridgeSize(n_dof, n_el, estimate_modes(bridge, max_frequency, max_modes, solve))


def check_bridge_size(bridge: SimpleBeam | Frame, max_frequency: float, max_modes: int, solve: Solver,
                      limit: int | None = None) -> BridgeSize:
    """Refuse (:class:`BridgeSizeError` naming ``spans``) a bridge whose model is estimated to need more
    than ``limit`` bytes (None: the memory this machine has available), before it is assembled."""
    n_dof, n_el = _counts(bridge)
    if limit is None:
        limit, text = available_memory()
    else:
        text = f"the limit of {format_bytes(limit)}"
    if limit is None:
        return BridgeSize(n_dof, n_el, 0)
    if BYTES_PER_ELEMENT * n_el > limit:  # too many elements to assemble: no mode count can be made
        size = BridgeSize(n_dof, n_el, 0)
    else:
        size = bridge_size(bridge, max_frequency, max_modes, solve)
    if size.bytes <= limit:
        return size
    # the shapes grow with the square of the span count (DOFs x modes), the elements linearly
    n = len(bridge.spans)
    a, b = BYTES_PER_SHAPE_ENTRY * size.n_dof * size.n_modes / n**2, BYTES_PER_ELEMENT * size.n_elements / n
    fit = int((-b + math.sqrt(b * b + 4.0 * a * limit)) / (2.0 * a)) if a > 0 else int(limit // b)
    raise BridgeSizeError(
        f"bridge '{bridge.name}'", "spans", list(bridge.spans),
        f"about {fit} such spans at most",
        f"{len(bridge.spans)} spans need about {format_bytes(size.bytes)}, over {text}")


__all__ = ["BridgeSize", "BridgeSizeError", "bridge_size", "check_bridge_size", "estimate_modes"]
