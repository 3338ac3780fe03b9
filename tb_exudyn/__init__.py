"""tb_exudyn: random vibration of a train crossing a bridge.

Vehicles are Exudyn rigid bodies on spring-damper suspensions, the bridge a reduced flexible body
from a spatial-beam finite-element model, wheel and rail coupled by a user function that carries
the track irregularity. Random responses by the pseudo-excitation method, checked by Monte Carlo.

The public API is re-exported here explicitly; see README.md and docs/.
"""

from .scenario import (
    Scenario,
    ScenarioError,
    list_models,
    load_bridge,
    load_scenario,
    load_vehicle,
    save_scenario,
)

__version__ = "0.1.0"

__all__ = [
    "Scenario",
    "ScenarioError",
    "__version__",
    "list_models",
    "load_bridge",
    "load_scenario",
    "load_vehicle",
    "save_scenario",
]
