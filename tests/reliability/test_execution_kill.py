"""Kill tests (issue 15): a run over an old result is SIGKILLed during its sweep and at every step of
its final save; the folder then loads as the old result or as the new complete one, never a mix, and
``--resume`` gives the new complete result.

Problem: the tiny sprung-mass scenario of execution_helpers (batched engine, 4 tasks) run with
``--overwrite`` into a folder holding the result of the same model at 250 km/h (the old result).
The kill is exact: the child process sends itself SIGKILL right after its k-th checkpoint file (the
sweep) or right after its k-th rename of a file or folder of the result (the final save; k = 0: as
the save starts), for every k until the run completes. References: each scenario run alone into a
fresh folder (runs are deterministic: compared bitwise).
"""

from __future__ import annotations

import json
import re
import subprocess
import sys

import numpy as np
import pytest

from tb_exudyn import storage

from .execution_helpers import ROOT, cli, env, run_args, std_of, write_scenario

pytestmark = pytest.mark.exudyn

KILLER = r"""
import os, signal, sys
from pathlib import Path
out, mode, k, args = Path(sys.argv[1]).resolve(), sys.argv[2], int(sys.argv[3]), sys.argv[4:]
count = [0]

def step():
    count[0] += 1
    if count[0] == k:
        os.kill(os.getpid(), signal.SIGKILL)

if mode == "sweep":
    from tb_exudyn.execution.checkpoint import Checkpoint
    save = Checkpoint.save
    def counted(self, task, result):
        save(self, task, result)
        step()
    Checkpoint.save = counted
else:
    def in_result(path):
        p = Path(os.path.abspath(path))
        if out not in p.parents:
            return False
        head = p.relative_to(out).parts[0]
        return head == "pem" or head.startswith(".pem")
    for name in ("replace", "rename"):
        real = getattr(os, name)
        def moved(a, b, *rest, _real=real, **kw):
            _real(a, b, *rest, **kw)
            if in_result(a) or in_result(b):
                step()
        setattr(os, name, moved)
    if k == 0:
        from tb_exudyn.results.random_response import RandomResponse
        def killed(self, folder):
            os.kill(os.getpid(), signal.SIGKILL)
        RandomResponse.save = killed
from tb_exudyn.cli import main
sys.exit(main(args))
"""


@pytest.fixture(scope="module")
def setup(tmp_path_factory):
    base = tmp_path_factory.mktemp("kill")
    new, old = write_scenario(base / "tiny.toml"), write_scenario(base / "old.toml", name="old", speed=250.0)
    refs = {}
    for sc in (new, old):
        folder = base / f"ref-{sc.stem}"
        assert cli(*run_args(sc, folder)).returncode == 0
        refs[sc.stem] = std_of(folder / "pem")
    return base, new, old, refs


def state_of(folder, refs) -> str:
    """'old', 'new', 'none' (nothing loads) or 'MIX ...' (arrays and metadata of different runs)."""
    std = std_of(folder / "pem")
    if std is None:
        return "none"
    try:
        name = json.loads((folder / "pem" / "meta.json").read_text())["scenario_toml"]
    except (OSError, ValueError, KeyError):
        return "MIX (no metadata)"
    meta = "new" if 'name = "tiny"' in name else "old" if 'name = "old"' in name else "?"
    arrays = "new" if np.array_equal(std, refs["tiny"]) else "old" if np.array_equal(std, refs["old"]) else "?"
    return meta if meta == arrays != "?" else f"MIX (metadata {meta}, arrays {arrays})"


def killed_run(base, name, new, old, mode, k):
    out = base / name
    assert cli(*run_args(old, out)).returncode == 0
    args = [str(a) for a in run_args(new, out, "--overwrite")]
    proc = subprocess.run([sys.executable, "-c", KILLER, str(out), mode, str(k), *args], capture_output=True,
                          text=True, env=env(), cwd=ROOT, timeout=120)
    return out, proc


def test_sigkill_during_the_sweep_leaves_the_old_result_and_resume_completes_the_new(setup):
    base, new, old, refs = setup
    out, proc = killed_run(base, "sweep", new, old, "sweep", 2)
    assert proc.returncode == -9, proc.stderr[-2000:]
    assert state_of(out, refs) == "old"
    resumed = cli(*run_args(new, out, "--resume"))
    assert resumed.returncode == 0, resumed.stderr[-2000:]
    done = re.search(r"(\d+) tasks \((\d+) run, (\d+) from the checkpoint\)", resumed.stdout)
    assert done, resumed.stdout  # killed after 2 saved tasks: those 2 are reused, the rest is run
    assert int(done[3]) == 2 and int(done[1]) == int(done[2]) + 2 and int(done[2]) >= 1, done[0]
    assert state_of(out, refs) == "new"


@pytest.mark.xfail(not hasattr(storage, "save_result_folder"), strict=True,
                   reason="result folders are written file by file until the reliability branch's whole-folder "
                          "writes (storage.py save_result_folder) are merged")
def test_sigkill_at_every_step_of_the_final_save_never_leaves_a_mix(setup):
    base, new, old, refs = setup
    seen = []
    for k in range(10):
        out, proc = killed_run(base, f"save{k}", new, old, "save", k)
        state = state_of(out, refs)
        seen.append((k, proc.returncode, state))
        assert state in ("old", "new"), seen
        if proc.returncode == 0:  # k beyond the save's last step: the run completed (its checkpoint removed)
            assert state == "new" and not (out / "checkpoint").exists(), seen
            break
        resumed = cli(*run_args(new, out, "--resume"))
        assert resumed.returncode == 0 and state_of(out, refs) == "new", (seen, resumed.stderr[-2000:])
    else:
        pytest.fail(f"the final save was still killed at step 9: {seen}")
    assert len(seen) >= 2 and seen[0][1] == -9, seen
