"""The same result means the same bits (issue 49): one worker, two workers, a run killed part-way
then resumed and a Dask executor give bitwise the same result, for PEM and for Monte Carlo.

Problem: the tiny sprung-mass scenario of execution_helpers (the VBI-2D damped sprung mass over the
25 m beam at 300 km/h, 6 frequencies, two channels; batched engine: the mean task and the column
slices; Monte Carlo: 4 samples on the linear model) run through the command in a child process.
Reference: the same command with ``--workers 1``, uninterrupted. Why bitwise: a task's result does
not depend on the worker that computes it or on what that worker did before, tasks are cut by the
scenario and the machine's core count (not by ``--workers``), and the parent reduces them in task
order (:mod:`tb_exudyn.execution.tasks`), reading a finished task back from its checkpoint file with
its exact bytes; so the tolerance is zero, for every array of the result (the derived statistics
too: the Rice rate, rho and the bandwidth come from sums the same reduction forms).

The interruption is exact, not timed: the child SIGKILLs itself right after its k-th checkpoint file
(test_execution_kill.py's KILLER), so the resumed run reads k tasks and runs the rest.
"""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

from tb_exudyn.results import load_results

from .execution_helpers import ROOT, cli, env, run_args, write_scenario
from .test_execution_kill import KILLER

pytestmark = pytest.mark.exudyn

#: every array a result may hold (None where a method has none)
ARRAYS = ("time", "mean", "std", "psd", "var_by_type", "std_rate", "mean_rate", "rho", "bandwidth", "mean_ci",
          "std_ci", "min_wheel_force", "sample_min", "sample_max")
FOLDER = {"pem": "pem", "mc": "mc_linear"}


def _run(scenario, out, method, *extra):
    proc = cli(*run_args(scenario, out, "--method", method, *extra))
    assert proc.returncode == 0, proc.stderr[-2000:]
    return proc


def _same(a, b) -> list[str]:
    """The names of the arrays that differ (by even one bit) between results ``a`` and ``b``."""
    assert a.channels == b.channels
    out = []
    for name in ARRAYS:
        x, y = getattr(a, name, None), getattr(b, name, None)
        assert (x is None) == (y is None), name
        if x is not None and not np.array_equal(x, y, equal_nan=True):
            out.append(name)
    return out


@pytest.fixture(scope="module")
def scenario(tmp_path_factory):
    return write_scenario(tmp_path_factory.mktemp("bitwise") / "tiny.toml")


@pytest.mark.parametrize("method", ["pem", "mc"])
def test_workers_and_resume_give_the_same_bits(scenario, tmp_path, method):
    _run(scenario, tmp_path / "one", method)
    ref = load_results(tmp_path / "one" / FOLDER[method])
    assert ref.provenance["executor"] == "in-process"

    _run(scenario, tmp_path / "two", method, "--workers", 2)
    two = load_results(tmp_path / "two" / FOLDER[method])
    assert two.provenance["executor"].startswith("process pool"), two.provenance["executor"]
    assert _same(ref, two) == []

    out = tmp_path / "killed"
    args = [str(a) for a in run_args(scenario, out, "--method", method, "--workers", 2)]
    proc = subprocess.run([sys.executable, "-c", KILLER, str(out), "sweep", "2", *args], capture_output=True,
                          text=True, env=env(), cwd=ROOT, timeout=300)
    assert proc.returncode == -9, proc.stderr[-2000:]  # killed after its 2nd checkpoint file
    _run(scenario, out, method, "--workers", 2, "--resume")
    resumed = load_results(out / FOLDER[method])
    stats = {k: resumed.provenance[k] for k in ("tasks", "tasks_run", "tasks_from_checkpoint")}
    assert stats["tasks_from_checkpoint"] == 2 and stats["tasks_run"] >= 1, stats
    assert _same(ref, resumed) == []


@pytest.mark.parametrize("method", ["pem", "mc"])
def test_a_dask_executor_gives_the_same_bits(scenario, tmp_path, method):
    """The same tasks on a local Dask cluster of two worker processes (the executor the README names),
    against the command's one-worker result read back."""
    distributed = pytest.importorskip("distributed", reason="the 'dask' extra is not installed")
    import warnings

    from tb_exudyn import load_scenario
    from tb_exudyn.methods import run_monte_carlo, run_pem

    _run(scenario, tmp_path / "one", method)
    ref = load_results(tmp_path / "one" / FOLDER[method])
    sc = load_scenario(scenario)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        with distributed.Client(cluster) as client, warnings.catch_warnings():
            warnings.simplefilter("ignore")  # the tiny scenario's own advice (its short approach)
            if method == "pem":
                got = run_pem(sc, executor=client.get_executor(), progress=False, engine="batched")
            else:
                got = run_monte_carlo(sc, executor=client.get_executor(), progress=False, engine="batched")
    assert got.provenance["executor"] != "in-process"
    assert _same(ref, got) == []
