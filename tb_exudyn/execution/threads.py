"""Thread limits: single-threaded BLAS while a run integrates, and in worker processes.

The per-step work of a run is many small numpy products (the wheel-rail coupling, the bridge's
mode shapes). A multi-threaded OpenBLAS wakes its threads for the larger of them and lets them
spin; on a 2-core machine, next to Exudyn's thread and other processes, that made a crossing of
the reference study's train about three times slower (1.7 ms instead of 0.53 ms per step,
measured). Runs are parallelised by processes instead (one run per worker), so a run keeps its
BLAS on one thread: through ``threadpoolctl`` when it is installed, else by calling OpenBLAS's
own ``*_set_num_threads`` in the libraries loaded into the process (Linux); else nothing changes.
"""

from __future__ import annotations

import ctypes
import os
from contextlib import contextmanager
from pathlib import Path
from typing import Iterator

#: the environment variables numpy's BLAS libraries read when a process starts
THREAD_VARIABLES = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMEXPR_NUM_THREADS")

_SETTERS = (
    ("scipy_openblas_set_num_threads64_", "scipy_openblas_get_num_threads64_"),
    ("scipy_openblas_set_num_threads", "scipy_openblas_get_num_threads"),
    ("openblas_set_num_threads64_", "openblas_get_num_threads64_"),
    ("openblas_set_num_threads", "openblas_get_num_threads"),
)


def _loaded_openblas() -> list[tuple[object, object]]:
    """(setter, getter) pairs of every OpenBLAS loaded into this process (Linux /proc only)."""
    maps = Path("/proc/self/maps")
    if not maps.exists():
        return []
    paths = sorted({line.split()[-1] for line in maps.read_text().splitlines()
                    if "openblas" in line.lower() and line.split()[-1].startswith("/")})
    pairs = []
    for path in paths:
        try:
            lib = ctypes.CDLL(path)
        except OSError:
            continue
        for set_name, get_name in _SETTERS:
            if hasattr(lib, set_name) and hasattr(lib, get_name):
                pairs.append((getattr(lib, set_name), getattr(lib, get_name)))
                break
    return pairs


@contextmanager
def single_threaded_blas() -> Iterator[None]:
    """Within the block, BLAS libraries use one thread; restored afterwards."""
    try:
        from threadpoolctl import threadpool_limits
    except ImportError:
        threadpool_limits = None
    if threadpool_limits is not None:
        with threadpool_limits(limits=1, user_api="blas"):
            yield
        return
    pairs = _loaded_openblas()
    before = [get() for _, get in pairs]
    for set_threads, _ in pairs:
        set_threads(1)
    try:
        yield
    finally:
        for (set_threads, _), n in zip(pairs, before):
            set_threads(n)


@contextmanager
def single_threaded_workers() -> Iterator[None]:
    """Set the BLAS thread variables to 1 while worker processes start (they inherit them, and a
    spawned process reads them before numpy loads its BLAS)."""
    old = {k: os.environ.get(k) for k in THREAD_VARIABLES}
    os.environ.update({k: "1" for k in THREAD_VARIABLES})
    try:
        yield
    finally:
        for k, v in old.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v
