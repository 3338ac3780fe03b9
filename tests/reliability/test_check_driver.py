"""The EN 1991-2 check on the method driver (issue 48): its cases are tasks, so the check has the process
pool, a checkpoint and --resume, and its table does not depend on how the tasks ran.

Problem: single_span_32m (ballasted: three mass cases) under HSLM-A1 and HSLM-A2 at a line speed of 200
km/h: six moving-force tasks (mass case x train), 15-43 speeds each, a few tenths of a second each, and the
static load models' task (LM71 for the deformation criteria). Reference: the same
command run once, uninterrupted, in this process (``--workers 1``); the tasks are reduced in task order
and each runs on one BLAS thread on the modes the plan computed, so every other way of running them must
give check.csv to the bit (compared as bytes: no tolerance).

- ``--workers 2`` (a local pool of two spawned processes);
- Ctrl-C (SIGINT, as a terminal sends it) when the fourth moving-force task starts, then the same command with
  ``--resume``: three tasks read from the checkpoint, three run;
- SIGKILL of a child process when its fourth moving-force task starts (no handler runs: the checkpoint is what a kill
  leaves), then ``--resume`` in this process.
"""

from __future__ import annotations

import importlib
import os
import signal
import subprocess
import sys
from pathlib import Path

import pytest

from tb_exudyn.cli import main

from .execution_helpers import ROOT

method_module = importlib.import_module("tb_exudyn.methods.check")
TASKS = 7  # three mass cases x two trains, and the static load models (LM71) last


def argv(out: Path, *more: str) -> list[str]:
    return ["check", "single_span_32m", "--line-speed-kmh", "200", "--trains", "HSLM-A1", "HSLM-A2", "--out", str(out),
            "--no-progress", "--no-figures", *more]


@pytest.fixture(scope="module")
def reference(tmp_path_factory) -> bytes:
    out = tmp_path_factory.mktemp("reference") / "out"
    assert main(argv(out, "--workers", "1")) == 0
    return (out / "check.csv").read_bytes()


def test_two_workers_give_one_workers_table_bitwise(reference, tmp_path, capsys):
    out = tmp_path / "out"
    assert main(argv(out, "--workers", "2")) == 0
    said = capsys.readouterr().out
    assert f"{TASKS} tasks, process pool (2 workers)" in said, said
    assert (out / "check.csv").read_bytes() == reference


def test_a_ctrl_c_half_way_and_resume_give_the_same_table(reference, tmp_path, capsys, monkeypatch):
    out = tmp_path / "out"
    real, calls = method_module.moving_force_task, []

    def fourth_interrupted(task):  # noqa: ANN001, ANN202
        calls.append(task.case)
        if len(calls) == 4:
            os.kill(os.getpid(), signal.SIGINT)  # handled as a terminal's Ctrl-C: KeyboardInterrupt here
        return real(task)

    with monkeypatch.context() as patched:
        patched.setattr(method_module, "moving_force_task", fourth_interrupted)
        assert main(argv(out, "--workers", "1")) == 130
    err = capsys.readouterr().err
    assert "keeps 3 finished tasks in checkpoint-check/; run the same command with --resume" in err, err
    assert not (out / "check.csv").exists()
    assert main(argv(out, "--workers", "1")) == 2 and "--resume to continue it" in capsys.readouterr().err
    assert main(argv(out, "--workers", "1", "--resume")) == 0
    assert f"{TASKS} tasks, 3 from the checkpoint" in capsys.readouterr().out
    assert (out / "check.csv").read_bytes() == reference
    assert sorted(os.listdir(out)) == ["check.csv", "check.html"]  # the checkpoint removed with the files written


KILLED = r"""
import importlib, os, signal, sys
chk = importlib.import_module("tb_exudyn.methods.check")
real, calls = chk.moving_force_task, []

def fourth_killed(task):
    calls.append(1)
    if len(calls) == 4:
        os.kill(os.getpid(), signal.SIGKILL)
    return real(task)

chk.moving_force_task = fourth_killed
from tb_exudyn.cli import main
sys.exit(main(sys.argv[1:]))
"""


def test_a_kill_half_way_and_resume_give_the_same_table(reference, tmp_path, capsys):
    out = tmp_path / "out"
    env = {**os.environ, "PYTHONPATH": str(ROOT), "MPLBACKEND": "Agg", "OMP_NUM_THREADS": "1",
           "OPENBLAS_NUM_THREADS": "1"}
    proc = subprocess.run([sys.executable, "-c", KILLED, *argv(out, "--workers", "1")], env=env, cwd=tmp_path,
                          capture_output=True, text=True, timeout=600)
    assert proc.returncode == -signal.SIGKILL, proc.stderr
    assert len(list((out / "checkpoint-check" / "tasks").glob("*.npz"))) == 3
    assert main(argv(out, "--workers", "1", "--resume")) == 0
    assert f"{TASKS} tasks, 3 from the checkpoint" in capsys.readouterr().out
    assert (out / "check.csv").read_bytes() == reference


def test_a_dask_executor_gives_the_same_table(reference, tmp_path):
    """The same seven tasks on a local Dask cluster of two worker processes (``check(executor=...)``, the
    executor README names), against the command's one-worker check.csv."""
    distributed = pytest.importorskip("distributed", reason="the 'dask' extra is not installed")
    import warnings

    from tb_exudyn.codes import check

    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        with distributed.Client(cluster) as client, warnings.catch_warnings():
            warnings.simplefilter("ignore")
            result = check("single_span_32m", 200.0, trains=["HSLM-A1", "HSLM-A2"], executor=client.get_executor(),
                           out=tmp_path / "out")
    assert result.run["tasks"] == TASKS and result.run["executor"] != "in-process"
    assert (tmp_path / "out" / "check.csv").read_bytes() == reference


def test_without_a_worker_count_a_small_check_runs_here_and_a_large_one_in_a_pool():
    """A worker's start (1-2 s of imports) outweighs a small check's integrations: without ``workers`` a
    check below IN_PROCESS_WORK (steps x modes x speeds) runs in this process; li_zhu_2011_bridge under
    HSLM-A at 250 km/h (33 CPU-s measured) is above it (its plan only: nothing is integrated here)."""
    from tb_exudyn.codes import check

    chk = importlib.import_module("tb_exudyn.codes.check")
    from tb_exudyn.codes.check_plan import plan_check

    assert check("single_span_32m", 120.0, trains=["HSLM-A1"]).run["executor"] == "in-process"
    assert chk._work(plan_check("single_span_32m", 120.0, trains=["HSLM-A1"])) < chk.IN_PROCESS_WORK
    assert chk._work(plan_check("li_zhu_2011_bridge", 250.0, trains=["hslm_a"])) > 4 * chk.IN_PROCESS_WORK


def test_static_deformations_travel_whole_and_a_continuous_girder_gets_lm71_alone_too():
    """The static task's result as arrays (its checkpoint file) gives back every field to the bit; on a
    continuous girder the default load models add SW/0, so the comfort criterion's LM71 alone (A2.4.4.3.2) is a
    task of its own."""
    import numpy as np

    from tb_exudyn.codes.check_plan import plan_check
    from tb_exudyn.codes.deformation import static_deformations
    from tb_exudyn.scenario.io import load_bridge

    sd = static_deformations(load_bridge("single_span_32m").replace(elements_per_span=16))
    back = method_module.static_of(method_module.static_arrays(sd))
    for name in sd.__dataclass_fields__:
        a, b = getattr(sd, name), getattr(back, name)
        assert len(a) == len(b) and all(np.array_equal(x, y) for x, y in zip(a, b)), name
    loads = [t.data.loads for t in method_module._static_tasks(plan_check("continuous_3x32m", 200.0, trains=["HSLM-A1"]))]
    assert loads == [(), ("LM71",)]
    assert [t.data.loads for t in method_module._static_tasks(plan_check("single_span_32m", 200.0, trains=["HSLM-A1"]))] \
        == [()]
