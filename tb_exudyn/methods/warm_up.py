"""The compiled code of a first run, compiled before the run needs it (:func:`tb_exudyn.jit.warm_up`).

A run that finds the compiled code's cache cold (:func:`tb_exudyn.jit.is_warm`) starts
:mod:`.warm_up_run` in two background processes, ``python -m tb_exudyn.methods.warm_up_run float64``
and ``... float32``, while it sets the run up. Each runs the tasks of a tiny PEM sweep that need its
precision, on the very code path of a real run (:class:`~tb_exudyn.methods.pem.method.PemWorker`):
float64 the mean task (the linear mean's gravity column) and the grid's column tasks (the harmonic
step, the reducer's kernels with the PSD maps and the local grid-error estimate's node sums), float32
the grid error's midpoint tasks (``BatchedOptions.grid_error_precision``). Numba compiles every
function for the argument types it is called with, and these are the types of any model's run (the
arrays' dtypes, dimensions and layouts do not depend on the model's size), so the run's workers then
load everything from the cache. The two precisions compile in parallel on two cores, beside the
run's own set-up, instead of one after the other inside every worker (each worker compiled both: the
float64 code when its first task started, the float32 code at its first midpoint task).

The tiny sweep: the shipped scenario ``quick`` (one ICE motor car over a 32 m span, the three
irregularity types, channels of every kind: the bridge's, the body's with EN 12299's weighted
accelerations and Sperling, the axle's forces and their ratios) on 8 linear frequencies (coarse
enough that the local estimate refines some cells) with a 10 m approach. It runs in about two seconds
once compiled.
"""

from __future__ import annotations

from typing import Any

from .. import jit

#: the module a warm-up process runs (``python -m RUNNER precision``)
RUNNER = "tb_exudyn.methods.warm_up_run"
PRECISIONS = ("float64", "float32")


def start(cls: Any, options: Any, announce: Any = None, harmonic: bool = True) -> bool:
    """Before a run on engine class ``cls`` with ``options``: the code it compiles
    (``cls.compiled_precisions``), compiled in the background if the cache is cold
    (:func:`tb_exudyn.jit.warm_up`, ``announce`` told one line). Whether it started."""
    precisions = cls.compiled_precisions(options, harmonic) if hasattr(cls, "compiled_precisions") else ()
    if not precisions:
        return False
    return jit.warm_up(RUNNER, tuple(p for p in precisions if p in PRECISIONS), announce)


__all__ = ["PRECISIONS", "RUNNER", "start"]
