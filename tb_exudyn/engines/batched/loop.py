"""The step loop of the batched engine: the columns of a source integrated over the crossing."""

from __future__ import annotations

from typing import Any

import numpy as np

from ... import jit
from ...system.columns import HarmonicColumns, ProfileColumns, StaticLoadColumns
from .inputs import shared_inputs
from .kernels import PRECISIONS
from .outputs import _Outputs
from .run import _Operators, _Run
from .steps import BLOCK_STEPS, step_block

#: bytes of a column chunk's state (q~, v~, a~, Delta): about a core's L2 cache (2 MB here); measured
#: on the reference study (600 columns): 1.25 MB 8.6 s, 2.5 MB 8.2 s, 5 MB 9.0 s, no chunks 9.6 s
CHUNK_BYTES = 2_500_000
#: fewest complex columns of a chunk (below, the per-step calls cost more than the cache saves)
MIN_CHUNK = 64


def chunks(cols: np.ndarray, n: int, itemsize: int) -> list[np.ndarray]:
    """The columns of a component with n coordinates cut into chunks whose state (q~, v~, a~, Delta:
    4 n x 2 columns of ``itemsize`` bytes) stays within CHUNK_BYTES, each at least MIN_CHUNK wide:
    a chunk is integrated over a block of steps while its state stays in the core's cache."""
    width = max(MIN_CHUNK, int(CHUNK_BYTES // (8 * n * itemsize)))
    k = max(1, -(-cols.size // width))
    return [c for c in np.array_split(cols, k) if c.size]


def integrate(engine: Any, source: Any, reducer: Any, precision: str | None = None, lin: Any = None,
              components: Any = None, step: str = "compiled") -> dict[str, np.ndarray]:
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
    the reducer in time order once every chunk has passed them. ``step``: "compiled" (the runs of
    harmonic columns and of the gravity column by :mod:`.compiled`, the others by numpy calls) or
    "numpy" (every run by numpy calls, :meth:`.run._Run.solve` and :meth:`.run._Run.update`).
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
    rail_ch = [i for i, _, _ in cm.rail]
    integrated = {int(g) for r in runs for g in r.comp.coords}
    shared0 = sum(1 for _, g, _ in cm.node if g in integrated)  # node channels come first
    bridge_rows = {i: shared0 + j for j, i in enumerate(bridge_ch)}
    contact_rows = {i: shared0 + len(bridge_ch) + j for j, i in enumerate(contact_ch)}
    rail_rows = {i: shared0 + len(bridge_ch) + len(contact_ch) + j for j, i in enumerate(rail_ch)}
    order: list[int] = []
    outs: list[_Outputs] = []
    first_of: dict[Any, _Outputs] = {}
    for r in runs:  # the chunks of a component share its rows of node channels
        outs.append(_Outputs(cm, r, overlap, order, bridge_rows, contact_rows, first_of.get(r.ops), rail_rows, cp))
        first_of.setdefault(r.ops, outs[-1])
    order += bridge_ch + contact_ch + rail_ch
    order += sorted(set(range(n_ch)) - set(order))  # moving loads and channels no input reaches: zero
    ext = np.argsort(np.array(order, dtype=np.int64))  # internal row of each channel
    shared_rows = slice(shared0, n_ch)  # summed over components: cleared at every output time
    pool = [np.zeros((n_ch, m), dtype=complex) for _ in range(-(-BLOCK_STEPS // engine.ratio) + 1)]

    cdtype = PRECISIONS[precision][1]
    harmonic = isinstance(source, HarmonicColumns)

    def shared(block: Any) -> Any:
        """Every step's shared inputs of the block: exp(i Omega v t) of the harmonic columns (one
        call for the block: (T, m)), the profiles at the axles (None where every input is zero)."""
        if harmonic:
            return shared_inputs(source, block.t, False, block.x, cp.speed, cdtype)
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
    # Numba is loaded only for runs the compiled step takes (not a coupled bridge block: run.compile)
    if step == "compiled" and (harmonic or isinstance(source, StaticLoadColumns)) and any(not r.ops.coupled for r in runs):
        module = jit.load("tb_exudyn.engines.batched.compiled")
        for run in runs:
            run.compile(module, coef, h)
    shapes = {key: fn for o in operators if o.nb for key, fn in o.rail_shapes(cp.bridge).items()}
    block = step_block(cp, 0, 1, h, shapes)
    Y = pool[0]
    sh0 = shared(block)[0]
    for run, out in zip(runs, outs):
        run.start(block, sh0, ga)
        out.write(run, Y, ga, True, _rails(block, run, 0))
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
            if run.kernel is not None:
                run.run_block(block, sh, buffers, out, ga)
                continue
            for k in range(block.size):
                rec = k in buffers
                run.solve(k, block, sh[k], rec)
                if rec:
                    out.write(run, buffers[k], ga, False, _rails(block, run, k))
                run.update(coef, h)
        for k in records:
            reducer.record((n + k) // engine.ratio, buffers[k], ext)
        n += block.size
    return reducer.result()


def _rails(block: Any, run: Any, k: int) -> Any:
    """The rail shapes at the axles at step k of ``block`` in ``run``'s modes (None: no axle on the body)."""
    rails = block.rails.get(run.ops.shape_key) if run.ops.nb else None
    return None if rails is None else rails[k]


__all__ = ["CHUNK_BYTES", "MIN_CHUNK", "chunks", "integrate"]
