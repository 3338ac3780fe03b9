"""How a computation runs: tasks on an executor, checkpoints, thread limits.

:class:`Execution` is the one object that says how (workers or an executor, the output folder,
resume, progress); it changes no number: a result is bitwise the same for any number of workers, any
executor and after a resume.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Mapping, Sequence

import numpy as np

from ..errors import SettingError
from ..results.storage import check_writable
from .checkpoint import Checkpoint, fingerprint
from .tasks import Task, run_tasks
from .threads import single_threaded_blas, single_threaded_workers


@dataclass(frozen=True)
class Execution:
    """How tasks run.

    Attributes
    ----------
    workers : processes of the local pool (None: all cores; 1: in this process)
    executor : any ``concurrent.futures.Executor`` to use instead (e.g. a Dask client's executor)
    out : the output folder (checkpoints and results go below it), or None: nothing written
    resume : reuse the finished tasks of a checkpoint in ``out``
    progress : show a progress bar with the time left
    slices : relative sizes of the tasks an engine that integrates many columns at once gets (None:
        one per core and a half one); a result depends on them only at round-off, and not on
        ``workers`` or ``executor``; give more for an executor with more workers
    where : what the settings came from, for messages (a function name, or "command line")
    """

    workers: int | None = None
    executor: Any = None
    out: str | Path | None = None
    resume: bool = False
    progress: bool = True
    slices: Sequence[float] | None = None
    where: str = "Execution"

    def __post_init__(self) -> None:
        w = self.workers
        if w is not None and (isinstance(w, bool) or not isinstance(w, int) or w < 1):
            raise SettingError(self.where, "workers", w, "a whole number >= 1, or None for all cores")
        if self.slices is not None and (len(self.slices) == 0 or not all(
                isinstance(x, (int, float)) and np.isfinite(x) and x > 0 for x in self.slices)):
            raise SettingError(self.where, "slices", self.slices, "positive relative sizes, e.g. (1, 1, 0.5)")
        if self.resume and self.out is None:
            raise SettingError(self.where, "resume", True, "resume only together with an output folder",
                               "nothing to resume from")

    @property
    def cores(self) -> int:
        """The cores of this machine."""
        return os.cpu_count() or 1

    def output_folder(self) -> Path | None:
        """The output folder, created and checked writable (None without one)."""
        return None if self.out is None else check_writable(self.out)

    def checkpoint(self, name: str, identity: Mapping[str, Any]) -> Checkpoint | None:
        """The checkpoint ``out/name`` of the computation ``identity`` (None without an output folder)."""
        out = self.output_folder()
        return None if out is None else Checkpoint(out / name, fingerprint(identity), self.resume)

    def run(self, tasks: Sequence[Task], *, setup: Callable[..., Any], setup_args: tuple,
            work: Callable[[Any, Task], dict], reduce: Callable[[int, Task, dict], None],
            checkpoint: Checkpoint | None, desc: str) -> dict[str, Any]:
        """Run the tasks (see :func:`.tasks.run_tasks`) and return the run statistics."""
        return run_tasks(tasks, setup=setup, setup_args=setup_args, work=work, reduce=reduce, workers=self.workers,
                         executor=self.executor, checkpoint=checkpoint, progress=self.progress, desc=desc)


__all__ = ["Checkpoint", "Execution", "Task", "fingerprint", "run_tasks", "single_threaded_blas",
           "single_threaded_workers"]
