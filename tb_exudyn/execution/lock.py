"""One run per output folder at a time: a lock that a dead process does not hold.

The lock is ``fcntl.flock`` on ``<folder>/.tb_exudyn.lock``, held while the file is open. The kernel
releases it when the process ends in any way (SIGKILL included), so a killed run never blocks the next
one; the file names the holder (process id, host, start time, command) for the message a second run
gets. The holder removes the file when it is done, while it still holds the lock; a process that
locked a file meanwhile removed checks that it locked the file at the path, else tries again (the usual
lock-file protocol). Worker processes do not inherit the lock (Python opens files non-inheritable).

Within one process the lock is re-entrant for the thread holding it (the command line holds it over a
whole command, the method it calls takes it again); another thread of the same process is refused
like another process.

On a file system without ``flock`` (some network file systems) or without ``fcntl`` (Windows) the run
goes on unlocked, with a notice.
"""

from __future__ import annotations

import json
import os
import socket
import sys
import threading
import time
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Iterator

from ..errors import OutputFolderError
from .notices import notice

try:
    import fcntl
except ImportError:  # pragma: no cover - Windows
    fcntl = None  # type: ignore[assignment]

#: the lock file in an output folder
LOCK_NAME = ".tb_exudyn.lock"


@dataclass
class _Held:
    fd: int | None
    thread: int
    count: int


_HELD: dict[str, _Held] = {}
_GUARD = threading.Lock()


def _holder(fd: int) -> str:
    """What the lock file says about its holder, as a phrase."""
    try:
        data = json.loads(os.pread(fd, 4096, 0).decode("utf-8"))
        command = " ".join(str(data.get("command", "")).split())[:80]
        return (f"pid {data.get('pid')} on {data.get('host')}, started {data.get('started')}"
                + (f": {command}" if command else ""))
    except (OSError, ValueError, AttributeError):
        return "a process that has not written its details yet"


def _acquire(path: Path, where: str, remedy: str) -> int | None:
    """Lock ``path`` (created if needed); the open descriptor, or None when locks are not available."""
    if fcntl is None:  # pragma: no cover - Windows
        notice(f"cannot lock output folder {str(path.parent)!r} on this system: make sure no other run uses it")
        return None
    while True:
        try:
            fd = os.open(path, os.O_RDWR | os.O_CREAT | getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_CLOEXEC", 0),
                         0o666)
        except OSError as exc:  # a read-only folder, or a lock path that is not a file
            notice(f"cannot lock output folder {str(path.parent)!r} ({exc.strerror or exc}): make sure no other run "
                   "uses it")
            return None
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            holder = _holder(fd)
            os.close(fd)
            raise OutputFolderError(f"{where}: output folder {str(path.parent)!r} is in use by another run ({holder}): "
                                    f"{remedy}") from None
        except OSError as exc:  # no flock on this file system
            os.close(fd)
            notice(f"cannot lock output folder {str(path.parent)!r} ({exc.strerror or exc}): make sure no other run "
                   "uses it")
            return None
        try:
            same = os.stat(path, follow_symlinks=False).st_ino == os.fstat(fd).st_ino
        except FileNotFoundError:
            same = False
        if same:
            return fd
        os.close(fd)  # the holder removed the file after we opened it: lock the new one


@contextmanager
def folder_lock(folder: str | Path, where: str = "run",
                remedy: str = "wait for it to end, or use another output folder") -> Iterator[None]:
    """Hold the lock of ``folder`` (an existing folder) in the block; OutputFolderError naming the
    folder and the other run when another run holds it."""
    folder = Path(folder)
    key = os.path.realpath(folder)
    me = threading.get_ident()
    with _GUARD:
        held = _HELD.get(key)
        if held is not None:
            if held.thread != me:
                raise OutputFolderError(f"{where}: output folder {str(folder)!r} is in use by another run of this "
                                        f"process (thread {held.thread}): {remedy}")
            held.count += 1
        else:
            path = Path(key) / LOCK_NAME
            fd = _acquire(path, where, remedy)
            if fd is not None:
                info = {"pid": os.getpid(), "host": socket.gethostname(),
                        "started": time.strftime("%Y-%m-%d %H:%M:%S"), "command": " ".join(sys.argv)[:400]}
                os.ftruncate(fd, 0)
                os.pwrite(fd, json.dumps(info).encode("utf-8"), 0)
            held = _HELD[key] = _Held(fd, me, 1)
    try:
        yield
    finally:
        with _GUARD:
            held.count -= 1
            if held.count == 0:
                del _HELD[key]
                if held.fd is not None:
                    try:
                        os.unlink(Path(key) / LOCK_NAME)  # while still locked (see the module docstring)
                    except OSError:
                        pass
                    os.close(held.fd)


def held_here(folder: str | Path) -> bool:
    """Whether this process holds the lock of ``folder``."""
    return os.path.realpath(folder) in _HELD


__all__ = ["LOCK_NAME", "folder_lock", "held_here"]
