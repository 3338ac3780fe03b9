"""Independent tasks on an executor, with checkpoints, resume, ordered reduction and progress.

PEM frequencies and Monte Carlo samples are independent tasks. A worker builds the model once (the
``setup`` function, cached per process and per setup key) and then runs many tasks on it. Results
are reduced in task order whatever order they finish in, so a result never depends on the number
of workers or on a resume. With a checkpoint folder every finished task is written atomically as
it arrives; ``resume=True`` reads those back instead of running them again, so an interrupted sweep
loses at most the tasks in flight.

Executors: ``workers=1`` runs in this process; ``workers=N`` a local process pool (spawned
processes, numpy/BLAS threads set to 1); any ``concurrent.futures.Executor`` may be passed instead
(e.g. a Dask distributed client's ``get_executor()``).
"""

from __future__ import annotations

import multiprocessing
import os
import re
import threading
from concurrent.futures import FIRST_COMPLETED, Executor, Future, ProcessPoolExecutor, wait
from dataclasses import dataclass
from typing import Any, Callable, Sequence

import numpy as np
from tqdm.auto import tqdm

from .checkpoint import Checkpoint, fingerprint
from .threads import single_threaded_workers

_KEY = re.compile(r"^[A-Za-z0-9_.-]+$")


@dataclass(frozen=True)
class Task:
    """One unit of work: a file-name-safe unique key and plain (picklable) data."""

    key: str
    data: Any




# ------------------------------------------------------------------------------------- worker side
_LOCAL = threading.local()  # per thread: executors with several threads per process stay safe


def _execute(setup: Callable[..., Any], setup_args: tuple, setup_key: str, work: Callable, task: Task):
    """Runs in a worker: build (once per thread and setup key) then do one task."""
    cache = getattr(_LOCAL, "cache", None)
    if cache is None or cache[0] != setup_key:
        _LOCAL.cache = cache = (setup_key, setup(*setup_args))  # one model per thread at a time
    return work(cache[1], task)


# ------------------------------------------------------------------------------------- helpers
def _progress(total: int, initial: int, desc: str, enabled: bool):
    if not enabled:
        return None
    return tqdm(total=total, initial=initial, desc=desc, unit="task", dynamic_ncols=True)


# ------------------------------------------------------------------------------------- driver
def run_tasks(
    tasks: Sequence[Task],
    *,
    setup: Callable[..., Any],
    setup_args: tuple,
    work: Callable[[Any, Task], dict[str, np.ndarray]],
    reduce: Callable[[int, Task, dict[str, np.ndarray]], None],
    workers: int | None = None,
    executor: Executor | None = None,
    checkpoint: Checkpoint | None = None,
    progress: bool = True,
    desc: str = "tasks",
) -> dict[str, Any]:
    """Run ``work(setup(*setup_args), task)`` for every task and call ``reduce(i, task, result)`` in
    task order. ``setup`` and ``work`` must be module-level functions (they are sent to workers).

    Returns run statistics: tasks run, tasks read from the checkpoint, workers, executor kind.
    """
    keys = [t.key for t in tasks]
    if len(set(keys)) != len(keys) or not all(_KEY.match(k) for k in keys):
        raise ValueError("task keys must be unique and file-name safe")
    setup_key = fingerprint({"setup": f"{setup.__module__}.{setup.__qualname__}", "args": repr(setup_args)})
    n = len(tasks)
    results: dict[int, dict[str, np.ndarray]] = {}
    next_reduce = 0

    def deliver(i: int, result: dict[str, np.ndarray]) -> None:
        nonlocal next_reduce
        results[i] = result
        while next_reduce in results:
            reduce(next_reduce, tasks[next_reduce], results.pop(next_reduce))
            next_reduce += 1

    todo = []
    from_checkpoint = 0
    for i, task in enumerate(tasks):
        if checkpoint is not None and checkpoint.done(task.key):
            deliver(i, checkpoint.load(task.key))
            from_checkpoint += 1
        else:
            todo.append(i)

    bar = _progress(n, from_checkpoint, desc, progress)

    def finished(i: int, result: dict[str, np.ndarray]) -> None:
        if checkpoint is not None:
            checkpoint.save(tasks[i].key, result)
        deliver(i, result)
        if bar is not None:
            bar.update(1)

    n_workers = 1 if executor is None and (workers or os.cpu_count() or 1) <= 1 else workers
    kind = "in-process"
    try:
        if executor is None and n_workers == 1:
            for i in todo:
                finished(i, _execute(setup, setup_args, setup_key, work, tasks[i]))
        else:
            own = executor is None
            if own:
                kind = f"process pool ({n_workers or os.cpu_count()} workers)"
                with single_threaded_workers():
                    pool: Executor = ProcessPoolExecutor(
                        max_workers=n_workers or os.cpu_count(), mp_context=multiprocessing.get_context("spawn")
                    )
                    _drain(pool, todo, tasks, setup, setup_args, setup_key, work, finished, own=True)
            else:
                kind = type(executor).__name__
                _drain(executor, todo, tasks, setup, setup_args, setup_key, work, finished, own=False)
    finally:
        if bar is not None:
            bar.close()
    if next_reduce != n:  # pragma: no cover - a bug, not a user error
        raise RuntimeError(f"only {next_reduce} of {n} task results were reduced")
    return {"tasks": n, "tasks_run": len(todo), "tasks_from_checkpoint": from_checkpoint, "executor": kind}


def _drain(pool: Executor, todo, tasks, setup, setup_args, setup_key, work, finished, own: bool) -> None:
    """Submit a bounded window of tasks and hand results over as they complete."""
    # a bounded window keeps finished-but-unreduced results few; executors that do not say how many
    # workers they have (Dask's) get a window wide enough for a cluster
    workers = getattr(pool, "_max_workers", None)
    window = 4 * workers if workers else 256
    pending: dict[Future, int] = {}
    queue = list(todo)
    try:
        while queue or pending:
            while queue and len(pending) < window:
                i = queue.pop(0)
                pending[pool.submit(_execute, setup, setup_args, setup_key, work, tasks[i])] = i
            done, _ = wait(pending, return_when=FIRST_COMPLETED)
            for fut in sorted(done, key=lambda f: pending[f]):
                i = pending.pop(fut)
                finished(i, fut.result())
    except BaseException:
        for fut in pending:
            fut.cancel()
        if own:
            pool.shutdown(wait=False, cancel_futures=True)
        raise
    if own:
        pool.shutdown(wait=True)
