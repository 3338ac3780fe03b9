"""Builder: turns a scenario into an Exudyn train-bridge system.

With the Exudyn engine, the only place that imports Exudyn. The plain-numpy physics it uses (the
wheel-rail coupling, the excitation, the channels, the linear system) lives in
:mod:`tb_exudyn.system` and is re-exported here for convenience.

- :func:`build_model` -> :class:`TrainBridgeModel` (built once, re-excited many times);
- :func:`linear_system` -> the model's :class:`~tb_exudyn.system.linear.LinearSystem`;
- vehicles: one builder per vehicle kind, registered in :data:`.vehicles.VEHICLE_BUILDERS`.
"""

from __future__ import annotations

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
from .linear import linear_system
from .model import TrainBridgeModel, bridge_modes, build_model, channel_list, closed_form_modes, scenario_checks
from .vehicles import VEHICLE_BUILDERS

__all__ = [
    "Channel", "ContactLayout", "ContactState", "Excitation", "HarmonicExcitation", "NoExcitation",
    "ProfileExcitation", "Recording", "TrainBridgeModel", "VEHICLE_BUILDERS", "WheelRailCoupling", "bridge_modes",
    "build_model", "channel_list", "closed_form_modes", "linear_system", "rail_inputs", "sampled_profile",
    "scenario_checks",
]
