"""A first run's compile (issue 49): said while it happens, done once in the background, and the
run's workers load the code instead of compiling it again.

- The lock: a process that loads the compiled code waits while a warm-up process holds the cache
  directory's lock and goes on when it ends (a child holding the lock until the test closes its
  stdin: an event, not a delay).
- A run on an empty cache (slow: it compiles, about a minute of CPU): the command says
  "compiling the integrator once" before the run's tasks, the warm-up marks both precisions compiled,
  and the run's own processes write nothing into the cache after the warm-up finished (they loaded
  every function from it); a second run says nothing about compiling.
"""

from __future__ import annotations

import fcntl
import os
import subprocess
import sys
import threading
from pathlib import Path

import pytest

from tb_exudyn import jit

ROOT = Path(__file__).resolve().parents[2]


def _env(cache: Path) -> dict[str, str]:
    return {**os.environ, "PYTHONPATH": str(ROOT), "NUMBA_CACHE_DIR": str(cache), "OMP_NUM_THREADS": "1",
            "OPENBLAS_NUM_THREADS": "1", "MPLBACKEND": "Agg"}


def test_a_loader_waits_while_a_warm_up_holds_the_lock(tmp_path):
    fd = os.open(tmp_path / jit.LOCK, os.O_RDWR | os.O_CREAT, 0o644)
    fcntl.flock(fd, fcntl.LOCK_SH)  # as jit.warm_up: taken here, held by the child it is passed to
    child = subprocess.Popen([sys.executable, "-c", "import sys; sys.stdin.read()"], stdin=subprocess.PIPE,
                             pass_fds=(fd,))
    os.close(fd)
    waiter = threading.Thread(target=jit._await_warm_up, args=(tmp_path,), daemon=True)
    try:
        waiter.start()
        waiter.join(0.5)
        assert waiter.is_alive(), "the loader did not wait for the warm-up's lock"
    finally:
        child.stdin.close()  # the warm-up ends: its lock is released
        child.wait(timeout=60)
    waiter.join(60)
    assert not waiter.is_alive(), "the loader still waits after the warm-up ended"


def test_no_second_warm_up_while_one_runs(tmp_path, monkeypatch):
    """A sweep's workers each plan a PEM: none of them starts a warm-up while the parent's runs."""
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path))
    monkeypatch.delenv(jit.WARMING_ENV, raising=False)
    fd = os.open(tmp_path / jit.LOCK, os.O_RDWR | os.O_CREAT, 0o644)
    fcntl.flock(fd, fcntl.LOCK_SH)
    child = subprocess.Popen([sys.executable, "-c", "import sys; sys.stdin.read()"], stdin=subprocess.PIPE,
                             pass_fds=(fd,))
    os.close(fd)
    try:
        said = []
        assert not jit.warm_up("tb_exudyn.no_such_module", ("float64",), said.append) and not said
    finally:
        child.stdin.close()
        child.wait(timeout=60)


def test_no_lock_no_wait(tmp_path):
    jit._await_warm_up(tmp_path)  # no lock file: returns at once (a hang fails by the suite's timeout)
    (tmp_path / jit.LOCK).touch()
    jit._await_warm_up(tmp_path)  # a lock file nobody holds (a warm-up that ended)


@pytest.mark.slow
@pytest.mark.exudyn
def test_a_first_run_compiles_once_in_the_background_and_says_so(tmp_path):
    cache = tmp_path / "cache"
    args = [sys.executable, "-m", "tb_exudyn", "run", "quick", "--no-figures", "--workers", "2"]
    first = subprocess.run([*args, "--out", str(tmp_path / "a")], capture_output=True, text=True, env=_env(cache),
                           timeout=1200, cwd=tmp_path)
    assert first.returncode == 0, first.stderr[-2000:]
    assert "compiling the integrator once" in first.stderr, first.stderr[-2000:]
    stamps = sorted(cache.glob("warm-*"))
    assert {p.name.rsplit("-", 1)[1] for p in stamps} == {"float64", "float32"}, stamps
    done = max(p.stat().st_mtime for p in stamps)
    later = [p.name for p in cache.rglob("*.nb[ic]") if p.stat().st_mtime > done]
    assert later == [], f"the run's own processes compiled {later} after the warm-up"
    second = subprocess.run([*args, "--out", str(tmp_path / "b")], capture_output=True, text=True, env=_env(cache),
                            timeout=600, cwd=tmp_path)
    assert second.returncode == 0 and "compiling" not in second.stderr, second.stderr[-2000:]
