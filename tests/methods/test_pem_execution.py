"""PEM execution: the result does not depend on workers, executor or interruption.

Problem for all tests: the damped VBI-2D sprung mass over the 25 m beam at 300 km/h, German
low-interference vertical profile, 6 frequencies 2-20 Hz, two output channels. The reference is the
in-process run (workers=1). Runs are deterministic, reduction is in task order, so results must be
bitwise equal; the tolerance is zero.
"""

from __future__ import annotations

import signal
import subprocess
import sys
import textwrap

import numpy as np
import pytest

from tb_exudyn.results import load_results
from tb_exudyn.scenario import save_scenario
from tb_exudyn.methods import run_pem

from .test_pem import sprung_mass_scenario

pytestmark = pytest.mark.exudyn


@pytest.fixture(scope="module")
def scenario():
    return sprung_mass_scenario(lead_in=20.0, run_out=5.0, f_min=2.0, f_max=20.0, n_freq=6,
                                channels=("bridge.span1.mid.acc_z", "car1.body.acc_z"))


@pytest.fixture(scope="module")
def reference(scenario):
    return run_pem(scenario, workers=1, progress=False, engine="exudyn")


def _same(a, b):
    assert a.channels == b.channels
    for name in ("time", "mean", "std", "psd", "var_by_type", "std_rate", "mean_rate", "rho", "bandwidth"):
        assert np.array_equal(getattr(a, name), getattr(b, name)), name


def test_two_workers_equal_one(scenario, reference):
    _same(run_pem(scenario, workers=2, progress=False, engine="exudyn"), reference)


def test_saved_result_loads_back(scenario, reference, tmp_path):
    r = run_pem(scenario, workers=1, out=tmp_path, progress=False, engine="exudyn")
    _same(load_results(tmp_path / "pem"), reference)


def test_killed_sweep_resumes_to_the_same_result(scenario, reference, tmp_path):
    """A sweep in another process is killed (SIGKILL: no clean-up at all) right after its second task
    is on disk (the child kills itself there: exact, whatever the machine's load); resuming reads the
    finished tasks and runs only the rest (7 tasks: the mean and 6 columns)."""
    scenario_file = save_scenario(scenario, tmp_path / "s.toml")
    out = tmp_path / "run"
    code = textwrap.dedent(f"""
        import os, signal
        import tb_exudyn as tbx
        from tb_exudyn.execution.checkpoint import Checkpoint
        from tb_exudyn.methods import run_pem
        save, saved = Checkpoint.save, []
        def counted(self, task, result):
            save(self, task, result)
            saved.append(task.key)
            if len(saved) == 2:
                os.kill(os.getpid(), signal.SIGKILL)
        Checkpoint.save = counted
        run_pem(tbx.load_scenario({str(scenario_file)!r}), workers=1, out={str(out)!r}, progress=False, engine="exudyn")
    """)
    proc = subprocess.run([sys.executable, "-c", code], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                          text=True, timeout=300)
    assert proc.returncode == -signal.SIGKILL, proc.stderr[-2000:]
    done = len(list((out / "checkpoint" / "tasks").glob("*.npz")))
    assert done == 2, f"killed after its second checkpoint file, {done} on disk"
    resumed = run_pem(scenario, workers=1, out=out, resume=True, progress=False, engine="exudyn")
    assert resumed.provenance["tasks"] == 7
    assert resumed.provenance["tasks_from_checkpoint"] == done
    assert resumed.provenance["tasks_run"] == 7 - done
    _same(resumed, reference)


def test_dask_local_cluster_gives_the_same_result(scenario, reference):
    distributed = pytest.importorskip("distributed", reason="the 'dask' extra is not installed")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        with distributed.Client(cluster) as client:
            result = run_pem(scenario, executor=client.get_executor(), progress=False, engine="exudyn")
    _same(result, reference)
