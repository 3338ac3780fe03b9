"""Atomic file writes: a file is either its old content or the whole new one, never half of it.

Each file is written to a hidden temporary file beside it (``.<name>.<random>.tmp``) and renamed
into place only when it is complete; on any error (full disk, Ctrl-C) the temporary files are
removed, and so are the folders the write created. :func:`write_atomic_group` writes several files
as one (a CSV table and its sidecar): every temporary file is complete before the first rename.
With ``replace=False`` a file is put in place only if nothing has that name by then (a hard link,
which fails on an existing entry, then the temporary name is removed; where the file system has no
hard links, a last check and a rename).

The renames of a group are one step for Ctrl-C: a SIGINT that arrives while the files are put in place
is held until the last rename (and the removals the group asks for) is done, then delivered, so an
interrupted group is either not placed at all or placed whole (:func:`interrupts_held`).
"""

from __future__ import annotations

import errno
import os
import signal
import tempfile
import threading
from pathlib import Path
from typing import Any, BinaryIO, Callable, Sequence

#: errors of os.link that mean "no hard links here", not "the name is taken"
_NO_LINKS = {errno.EPERM, errno.EXDEV, errno.EMLINK, getattr(errno, "ENOTSUP", -1), getattr(errno, "EOPNOTSUPP", -1),
             getattr(errno, "ENOSYS", -1)}


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def write_atomic(path: str | Path, write: Callable[[BinaryIO], object], *, replace: bool = True) -> Path:
    """Call ``write(binary_file)`` on a temporary file beside ``path``, then rename it into place.

    The file gets the usual permissions (0666 less the umask), not mkstemp's private 0600. On any
    error (or Ctrl-C) the temporary file is removed and ``path`` is left as it was. ``replace=False``:
    FileExistsError (and nothing written) if ``path`` exists when the file is put in place.
    """
    def by_name(tmp: Path) -> None:
        with open(tmp, "wb") as fh:
            write(fh)

    return write_atomic_named(path, by_name, replace=replace)


def write_atomic_named(path: str | Path, write: Callable[[Path], object], *, replace: bool = True) -> Path:
    """:func:`write_atomic` for writers that need a file name, not a file object (e.g. a NetCDF
    library): ``write(temporary path)`` beside ``path``, then the rename into place."""
    return write_atomic_group([(path, write)], replace=replace)[0]


def write_atomic_group(items: Sequence[tuple[str | Path, Callable[[Path], object]]], *,
                       replace: bool = True, remove: Sequence[str | Path] = ()) -> list[Path]:
    """Write several files as one: ``write(temporary path)`` for each ``(path, write)``, and only
    when all are complete rename them into place, in order, then remove the entries ``remove`` (stale
    files of an earlier group that the new one has no counterpart for).

    On an error before the renames nothing is changed (temporary files and created folders are
    removed). With ``replace=False`` a file whose name was taken in the meantime raises
    FileExistsError and the files of this group already put in place are removed again. (With
    ``replace=True`` a failing rename after the first cannot bring back the replaced file; renames
    within a folder need no space and do not fail in practice.) A Ctrl-C during the renames is
    delivered after them (:func:`interrupts_held`): the group is then in place, whole.
    """
    paths = [Path(p) for p, _ in items]
    temps: list[Path] = []
    placed: list[Path] = []
    created: list[Path] = []
    held = interrupts_held()
    try:
        for path, (_, write) in zip(paths, items):
            created += _make_parents(path.parent)
            fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
            os.close(fd)
            temps.append(Path(tmp))
            write(Path(tmp))
            os.chmod(tmp, 0o666 & ~_umask())
        with held:
            for path, tmp in zip(paths, temps):
                _place(tmp, path, replace)
                placed.append(path)
            for stale in remove:
                if os.path.lexists(stale) and not Path(stale).is_dir():
                    os.unlink(stale)
    except BaseException:
        for tmp in temps:
            if os.path.lexists(tmp):
                os.unlink(tmp)
        if not replace:  # these were new files: take them away again
            for path in placed:
                os.unlink(path)
        for folder in created:
            try:
                os.rmdir(folder)
            except OSError:
                pass
        raise
    finally:
        held.deliver()
    return paths


class interrupts_held:  # noqa: N801 - used as a context manager, like contextlib's
    """Hold SIGINT (Ctrl-C) in the block: one that arrives is recorded, not raised; :meth:`deliver`
    (after the block) raises it again through the handler that was in place (KeyboardInterrupt by
    default). Only the main thread can set a signal handler: elsewhere (and where SIGINT is ignored or
    not Python's to handle) the block runs as it is."""

    def __init__(self) -> None:
        self._old: Any = None
        self._pending = False
        self._active = False

    def _record(self, signum: int, frame: object) -> None:  # noqa: ARG002
        self._pending = True

    def __enter__(self) -> "interrupts_held":
        if threading.current_thread() is threading.main_thread():
            old = signal.getsignal(signal.SIGINT)
            if callable(old):
                self._old = old
                signal.signal(signal.SIGINT, self._record)
                self._active = True
        return self

    def __exit__(self, *exc: object) -> None:
        if self._active:
            signal.signal(signal.SIGINT, self._old)
            self._active = False

    def deliver(self) -> None:
        """Raise a held SIGINT again (once), now that its handler is back."""
        if self._pending:
            self._pending = False
            self._old(signal.SIGINT, None)


def _make_parents(folder: Path) -> list[Path]:
    """Create ``folder`` and its missing parents; the folders created, deepest first."""
    missing = []
    p = folder
    while not os.path.lexists(p) and p != p.parent:
        missing.append(p)
        p = p.parent
    folder.mkdir(parents=True, exist_ok=True)
    return missing


def _place(tmp: Path, path: Path, replace: bool) -> None:
    if replace:
        os.replace(tmp, path)
        return
    try:
        os.link(tmp, path)
    except FileExistsError:
        raise
    except OSError as exc:
        if exc.errno not in _NO_LINKS:
            raise
        if os.path.lexists(path):
            raise FileExistsError(errno.EEXIST, os.strerror(errno.EEXIST), str(path)) from None
        os.replace(tmp, path)
        return
    os.unlink(tmp)


def write_text_atomic(path: str | Path, text: str, *, replace: bool = True) -> Path:
    """Write UTF-8 text atomically."""
    return write_atomic(path, lambda fh: fh.write(text.encode("utf-8")), replace=replace)
