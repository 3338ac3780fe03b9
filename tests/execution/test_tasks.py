"""The task runner shared by PEM and Monte Carlo: ordered reduction, checkpoints, resume.

Pure Python/numpy: the 'model' is a seeded random matrix and a task multiplies it with a vector, so
the exact expected reduction is computed here independently (a plain loop in task order). Results
must be bitwise equal, because the runner promises reduction in task order whatever order tasks
finish in (floating-point sums are order dependent, so any reordering would show).
"""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

from tb_exudyn.errors import CheckpointError
from tb_exudyn.execution import Checkpoint, Task, run_tasks


def setup_model(n: int, seed: int) -> np.ndarray:
    return np.random.default_rng(seed).standard_normal((n, n))


def work(model: np.ndarray, task: Task) -> dict[str, np.ndarray]:
    x = np.sin(np.arange(model.shape[0]) * (1.0 + task.data))
    return {"y": model @ x * 1e-3 ** task.data}


def _run(tmp_path=None, resume=False, executor=None, stop_after=None, n_tasks=40):
    tasks = [Task(f"t{i:03d}", i % 7) for i in range(n_tasks)]
    acc = {"sum": np.zeros(30), "order": []}

    def reduce(i, task, result):
        if stop_after is not None and len(acc["order"]) >= stop_after:
            raise KeyboardInterrupt
        acc["sum"] = acc["sum"] + result["y"]
        acc["order"].append(i)

    cp = Checkpoint(tmp_path, "fp1", resume) if tmp_path is not None else None
    stats = run_tasks(tasks, setup=setup_model, setup_args=(30, 5), work=work, reduce=reduce, workers=1,
                      executor=executor, checkpoint=cp, progress=False)
    return acc, stats


def _expected(n_tasks=40):
    model = setup_model(30, 5)
    total = np.zeros(30)
    for i in range(n_tasks):
        total = total + work(model, Task("x", i % 7))["y"]
    return total


def test_in_process_reduction_is_in_task_order():
    acc, stats = _run()
    assert acc["order"] == list(range(40))
    assert np.array_equal(acc["sum"], _expected())
    assert stats["tasks_run"] == 40


def test_executor_gives_the_same_bits():
    """Tasks finish out of order on a thread pool; the reduced sum must still be bitwise equal."""
    with ThreadPoolExecutor(max_workers=4) as ex:
        acc, stats = _run(executor=ex)
    assert acc["order"] == list(range(40))
    assert np.array_equal(acc["sum"], _expected())
    assert stats["executor"] == "ThreadPoolExecutor"


def test_interrupted_then_resumed_equals_uninterrupted(tmp_path):
    """Stop after 13 tasks (KeyboardInterrupt, as Ctrl-C); the 13 finished tasks are on disk (at least
    those reduced); the resumed run reads them back and runs only the rest; the result is bitwise equal."""
    with pytest.raises(KeyboardInterrupt):
        _run(tmp_path, stop_after=13)
    on_disk = len(list((tmp_path / "tasks").glob("*.npz")))
    assert 13 <= on_disk < 40
    acc, stats = _run(tmp_path, resume=True)
    assert stats["tasks_from_checkpoint"] == on_disk and stats["tasks_run"] == 40 - on_disk
    assert np.array_equal(acc["sum"], _expected())
    assert not list(tmp_path.glob("tasks/.*.tmp")), "no temporary files left behind"


def test_resume_refuses_another_computation(tmp_path):
    Checkpoint(tmp_path, "fp1", resume=False)
    with pytest.raises(CheckpointError, match="another computation"):
        Checkpoint(tmp_path, "fp2", resume=True)


def test_fresh_run_clears_old_task_files(tmp_path):
    _run(tmp_path)
    acc, stats = _run(tmp_path, resume=False)
    assert stats["tasks_run"] == 40 and stats["tasks_from_checkpoint"] == 0


def test_bad_task_keys_are_refused():
    with pytest.raises(ValueError, match="file-name safe"):
        run_tasks([Task("a/b", 0)], setup=setup_model, setup_args=(2, 1), work=work,
                  reduce=lambda *a: None, workers=1, progress=False)


class _BreaksAfter(ThreadPoolExecutor):
    """A thread pool that behaves like a process pool whose worker was killed after ``n`` submits:
    submit raises BrokenProcessPool from then on (as ProcessPoolExecutor.submit does once a worker
    has died, even before any result says so)."""

    def __init__(self, n: int) -> None:
        super().__init__(max_workers=2)
        self.left = n

    def submit(self, *args, **kwargs):
        from concurrent.futures.process import BrokenProcessPool

        if self.left == 0:
            raise BrokenProcessPool("A child process terminated abruptly")
        self.left -= 1
        return super().submit(*args, **kwargs)


@pytest.mark.parametrize("n", [0, 5])
def test_a_pool_broken_at_submit_is_the_one_line_resource_error(tmp_path, n):
    """The pool breaks between two results (seen first by submit, not by a result): the run ends
    with the same ResourceError as a broken result, and the tasks finished before are on disk."""
    from tb_exudyn.errors import ResourceError

    with _BreaksAfter(n) as ex, pytest.raises(ResourceError, match="a worker process ended abruptly"):
        _run(tmp_path, executor=ex, n_tasks=80)
    assert len(list(tmp_path.glob("t*.npz"))) <= n
