"""The batched engine: every column of a task in one time integration of the linear model.

The train-bridge model is linear and every column shares its time-varying matrices; only the input
differs. So all columns of a task (PEM: one complex column per irregularity type and frequency, the
real part the cosine run and the imaginary part the sine run; Monte Carlo: two real samples per
complex column) are integrated together, with exactly Exudyn's generalized-alpha step
(:mod:`tb_exudyn.engines.alpha`), on the very model the Exudyn runs use: M, K0, D0 from Exudyn's
``ComputeLinearizedSystem`` and the contact of the ``WheelRailCoupling``
(:class:`~tb_exudyn.system.linear.LinearSystem`). The model being linear, each step is solved exactly
(Exudyn to its Newton tolerance). Initial accelerations from M qdd0 = f(q0, v0, 0) and a0 = qdd0
(Exudyn's computeInitialAccelerations); the step h = end_time / n_steps and the output grid are the
Exudyn engine's (:func:`~tb_exudyn.system.conventions.run_steps`).

What makes it fast:

- the contact forces by Woodbury over the contact rows of the vehicles with an axle on the bridge;
  vehicles off the bridge advance by a constant folded operator (:mod:`.run`);
- independent components (e.g. the vertical in-plane and lateral out-of-plane motion of a symmetric
  car on a symmetric track) each integrate only the columns that excite them, and coordinates no
  input reaches are not integrated at all (:mod:`tb_exudyn.system.components`);
- complex columns computed on their float64 view, in-place BLAS (:mod:`.kernels`);
- single-threaded BLAS, one process per core, each owning large slices of the columns (tasks);
- outputs reduced at every output step by the method's reducer, never stored as histories.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ...builder import linear_system
from ...execution.threads import single_threaded_blas
from ...system.components import find_components
from ...system.conventions import scenario_steps
from ...system.excitation import taper
from ..alpha import GeneralizedAlpha
from ..base import Engine
from .outputs import _Outputs
from .inputs import shared_inputs
from .run import _Run, _Step


class BatchedEngine(Engine):
    """The linear model's columns integrated together (no options)."""

    name = "batched"
    full_model = False

    def __init__(self, scenario: Any, options: Any = None, wheel_forces: bool = False) -> None:
        with single_threaded_blas():
            super().__init__(scenario, options, wheel_forces)
            self.lin = linear_system(self.model, scenario.analysis.linearization)
            steps = scenario_steps(scenario)
            self.n_steps, self.ratio = steps.n_steps, steps.ratio
            self.alpha = GeneralizedAlpha(float(scenario.analysis.spectral_radius), steps.h)
            self.output_time = steps.output_times
            self.components = find_components(self.lin, self.output_time)

    def describe(self) -> dict[str, Any]:
        ga = self.alpha
        return {
            "engine": self.name,
            "linearization": self.lin.linearization,
            "generalized_alpha": {"spectral_radius": ga.rho, "alpha_m": ga.alpha_m, "alpha_f": ga.alpha_f,
                                  "gamma": ga.gamma, "beta": ga.beta, "time_step_s": ga.h, "steps": self.n_steps},
            "components": [{"coordinates": c.size, "bridge_modes": c.n_bridge, "contacts": int(c.rows.size),
                            "kinds": [("vertical", "alignment", "cross_level")[k] for k in c.kinds]}
                           for c in self.components],
            "coordinates": self.lin.n,
        }

    def integrate(self, source: Any, reducer: Any) -> dict[str, np.ndarray]:
        with single_threaded_blas():
            return integrate(self, source, reducer)


def integrate(engine: BatchedEngine, source: Any, reducer: Any) -> dict[str, np.ndarray]:
    """Integrate the columns of ``source`` over the crossing, handing the outputs of every output
    time to ``reducer.record(i, Y, ext)``; returns ``reducer.result()``.

    ``source`` is a column source (:mod:`tb_exudyn.system.columns`): ``width`` (number of complex
    columns) and ``columns_for(kinds)`` (the columns a component excited by those kinds integrates);
    its per-step inputs come from :mod:`.inputs`.
    """
    lin, ga, cm = engine.lin, engine.alpha, engine.outputs
    cp = lin.coupling
    n_ch, m = len(cm.names), source.width
    runs = [_Run(lin, ga, comp, cols, source) for comp in engine.components
            if (cols := source.columns_for(comp.kinds)).size]
    overlap = np.zeros((lin.k.size, m), dtype=np.int64)  # components integrating (contact row, column)
    for run in runs:
        overlap[np.ix_(run.rows, run.cols)] += 1
    # internal channel order: node channels per component and order, bridge, contacts, the rest
    bridge_ch = [i for o in range(3) for i, _, oo in cm.bridge if oo == o]
    contact_ch = [i for i, _ in cm.contact]
    integrated = {int(g) for r in runs for g in r.comp.coords}
    shared0 = sum(1 for _, g, _ in cm.node if g in integrated)  # node channels come first
    bridge_rows = {i: shared0 + j for j, i in enumerate(bridge_ch)}
    contact_rows = {i: shared0 + len(bridge_ch) + j for j, i in enumerate(contact_ch)}
    order: list[int] = []
    outs = [_Outputs(cm, r, overlap, order, bridge_rows, contact_rows) for r in runs]
    order += bridge_ch + contact_ch
    order += sorted(set(range(n_ch)) - set(order))  # moving loads and channels no input reaches: zero
    ext = np.argsort(np.array(order, dtype=np.int64))  # internal row of each channel
    shared_rows = slice(shared0, n_ch)  # summed over components: cleared at every output time
    Y = np.zeros((n_ch, m), dtype=complex)

    def record(i: int, first: bool) -> None:
        Y[shared_rows] = 0.0
        for run, out in zip(runs, outs):
            out.write(run, Y, ga, first)
        reducer.record(i, Y, ext)

    coef = ga.update_coefficients()
    h = ga.h
    x_ref, length = float(cp.axle_start[0]), cp.bridge.length

    taper_end = (x_ref + cp.taper_length - float(cp.positions(0.0).min())) / cp.speed
    ones, zeros = np.ones(cp.axle_start.size), np.zeros(cp.axle_start.size)

    def step_at(t: float) -> _Step:
        x = cp.positions(t)
        on = (x >= 0.0) & (x <= length)
        st = cp.contact_state(t) if on.any() else None  # off the bridge the rail shapes are zero
        if t >= taper_end:
            w, dw = ones, zeros
        else:
            w, dw = taper(x, x_ref, cp.taper_length)
        return _Step(t, cp.speed, x, on, None if st is None else st.S, None if st is None else st.dS,
                     w, dw, t >= taper_end, not (w.any() or dw.any()))

    step = step_at(0.0)
    shared = shared_inputs(source, step)
    for run in runs:
        run.start(step, shared, ga)
    record(0, True)
    for n in range(1, engine.n_steps + 1):
        step = step_at(n * h)
        shared = shared_inputs(source, step)
        rec = n % engine.ratio == 0
        for run in runs:
            run.solve(step, shared, rec)
        if rec:
            record(n // engine.ratio, False)
        for run in runs:
            run.update(coef, h)
    return reducer.result()


__all__ = ["BatchedEngine", "integrate"]
