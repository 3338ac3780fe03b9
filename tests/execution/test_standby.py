"""execution.standby: a pool started ahead of its work (tb-exudyn run's figure processes, issue 49)."""

from __future__ import annotations

import os

import pytest

from tb_exudyn.execution.standby import standby_pool


def test_a_standby_pool_starts_what_it_is_told_ahead_and_ends_with_its_block():
    """2 workers, 1 started ahead: one process exists before any work (it imported the module named,
    here json); the work runs in its processes (one or two: the second starts only when work finds
    none idle), which end with the block."""
    with standby_pool(2, ("json",), started=1) as pool:
        assert len(pool._processes) == 1
        pids = {f.result() for f in [pool.submit(os.getpid) for _ in range(4)]}
        assert os.getpid() not in pids and 1 <= len(pids) <= 2
        processes = list(pool._processes.values())
    assert all(not p.is_alive() for p in processes)  # ended with the block


def test_a_standby_pool_ends_at_once_on_an_error_and_none_is_started_for_no_workers():
    """An exception in the block (e.g. the analysis refused, or Ctrl-C) ends the processes at once
    and propagates; with 0 workers (--no-figures, one core) no pool is made."""
    with pytest.raises(RuntimeError, match="refused"):
        with standby_pool(1, ()) as pool:
            processes = list(pool._processes.values())
            raise RuntimeError("refused")
    assert processes and all(not p.is_alive() for p in processes)
    with standby_pool(0, ("json",)) as none:
        assert none is None
