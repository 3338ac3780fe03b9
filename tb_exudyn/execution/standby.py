"""A process pool started ahead of its work: its processes start and import what they will need while
the caller computes something else, and take the work when it comes.

``tb-exudyn run`` starts its figure process(es) this way before the analysis (their imports,
matplotlib and the plotting code, about 1.5 CPU-s, fall in the analysis' single-process set-up) and
gives them a result's figures as soon as the result is saved (issue 49). The processes are the
analysis pool's kind (:func:`~tb_exudyn.execution.tasks.worker_start`): spawned, one BLAS thread,
Ctrl-C ignored (the main process handles it), ended with the main process however it ends.
"""

from __future__ import annotations

import importlib
import multiprocessing
import os
from concurrent.futures import ProcessPoolExecutor
from contextlib import contextmanager
from typing import Iterator, Sequence

from .tasks import _sigint_blocked, _stop_pool, worker_start
from .threads import single_threaded_workers


def _standby_start(parent: int, modules: tuple[str, ...]) -> None:
    worker_start(parent)
    for name in modules:
        importlib.import_module(name)


def _ready() -> int:
    return os.getpid()


@contextmanager
def standby_pool(workers: int, modules: Sequence[str], started: int | None = None,
                 ) -> Iterator[ProcessPoolExecutor | None]:
    """A pool of ``workers`` spawned processes, each importing ``modules`` (names) as it starts;
    ``started`` of them (default all) start now, the others when work comes and none is idle (so that
    a machine of many cores does not hold many idle processes, about 100 MB each, while the caller
    computes); None when ``workers`` < 1. On leaving the block the pool ends: after its work when the
    block ended normally, at once (what waits cancelled, the processes terminated) on an exception
    or Ctrl-C."""
    if workers < 1:
        yield None
        return
    with _sigint_blocked(), single_threaded_workers():
        pool = ProcessPoolExecutor(max_workers=workers, mp_context=multiprocessing.get_context("spawn"),
                                   initializer=_standby_start, initargs=(os.getpid(), tuple(modules)))
        for _ in range(workers if started is None else min(started, workers)):
            pool.submit(_ready)  # a process is started per task submitted while none is idle
    try:
        yield pool
    except BaseException:
        _stop_pool(pool)
        raise
    pool.shutdown(wait=True)


__all__ = ["standby_pool"]
