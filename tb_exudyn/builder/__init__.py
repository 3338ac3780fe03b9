"""Builder: turns a scenario into an Exudyn train-bridge system.

With the solvers, the only place that imports Exudyn. :mod:`.coupling` (the wheel-rail physics),
:mod:`.excitation` (irregularity input as data) and :mod:`.channels` (output names and values)
are plain numpy and usable by other integrators without Exudyn: the Exudyn parts
(:func:`build_model`, :class:`TrainBridgeModel`, :class:`BuildOptions`, ...) are imported on
first use.
"""

from __future__ import annotations

import importlib
from typing import Any

from .channels import Channel, Recording
from .coupling import ContactLayout, ContactState, WheelRailCoupling
from .excitation import (
    Excitation,
    HarmonicExcitation,
    NoExcitation,
    ProfileExcitation,
    rail_inputs,
    sampled_profile,
)

_LAZY = {
    "BuildOptions": ".vehicles",
    "TrainBridgeModel": ".model",
    "bridge_modes": ".model",
    "build_model": ".model",
    "closed_form_modes": ".model",
    "channel_list": ".model",
    "scenario_checks": ".model",
}

__all__ = [
    "BuildOptions", "Channel", "ContactLayout", "ContactState", "Excitation", "HarmonicExcitation",
    "NoExcitation", "ProfileExcitation", "Recording", "TrainBridgeModel", "WheelRailCoupling", "bridge_modes",
    "build_model", "channel_list", "closed_form_modes", "rail_inputs", "sampled_profile", "scenario_checks",
]


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        return getattr(importlib.import_module(_LAZY[name], __name__), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
