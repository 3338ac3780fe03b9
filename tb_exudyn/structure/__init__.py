"""Bridge structural model: spatial-beam finite elements, modal reduction, rail-level mode shapes.

Entry point: :func:`modal_bridge` (bridge data -> mass-normalised :class:`ModalBridge`);
:func:`modal_report` lists frequencies, mode types and effective masses of :func:`bridge_modes`.
"""

from .assembly import FEModel, StructureError, assemble, assemble_pier, located
from .continuous import assemble_continuous  # registers the kind 'continuous' with assemble
from .fe import (
    FEModes,
    ModalReport,
    RailShapeEvaluator,
    bridge_modes,
    modal_bridge,
    modal_bridge_from_modes,
    modal_report,
    rayleigh_coefficients,
    rayleigh_damping_ratios,
    solve_modes,
)
from .modal import ModalBridge, RailShapes, simply_supported_modes

__all__ = [
    "FEModel", "FEModes", "ModalBridge", "ModalReport", "RailShapeEvaluator", "RailShapes",
    "StructureError", "assemble", "assemble_continuous", "assemble_pier", "bridge_modes", "located", "modal_bridge",
    "modal_bridge_from_modes", "modal_report", "rayleigh_coefficients", "rayleigh_damping_ratios",
    "simply_supported_modes", "solve_modes",
]
