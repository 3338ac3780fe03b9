"""Compiled code: Numba, imported on first use, its code cached per user.

The modules of compiled functions (the batched engine's step, :mod:`tb_exudyn.engines.batched.compiled`,
and the PEM reducer's kernels, :mod:`tb_exudyn.methods.compiled_reduction`) are imported only through
:func:`load`, by a process that uses them, so that importing the package (and every command that does
not integrate) does not pay Numba's import (about 0.25 s here). Their functions are cached in the
user's cache directory (:func:`cache_dir`): a process compiles them once per installed version (about
26 s here for both precisions of the step, counted in ``benchmarks/bench_speed.py``) and every later
process, e.g. each worker of a run, loads them from there. Nothing is written into the installed
package or an output folder: where the cache directory cannot be written, the functions are compiled
in memory in every process (with a warning).

A first run (the cache cold: :func:`is_warm`) compiles the code before it needs it: :func:`warm_up`
starts one background process per precision (:mod:`tb_exudyn.methods.warm_up`), which compile
in parallel while the run sets its model up, and says so in one line. They hold a lock on
``.warming.lock`` in the cache directory (a shared ``flock`` taken by the starting process on their
behalf, so held from before they start until the last of them ends, however it ends); a process that
loads the compiled code (:func:`load`: the run's workers) waits for that lock first, then loads the
code from the cache instead of compiling it again. Each warm-up process marks its precision done
(:func:`mark_warm`) in a file named by everything the cache depends on (:func:`_cache_key`).
"""

from __future__ import annotations

import hashlib
import importlib
import os
import platform
import subprocess
import sys
import time
import warnings
from pathlib import Path
from types import ModuleType
from typing import Callable

from numpy.typing import NDArray
import numpy as np

from ._version import __version__

_MODULES: dict[str, ModuleType] = {}
#: whether the compiled functions are cached on disk (set when a module is loaded)
CACHE = True
#: the modules of compiled functions (the files their cache depends on)
COMPILED = ("tb_exudyn.engines.batched.compiled", "tb_exudyn.methods.compiled_reduction")
#: the lock the warm-up processes hold (in the cache directory)
LOCK = ".warming.lock"
#: set in the warm-up processes: they do not wait for their own lock
WARMING_ENV = "TB_EXUDYN_WARMING"
#: what a first run says while it compiles
COMPILING = ("compiling the integrator once (about 30-60 s on 2 cores, beside the model's set-up; cached "
             "after, in {path})")


def cache_dir() -> Path:
    """The directory of tb_exudyn's compiled code: ``$NUMBA_CACHE_DIR`` if the user set one, else the
    platform's user cache directory (``$XDG_CACHE_HOME`` or ``~/.cache`` on Linux,
    ``~/Library/Caches`` on macOS, ``%LOCALAPPDATA%`` on Windows) + ``tb_exudyn/numba``."""
    if os.environ.get("NUMBA_CACHE_DIR"):
        return Path(os.environ["NUMBA_CACHE_DIR"])
    if sys.platform == "win32":
        base = Path(os.environ.get("LOCALAPPDATA") or Path.home() / "AppData" / "Local")
    elif sys.platform == "darwin":
        base = Path.home() / "Library" / "Caches"
    else:
        base = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache")
    return base / __name__.partition(".")[0] / "numba"  # the package's name: tb_exudyn


def _writable(path: Path) -> bool:
    try:
        path.mkdir(parents=True, exist_ok=True)
        probe = path / f".probe-{os.getpid()}"
        probe.write_bytes(b"")
        probe.unlink()
        return True
    except OSError:
        return False


def _cache_key() -> str:
    """A digest of what the cache's validity depends on: the versions of Python, Numba and tb_exudyn,
    the machine, and the size and modification time of the compiled modules' sources (as Numba's
    own index records them: a reinstall makes the cache stale)."""
    from importlib.metadata import PackageNotFoundError, version
    from importlib.util import find_spec

    try:
        numba_version = version("numba")
    except PackageNotFoundError:
        numba_version = "none"
    parts = [sys.version, numba_version, __version__, platform.machine()]
    for name in COMPILED:
        spec = find_spec(name)
        st = os.stat(spec.origin) if spec is not None and spec.origin else None
        parts.append(f"{name}:{st.st_size}:{st.st_mtime}" if st is not None else f"{name}:missing")
    return hashlib.sha256("\n".join(parts).encode()).hexdigest()[:16]


def _stamp(precision: str) -> Path:
    return cache_dir() / f"warm-{_cache_key()}-{precision}"


def is_warm(precisions: tuple[str, ...]) -> bool:
    """Whether the compiled code of ``precisions`` is in the cache (a warm-up or a run finished it
    with these sources and versions); a hint: a stale one only means the workers compile."""
    try:
        return all(_stamp(p).is_file() for p in precisions)
    except OSError:
        return False


def mark_warm(precision: str) -> None:
    """Record that the compiled code of ``precision`` is in the cache (the file :func:`is_warm` reads)."""
    try:
        _stamp(precision).touch()
    except OSError:
        pass


def warm_up(module: str, precisions: tuple[str, ...], announce: Callable[[str], None] | None = None) -> bool:
    """Compile the code in the background if the cache is cold (the module docstring): one process
    ``python -m module precision`` per precision of ``precisions`` not yet in the cache (the module
    marks it done: :func:`mark_warm`), ``announce`` told one line.
    Returns whether processes were started (not where the cache cannot be written, when it is warm,
    while another warm-up runs, or in a warm-up process itself)."""
    if os.environ.get(WARMING_ENV):
        return False
    todo = [p for p in precisions if not is_warm((p,))]
    path = cache_dir()
    if not todo or not _writable(path):
        return False
    try:
        import fcntl
    except ImportError:  # not on this platform: the workers compile, as without a warm-up
        return False

    fd = os.open(path / LOCK, os.O_RDWR | os.O_CREAT, 0o644)
    try:
        try:  # exclusive first: fails while another warm-up runs (or starts), whose code this run then waits for
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            return False
        fcntl.flock(fd, fcntl.LOCK_SH)  # held on the children's behalf: they inherit this very lock
        env = {**os.environ, WARMING_ENV: "1", "OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1"}
        for precision in todo:
            subprocess.Popen([sys.executable, "-m", module, precision], env=env,
                             stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                             pass_fds=(fd,), start_new_session=True)
    finally:
        os.close(fd)  # the lock stays while a child holds it
    if announce is not None:
        announce(COMPILING.format(path=path))
    return True


def _await_warm_up(path: Path, limit: float = 600.0) -> None:
    """Wait until no warm-up process holds the cache directory's lock (none running: at once), at
    most ``limit`` seconds (a warm-up that hangs costs that, then this process compiles its own)."""
    if os.environ.get(WARMING_ENV) or not (path / LOCK).is_file():
        return
    try:
        import fcntl

        fd = os.open(path / LOCK, os.O_RDONLY)
    except (ImportError, OSError):
        return
    try:
        end = time.monotonic() + limit
        while True:
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
                return
            except BlockingIOError:
                if time.monotonic() > end:
                    return
                time.sleep(0.1)
            except OSError:
                return
    finally:
        os.close(fd)


def _serialise_cache_saves() -> None:
    """Numba's cache writes an entry by reading its function's index, choosing the first free data
    file number, writing the index, then the data: two processes that compile different types of one
    function at once (the warm-up's two precisions, a run's workers) can choose the same number, and
    the index then names the other's code for a type. Here each save holds an exclusive ``flock`` on
    ``.save.lock`` in its function's cache folder, so that it reads the index another process just
    wrote (nothing changes where Numba's cache class is not the one this was written for)."""
    try:
        import fcntl
        from numba.core import caching
    except ImportError:
        return
    cls = getattr(caching, "IndexDataCacheFile", None)
    save = getattr(cls, "save", None)
    if save is None or getattr(save, "serialised", False) or not hasattr(cls, "_load_index"):
        return

    def serialised(self, key, data):  # noqa: ANN001, ANN202
        try:
            fd = os.open(os.path.join(self._cache_path, ".save.lock"), os.O_RDWR | os.O_CREAT, 0o644)
        except (OSError, AttributeError, TypeError):
            return save(self, key, data)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX)
            return save(self, key, data)
        finally:
            os.close(fd)

    serialised.serialised = True  # type: ignore[attr-defined]
    cls.save = serialised


def load(name: str) -> ModuleType:
    """The module of compiled functions ``name`` (a full module name), imported on its first call with
    Numba's cache pointed at :func:`cache_dir` for its functions only (``numba.config.CACHE_DIR`` is
    restored after they are declared: other Numba code in the process keeps its own cache location)."""
    global CACHE
    if name not in _MODULES:
        import numba

        path = cache_dir()
        CACHE = _writable(path)
        if CACHE:
            _await_warm_up(path)
            _serialise_cache_saves()
        if not CACHE:
            warnings.warn(f"the cache directory of tb_exudyn's compiled code {path} cannot be written: its "
                          "functions are compiled in every process (about 10 s each); set NUMBA_CACHE_DIR to a "
                          "writable folder", RuntimeWarning, stacklevel=2)
        before = numba.config.CACHE_DIR
        numba.config.CACHE_DIR = str(path) if CACHE else ""  # read by the module when it is imported
        try:
            _MODULES[name] = importlib.import_module(name)
        finally:
            numba.config.CACHE_DIR = before
    return _MODULES[name]


def blas_pointers(dtype: np.dtype) -> NDArray[np.int64]:
    """The address of the BLAS gemm of ``dtype`` (float64: d, float32: s), as a (1,) array, in scipy's
    BLAS (``scipy.linalg.cython_blas``: the library behind ``scipy.linalg.blas``, so the batched
    engine's compiled step makes the numpy step's very calls)."""
    from numba.extending import get_cython_function_address

    p = "d" if np.dtype(dtype) == np.float64 else "s"
    return np.array([get_cython_function_address("scipy.linalg.cython_blas", p + name)
                     for name in ("gemm",)], dtype=np.int64)


def blas_scratch(dtype: np.dtype) -> tuple[NDArray[np.int64], NDArray[np.int32], np.ndarray, NDArray[np.uint8]]:
    """What a compiled function calling BLAS of ``dtype`` takes first: the addresses
    (:func:`blas_pointers`), scratch for the integer and scalar arguments passed by reference, and the
    characters N, T."""
    return (blas_pointers(dtype), np.zeros(8, dtype=np.int32), np.zeros(4, dtype=dtype),
            np.frombuffer(b"NT", dtype=np.uint8).copy())


__all__ = ["CACHE", "blas_pointers", "blas_scratch", "cache_dir", "is_warm", "load", "mark_warm", "warm_up"]
