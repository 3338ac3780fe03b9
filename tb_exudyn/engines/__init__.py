"""Engines: integrators of column sources on a scenario's model, behind one protocol (:mod:`.base`).

- ``"exudyn"`` (:mod:`.exudyn`): one Exudyn run per real part of a column: the reference;
- ``"batched"`` (:mod:`.batched`): every column of a task in one integration of the linear model
  with Exudyn's generalized-alpha step: the everyday engine;
- ``"dense"`` (:mod:`.dense`): the same linear model and step on full matrices, no structure used: a
  small reference for the batched engine and the naive baseline of the speed benchmark.

Engines import Exudyn (they build the model), so they are loaded on first use: adding an engine is
one module with an :class:`~.base.Engine` subclass and one line in :data:`ENGINES`.
"""

from __future__ import annotations

import importlib
from typing import Any

from ..errors import SettingError
from ..scenario.model import LINEAR_ROW_KINDS

#: the engine a method runs on when none is given (``run_pem``, ``run_monte_carlo``, ``simulate``, the
#: sweep, the command line's ``--engine``); the deterministic run is always Exudyn's
DEFAULT_ENGINE = "batched"
#: name -> (module, class) of every engine
ENGINES: dict[str, tuple[str, str]] = {
    "exudyn": ("tb_exudyn.engines.exudyn", "ExudynEngine"),
    "batched": ("tb_exudyn.engines.batched", "BatchedEngine"),
    "dense": ("tb_exudyn.engines.dense", "DenseEngine"),
}


def engine_class(name: str, where: str = "engine") -> Any:
    """The engine class registered as ``name`` (imported on first use)."""
    if name not in ENGINES:
        raise SettingError(where, "engine", name, " or ".join(repr(n) for n in ENGINES))
    module, cls = ENGINES[name]
    return getattr(importlib.import_module(module), cls)


def check_engine(name: str, scenario: Any, options: Any = None, *, linearized: bool = True,
                 where: str = "engine") -> Any:
    """The engine class after its capability checks on ``scenario`` (CapabilityError before any run).

    ``linearized``: the method runs the engine's linear form where it has one (PEM); a Monte Carlo
    on a full-model engine linearises nothing, so ``analysis.linearization`` does not apply there."""
    cls = engine_class(name, where)
    if linearized or not cls.full_model:
        others = [(n, engine_class(n)) for n in ENGINES if n != name]
        lin = scenario.analysis.linearization
        rows = any(v.kind in LINEAR_ROW_KINDS for v in scenario.train.vehicles)
        can = [n for n, c in others if lin in c.linearizations and (c.linear_rows or not rows)]
        cls.check(scenario, options, f"engine {' or '.join(map(repr, can))} can" if can else "")
    return cls


def make_engine(name: str, scenario: Any, options: Any = None, wheel_forces: bool = False, system: Any = None) -> Any:
    """Build an engine (in a worker: once per worker and setup); ``system``: a linear engine's
    :class:`~.linear_model.LinearModel`, built once in the parent (None: the engine makes its own)."""
    cls = engine_class(name)
    return cls(scenario, options, wheel_forces) if system is None else cls(scenario, options, wheel_forces, system)


__all__ = ["DEFAULT_ENGINE", "ENGINES", "check_engine", "engine_class", "make_engine"]
