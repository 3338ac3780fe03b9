"""One run per output folder at a time, and no run over another run's files unless told to
overwrite (issues 15 and 17).

Problem: the tiny sprung-mass scenario of execution_helpers (batched engine, 4 tasks). The
reference for "the new complete result" is the same scenario run alone into a fresh folder (runs
are deterministic: bitwise equal).
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import textwrap
import threading

import numpy as np
import pytest

from tb_exudyn.errors import OutputFolderError
from tb_exudyn.execution import folder_lock
from tb_exudyn.execution.output import RunFiles, prepare_folder

from .execution_helpers import assert_one_line_error, cli, env, run_args, snapshot, std_of, write_scenario

pytestmark = pytest.mark.exudyn


@pytest.fixture(scope="module")
def scenarios(tmp_path_factory):
    base = tmp_path_factory.mktemp("scenarios")
    return write_scenario(base / "tiny.toml"), write_scenario(base / "other.toml", name="other", speed=250.0)


@pytest.fixture(scope="module")
def reference(scenarios, tmp_path_factory):
    """sigma of each scenario run alone into a fresh folder."""
    out = {}
    for sc in scenarios:
        folder = tmp_path_factory.mktemp("ref") / "out"
        assert cli(*run_args(sc, folder)).returncode == 0
        out[sc.stem] = std_of(folder / "pem")
    return out


# ------------------------------------------------------------------------------------- the lock
HOLD = textwrap.dedent("""
    import sys
    from tb_exudyn.execution import folder_lock
    with folder_lock(sys.argv[1], "holder"):
        print("locked", flush=True)
        sys.stdin.read()  # held until the test ends it (an event: a delay could run out under load)
""")


def hold_lock(folder):
    proc = subprocess.Popen([sys.executable, "-c", HOLD, str(folder)], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                            text=True, env=env())
    assert proc.stdout.readline().strip() == "locked"
    return proc


def test_a_run_into_a_folder_in_use_is_refused_naming_the_folder_and_the_other_run(scenarios, tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    holder = hold_lock(out)
    try:
        before = snapshot(out)
        proc = cli(*run_args(scenarios[0], out))
        line = assert_one_line_error(proc, str(out), "in use by another run", f"pid {holder.pid}", "--out")
        assert "command line" in line
        assert snapshot(out) == before, "the refused run changed the folder"
    finally:
        holder.kill()
        holder.wait()


def test_a_killed_runs_lock_does_not_block_the_next_run(scenarios, tmp_path, reference):
    """SIGKILL leaves the lock file; the kernel has released the lock with the process."""
    out = tmp_path / "out"
    out.mkdir()
    holder = hold_lock(out)
    os.kill(holder.pid, signal.SIGKILL)
    holder.wait()
    assert (out / ".tb_exudyn.lock").exists()
    proc = cli(*run_args(scenarios[0], out))
    assert proc.returncode == 0, proc.stderr
    assert np.array_equal(std_of(out / "pem"), reference["tiny"])
    assert not (out / ".tb_exudyn.lock").exists(), "the lock file is removed when its run ends"


def test_the_lock_is_reentrant_for_its_thread_and_refuses_another(tmp_path):
    seen = []
    with folder_lock(tmp_path, "test"):
        with folder_lock(tmp_path, "test"):  # the command line's lock, then the method's
            pass

        def other():
            try:
                with folder_lock(tmp_path, "test"):
                    seen.append("entered")
            except OutputFolderError as exc:
                seen.append(str(exc))

        t = threading.Thread(target=other)
        t.start()
        t.join()
    assert len(seen) == 1 and "in use by another run of this process" in seen[0]
    with folder_lock(tmp_path, "test"):  # free again
        pass


# ------------------------------------------------------------------------------------- another run's files
def test_a_second_run_into_a_used_folder_is_refused_and_changes_nothing(scenarios, tmp_path):
    """A finished run (its checkpoint removed after the save) and a second one into its folder: one
    line naming the folder, the result and --overwrite; nothing changed. With the checkpoint kept
    (--keep-checkpoint) the line offers --resume too."""
    out = tmp_path / "out"
    assert cli(*run_args(scenarios[0], out)).returncode == 0
    assert not (out / "checkpoint").exists()
    before = snapshot(out)
    proc = cli(*run_args(scenarios[1], out))
    line = assert_one_line_error(proc, str(out), "the result pem/", "--overwrite")
    assert "--resume" not in line
    assert snapshot(out) == before
    kept = tmp_path / "kept"
    assert cli(*run_args(scenarios[0], kept, "--keep-checkpoint")).returncode == 0
    before = snapshot(kept)
    proc = cli(*run_args(scenarios[1], kept))
    assert_one_line_error(proc, str(kept), "the result pem/", "--overwrite", "--resume")
    assert snapshot(kept) == before


def test_a_killed_runs_checkpoint_is_not_deleted_by_a_run_without_resume(scenarios, tmp_path):
    """Before: a run without --resume deleted the finished tasks of an interrupted sweep (data lost)."""
    out = tmp_path / "out"
    assert cli(*run_args(scenarios[0], out, "--keep-checkpoint")).returncode == 0
    os.unlink(out / "pem" / "meta.json")  # as if the sweep had been killed before its result was saved
    os.unlink(out / "pem" / "arrays.npz")
    os.rmdir(out / "pem")
    before = snapshot(out)
    proc = cli(*run_args(scenarios[0], out))
    assert_one_line_error(proc, str(out), "checkpoint/ (", " finished tasks)", "--resume", "--overwrite")
    assert snapshot(out) == before


def test_overwrite_replaces_the_old_run_and_only_it(scenarios, tmp_path, reference):
    """--overwrite: the new result, the old run's figures and the folder's report gone, the other
    method's result and a user's file kept."""
    out = tmp_path / "out"
    assert cli(*run_args(scenarios[1], out)).returncode == 0
    (out / "pem" / "figures").mkdir()
    (out / "pem" / "figures" / "old.png").write_bytes(b"png")
    (out / "figures").mkdir()
    (out / "figures" / "car1.body.acc_z.pem_vs_mc.png").write_bytes(b"png")
    (out / "report.html").write_text("<html>old</html>")
    (out / "mc").mkdir()
    (out / "mc" / "meta.json").write_text("{}")
    (out / "notes.txt").write_text("mine")
    proc = cli(*run_args(scenarios[0], out, "--overwrite"))
    assert proc.returncode == 0, proc.stderr
    assert np.array_equal(std_of(out / "pem"), reference["tiny"])
    assert not (out / "pem" / "figures").exists() and not (out / "report.html").exists()
    assert not list((out / "figures").iterdir())
    assert (out / "mc" / "meta.json").read_text() == "{}" and (out / "notes.txt").read_text() == "mine"


def test_resume_and_overwrite_together_are_refused(scenarios, tmp_path):
    proc = cli(*run_args(scenarios[0], tmp_path / "out", "--resume", "--overwrite"))
    assert_one_line_error(proc, "command line", "--overwrite", "--resume")


def test_resume_of_a_folder_with_a_result_and_no_checkpoint_is_refused(tmp_path):
    (tmp_path / "pem").mkdir()
    (tmp_path / "pem" / "meta.json").write_text("{}")
    before = snapshot(tmp_path)
    with pytest.raises(OutputFolderError, match="no checkpoint to resume from.*overwrite=True"):
        prepare_folder(tmp_path, RunFiles("pem", "checkpoint"), resume=True, overwrite=False, where="run_pem")
    assert snapshot(tmp_path) == before


def test_methods_of_one_folder_share_it(tmp_path):
    """PEM and Monte Carlo side by side (tb-exudyn compare DIR DIR): a Monte Carlo run into a folder
    holding only a PEM run's files is not refused, and overwriting it leaves the PEM files."""
    (tmp_path / "pem").mkdir()
    (tmp_path / "pem" / "meta.json").write_text("{}")
    (tmp_path / "checkpoint" / "tasks").mkdir(parents=True)
    (tmp_path / "checkpoint" / "tasks" / "pem-mean.npz").write_bytes(b"x")
    before = snapshot(tmp_path)
    prepare_folder(tmp_path, RunFiles("mc", "checkpoint-mc"), resume=False, overwrite=False, where="run_monte_carlo")
    prepare_folder(tmp_path, RunFiles("mc", "checkpoint-mc"), resume=False, overwrite=True, where="run_monte_carlo")
    assert snapshot(tmp_path) == before


def test_nothing_is_written_outside_the_output_folder(scenarios, tmp_path):
    """A run, a refused run and an overwriting run, from another working folder: every new entry is
    inside --out (the scenario's folder and the working folder unchanged)."""
    work = tmp_path / "cwd"
    work.mkdir()
    out = tmp_path / "out"
    before = snapshot(tmp_path)
    for extra in ((), (), ("--overwrite",)):
        cli(*run_args(scenarios[0], out, *extra), cwd=work)
    after = snapshot(tmp_path)
    new = {k for k in after if k not in before or after[k] != before[k]}
    assert new and all(k == "out" or k.startswith("out/") for k in new), sorted(new)
