"""The batched engine: every column of a task in one time integration of the linear model.

The train-bridge model is linear and every column shares its time-varying matrices; only the input
differs. So all columns of a task (PEM: one complex column per irregularity type and frequency, the
real part the cosine run and the imaginary part the sine run; Monte Carlo: two real samples per
complex column) are integrated together, with exactly Exudyn's generalized-alpha step
(:mod:`tb_exudyn.engines.alpha`), on the very model the Exudyn runs use: M, K0, D0 from Exudyn's
``ComputeLinearizedSystem`` and the rows of the ``WheelRailCoupling`` (penalty rows and general
linear rows, :class:`~tb_exudyn.system.coupling.RowMaps`). The model being linear, each step is
solved exactly (Exudyn to its Newton tolerance). Initial accelerations from M qdd0 = f(q0, v0, 0)
and a0 = qdd0 (Exudyn's computeInitialAccelerations); the step h = end_time / n_steps and the
output grid are the Exudyn engine's (:func:`~tb_exudyn.system.conventions.run_steps`).

What makes it fast:

- the contact forces by Woodbury over the contact rows of the vehicles with an axle on the bridge;
  vehicles off the bridge advance by a constant folded operator (:mod:`.run`);
- the time-only data of a step (axle positions, taper, rail shapes) and the bridge parts of the
  per-step operators computed for blocks of steps at once (:mod:`.steps`, :meth:`.run._Run.prepare`);
- independent components (e.g. the vertical in-plane and lateral out-of-plane motion of a symmetric
  car on a symmetric track) each integrate only the columns that excite them, and coordinates no
  input reaches are not integrated at all (:mod:`tb_exudyn.system.components`);
- complex columns computed on their real view, in-place BLAS (:mod:`.kernels`), in float64 or, as an
  option, float32 (about twice the speed; see :class:`BatchedOptions` for its error);
- single-threaded BLAS, one process per core, each owning large slices of the columns (tasks);
- outputs reduced at every output step by the method's reducer, never stored as histories, and only
  for the selected channels.

Options (:class:`BatchedOptions`): the precision, and where the mean comes from (Exudyn's
deterministic run, or the same linear model with the gravity load as one more column:
:mod:`.mean`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from ...builder import linear_system
from ...errors import SettingError
from ...execution.threads import single_threaded_blas
from ...system.columns import HarmonicColumns, ProfileColumns
from ...system.components import find_components
from ...system.conventions import scenario_steps
from ..alpha import GeneralizedAlpha
from ..base import Engine, on_linear_system
from .inputs import shared_inputs
from .kernels import PRECISIONS
from .outputs import _Outputs
from .run import _Operators, _Run
from .steps import BLOCK_STEPS, mode_shapes, step_block

#: where a linear engine's mean comes from
MEANS: tuple[str, ...] = ("exudyn", "linear")
#: bytes of a column chunk's state (q~, v~, a~, Delta): about a core's L2 cache (2 MB here); measured
#: on the reference study (600 columns): 1.25 MB 8.6 s, 2.5 MB 8.2 s, 5 MB 9.0 s, no chunks 9.6 s
CHUNK_BYTES = 2_500_000
#: fewest complex columns of a chunk (below, the per-step calls cost more than the cache saves)
MIN_CHUNK = 64


@dataclass(frozen=True)
class BatchedOptions:
    """Options of the batched engine.

    Attributes
    ----------
    precision : "float64" (default: the reference) or "float32" (state and products in single
        precision: 10-20 % faster on the reference study; its sigma within 1e-5 of each channel's
        largest sigma, the PSD map within 2e-3 of its largest value; accelerations of stiff parts
        driven far below their frequency carry about 6e-8 (f_n / f)^2 relative error:
        docs/speed.md, tests/engines/test_batched_kernels.py)
    mean : "linear" (default: the model linearised about the static state under the dead loads,
        the gravity load integrated like one more column, :mod:`.mean`: no Exudyn run; on the
        reference study within 1.1e-3 of each channel's largest |mean| and 3e-5 of its largest
        sigma of Exudyn's run, what remains being the finite rotations, docs/speed.md) or "exudyn"
        (Exudyn's deterministic run: a full-model run that no other core can share, 3-8 s of the
        reference study)
    """

    precision: str = "float64"
    mean: str = "linear"

    def __post_init__(self) -> None:
        if self.precision not in PRECISIONS:
            raise SettingError("BatchedOptions", "precision", self.precision, " or ".join(map(repr, PRECISIONS)))
        if self.mean not in MEANS:
            raise SettingError("BatchedOptions", "mean", self.mean, " or ".join(map(repr, MEANS)))


class BatchedEngine(Engine):
    """The linear model's columns integrated together (options: :class:`BatchedOptions`)."""

    name = "batched"
    full_model = False

    def __init__(self, scenario: Any, options: Any = None, wheel_forces: bool = False) -> None:
        with single_threaded_blas():
            super().__init__(scenario, options, wheel_forces)
            self.options = _options(options)
            self.lin = linear_system(self.model, scenario.analysis.linearization)
            steps = scenario_steps(scenario)
            self.n_steps, self.ratio = steps.n_steps, steps.ratio
            self.alpha = GeneralizedAlpha(float(scenario.analysis.spectral_radius), steps.h)
            self.output_time = steps.output_times
            self.components = find_components(self.lin, self.output_time)

    @classmethod
    def on_system(cls, lin: Any, steps: Any, spectral_radius: float, outputs: Any, options: Any = None) -> "BatchedEngine":
        """The engine on a linear system built by hand (:func:`~tb_exudyn.engines.base.on_linear_system`)."""
        engine = on_linear_system(cls, lin, steps, spectral_radius, outputs, _options(options))
        engine.components = find_components(lin, engine.output_time)
        return engine

    @classmethod
    def check(cls, scenario: Any, options: Any = None, others: str = "") -> None:
        super().check(scenario, options, others)
        _options(options)

    @classmethod
    def default_options(cls) -> BatchedOptions:
        return BatchedOptions()

    @classmethod
    def describe_options(cls, options: Any) -> dict[str, Any]:
        opts = _options(options)
        return {"precision": opts.precision, "mean": opts.mean}

    @property
    def precision(self) -> str:
        return self.options.precision

    def describe(self) -> dict[str, Any]:
        ga = self.alpha
        return {
            "engine": self.name,
            "linearization": self.lin.linearization,
            "precision": self.precision,
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

    def mean(self) -> dict[str, np.ndarray]:
        if self.options.mean == "linear":
            from .mean import linear_mean

            with single_threaded_blas():
                return linear_mean(self)
        return super().mean()


def _options(options: Any) -> BatchedOptions:
    if options is None:
        return BatchedOptions()
    if not isinstance(options, BatchedOptions):
        raise SettingError("engine options", "options", type(options).__name__,
                           "a BatchedOptions (tb_exudyn.engines.batched.BatchedOptions) or None")
    return options


def chunks(cols: np.ndarray, n: int, itemsize: int) -> list[np.ndarray]:
    """The columns of a component with n coordinates cut into chunks whose state (q~, v~, a~, Delta:
    4 n x 2 columns of ``itemsize`` bytes) stays within CHUNK_BYTES, each at least MIN_CHUNK wide:
    a chunk is integrated over a block of steps while its state stays in the core's cache."""
    width = max(MIN_CHUNK, int(CHUNK_BYTES // (8 * n * itemsize)))
    k = max(1, -(-cols.size // width))
    return [c for c in np.array_split(cols, k) if c.size]


def integrate(engine: Any, source: Any, reducer: Any, precision: str | None = None, lin: Any = None,
              components: Any = None) -> dict[str, np.ndarray]:
    """Integrate the columns of ``source`` over the crossing, handing the outputs of every output
    time to ``reducer.record(i, Y, ext)``; returns ``reducer.result()``.

    ``engine`` gives the linear system (``lin``), the step (``alpha``, ``n_steps``, ``ratio``), the
    outputs (``outputs``) and the components; ``source`` is a column source
    (:mod:`tb_exudyn.system.columns`): ``width`` (number of complex columns) and
    ``columns_for(kinds)`` (the columns a component excited by those kinds integrates); its per-step
    inputs come from :mod:`.inputs`. ``lin`` and ``components`` replace the engine's linear system
    and its components (the linear mean's static linearization). The steps go in blocks (:mod:`.steps`): per block the
    components' per-step operators are prepared, then each chunk of columns (:func:`chunks`) runs
    through the block's steps; the outputs of the block's output times are buffered and handed to
    the reducer in time order once every chunk has passed them.
    """
    ga, cm = engine.alpha, engine.outputs
    lin = engine.lin if lin is None else lin
    precision = precision or engine.precision
    cp = lin.coupling
    n_rows = cp.n_contacts + cp.n_linear
    n_ch, m = len(cm.names), source.width
    runs: list[_Run] = []
    for comp in (engine.components if components is None else components):
        cols = source.columns_for(comp.kinds)
        if cols.size:
            ops = _Operators(lin, ga, comp, precision)
            runs += [_Run(ops, c, source, cp) for c in chunks(cols, comp.size, np.dtype(ops.dtype).itemsize)]
    operators = list(dict.fromkeys(run.ops for run in runs))
    overlap = np.zeros((n_rows, m), dtype=np.int64)  # components integrating (contact row, column)
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
    outs: list[_Outputs] = []
    first_of: dict[Any, _Outputs] = {}
    for r in runs:  # the chunks of a component share its rows of node channels
        outs.append(_Outputs(cm, r, overlap, order, bridge_rows, contact_rows, first_of.get(r.ops)))
        first_of.setdefault(r.ops, outs[-1])
    order += bridge_ch + contact_ch
    order += sorted(set(range(n_ch)) - set(order))  # moving loads and channels no input reaches: zero
    ext = np.argsort(np.array(order, dtype=np.int64))  # internal row of each channel
    shared_rows = slice(shared0, n_ch)  # summed over components: cleared at every output time
    pool = [np.zeros((n_ch, m), dtype=complex) for _ in range(-(-BLOCK_STEPS // engine.ratio) + 1)]

    cdtype = PRECISIONS[precision][1]
    harmonic = isinstance(source, HarmonicColumns)

    def shared(block: Any) -> list[Any]:
        """Every step's shared inputs of the block: exp(i Omega v t) of the harmonic columns (one
        call for the block), the profiles at the axles (None where every input is zero)."""
        if harmonic:
            return list(shared_inputs(source, block.t, False, block.x, cp.speed, cdtype))
        if not isinstance(source, ProfileColumns):
            return [None] * block.size
        live = np.flatnonzero(~block.zero)
        out: list[Any] = [None] * block.size
        if live.size:
            value, slope = source.at(block.x[live].reshape(-1))
            n_a = block.x.shape[1]
            for i, k in enumerate(live):
                out[k] = (value[i * n_a:(i + 1) * n_a], slope[i * n_a:(i + 1) * n_a])
        return out

    coef = ga.update_coefficients()
    h = ga.h
    shapes = {o.shape_key: mode_shapes(cp.bridge, o.modes) for o in operators if o.nb}
    block = step_block(cp, 0, 1, h, shapes)
    Y = pool[0]
    sh0 = shared(block)[0]
    for run, out in zip(runs, outs):
        run.start(block, sh0, ga)
        out.write(run, Y, ga, True)
    reducer.record(0, Y, ext)
    n = 1
    while n <= engine.n_steps:
        block = step_block(cp, n, min(n + BLOCK_STEPS, engine.n_steps + 1), h, shapes)
        for ops in operators:
            ops.prepare(block)
        sh = shared(block)
        records = [k for k in range(block.size) if (n + k) % engine.ratio == 0]
        buffers = dict(zip(records, pool))
        for Yb in buffers.values():
            Yb[shared_rows] = 0.0
        for run, out in zip(runs, outs):
            for k in range(block.size):
                rec = k in buffers
                run.solve(k, block, sh[k], rec)
                if rec:
                    out.write(run, buffers[k], ga, False)
                run.update(coef, h)
        for k in records:
            reducer.record((n + k) // engine.ratio, buffers[k], ext)
        n += block.size
    return reducer.result()


__all__ = ["BatchedEngine", "BatchedOptions", "CHUNK_BYTES", "MEANS", "MIN_CHUNK", "chunks", "integrate"]
