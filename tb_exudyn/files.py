"""Files a user named, read and written defensively: regular files only, bounded size, never blocking.

A path given to tb_exudyn (a scenario, a spectrum table, a result folder's files) may point at
anything: a FIFO (reading blocks forever), a device such as ``/dev/zero`` (reading never ends), a
directory, or a symbolic link to any of those. :func:`read_regular` opens the path without
blocking (``O_NONBLOCK``), checks with ``fstat`` on the open descriptor that it is a regular file
(so the check and the read concern the same file), refuses it when it is larger than the caller's
limit, and reads at most that many bytes. With ``follow_symlinks=False`` a symbolic link itself is
refused (``O_NOFOLLOW``): files inside a result folder must be the folder's own.

Refusals raise :class:`FileRefused` with a short reason; each caller turns it into its own
one-line user error (ScenarioError, ResultsError, SpectrumError) naming the file.

Writing a file the user named (``tb-exudyn export --output``, ``report --html``):
:func:`output_targets` refuses, before anything is computed or written, a target inside a result
folder (one holding ``meta.json`` and ``arrays.npz``) or a checkpoint folder (``manifest.json`` and
``tasks/``), which own their files; a target that is not a regular file (FIFO, device, directory,
socket, or a symbolic link to one or to nothing; nothing is opened); and an existing regular file
unless told to overwrite (a symbolic link to a regular file is then written through: the file it
points to is replaced). The same for each sidecar file written beside the target.
:func:`write_output` writes the files atomically (:mod:`tb_exudyn.atomic`) after checking the free
space for the bytes to write, so a full disk leaves the target as it was and no temporary file.
Both raise :class:`~tb_exudyn.errors.OutputFolderError`, one line naming the file and the option
(``where``/``key``: the caller and its argument, e.g. ``export`` and ``path``; the parts are kept on
the error, and a caller that names things otherwise, the command line, restates it).
"""

from __future__ import annotations

import errno
import os
import re
import stat
import tempfile
from pathlib import Path
from typing import BinaryIO, Callable, Sequence, Union

from .atomic import write_atomic_group
from .errors import OutputFolderError

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


def entry_kind(path: str | Path) -> str | None:
    """What ``path`` is when it is not a regular file or a symbolic link ('a directory', 'a FIFO (named
    pipe)', ...); None for a regular file, a symbolic link or nothing."""
    try:
        mode = os.lstat(path).st_mode
    except FileNotFoundError:
        return None
    return None if stat.S_ISREG(mode) or stat.S_ISLNK(mode) else _kind(mode)


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
        raise FileRefused(f"not UTF-8 (byte 0x{data[exc.start]:02x} at offset {exc.start}, "
                          f"line {line})") from None


def read_text(path: str | Path, *, max_bytes: int, follow_symlinks: bool = True) -> str:
    """UTF-8 text of a regular file of at most ``max_bytes`` bytes; FileRefused otherwise."""
    return decode_utf8(read_regular(path, max_bytes=max_bytes, follow_symlinks=follow_symlinks))


# ============================================================================================ writing
#: the entries by which a result folder (tb_exudyn.storage.RESULT_FILES) and a checkpoint
#: folder (tb_exudyn.execution.checkpoint) are recognised; such folders own everything inside them
RESULT_FOLDER_FILES = ("arrays.npz", "meta.json")
CHECKPOINT_FOLDER_FILES = ("manifest.json", "tasks")
#: free space asked beyond the bytes of the files: this many file-system blocks per file (the last,
#: partly filled block and metadata), plus 1 % of the bytes
SPACE_MARGIN_BLOCKS = 2


#: how a message names the argument that replaces an existing file
OVERWRITE = "overwrite=True"


def _refused(where: str, key: str, named: Path, what: str, allowed: str) -> OutputFolderError:
    """``WHERE: key 'KEY' = 'PATH': WHAT (allowed: ALLOWED)``, the path in full."""
    return OutputFolderError(f"{where}: key '{key}' = {str(named)!r}: {what} (allowed: {allowed})", where=where,
                             key=key, value=str(named), allowed=allowed, reason=what)


def owning_folder(path: Path) -> str | None:
    """The result or checkpoint folder that ``path`` (resolved) would be written into, if any, as a
    phrase ('the result folder 'X''); these folders hold only their own files."""
    return _owner(path)


def _owner(path: Path) -> str | None:
    """The result or checkpoint folder that ``path`` (resolved) would be written into, if any."""
    if path.name in RESULT_FOLDER_FILES and any(os.path.lexists(path.parent / n) for n in RESULT_FOLDER_FILES):
        return f"the result folder {str(path.parent)!r} (its {path.name})"
    for folder in (path.parent, *path.parent.parents):
        if all(os.path.lexists(folder / n) for n in RESULT_FOLDER_FILES):
            return f"the result folder {str(folder)!r}"
        if all(os.path.lexists(folder / n) for n in CHECKPOINT_FOLDER_FILES):
            return f"the checkpoint folder {str(folder)!r}"
    return None


def _target(path: Path, named: Path, label: str, *, overwrite: bool, derived: bool, where: str, key: str) -> Path:
    """The path to write for one target (see :func:`output_targets`)."""
    opt = OVERWRITE
    allowed = f"a new file, or an existing regular file with {opt}"
    try:
        st = os.lstat(path)
    except FileNotFoundError:
        st = None
    except OSError as exc:  # e.g. a file where a folder of the path should be
        raise _refused(where, key, named, f"{label}cannot be written there ({exc.strerror or exc})",
                       "a file whose folders are folders") from None
    real = path
    if st is not None and stat.S_ISLNK(st.st_mode):
        link = os.readlink(path)
        if derived:  # the command's own file in a folder it owns: never written through a link
            raise _refused(where, key, named, f"{label}is a symbolic link (to {link!r}), not the folder's own file",
                           "a regular file, or no file")
        try:
            st = os.stat(path)
        except OSError:
            raise _refused(where, key, named, f"{label}is a symbolic link to {link!r}, which does not exist",
                           allowed) from None
        real = Path(os.path.realpath(path))
        if not stat.S_ISREG(st.st_mode):
            raise _refused(where, key, named, f"{label}is a symbolic link to {_kind(st.st_mode)} ({link!r}), not a "
                                              "regular file", allowed)
    elif st is not None and not stat.S_ISREG(st.st_mode):
        raise _refused(where, key, named, f"{label}is {_kind(st.st_mode)}, not a regular file", allowed)
    if not derived:
        owner = _owner(Path(os.path.realpath(real)))
        if owner is not None:
            raise _refused(where, key, named, f"{label}is inside {owner}, which holds only the result's own files: "
                                              "writing there would damage it",
                           "a file outside result and checkpoint folders")
        if st is not None and not overwrite:
            raise _refused(where, key, named, f"{label}exists", f"a new file name, or {opt} to replace the file")
    return real


def output_targets(path: str | Path, *, sidecars: Sequence[str | Path] = (), overwrite: bool = False,
                   derived: bool = False, where: str, key: str) -> list[Path]:
    """Check a file the user named (and the sidecar files written beside it) before writing it
    (see the module docstring); returns the paths to write, the target's first.

    ``derived``: the target is the command's own default file (a folder's ``report.html``, rewritten
    every time): only a target that is not a regular file (a symbolic link included) is refused.
    Raises OutputFolderError.
    """
    named = Path(path)
    out = [_target(named, named, "", overwrite=overwrite, derived=derived, where=where, key=key)]
    for side in sidecars:
        side = Path(side)
        out.append(_target(side, named, f"its sidecar file {str(side)!r} ", overwrite=overwrite, derived=derived,
                           where=where, key=key))
    return out


def _free_space(folder: Path) -> tuple[int, int] | None:
    """(bytes free to this user, block size) of the file system of ``folder`` (or of its nearest
    existing parent); None where it cannot be known."""
    p = folder
    while not os.path.isdir(p) and p != p.parent:
        p = p.parent
    try:
        st = os.statvfs(p)
    except (OSError, AttributeError):
        return None
    return st.f_bavail * st.f_frsize, st.f_frsize


Content = Union[bytes, memoryview, Callable[[Path], object]]


def write_output(items: Sequence[tuple[Path, Content]], *, named: str | Path, overwrite: bool, where: str, key: str,
                 size: int | None = None, remove: Sequence[Path] = ()) -> list[Path]:
    """Write the files ``items`` (path, bytes or ``write(temporary path)``) checked by
    :func:`output_targets`, atomically and as one (:func:`tb_exudyn.atomic.write_atomic_group`).

    First the free space is checked against the bytes to write (plus ``size``, an estimate for the
    callables) and a margin (SPACE_MARGIN_BLOCKS blocks per file, 1 %); any OSError of the write (a
    full disk after all, no permission) is an OutputFolderError naming ``named`` and the file that
    failed; nothing is left behind. ``overwrite=False``: a file that appeared meanwhile is not
    replaced (the files of the group already in place are taken back). ``remove``: stale files of an
    earlier write that this one has no counterpart for, removed with the renames (a Ctrl-C there is
    held until they are done)."""
    named = Path(named)
    need = sum(memoryview(c).nbytes for _, c in items if not callable(c)) + (size or 0)
    space = _free_space(Path(items[0][0]).parent)
    if space is not None:
        free, block = space
        want = need + len(items) * SPACE_MARGIN_BLOCKS * block + need // 100
        if want > free:
            raise _refused(where, key, named,
                           f"needs {_size_text(need)} but its file system has {_size_text(free)} free",
                           f"a place with at least {_size_text(want)} free")

    def writer(content: Content) -> Callable[[Path], object]:
        if callable(content):
            return content
        def write(tmp: Path) -> None:
            with open(tmp, "wb") as fh:
                fh.write(content)
        return write

    paths = [Path(p) for p, _ in items]
    try:
        return write_atomic_group([(p, writer(c)) for p, c in zip(paths, (c for _, c in items))], replace=overwrite,
                                  remove=remove)
    except FileExistsError as exc:
        raise _refused(where, key, named, f"{_which(exc, paths)}appeared while it was written: not replaced",
                       f"a new file name, or {OVERWRITE} to replace the file") from None
    except OSError as exc:
        raise _refused(where, key, named, f"{_which(exc, paths)}cannot be written ({exc.strerror or exc})",
                       "a file in a writable folder with room for it") from None


def _which(exc: OSError, paths: Sequence[Path]) -> str:
    """'' when the error concerns the first file (or its temporary file) or no file, else 'its sidecar file X '."""
    name = getattr(exc, "filename", None)
    if not name:
        return ""
    base = Path(name).name
    for i, p in enumerate(paths):
        if base == p.name or re.fullmatch(rf"\.{re.escape(p.name)}\.[^.]+\.tmp", base):
            return "" if i == 0 else f"its sidecar file {str(p)!r} "
    return f"file {str(name)!r} "


#: what an output folder may be, for the messages of check_writable
WRITABLE_FOLDER = "a folder this user can create files in, or a new folder's path under one"


def check_writable(folder: str | Path, *, create: bool = True) -> Path:
    """Create ``folder`` if needed and check that files can be written there (before any run starts).

    ``create=False``: the same checks read only, nothing created or written, for a command that checks
    its output folder before its other arguments: the folder, or for a new one the nearest existing
    folder of its path, must be a folder this user may write in (``os.access``). A place only a write
    can test (/proc, /sys, a read-only folder for root, whom permissions do not stop) is found by the
    call with ``create=True`` that follows before any work.

    Raises OutputFolderError (an OSError the CLI reports as a user error) naming the folder, why it is
    not one (a file, a FIFO, a file on its path, no permission, a file system that takes no files such
    as /proc) and what is allowed (:data:`WRITABLE_FOLDER`).
    """
    folder = Path(folder)
    if not create:
        why = None if folder.is_dir() else _not_a_folder(folder)
        if why is not None:
            raise _not_writable(folder, why)
        place = folder if folder.is_dir() else next((p for p in folder.parents if p.is_dir()), None)
        if place is not None and not os.access(place, os.W_OK | os.X_OK):
            raise _not_writable(folder, "this user may not create files in it" if place == folder else
                                f"cannot be created: this user may not create files in {str(place)!r}")
        return folder
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise _not_writable(folder, _not_a_folder(folder) or f"cannot be created ({exc.strerror or exc})") from None
    try:
        fd, tmp = tempfile.mkstemp(dir=folder, prefix=".write-test.")
        os.close(fd)
        os.unlink(tmp)
    except OSError as exc:
        raise _not_writable(folder, f"no file can be created in it ({exc.strerror or exc})") from None
    return folder


def _not_writable(folder: Path, why: str) -> OutputFolderError:
    return OutputFolderError(f"output folder {str(folder)!r} is not writable: {why} (allowed: {WRITABLE_FOLDER})",
                             key="out", value=str(folder), allowed=WRITABLE_FOLDER, reason=why)


def _not_a_folder(folder: Path) -> str | None:
    """Why ``folder`` cannot be a folder: it, or a path it lies under, is something else (None if not)."""
    for i, path in enumerate((folder, *folder.parents)):
        try:
            mode = os.stat(path).st_mode
        except OSError:
            continue
        if stat.S_ISDIR(mode):
            return None
        what = entry_kind(path) or "a file"
        return f"it is {what}" if i == 0 else f"{str(path)!r} on its path is {what}, not a folder"
    return None


__all__ = ["CHECKPOINT_FOLDER_FILES", "MIB", "RESULT_FOLDER_FILES", "SPACE_MARGIN_BLOCKS", "FileRefused", "decode_utf8",
           "check_writable", "entry_kind", "open_regular", "output_targets", "owning_folder", "read_regular", "read_text",
           "write_output"]
