"""Reading files a user named, defensively: regular files only, bounded size, never blocking.

A path given to tb_exudyn (a scenario, a spectrum table, a result folder's files) may point at
anything: a FIFO (reading blocks forever), a device such as ``/dev/zero`` (reading never ends), a
directory, or a symbolic link to any of those. :func:`read_regular` opens the path without
blocking (``O_NONBLOCK``), checks with ``fstat`` on the open descriptor that it is a regular file
(so the check and the read concern the same file), refuses it when it is larger than the caller's
limit, and reads at most that many bytes. With ``follow_symlinks=False`` a symbolic link itself is
refused (``O_NOFOLLOW``): files inside a result folder must be the folder's own.

Refusals raise :class:`FileRefused` with a short reason; each caller turns it into its own
one-line user error (ScenarioError, ResultsError, SpectrumError) naming the file.
"""

from __future__ import annotations

import errno
import os
import stat
from pathlib import Path
from typing import BinaryIO

MIB = 1024 * 1024


class FileRefused(Exception):
    """A path is not a regular file that may be read (the message says why, without the path)."""


def _kind(mode: int) -> str:
    if stat.S_ISDIR(mode):
        return "a directory"
    if stat.S_ISFIFO(mode):
        return "a FIFO (named pipe)"
    if stat.S_ISCHR(mode) or stat.S_ISBLK(mode):
        return "a device"
    if stat.S_ISSOCK(mode):
        return "a socket"
    return "not a regular file"


def _size_text(n: int) -> str:
    return f"{n / MIB:.3g} MiB" if n >= MIB else f"{n} bytes"


def open_regular(path: str | Path, *, max_bytes: int | None, follow_symlinks: bool) -> BinaryIO:
    """Open ``path`` for binary reading if it is a regular file of at most ``max_bytes`` bytes.

    Never blocks (a FIFO is opened non-blocking and then refused) and never opens a device that a
    ``stat`` already shows to be one. Raises FileNotFoundError when the path does not exist and
    FileRefused for a symbolic link (``follow_symlinks=False``), a FIFO, device, socket or
    directory, an unreadable file, or a file over the size limit.
    """
    path = Path(path)
    try:
        st = os.stat(path, follow_symlinks=follow_symlinks)
    except FileNotFoundError:
        raise
    except OSError as exc:
        raise FileRefused(f"cannot be read ({exc.strerror or exc})") from None
    if not follow_symlinks and stat.S_ISLNK(st.st_mode):
        raise FileRefused(f"is a symbolic link (to {os.readlink(path)!r}): only regular files are read here")
    if not stat.S_ISREG(st.st_mode):
        raise FileRefused(f"is {_kind(st.st_mode)}, not a regular file")
    flags = os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0) | getattr(os, "O_BINARY", 0)
    if not follow_symlinks:
        flags |= getattr(os, "O_NOFOLLOW", 0)
    try:
        fd = os.open(path, flags)
    except FileNotFoundError:
        raise
    except OSError as exc:
        if exc.errno == errno.ELOOP:
            raise FileRefused("is a symbolic link: only regular files are read here") from None
        raise FileRefused(f"cannot be read ({exc.strerror or exc})") from None
    try:
        st = os.fstat(fd)  # the file actually opened (it may have been swapped since the stat)
        if not stat.S_ISREG(st.st_mode):
            raise FileRefused(f"is {_kind(st.st_mode)}, not a regular file")
        if max_bytes is not None and st.st_size > max_bytes:
            raise FileRefused(f"is {_size_text(st.st_size)}, more than the {_size_text(max_bytes)} allowed")
        if hasattr(os, "set_blocking"):
            os.set_blocking(fd, True)
        return os.fdopen(fd, "rb")
    except BaseException:
        os.close(fd)
        raise


def read_regular(path: str | Path, *, max_bytes: int, follow_symlinks: bool) -> bytes:
    """The bytes of a regular file of at most ``max_bytes`` bytes (see :func:`open_regular`).

    Reads at most ``max_bytes + 1`` bytes, so a file that grows while it is read is refused too.
    """
    with open_regular(path, max_bytes=max_bytes, follow_symlinks=follow_symlinks) as fh:
        data = fh.read(max_bytes + 1)
    if len(data) > max_bytes:
        raise FileRefused(f"holds more than the {_size_text(max_bytes)} allowed")
    return data


def decode_utf8(data: bytes) -> str:
    """``data`` as UTF-8 text; FileRefused saying where the first invalid byte is."""
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = data.count(b"\n", 0, exc.start) + 1
        raise FileRefused(f"is not UTF-8 text (byte 0x{data[exc.start]:02x} at offset {exc.start}, "
                          f"line {line})") from None


def read_text(path: str | Path, *, max_bytes: int, follow_symlinks: bool = True) -> str:
    """UTF-8 text of a regular file of at most ``max_bytes`` bytes; FileRefused otherwise."""
    return decode_utf8(read_regular(path, max_bytes=max_bytes, follow_symlinks=follow_symlinks))


__all__ = ["MIB", "FileRefused", "decode_utf8", "open_regular", "read_regular", "read_text"]
