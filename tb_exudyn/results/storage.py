"""Result files: arrays as npz (read with allow_pickle=False) plus JSON metadata, written atomically.

A result folder holds ``arrays.npz`` and ``meta.json``; a checkpoint folder holds one small npz per
finished task. Every write goes to a temporary file in the same folder and is renamed into place,
so an interrupted run never leaves a half-written file that looks whole. Nothing is pickled:
opening someone's results cannot run code.
"""

from __future__ import annotations

import json
import os
import tempfile
from pathlib import Path
from typing import Any, Mapping

import numpy as np

from ..atomic import write_atomic, write_text_atomic
from ..errors import OutputFolderError


def save_npz_atomic(path: str | Path, arrays: Mapping[str, np.ndarray]) -> None:
    """Write arrays to ``path`` (.npz, uncompressed) atomically; object arrays are refused."""
    for name, a in arrays.items():
        if np.asarray(a).dtype == object:
            raise TypeError(f"array {name!r} has dtype object: not storable without pickle")
    write_atomic(Path(path), lambda fh: np.savez(fh, **{k: np.asarray(v) for k, v in arrays.items()}))


def load_npz(path: str | Path) -> dict[str, np.ndarray]:
    """Read every array of an npz file (never unpickles)."""
    with np.load(Path(path), allow_pickle=False) as data:
        return {k: data[k] for k in data.files}


def save_json_atomic(path: str | Path, meta: Mapping[str, Any]) -> None:
    text = json.dumps(meta, indent=2, sort_keys=True, default=json_default)
    write_text_atomic(path, text)


def load_json(path: str | Path) -> dict[str, Any]:
    return json.loads(Path(path).read_text(encoding="utf-8"))


def json_default(obj: Any) -> Any:
    if isinstance(obj, (np.integer,)):
        return int(obj)
    if isinstance(obj, (np.floating,)):
        return float(obj)
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, Path):
        return str(obj)
    raise TypeError(f"{type(obj).__name__} is not JSON serialisable")


def check_writable(folder: str | Path) -> Path:
    """Create ``folder`` if needed and check that files can be written there (before any run starts).

    Raises OutputFolderError (an OSError the CLI reports as a user error) naming the folder.
    """
    folder = Path(folder)
    try:
        folder.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(dir=folder, prefix=".write-test.")
        os.close(fd)
        os.unlink(tmp)
    except OSError as exc:
        raise OutputFolderError(f"output folder {str(folder)!r} is not writable: {exc.strerror or exc}") from None
    return folder
