"""What a linear engine needs of a scenario's built model, as plain data (no Exudyn).

The parent builds the Exudyn model once (for the modes and the plan), and from it
:func:`tb_exudyn.engines.exudyn_runs.linear_model` makes a :class:`LinearModel`: the linear system
about ``analysis.linearization``, the output map, the channels and derived channels, the scenario's
warnings and, for the linear mean, the static state under the dead loads and the linear system about
it. The workers receive it (pickled) and build no model: a linear engine (batched, dense) given one
imports no Exudyn. A worker builds the model only for what only Exudyn gives (the Exudyn mean:
``mean="exudyn"``, or "auto" where the linear mean does not apply; the dense engine's linear mean,
a test reference, which evaluates the model's dead loads step by step).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np


@dataclass(frozen=True)
class LinearMeanInputs:
    """The linear mean's data (:mod:`tb_exudyn.engines.batched.mean`): the static state u_s of the
    train standing on the approach at t = 0 under the dead loads, the linear system about it (None:
    the columns' own, already about "static"), the bridge's mode count and description."""

    static: np.ndarray = field(repr=False)
    lin_static: Any = field(repr=False)
    bridge_modes: int
    bridge_description: str


@dataclass(frozen=True)
class LinearModel:
    """A scenario's linear model and outputs, built once in the parent (see the module docstring).

    lin : the :class:`~tb_exudyn.system.linear.LinearSystem` about ``analysis.linearization``
    outputs : the :class:`~tb_exudyn.system.channels.OutputMap` of the engine's outputs
    selected : (name, unit) of the scenario's channels (the first outputs)
    derived : the derived channels' definitions (:mod:`tb_exudyn.system.derived`)
    force_channels : the names of every vertical wheel force of the model (the mean's force rows)
    warnings : the scenario's warnings found while building
    n_coordinates : the model's ODE2 coordinates (the memory estimate)
    mean : the linear mean's inputs (None: not asked for)
    """

    lin: Any = field(repr=False)
    outputs: Any = field(repr=False)
    selected: tuple[tuple[str, str], ...]
    derived: tuple[Any, ...] = field(repr=False)
    force_channels: tuple[str, ...]
    warnings: tuple[str, ...]
    n_coordinates: int
    mean: LinearMeanInputs | None = None


__all__ = ["LinearMeanInputs", "LinearModel"]
