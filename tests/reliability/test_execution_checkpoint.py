"""Checkpoints that prove what they hold (issue 15): every damaged or foreign task file is found on
resume, never used, its task computed again with a one-line notice naming it, and later resumes
are not blocked.

Problem: the task runner's own test model (tests/execution/test_tasks.py): 40 tasks, each a seeded
30 x 30 random matrix times a vector, reduced by summation in task order. The reference is the sum
computed in a plain loop, independently of the runner; because the runner reduces in task order, a
resumed run must equal it bitwise (tolerance zero), whichever files were damaged.
"""

from __future__ import annotations

import json
import os
import warnings
import zipfile
from pathlib import Path

import numpy as np
import pytest

from tb_exudyn.errors import CheckpointError
from tb_exudyn.execution import Checkpoint, RunNotice, Task, run_tasks
from tb_exudyn.execution.checkpoint import META, TASK_FORMAT

from ..execution.test_tasks import _expected, setup_model, work

N = 40
TASKS = [Task(f"t{i:03d}", i % 7) for i in range(N)]
VICTIM = TASKS[17]


def run(folder: Path, resume: bool, fingerprint: str = "fp1", tasks=TASKS, on_reduce=None):
    """The 40 tasks with a checkpoint in ``folder``: (sum, stats, notices)."""
    acc = {"sum": np.zeros(30)}

    def reduce(i, task, result):
        if on_reduce is not None:
            on_reduce(i)
        acc["sum"] = acc["sum"] + result["y"]

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        cp = Checkpoint(folder, fingerprint, resume)
        stats = run_tasks(tasks, setup=setup_model, setup_args=(30, 5), work=work, reduce=reduce, workers=1,
                          checkpoint=cp, progress=False)
    notices = [str(w.message) for w in caught if issubclass(w.category, RunNotice)]
    return acc["sum"], stats, notices


@pytest.fixture
def done(tmp_path):
    """A finished checkpoint of the 40 tasks."""
    total, stats, _ = run(tmp_path, resume=False)
    assert stats["tasks_run"] == N and np.array_equal(total, _expected())
    return tmp_path


def path_of(folder: Path, task: Task = VICTIM) -> Path:
    return folder / "tasks" / f"{task.key}.npz"


def member_data_offset(path: Path, name: str) -> int:
    """Where the bytes of member ``name`` start in the zip file."""
    with zipfile.ZipFile(path) as zf:
        info = zf.getinfo(name)
    with open(path, "rb") as fh:
        fh.seek(info.header_offset + 26)
        n_name, n_extra = np.frombuffer(fh.read(4), dtype="<u2")
    return info.header_offset + 30 + int(n_name) + int(n_extra)


def rewrite_zip(path: Path, change) -> None:
    """Rewrite a task file with ``change(name, data) -> data`` applied to its members."""
    with zipfile.ZipFile(path) as zf:
        members = [(i.filename, zf.read(i)) for i in zf.infolist()]
    with zipfile.ZipFile(path, "w", compression=zipfile.ZIP_STORED) as zf:
        for name, data in members:
            zf.writestr(name, change(name, data))


def truncate(folder):
    p = path_of(folder)
    p.write_bytes(p.read_bytes()[: p.stat().st_size // 2])


def empty(folder):
    path_of(folder).write_bytes(b"")


def flip_data(folder):
    """A bit flip in the array's data (the zip's CRC is rewritten to match: only our checksum sees it)."""
    def change(name, data):
        if name != "y.npy":
            return data
        b = bytearray(data)
        b[-5] ^= 0x10
        return bytes(b)
    rewrite_zip(path_of(folder), change)


def flip_in_place(folder):
    """Flipped bytes in the file itself (the zip's own CRC no longer matches)."""
    p = path_of(folder)
    data = bytearray(p.read_bytes())
    at = member_data_offset(p, "y.npy") + 140
    data[at:at + 4] = bytes(x ^ 0xFF for x in data[at:at + 4])
    p.write_bytes(bytes(data))


def header_shape(folder):
    """The npy header claims another shape (same length, so the file size is unchanged)."""
    rewrite_zip(path_of(folder), lambda name, data: data.replace(b"(30,)", b"(31,)") if name == "y.npy" else data)


def garbage_description(folder):
    rewrite_zip(path_of(folder), lambda name, data: b"\x00{garbage\xff" if name == META else data)


def other_fingerprint(folder):
    """A valid file of another computation under this task's name."""
    other = Checkpoint(folder.parent / "other", "fp-other", resume=False)
    other.save(VICTIM, {"y": np.full(30, 7.0)})
    os.replace(other.path(VICTIM.key), path_of(folder))


def other_key(folder):
    os.replace(path_of(folder, TASKS[3]), path_of(folder))
    Checkpoint(folder, "fp1", resume=True).save(TASKS[3], work(setup_model(30, 5), TASKS[3]))


def other_task_data(folder):
    """A valid file of this computation and key, written for other task data."""
    Checkpoint(folder, "fp1", resume=True).save(Task(VICTIM.key, 99), {"y": np.full(30, 7.0)})


def rescaled_plain_npz(folder):
    """The arrays rescaled and saved with plain np.savez (as a user might): no description."""
    p = path_of(folder)
    with zipfile.ZipFile(p) as zf, zf.open("y.npy") as fh:
        y = np.lib.format.read_array(fh)
    with open(p, "wb") as fh:
        np.savez(fh, y=2 * y)


def symlink_to_dev_zero(folder):
    p = path_of(folder)
    p.unlink()
    p.symlink_to("/dev/zero")


def fifo(folder):
    p = path_of(folder)
    p.unlink()
    os.mkfifo(p)


def directory(folder):
    p = path_of(folder)
    p.unlink()
    p.mkdir()
    (p / "x").write_text("x")


DAMAGES = [truncate, empty, flip_data, flip_in_place, header_shape, garbage_description, other_fingerprint,
           other_key, other_task_data, rescaled_plain_npz, symlink_to_dev_zero, fifo, directory]


@pytest.mark.parametrize("damage", DAMAGES, ids=[d.__name__ for d in DAMAGES])
def test_a_damaged_or_foreign_task_file_is_computed_again_with_a_notice(done, damage):
    damage(done)
    total, stats, notices = run(done, resume=True)
    assert np.array_equal(total, _expected()), "a damaged file was used"
    assert stats["tasks_run"] == 1 and stats["tasks_from_checkpoint"] == N - 1
    assert notices and all(str(path_of(done)) in n and "\n" not in n for n in notices), notices
    # the next resume is not blocked, and uses the recomputed file (a folder in the file's place is
    # not tb_exudyn's to delete: its task is computed again each time, with the notices)
    again, stats2, notices2 = run(done, resume=True)
    assert np.array_equal(again, _expected())
    if damage is directory:
        assert stats2["tasks_run"] == 1 and len(notices2) == 2
    else:
        assert len(notices) == 1 and stats2["tasks_run"] == 0 and not notices2


def test_a_garbage_manifest_is_replaced_and_every_task_file_still_used(done):
    (done / "manifest.json").write_bytes(b"\xff\xfe{{ not json")
    total, stats, notices = run(done, resume=True)
    assert np.array_equal(total, _expected()) and stats["tasks_run"] == 0
    assert len(notices) == 1 and "manifest.json" in notices[0] and "damaged" in notices[0]
    assert json.loads((done / "manifest.json").read_text())["fingerprint"] == "fp1"


def test_another_computations_files_without_manifest_are_all_recomputed(done):
    """Every file belongs to another computation and the manifest is gone: every task computed again;
    five notices name files, one more line counts the rest."""
    other = done.parent / "other"
    run(other, resume=False, fingerprint="fp-other")
    for f in (other / "tasks").glob("*.npz"):
        os.replace(f, done / "tasks" / f.name)
    (done / "manifest.json").unlink()
    total, stats, notices = run(done, resume=True)
    assert np.array_equal(total, _expected()) and stats["tasks_run"] == N
    assert len(notices) == 6 and all("another computation" in n for n in notices[:5]) and "35 more" in notices[5]


def test_resume_of_another_computation_is_refused_naming_the_folder_and_the_remedy(done):
    with pytest.raises(CheckpointError) as info:
        Checkpoint(done, "fp2", resume=True, remedy="use --overwrite to replace it")
    assert str(done) in str(info.value) and "--overwrite" in str(info.value)


def test_a_file_changed_between_its_check_and_its_use_is_refused_by_name(done):
    """Task 0's reduction damages task 39's file (already checked): reading it for its reduction finds
    the change and refuses with the file's name; the next resume computes that task again."""
    victim = path_of(done, TASKS[39])
    with pytest.raises(CheckpointError, match=str(victim)):
        run(done, resume=True, on_reduce=lambda i: i == 0 and flip_data_at(victim))
    total, stats, _ = run(done, resume=True)
    assert np.array_equal(total, _expected()) and stats["tasks_run"] == 1


def flip_data_at(path: Path) -> None:
    def change(name, data):
        return data[:-1] + bytes([data[-1] ^ 1]) if name == "y.npy" else data
    rewrite_zip(path, change)


def test_leftovers_of_killed_writes_are_removed(done):
    leftover = done / "tasks" / ".t005.npz.abc123.tmp"
    leftover.write_bytes(b"half a file")
    run(done, resume=True)
    assert not leftover.exists()


def test_a_task_file_carries_fingerprint_key_task_shapes_and_checksums(done):
    """The description member: format, fingerprint, key, task digest, and per array dtype, shape,
    byte count and SHA-256 (no pickle anywhere: every member is an npy array or JSON)."""
    with zipfile.ZipFile(path_of(done)) as zf:
        assert sorted(zf.namelist()) == sorted([META, "y.npy"])
        head = json.loads(zf.read(META))
        y = zf.read("y.npy")
    assert head["format"] == TASK_FORMAT and head["fingerprint"] == "fp1" and head["key"] == VICTIM.key
    import hashlib

    spec = head["arrays"]["y"]
    assert spec["shape"] == [30] and spec["dtype"] == "<f8" and spec["bytes"] == len(y)
    assert spec["sha256"] == hashlib.sha256(y).hexdigest()
