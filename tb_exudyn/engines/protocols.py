"""The three interfaces between methods and engines, declared once (``typing.Protocol``).

- :class:`ColumnSource`: what an engine integrates: ``width`` columns of inputs (PEM's harmonic
  pseudo-excitations :class:`~tb_exudyn.system.columns.HarmonicColumns`, Monte Carlo's sampled
  profiles :class:`~tb_exudyn.system.columns.ProfileColumns`, the linear mean's gravity load
  :class:`~tb_exudyn.system.columns.StaticLoadColumns`);
- :class:`Reducer`: what an engine hands every output time to: ``record(i, Y, ext)`` with ``Y``
  (n_outputs, m) complex, the outputs of the m columns in the engine's internal row order and
  ``ext[c]`` the internal row of output c (``outputs.names`` order); ``result()`` the block's arrays.
  Implemented by :class:`~tb_exudyn.methods.pem.PsdReducer` (through
  :class:`~tb_exudyn.methods.pseudo_reduction.PseudoReduction`),
  :class:`~tb_exudyn.methods.monte_carlo.SampleReducer` (through
  :class:`~tb_exudyn.methods.reduction.SampleReduction`), the linear mean's recorder
  (:mod:`tb_exudyn.engines.batched.mean`) and the dense engine's mean recorder;
- :class:`ColumnEngine`: what a method asks of an engine (:class:`~tb_exudyn.engines.base.Engine`
  implements it): its capabilities, its outputs and time grid, ``integrate``, ``integrate_estimate``,
  ``mean`` (the mean task: the engine's deterministic run, see :meth:`~tb_exudyn.engines.base.Engine.mean`)
  and ``describe``.

Protocols are structural: a class implements one by having its members; the classes above also say
so in their docstrings, and ``tests/engines/test_protocols.py`` checks them with ``isinstance``.
"""

from __future__ import annotations

from typing import Any, ClassVar, Protocol, runtime_checkable

import numpy as np


@runtime_checkable
class ColumnSource(Protocol):
    """Columns of inputs to integrate together: ``width`` complex columns (a real input is the real
    part); the engines read the inputs through the source's own methods (``contact_inputs``,
    ``rail_values``, ... of :mod:`tb_exudyn.system.columns`)."""

    width: int


@runtime_checkable
class Reducer(Protocol):
    """What a method makes of an engine's outputs, one output time at a time."""

    def record(self, i: int, Y: np.ndarray, ext: np.ndarray) -> None:
        """Output time ``i``: ``Y`` (n_outputs, m) complex in the engine's row order, ``ext[c]`` the
        row of output c (``outputs.names`` order)."""

    def result(self) -> dict[str, np.ndarray]:
        """The block's arrays (plain, checkpointable)."""


@runtime_checkable
class ColumnEngine(Protocol):
    """An integrator of column sources on one scenario (built once per worker)."""

    name: ClassVar[str]
    full_model: ClassVar[bool]
    single_columns: ClassVar[bool]

    @property
    def fs(self) -> float:
        """The output rate [Hz]."""

    def integrate(self, source: Any, reducer: Any) -> dict[str, np.ndarray]:
        """Every column of ``source`` over the crossing into ``reducer``; ``reducer.result()`` and the
        engine's arrays."""

    def integrate_estimate(self, source: Any, reducer: Any) -> dict[str, np.ndarray]:
        """:meth:`integrate` for columns that only feed an error estimate (may be cheaper)."""

    def mean(self) -> dict[str, np.ndarray]:
        """The mean task's arrays: the engine's deterministic run (cached per engine)."""

    def describe(self) -> dict[str, Any]:
        """The engine's provenance."""


__all__ = ["ColumnEngine", "ColumnSource", "Reducer"]
