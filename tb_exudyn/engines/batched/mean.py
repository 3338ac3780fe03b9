"""The linear mean: the batched engine's own model under the gravity load, as one more column.

Instead of Exudyn's deterministic run (gravity, static start, no irregularity: one full-model run
that no other core can share), the model linearised about that run's own static state (linearization
"static": the suspensions' preload stiffness included, whatever linearization the columns use)
integrates the dead load from the static equilibrium on the approach
(:class:`~tb_exudyn.system.columns.StaticLoadColumns`), in float64 whatever the columns' precision.
It differs from Exudyn's run only by the rigid bodies' finite rotations (and Exudyn's Newton
tolerance): on the reference study within 1.1e-3 of each channel's largest |mean| and 3e-5 of its
largest sigma (docs/speed.md). The result has the form of :meth:`tb_exudyn.engines.base.Engine.mean`.
"""

from __future__ import annotations

import time as _time
from typing import Any

import numpy as np

from ...errors import CapabilityError
from ...system.channels import rail_rows
from ...system.columns import static_load_columns
from ...system.components import find_components
from ..base import exudyn_side
from .loop import integrate


class _MeanRecorder:
    """The gravity column's outputs at every output time (real part: the column has no imaginary input);
    a :class:`~tb_exudyn.engines.protocols.Reducer`."""

    def __init__(self, n_outputs: int, n_t: int) -> None:
        self.values = np.zeros((n_outputs, n_t))

    def record(self, i: int, Y: np.ndarray, ext: np.ndarray) -> None:
        self.values[:, i] = Y[ext, 0].real

    def result(self) -> dict[str, np.ndarray]:
        return {"values": self.values}


def linear_mean(engine: Any) -> dict[str, np.ndarray]:
    """The mean of ``engine``'s scenario from its linear model (see the module docstring), in the
    form of :meth:`~tb_exudyn.engines.base.Engine.mean` (:meth:`~tb_exudyn.engines.base.Engine.linear_mean_arrays`).
    CapabilityError where the gravity column does not apply (a bridge loaded at t = 0, moving point loads)."""
    start = _time.perf_counter()
    inputs = engine.system.mean  # the static state and the linear system about it, built in the parent
    if inputs is None:  # a LinearModel made without them: made now (on the model)
        inputs = exudyn_side().linear_model(engine.model, engine.wheel_forces, mean=True).mean
    static = inputs.static
    # the deterministic run's linear model is the one about its own static state (the suspensions'
    # preload included), whatever linearization the columns use
    lin = engine.lin if inputs.lin_static is None else inputs.lin_static
    try:
        source = static_load_columns(lin, static)
    except ValueError as exc:
        raise CapabilityError("engine 'batched'", "options.mean", "linear", "'exudyn' for this scenario", str(exc)) from None
    om = engine.outputs
    rec = _MeanRecorder(len(om.names), engine.steps.n_outputs)
    step = engine.options.step  # the columns' step: "compiled" or "numpy"
    if lin is engine.lin:
        integrate(engine, source, rec, precision="float64", step=step)
    else:
        integrate(engine, source, rec, precision="float64", lin=lin, components=find_components(lin, engine.output_time),
                  step=step)
    values = rec.values
    for i, g, order in om.node:  # displacements from the reference configuration: u_s + delta
        if order == 0:
            values[i] += static[g]
    for i, shape, order in om.bridge:
        if order == 0:
            values[i] += shape @ static[lin.bridge]
    rails = [(i, c) for i, c, order in om.rail if order == 0]
    if rails:  # the rail under a wheel: its moving row S(t) over the static state too
        cp = lin.coupling
        for k, t in enumerate(engine.steps.output_times):
            S = rail_rows(cp, float(t))
            for i, c in rails:
                values[i, k] += S[c] @ static[lin.bridge]
    provenance = {
        "engine": "batched", "mean_engine": "batched (linear model, gravity column)",
        "linearization": "static", "gravity": True, "initial_state": "static",
        "excitation": "none", "steps": engine.n_steps, "time_step_s": engine.alpha.h,
        "end_time_s": engine.n_steps * engine.alpha.h,
        "solver_settings": {"spectral_radius": engine.alpha.rho},
        "bridge_modes": inputs.bridge_modes, "bridge_model": inputs.bridge_description,
        "contact_damping_ratio": engine.scenario.analysis.contact_damping_ratio,
        "warnings": list(engine.warnings),
    }
    return engine.linear_mean_arrays(values, provenance, start)


__all__ = ["linear_mean"]
