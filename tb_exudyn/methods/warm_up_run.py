"""A warm-up process (:mod:`tb_exudyn.methods.warm_up`): ``python -m tb_exudyn.methods.warm_up_run
float64`` (or ``float32``) runs the tiny sweep's tasks of that precision and marks it compiled."""

from __future__ import annotations

import os
import sys
import warnings

from .. import jit
from ..execution import Execution
from ..scenario import load_scenario
from .common import MeanTask
from .driver import worker_setup, worker_task
from .pem.method import PemMethod
from .warm_up import PRECISIONS

#: the tiny sweep: the shipped scenario ``quick`` on a short, coarse grid
BASE, N_FREQ, LEAD_IN = "quick", 8, 10.0


def scenario():  # noqa: ANN201 - a Scenario
    """The tiny sweep's scenario (the module docstring)."""
    sc = load_scenario(BASE)
    return sc.replace(analysis=sc.analysis.replace(n_freq=N_FREQ, freq_spacing="linear"),
                      track=sc.track.replace(lead_in=LEAD_IN))


def tasks_of(precision: str) -> int:
    """Run the tiny sweep's tasks that take ``precision`` (the module docstring; float32: the grid
    error's columns, in BatchedOptions' default grid_error_precision); their number."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the tiny run's own advice (its short approach, its coarse grid)
        plan = PemMethod(scenario(), "batched").plan(Execution(workers=1, progress=False))
        state = worker_setup(plan.worker)
        n = 0
        for task in plan.tasks:
            midpoints = not isinstance(task.data, MeanTask) and task.data.midpoints
            if midpoints == (precision == "float32"):
                worker_task(state, task)
                n += 1
    return n


def main(argv: list[str]) -> int:
    if len(argv) != 1 or argv[0] not in PRECISIONS:
        print(f"usage: python -m {__name__} {{{','.join(PRECISIONS)}}}", file=sys.stderr)
        return 2
    os.environ[jit.WARMING_ENV] = "1"  # this process compiles: no waiting for, or starting of, another warm-up
    tasks_of(argv[0])
    jit.mark_warm(argv[0])
    return 0


__all__ = ["main", "scenario", "tasks_of"]


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
