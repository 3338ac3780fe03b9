"""Scenario data: dataclasses, TOML loading and validation, the library of named models."""

from .continuous import Continuous, ContinuousBearings
from .code_data import CONSTRUCTION_TYPES, MASS_CASES, CodeData, with_mass_case
from .errors import ScenarioError
from .io import load_bridge, load_scenario, load_vehicle, save_scenario, scenario_from_dict, scenario_to_toml
from .model import (
    AddedMass,
    Analysis,
    BeamSection,
    Bearings,
    Bridge,
    Car15,
    Car15Geometry,
    CreepCar,
    GivenCreep,
    HertzCreep,
    Frame,
    ModalTable,
    MovingForce,
    Pier,
    RigidBodyInertia,
    RigidWheelset,
    Scenario,
    SimpleBeam,
    SprungMass,
    Suspension,
    Suspension3,
    Track,
    TrackLine,
    Train,
    Vehicle,
    WheelRailContact,
    WheelsetInertia,
    YawDamper,
)
from .registry import list_models, model_files, models_dir
from .schema import describe_fields, to_dict

__all__ = [
    "Continuous", "ContinuousBearings",
    "CONSTRUCTION_TYPES", "MASS_CASES", "CodeData", "with_mass_case",
    "AddedMass", "Analysis", "BeamSection", "Bearings", "Bridge", "Car15", "Car15Geometry", "CreepCar", "Frame", "GivenCreep", "HertzCreep", "ModalTable",
    "MovingForce", "Pier", "RigidBodyInertia", "RigidWheelset", "Scenario", "ScenarioError", "SimpleBeam", "SprungMass",
    "Suspension", "Suspension3", "Track", "TrackLine", "Train", "Vehicle", "WheelRailContact", "WheelsetInertia", "YawDamper", "describe_fields", "list_models",
    "load_bridge", "load_scenario", "load_vehicle", "model_files", "models_dir", "save_scenario",
    "scenario_from_dict", "scenario_to_toml", "to_dict",
]
