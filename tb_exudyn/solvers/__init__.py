"""Solvers: time integration of built train-bridge models.

``run_deterministic`` (gravity, smooth track or one profile: the mean response or one sample);
``run_model`` re-runs a built model with a new excitation without rebuilding it; the integration
settings are data (:class:`SolverSettings`).
"""

from .deterministic import run_deterministic, run_model, summarize
from .engine import RunInfo, SimulationIncomplete, integrate
from .settings import SolverSettings

__all__ = ["RunInfo", "SimulationIncomplete", "SolverSettings", "integrate", "run_deterministic", "run_model", "summarize"]
