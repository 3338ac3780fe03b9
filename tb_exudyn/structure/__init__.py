"""Bridge structural model: spatial-beam finite elements, modal reduction, rail-level mode shapes.

Entry point: :func:`modal_bridge` (bridge data -> mass-normalised :class:`ModalBridge`; a ``modal_table``
bridge's modes read from its CSV tables, :mod:`.imported`);
:func:`modal_report` lists frequencies, mode types and effective masses of :func:`bridge_modes`.
"""

from ..scenario.model import ModalTable
from .assembly import FEModel, StructureError, assemble, assemble_pier, located
from .continuous import assemble_continuous  # registers the kind 'continuous' with assemble
from .fe import (
    FEModes,
    ModalReport,
    RailShapeEvaluator,
    bridge_modes,
    modal_bridge_from_modes,
    modal_report,
    rayleigh_coefficients,
    rayleigh_damping_ratios,
    solve_modes,
)
from .fe import modal_bridge as fe_modal_bridge
from .imported import export_modes, imported_modal_bridge
from .modal import ModalBridge, RailShapes, simply_supported_modes


def modal_bridge(bridge, max_frequency: float, max_modes: int = 0,  # noqa: ANN001
                 rayleigh: tuple[float, float] | None = None) -> ModalBridge:
    """The mass-normalised modal model of any bridge kind: the FE modes of a ``simple_beam`` or ``frame``
    (:func:`.fe.modal_bridge`), the tables of a ``modal_table`` (:func:`.imported.imported_modal_bridge`)."""
    if isinstance(bridge, ModalTable):
        return imported_modal_bridge(bridge, max_frequency, max_modes, rayleigh)
    return fe_modal_bridge(bridge, max_frequency, max_modes, rayleigh)


__all__ = [
    "FEModel", "FEModes", "ModalBridge", "ModalReport", "RailShapeEvaluator", "RailShapes",
    "StructureError", "assemble", "assemble_continuous", "assemble_pier", "bridge_modes", "export_modes",
    "imported_modal_bridge", "located", "modal_bridge",
    "modal_bridge_from_modes", "modal_report", "rayleigh_coefficients", "rayleigh_damping_ratios",
    "simply_supported_modes", "solve_modes",
]
