"""Builder: turns a scenario into an Exudyn train-bridge system.

With the Exudyn engine, the only place that imports Exudyn. The plain-numpy physics it uses (the
wheel-rail coupling, the excitation, the channels) lives in :mod:`tb_exudyn.system` and is
re-exported here; the Exudyn parts (:func:`build_model`, :class:`TrainBridgeModel`,
:class:`BuildOptions`, ...) are imported on first use.
"""

from __future__ import annotations

import importlib
from typing import Any

from ..system.channels import Channel, Recording
from ..system.coupling import ContactLayout, ContactState, WheelRailCoupling
from ..system.excitation import (
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
