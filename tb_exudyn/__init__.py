"""tb_exudyn: random vibration of a train crossing a bridge.

Vehicles are Exudyn rigid bodies on spring-damper suspensions, the bridge a reduced flexible body
from a spatial-beam finite-element model, wheel and rail coupled by a user function that carries
the track irregularity. Random responses by the pseudo-excitation method, checked by Monte Carlo.

The public API is re-exported here explicitly; see README.md and docs/.
"""

from .results import RandomResponse, TimeHistory, load_results
from .scenario import (
    Scenario,
    ScenarioError,
    list_models,
    load_bridge,
    load_scenario,
    load_vehicle,
    save_scenario,
)

from ._version import __version__


_LAZY = {
    "run_deterministic": "tb_exudyn.solvers.deterministic",
    "run_pem": "tb_exudyn.solvers.pem",
    "run_monte_carlo": "tb_exudyn.solvers.monte_carlo",
    "compare": "tb_exudyn.solvers.compare",
}


def __getattr__(name: str):
    """The solvers import Exudyn: load them on first use, so the rest works without it."""
    if name in _LAZY:
        import importlib

        return getattr(importlib.import_module(_LAZY[name]), name)
    raise AttributeError(f"module 'tb_exudyn' has no attribute {name!r}")


__all__ = [
    "RandomResponse",
    "Scenario",
    "ScenarioError",
    "TimeHistory",
    "__version__",
    "list_models",
    "load_bridge",
    "load_results",
    "load_scenario",
    "load_vehicle",
    "compare",
    "run_deterministic",
    "run_monte_carlo",
    "run_pem",
    "save_scenario",
]
