"""tb_exudyn: random vibration of a train crossing a bridge.

Vehicles are Exudyn rigid bodies on spring-damper suspensions, the bridge a reduced flexible body
from a spatial-beam finite-element model, wheel and rail coupled by a user function that carries
the track irregularity. Random responses by the pseudo-excitation method, checked by Monte Carlo.

The public API is re-exported here explicitly; see README.md and docs/develop.md.
"""

from ._version import __version__
from .errors import TbExudynError, UserError
from .execution import Execution
from .results import RandomResponse, TimeHistory, load_results
from .results.base import set_figure_loader
from .results.compare import compare
from .scenario import (
    Scenario,
    ScenarioError,
    list_models,
    load_bridge,
    load_scenario,
    load_vehicle,
    save_scenario,
)

#: the methods build and run Exudyn models: loaded on first use, so that reading scenarios and
#: results stays light
_LAZY = {
    "run_deterministic": "tb_exudyn.methods",
    "run_pem": "tb_exudyn.methods",
    "run_monte_carlo": "tb_exudyn.methods",
    "simulate": "tb_exudyn.methods",
    "BatchedOptions": "tb_exudyn.methods",
    "run_uq": "tb_exudyn.methods.uq",
}


def _plotting():
    """The plotting package (matplotlib): what ``result.plot`` draws with, loaded on the first figure."""
    import importlib

    return importlib.import_module("tb_exudyn.plotting")


set_figure_loader(_plotting)


def __getattr__(name: str):
    if name in _LAZY:
        import importlib

        return getattr(importlib.import_module(_LAZY[name]), name)
    raise AttributeError(f"module 'tb_exudyn' has no attribute {name!r}")


__all__ = [
    "BatchedOptions",
    "Execution",
    "RandomResponse",
    "Scenario",
    "ScenarioError",
    "TbExudynError",
    "TimeHistory",
    "UserError",
    "__version__",
    "compare",
    "list_models",
    "load_bridge",
    "load_results",
    "load_scenario",
    "load_vehicle",
    "run_deterministic",
    "run_monte_carlo",
    "run_pem",
    "run_uq",
    "save_scenario",
    "simulate",
]
