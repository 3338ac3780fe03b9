"""Independent tasks on an executor, with checkpoints, resume, ordered reduction and progress.

PEM frequencies and Monte Carlo samples are independent tasks. A worker builds the model once (the
``setup`` function, cached per process and per setup key) and then runs many tasks on it. Results
are reduced in task order whatever order they finish in, so a result never depends on the number
of workers or on a resume. With a checkpoint folder every finished task is written atomically as
it arrives; ``resume=True`` reads those back instead of running them again (each file checked first,
see :mod:`.checkpoint`; read when its turn to be reduced comes, so they are never all in memory), so
an interrupted sweep loses at most the tasks in flight.

Executors: ``workers=1`` runs in this process; ``workers=N`` a local process pool (spawned
processes, numpy/BLAS threads set to 1); any ``concurrent.futures.Executor`` may be passed instead
(e.g. a Dask distributed client's ``get_executor()``).

The pool's workers (:func:`worker_start`) ignore Ctrl-C (the main process handles it: it stops them
and re-raises, so one line is printed, not one traceback per worker; SIGINT is blocked while they are
spawned, so that one arriving during their start-up is dropped too) and end when the main process
ends, however it ends (Linux: ``prctl(PR_SET_PDEATHSIG, SIGKILL)``; elsewhere a thread that watches
the parent). A worker that dies (killed, out of memory) ends the run with a
:class:`~tb_exudyn.errors.ResourceError`; a user error raised in a worker reaches the caller as the
same exception (every error type is picklable).
"""

from __future__ import annotations

import ctypes
import ctypes.util
import multiprocessing
import os
import re
import signal
import sys
import threading
import time
from concurrent.futures import FIRST_COMPLETED, Executor, Future, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool
from contextlib import contextmanager, nullcontext
from dataclasses import dataclass
from typing import Any, Callable, Iterator, Sequence

import numpy as np
from tqdm.auto import tqdm

from ..errors import ResourceError
from .checkpoint import Checkpoint, fingerprint
from .threads import single_threaded_workers

_KEY = re.compile(r"^[A-Za-z0-9_.-]+$")
#: Linux prctl option: the signal a process gets when its parent (thread) ends
PR_SET_PDEATHSIG = 1


@dataclass(frozen=True)
class Task:
    """One unit of work: a file-name-safe unique key and plain (picklable) data, whose ``repr`` says
    everything the task computes (it is hashed into the task's checkpoint file)."""

    key: str
    data: Any


# ------------------------------------------------------------------------------------- worker side
_LOCAL = threading.local()  # per thread: executors with several threads per process stay safe


def _execute(setup: Callable[..., Any], setup_args: tuple, setup_key: str, work: Callable, task: Task):
    """Runs in a worker: build (once per thread and setup key) then do one task."""
    cache = getattr(_LOCAL, "cache", None)
    if cache is None or cache[0] != setup_key:
        _LOCAL.cache = None  # the old model goes before the new one is built
        _LOCAL.cache = cache = (setup_key, setup(*setup_args))  # one model per thread at a time
    return work(cache[1], task)


def _watch_parent(parent: int) -> None:
    while True:
        if os.getppid() != parent:
            os._exit(1)
        time.sleep(0.5)


def worker_start(parent: int) -> None:
    """A pool worker's initializer: ignore Ctrl-C (the main process handles it) and end when the main
    process ``parent`` ends (see the module docstring)."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    if hasattr(signal, "pthread_sigmask"):
        signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT})  # blocked while spawned: now ignored
    armed = False
    if sys.platform.startswith("linux"):
        try:
            libc = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6", use_errno=True)
            armed = libc.prctl(PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0) == 0
        except (OSError, AttributeError):
            armed = False
    if os.getppid() != parent:  # the parent ended before the signal was armed
        os._exit(1)
    if not armed:
        threading.Thread(target=_watch_parent, args=(parent,), daemon=True, name="tb_exudyn-parent-watch").start()


@contextmanager
def _sigint_blocked() -> Iterator[None]:
    """SIGINT blocked in this thread within the block (worker processes spawned in it inherit the mask;
    a Ctrl-C meanwhile is delivered when the block ends)."""
    if not hasattr(signal, "pthread_sigmask") or threading.current_thread() is not threading.main_thread():
        yield
        return
    old = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, old)


def _stop_pool(pool: ProcessPoolExecutor) -> None:
    """End a local pool now: cancel what waits, terminate the workers (their tasks are lost: not
    finished, so not in the checkpoint), kill any that outlives SIGTERM by 5 s, and wait for the pool's
    manager thread, which the interpreter joins at exit without a timeout. A worker terminated while it
    sends a result leaves that thread reading a message that never ends (the parent holds the result
    pipe's other end open, so no end-of-file comes): closing the parent's end ends the read (issue 49: a
    Ctrl-C'd 2-worker run printed its line and then did not exit, sometimes)."""
    processes = list((getattr(pool, "_processes", None) or {}).values())
    manager = getattr(pool, "_executor_manager_thread", None)
    writer = getattr(getattr(pool, "_result_queue", None), "_writer", None)  # shutdown forgets the queue
    pool.shutdown(wait=False, cancel_futures=True)
    for p in processes:
        try:
            p.terminate()
        except (OSError, AttributeError):
            pass
    for p in processes:
        try:
            p.join(timeout=5)
            if p.is_alive():
                p.kill()
                p.join(timeout=5)
        except (OSError, AttributeError, AssertionError, ValueError):
            pass
    if manager is not None and manager.is_alive() and writer is not None:
        manager.join(timeout=1)
        if manager.is_alive():  # reading: the workers are gone, so the parent's end is the last writer
            try:
                writer.close()
            except OSError:
                pass
            manager.join(timeout=10)


# ------------------------------------------------------------------------------------- helpers
class _Progress:
    """The progress bar with an estimate of the time left that does not count what happens before the
    tasks run at their pace: none until two tasks of this run have finished, then the tasks left at
    the rate between the first finished one and the last (a first run's compile, the workers' start
    and the model's set-up fall before the first; the bar's elapsed time still counts from the start)."""

    def __init__(self, total: int, initial: int, desc: str) -> None:
        # disable=None: no bar when stderr is not a terminal (a log file would get every redraw)
        self.bar = tqdm(total=total, initial=initial, desc=desc, unit="task", dynamic_ncols=True, disable=None,
                        bar_format="{l_bar}{bar}| {n_fmt}/{total_fmt} [{elapsed}{postfix}]",
                        postfix="time left: after the first tasks")
        self.first: tuple[float, int] | None = None

    def update(self, n: int = 1) -> None:
        now = time.monotonic()
        self.bar.update(n)
        done, total = self.bar.n, self.bar.total
        if self.first is None:
            self.first = (now, done)
        elif done > self.first[1] and done < total:
            rate = (now - self.first[0]) / (done - self.first[1])  # seconds per task at the run's pace
            self.bar.set_postfix_str(f"about {tqdm.format_interval(rate * (total - done))} left")

    def close(self) -> None:
        self.bar.close()


def _progress(total: int, initial: int, desc: str, enabled: bool) -> _Progress | None:
    return _Progress(total, initial, desc) if enabled else None


class _Stored:
    """A task result that waits in its checkpoint file until its turn to be reduced."""


_STORED = _Stored()


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
    ``workers``: processes of a local pool (None: one per core; 1: in this process), used as given
    (:func:`tb_exudyn.execution.resources.cap_workers` caps them).

    Returns run statistics: tasks run, tasks read from the checkpoint, workers, executor kind.
    """
    keys = [t.key for t in tasks]
    if len(set(keys)) != len(keys) or not all(_KEY.match(k) for k in keys):
        raise ValueError("task keys must be unique and file-name safe")
    setup_key = fingerprint({"setup": f"{setup.__module__}.{setup.__qualname__}", "args": repr(setup_args)})
    n = len(tasks)
    results: dict[int, Any] = {}
    next_reduce = 0

    def deliver(i: int, result: Any) -> None:
        nonlocal next_reduce
        results[i] = result
        while next_reduce in results:
            arrays = results.pop(next_reduce)
            if arrays is _STORED:
                arrays = checkpoint.load(tasks[next_reduce])  # type: ignore[union-attr]
            reduce(next_reduce, tasks[next_reduce], arrays)
            next_reduce += 1

    usable = checkpoint.verify(tasks) if checkpoint is not None else [False] * n
    todo = [i for i in range(n) if not usable[i]]
    from_checkpoint = n - len(todo)
    bar = _progress(n, from_checkpoint, desc, progress)

    def finished(i: int, result: dict[str, np.ndarray]) -> None:
        if checkpoint is not None:
            checkpoint.save(tasks[i], result)
        deliver(i, result)
        if bar is not None:
            bar.update(1)

    n_workers = workers or os.cpu_count() or 1
    kind = "in-process"
    try:
        if executor is None and n_workers == 1:
            for i in range(n):
                if usable[i]:
                    deliver(i, _STORED)
                else:
                    finished(i, _execute(setup, setup_args, setup_key, work, tasks[i]))
        else:
            for i in range(n):  # markers: each file is read when its turn comes
                if usable[i]:
                    deliver(i, _STORED)
            if todo and executor is None:
                kind = f"process pool ({n_workers} workers)"
                with single_threaded_workers():
                    pool = ProcessPoolExecutor(max_workers=n_workers, mp_context=multiprocessing.get_context("spawn"),
                                               initializer=worker_start, initargs=(os.getpid(),))
                    _drain(pool, todo, tasks, setup, setup_args, setup_key, work, finished, own=True)
            elif todo:
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
        try:
            while queue or pending:
                with _sigint_blocked() if own else nullcontext():  # a local pool spawns its workers in submit
                    while queue and len(pending) < window:
                        i = queue.pop(0)
                        pending[pool.submit(_execute, setup, setup_args, setup_key, work, tasks[i])] = i
                done, _ = wait(pending, return_when=FIRST_COMPLETED)
                for fut in sorted(done, key=lambda f: pending[f]):
                    i = pending.pop(fut)
                    finished(i, fut.result())
        except BrokenProcessPool:  # seen by a result or, when the pool broke between two results, by submit
            raise ResourceError(
                "a worker process ended abruptly: killed, out of memory (resume with fewer workers) or not "
                "started (a script starts them under 'if __name__ == \"__main__\":')") from None
    except BaseException:
        for fut in pending:
            fut.cancel()
        if own:
            _stop_pool(pool)  # type: ignore[arg-type]
        raise
    if own:
        pool.shutdown(wait=True)


__all__ = ["Task", "run_tasks", "worker_start"]
