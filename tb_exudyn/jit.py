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
"""

from __future__ import annotations

import importlib
import os
import sys
import warnings
from pathlib import Path
from types import ModuleType

from numpy.typing import NDArray
import numpy as np

_MODULES: dict[str, ModuleType] = {}
#: whether the compiled functions are cached on disk (set when a module is loaded)
CACHE = True


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


def load(name: str) -> ModuleType:
    """The module of compiled functions ``name`` (a full module name), imported on its first call with
    Numba's cache pointed at :func:`cache_dir` for its functions only (``numba.config.CACHE_DIR`` is
    restored after they are declared: other Numba code in the process keeps its own cache location)."""
    global CACHE
    if name not in _MODULES:
        import numba

        path = cache_dir()
        CACHE = _writable(path)
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


__all__ = ["CACHE", "blas_pointers", "blas_scratch", "cache_dir", "load"]
