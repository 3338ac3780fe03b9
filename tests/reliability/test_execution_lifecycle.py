"""A clean process lifecycle (issue 15): Ctrl-C prints one line and exits 130; the workers end when
the main process dies; an error raised in a worker reaches the command as the same one-line
message and exit status as with one worker.

Problem: the SLOW scenario of execution_helpers with 64 frequencies on the Exudyn engine with 2
workers (65 tasks of about 0.2 s: some 6 s of work left after the second task on a quiet machine, 30
times the poll interval of wait_for, so the sweep is still running when the test acts, however loaded
the machine), interrupted once some tasks are finished. The bounds on how long processes may take to
end are 30 s: they only tell a process that ends from one that never does. Linux only (/proc,
process groups).
"""

from __future__ import annotations

import os
import signal
import sys

import pytest

from .execution_helpers import (alive, assert_one_line_error, cli, descendants, error_lines, finished_tasks,
                                run_args, slow_scenario, start_cli, wait_for, write_scenario)

pytestmark = [pytest.mark.exudyn, pytest.mark.skipif(not sys.platform.startswith("linux"), reason="Linux /proc")]


def started_sweep(tmp_path, new_session=False, tasks=2):
    """A 2-worker sweep running with ``tasks`` tasks finished (0: its workers just spawned, still
    starting up): (process, its output folder, its children)."""
    out = tmp_path / "out"
    proc = start_cli(*run_args(slow_scenario(tmp_path / "slow.toml", n_freq=64), out, engine="exudyn", workers=2),
                     new_session=new_session)
    if tasks:
        assert wait_for(lambda: finished_tasks(out) >= tasks or proc.poll() is not None), "the sweep did not start"
    else:
        assert wait_for(lambda: len(descendants(proc.pid)) >= 2 or proc.poll() is not None), "no workers started"
    assert proc.poll() is None, proc.communicate()[1][-2000:]
    kids = descendants(proc.pid)
    assert len(kids) >= 2, "no worker processes"
    return proc, out, kids


@pytest.mark.parametrize("tasks", [0, 2], ids=["workers_starting", "sweep_running"])
def test_ctrl_c_prints_one_line_and_exits_130_without_worker_tracebacks(tmp_path, tasks):
    """SIGINT to the whole process group, as a terminal's Ctrl-C sends it (the workers get it too),
    while the workers start (importing: before, each printed its KeyboardInterrupt traceback) and
    while they run tasks."""
    proc, out, kids = started_sweep(tmp_path, new_session=True, tasks=tasks)
    os.killpg(proc.pid, signal.SIGINT)
    _, err = proc.communicate(timeout=300)
    assert proc.returncode == 130 and "Traceback" not in err, err[-2000:]
    assert error_lines(err) == ["tb-exudyn: interrupted; finished tasks are kept (run again with --resume)"]
    assert wait_for(lambda: not alive(kids), 30), "worker processes outlived the interrupted run"
    assert finished_tasks(out) >= tasks


def test_the_workers_end_when_the_main_process_is_killed(tmp_path):
    proc, _, kids = started_sweep(tmp_path)
    os.kill(proc.pid, signal.SIGKILL)
    proc.wait()
    wait_for(lambda: not alive(kids), 30)
    left = alive(kids)
    for pid in left:
        os.kill(pid, signal.SIGKILL)
    assert not left, f"{len(left)} of {len(kids)} child processes alive 30 s after SIGKILL of the main process"


def test_a_user_error_in_a_worker_is_the_same_one_line_error_as_in_one_process(tmp_path):
    """A channel pattern that matches nothing is found when a worker builds the model."""
    sc = write_scenario(tmp_path / "nomatch.toml", channels='["bridge.nomatch.*"]')
    one = cli(*run_args(sc, tmp_path / "a", workers=1))
    two = cli(*run_args(sc, tmp_path / "b", workers=2))
    line = assert_one_line_error(two, "analysis.channels[0]", "bridge.nomatch.*", "matches no channel")
    assert line == assert_one_line_error(one).replace(str(tmp_path / "a"), str(tmp_path / "b"))


def test_a_worker_killed_from_outside_ends_the_run_with_one_line(tmp_path):
    proc, out, kids = started_sweep(tmp_path)
    cmdlines = {p: open(f"/proc/{p}/cmdline", "rb").read() for p in kids}
    worker = next(p for p, cmd in cmdlines.items() if b"resource_tracker" not in cmd)
    os.kill(worker, signal.SIGKILL)
    _, err = proc.communicate(timeout=300)
    assert proc.returncode == 2 and "Traceback" not in err, err[-2000:]
    lines = error_lines(err)
    assert len(lines) == 1 and "a worker process ended abruptly" in lines[0] and "resume" in lines[0], lines
    assert wait_for(lambda: not alive(kids), 30), "processes left behind"
    assert finished_tasks(out) >= 2
