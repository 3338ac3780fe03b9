"""Atomic file writes: a file is either its old content or the whole new one, never half of it."""

from __future__ import annotations

import os
import tempfile
from pathlib import Path
from typing import BinaryIO, Callable


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def write_atomic(path: str | Path, write: Callable[[BinaryIO], object]) -> Path:
    """Call ``write(binary_file)`` on a temporary file beside ``path``, then rename it into place.

    The file gets the usual permissions (0666 less the umask), not mkstemp's private 0600. On any
    error (or Ctrl-C) the temporary file is removed and ``path`` is left as it was.
    """
    def by_name(tmp: Path) -> None:
        with open(tmp, "wb") as fh:
            write(fh)

    return write_atomic_named(path, by_name)


def write_atomic_named(path: str | Path, write: Callable[[Path], object]) -> Path:
    """:func:`write_atomic` for writers that need a file name, not a file object (e.g. a NetCDF
    library): ``write(temporary path)`` beside ``path``, then the rename into place."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    os.close(fd)
    try:
        write(Path(tmp))
        os.chmod(tmp, 0o666 & ~_umask())
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise
    return path


def write_text_atomic(path: str | Path, text: str) -> Path:
    """Write UTF-8 text atomically."""
    return write_atomic(path, lambda fh: fh.write(text.encode("utf-8")))
