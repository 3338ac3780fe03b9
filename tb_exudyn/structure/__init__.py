"""Bridge structural model: spatial-beam finite elements, modal reduction, rail-level mode shapes."""

from .modal import ModalBridge, RailShapes, simply_supported_modes

__all__ = ["ModalBridge", "RailShapes", "simply_supported_modes"]
