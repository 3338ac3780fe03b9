"""The one driver: every method's run is :func:`drive` over a :class:`Method`.

The skeleton, once for PEM, Monte Carlo, the deterministic run and the speed sweep:

1. ``method.plan(execution)``: the checks (before any folder is touched), the analysis set-up, the
   checkpoint's fingerprint, the tasks, the memory sizing and the method's state (a dataclass);
2. ``execution.claim(plan.files)``: the output folder's lock and its earlier files;
3. the checkpoint (``plan.identity``; none for a run without one);
4. ``execution.run``: every task through :func:`worker_setup` / :func:`worker_task` in the workers
   (a :class:`~tb_exudyn.methods.common.MeanTask` is the engine's ``mean()``, any other task the
   method's ``work``), reduced in task order by ``method.reduce(state, i, task, result)``;
5. ``method.finish(state, stats)``: the provenance and the result;
6. ``method.save(result, out)`` into the claimed folder.

A method whose single task must run in this process (the deterministic run: one Exudyn run whose
result is not a set of arrays) says ``in_process`` in its plan. What each method supplies is in
docs/develop.md ("The driver").
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import partial
from pathlib import Path
from typing import Any, Callable, Protocol

from ..execution import Execution, RunFiles, Task
from ..execution.tasks import run_tasks
from .common import MeanTask


@dataclass
class RunPlan:
    """What a method's :meth:`Method.plan` hands the driver.

    files : the output files the run owns (:class:`~tb_exudyn.execution.RunFiles`)
    tasks : the tasks, in reduction order
    identity : the checkpoint's fingerprint (:func:`~tb_exudyn.methods.common.fingerprint_identity`;
        None: no checkpoint)
    state : the method's state, reduced into by :meth:`Method.reduce`
    desc : the progress bar's label
    worker : what the workers get (a :class:`Worker`: picklable; its ``repr`` keys their set-up cache)
    in_process : run the tasks in this process, without progress (the deterministic run)
    """

    files: RunFiles
    tasks: list[Task]
    identity: dict[str, Any] | None
    state: Any
    worker: "Worker"
    desc: str
    in_process: bool = False


class Method(Protocol):
    """A method the driver runs (PEM: :class:`~tb_exudyn.methods.pem.PemMethod`; Monte Carlo:
    :class:`~tb_exudyn.methods.monte_carlo.MonteCarloMethod`; the deterministic run and the speed
    sweep: :class:`~tb_exudyn.methods.deterministic.DeterministicMethod`,
    :class:`~tb_exudyn.methods.sweep.SweepMethod`). It runs in this process; its plan names the
    :class:`Worker` the workers get."""

    def plan(self, execution: Execution) -> RunPlan:
        """The checks, the set-up, the fingerprint, the tasks, the sizing, the state and the worker."""

    def reduce(self, state: Any, i: int, task: Task, result: Any) -> None:
        """In this process, in task order: task ``i``'s result into ``state``."""

    def finish(self, state: Any, stats: dict[str, Any]) -> Any:
        """The result from the reduced state and the run's statistics."""

    def save(self, result: Any, out: Path) -> None:
        """The result into the claimed output folder."""


class Worker(Protocol):
    """A method's part in the workers (sent to them: picklable, its ``repr`` keys their set-up cache)."""

    def setup(self) -> Any:
        """Once per worker: what its tasks run on (the engine; or a tuple whose first item is the
        engine, e.g. Monte Carlo's engine and sampler; or None for tasks without one)."""

    def work(self, built: Any, task: Task) -> Any:
        """One task that is not the mean: its column source and reducer, the integration."""


def worker_setup(worker: Worker) -> tuple[Worker, Any]:
    """A worker's set-up (cached per process by ``repr(worker)``): the worker and what it built."""
    return worker, worker.setup()


def worker_task(state: tuple[Worker, Any], task: Task) -> Any:
    """A worker's task: the mean task is the built engine's ``mean()`` (one home for every method that
    asks for a mean: :meth:`tb_exudyn.engines.base.Engine.mean`), any other task the worker's ``work``."""
    worker, built = state
    if isinstance(task.data, MeanTask):
        engine = built[0] if isinstance(built, tuple) else built
        return engine.mean()
    return worker.work(built, task)


def drive(method: Method, execution: Execution) -> Any:
    """Run ``method`` under ``execution`` (the module docstring's skeleton) and return its result."""
    plan = method.plan(execution)
    reduce: Callable[..., None] = partial(method.reduce, plan.state)
    with execution.claim(plan.files) as out:
        checkpoint = (execution.checkpoint(plan.files.checkpoint, plan.identity)  # type: ignore[arg-type]
                      if plan.identity is not None else None)
        if plan.in_process:
            stats = run_tasks(plan.tasks, setup=worker_setup, setup_args=(plan.worker,), work=worker_task, reduce=reduce,
                              workers=1, checkpoint=checkpoint, progress=False, desc=plan.desc)
        else:
            stats = execution.run(plan.tasks, setup=worker_setup, setup_args=(plan.worker,), work=worker_task,
                                  reduce=reduce, checkpoint=checkpoint, desc=plan.desc)
        result = method.finish(plan.state, stats)
        if out is not None:
            method.save(result, out)
    return result


__all__ = ["Method", "RunPlan", "Worker", "drive", "worker_setup", "worker_task"]
