"""How a computation runs: tasks on an executor, checkpoints, the output folder, limits, threads.

:class:`Execution` is the one object that says how (workers or an executor, the output folder,
resume or overwrite, a memory limit, progress); it changes no number: a result is bitwise the same for
any number of workers, any executor and after a resume.

A method runs as ``with execution.claim(RunFiles("pem", "checkpoint")) as out:`` (the output folder
locked for this run, another run's files refused or, with ``overwrite``, cleared: :mod:`.output`,
:mod:`.lock`), then ``execution.checkpoint(...)`` and ``execution.run(...)``.
"""

from __future__ import annotations

import os
import sys
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Iterator, Mapping, Sequence

import numpy as np

from ..errors import SettingError
from ..storage import check_writable
from .checkpoint import Checkpoint, fingerprint
from .lock import folder_lock
from .notices import RunNotice, notice
from .output import RunFiles, prepare_folder, remove_entry
from .resources import MemoryLimit, cap_workers, memory_limit, parse_memory
from .tasks import Task, run_tasks
from .threads import single_threaded_blas, single_threaded_workers


@dataclass(frozen=True)
class Execution:
    """How tasks run.

    Attributes
    ----------
    workers : processes of the local pool (None: all cores; 1: in this process); at most one per
        core (more are capped, with a notice)
    executor : any ``concurrent.futures.Executor`` to use instead (e.g. a Dask client's executor)
    out : the output folder (checkpoints and results go below it), or None: nothing written
    resume : reuse the finished tasks of a checkpoint in ``out``
    overwrite : replace another run's result and checkpoint in ``out`` (without it, and without
        ``resume``, a run into a folder holding them is refused: :mod:`.output`)
    max_memory : the memory a run may use [bytes, or a text such as "4GB"] (None: what this machine
        has available); a run estimated above it is refused before it starts
    progress : show a progress bar with the time left
    slices : relative sizes of the tasks an engine that integrates many columns at once gets (None:
        one per core and a half one); a result depends on them only at round-off, and not on
        ``workers`` or ``executor``; give more for an executor with more workers
    where : what the settings came from, for messages (the caller's name; errors name the fields as
        their keys: ``workers``, ``out``, ``overwrite`` ...)
    keep_checkpoint : keep the checkpoint after the result is saved (default: removed then: the result
        holds everything, and the finished tasks of a large sweep take as much room as its PSD maps)
    """

    workers: int | None = None
    executor: Any = None
    out: str | Path | None = None
    resume: bool = False
    progress: bool = True
    slices: Sequence[float] | None = None
    where: str = "Execution"
    overwrite: bool = False
    max_memory: int | str | None = None
    keep_checkpoint: bool = False

    def __post_init__(self) -> None:
        w = self.workers
        if w is not None and (isinstance(w, bool) or not isinstance(w, int) or w < 1):
            raise SettingError(self.where, "workers", w, "a whole number >= 1, or None for all cores")
        if self.slices is not None and (len(self.slices) == 0 or not all(
                isinstance(x, (int, float)) and np.isfinite(x) and x > 0 for x in self.slices)):
            raise SettingError(self.where, "slices", self.slices, "positive relative sizes, e.g. (1, 1, 0.5)")
        if self.out is not None and not str(self.out).strip():
            raise SettingError(self.where, "out", self.out, "a folder path", "empty")
        if self.resume and self.out is None:
            raise SettingError(self.where, "resume", True, "resume only together with an output folder",
                               "nothing to resume from")
        if self.resume and self.overwrite:
            raise SettingError(self.where, "overwrite", True, "either resume=True or overwrite=True",
                               "resume continues a run, overwrite replaces it")
        if self.overwrite and self.out is None:
            raise SettingError(self.where, "overwrite", True, "overwrite only together with an output folder")
        object.__setattr__(self, "max_memory", parse_memory(self.max_memory, self.where, "max_memory"))
        if self.executor is None:
            object.__setattr__(self, "_pool_workers", cap_workers(self.workers, self.cores, self.where))

    @property
    def cores(self) -> int:
        """The cores of this machine."""
        return os.cpu_count() or 1

    @property
    def pool_workers(self) -> int:
        """Worker processes of the local pool (1: in this process), capped at the cores."""
        return getattr(self, "_pool_workers", None) or cap_workers(self.workers, self.cores, self.where)

    def memory_limit(self) -> MemoryLimit:
        """What a run may use: ``max_memory``, else the memory available now."""
        return memory_limit(self.max_memory, self.where)  # type: ignore[arg-type]

    def worker_limit(self) -> MemoryLimit | None:
        """The limit a run's estimate is checked against where its tasks are set up: ``max_memory``,
        else the memory available now on this machine (in-process and a local pool), else None: an
        executor's workers (another machine, perhaps) measure their own."""
        if self.executor is not None and self.max_memory is None:
            return None
        return self.memory_limit()

    def output_folder(self) -> Path | None:
        """The output folder, created and checked writable (None without one)."""
        return None if self.out is None else check_writable(self.out)

    @contextmanager
    def claim(self, files: RunFiles) -> Iterator[Path | None]:
        """The output folder for a run writing ``files``, locked within the block; another run's files
        refused or (``overwrite``) cleared first (:func:`.output.prepare_folder`). None without one.
        When the block ends without an error (the result saved), the run's checkpoint is removed unless
        ``keep_checkpoint``."""
        out = self.output_folder()
        if out is None:
            yield None
            return
        remedy = "wait for it to end, or use another out folder"
        with folder_lock(out, self.where, remedy):
            prepare_folder(out, files, resume=self.resume, overwrite=self.overwrite, where=self.where)
            yield out
            if files.checkpoint is not None and not self.keep_checkpoint:
                remove_entry(out / files.checkpoint)

    def checkpoint(self, name: str, identity: Mapping[str, Any]) -> Checkpoint | None:
        """The checkpoint ``out/name`` of the computation ``identity`` (None without an output folder)."""
        out = self.output_folder()
        if out is None:
            return None
        remedy = "use overwrite=True to replace it, another out folder, or the computation it holds"
        return Checkpoint(out / name, fingerprint(identity), self.resume, remedy)

    def run(self, tasks: Sequence[Task], *, setup: Callable[..., Any], setup_args: tuple,
            work: Callable[[Any, Task], dict], reduce: Callable[[int, Task, dict], None],
            checkpoint: Checkpoint | None, desc: str) -> dict[str, Any]:
        """Run the tasks (see :func:`.tasks.run_tasks`) and return the run statistics."""
        workers = None if self.executor is not None else self.pool_workers
        return run_tasks(tasks, setup=setup, setup_args=setup_args, work=work, reduce=reduce, workers=workers,
                         executor=self.executor, checkpoint=checkpoint, progress=self.progress, desc=desc)

    def announce(self, text: str) -> None:
        """Say one line about what the run does now (on stderr, with ``progress``: the compile of a
        first run, :func:`tb_exudyn.jit.warm_up`)."""
        if self.progress:
            print(f"tb-exudyn: {text}", file=sys.stderr, flush=True)

    def worker_processes(self, n_tasks: int) -> int:
        """Worker processes a run of ``n_tasks`` starts (0: the tasks run in this process)."""
        if self.executor is not None:
            return max(1, getattr(self.executor, "_max_workers", 1) or 1)
        w = min(self.pool_workers, max(1, n_tasks))
        return 0 if w == 1 else w


__all__ = ["Checkpoint", "Execution", "RunFiles", "RunNotice", "Task", "fingerprint", "folder_lock", "notice",
           "run_tasks", "single_threaded_blas", "single_threaded_workers"]
