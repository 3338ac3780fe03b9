"""Result files: arrays as npz plus JSON metadata; folders written whole, files read defensively.

A result folder holds ``arrays.npz`` (plain ``np.savez``, uncompressed) and ``meta.json``; a
checkpoint folder holds one small npz per finished task. Nothing is pickled: opening someone's
results cannot run code.

Writing (:func:`save_result_folder`): both files are written into a hidden temporary sibling
folder ``.<name>.tb-<host>-<pid>-<token>.writing``, flushed to disk, renamed ``....new`` (complete),
and then swapped into place (the old folder is renamed ``....old``, the new one takes its name,
the old one is deleted). A process killed at any point leaves either the old folder or the new
one under the folder's name, never the old metadata over new arrays. Leftovers of a killed
write are resolved the next time the folder is written or loaded (:func:`recover_folder`): a
``.writing`` folder is deleted, a complete ``.new`` one is put in place if the folder is missing
(else deleted), an ``.old`` one restored if the folder is missing (else deleted); hidden
``.arrays.npz.*.tmp`` / ``.meta.json.*.tmp`` files of killed file-by-file writes are deleted.
Leftovers of a process that is still running on this machine are left alone.

Reading (:func:`load_json`, :class:`NpzFile`, :func:`open_result_folder`): files inside a result
folder must be regular files (no symbolic links, FIFOs or devices; :mod:`tb_exudyn.files`); JSON is
limited in size and depth; every npz member's header (dtype, shape) is read and checked against
the member's size, and the caller checks the shapes against the metadata and each other, before
any data is read (:func:`check_members`), then the values (:func:`check_values`: finite, >= 0,
magnitudes). Every failure is a one-line :class:`ResultsError` naming the file and what is wrong.
Loaded arrays are made read-only (:func:`freeze`).

Saving runs the format's reading checks first on what would be written (:func:`check_before_save`,
the arrays seen as an npz by :class:`ArraysInMemory`, the metadata as JSON gives it back): a result
changed in Python into something that would not load is refused, nothing written.
"""

from __future__ import annotations

import hashlib
import json
import math
import os
import re
import secrets
import shutil
import socket
import time
import zipfile
from dataclasses import dataclass
from pathlib import Path
from typing import Any, BinaryIO, Callable, Iterator, Mapping, Sequence

import numpy as np

from .atomic import write_atomic, write_text_atomic
from .errors import OutputFolderError, ResultsError
from .files import MIB, FileRefused, check_writable, decode_utf8, open_regular, read_regular  # noqa: F401 (check_writable: its old home)

#: the files of a result folder, and what a save may replace with them (derived from the old result)
RESULT_FILES = ("arrays.npz", "meta.json")
DERIVED_ENTRIES = ("figures", "report.html")
MAX_JSON_BYTES = 16 * MIB
MAX_JSON_DEPTH = 64
MAX_NPZ_MEMBERS = 64
#: the largest magnitude of a stored value (a response, a standard deviation, a time) and of a stored square
#: (a PSD, a variance): squares and products of two values, and conversions to display units (x 1e3 for
#: mm, kN), stay far from the 1.8e308 a double holds; no response of a train on a bridge comes near
#: either in SI units (forces are below 1e8 N)
MAX_VALUE = 1e100
MAX_SQUARE = 1e200
#: leftovers of a write by another machine (same host name hash unknown to be dead) are kept this long [s]
FOREIGN_LEFTOVER_AGE = 24 * 3600.0
_MEMBER = re.compile(r"[A-Za-z_][A-Za-z0-9_]{0,63}\.npy\Z")
_LEGACY_TMP = re.compile(r"\.(arrays\.npz|meta\.json)\..+\.tmp\Z")


# ============================================================================================ writing
def save_npz_atomic(path: str | Path, arrays: Mapping[str, np.ndarray]) -> None:
    """Write arrays to ``path`` (.npz, uncompressed) atomically; object arrays are refused."""
    _refuse_objects(arrays)
    write_atomic(Path(path), lambda fh: np.savez(fh, **{k: np.asarray(v) for k, v in arrays.items()}))


def save_json_atomic(path: str | Path, meta: Mapping[str, Any]) -> None:
    write_text_atomic(path, _json_text(meta))


def _json_text(meta: Mapping[str, Any]) -> str:
    return json.dumps(meta, indent=2, sort_keys=True, default=json_default)


def _refuse_objects(arrays: Mapping[str, Any]) -> None:
    for name, a in arrays.items():
        if np.asarray(a).dtype == object:
            raise TypeError(f"array {name!r} has dtype object: not storable without pickle")


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


def _host_tag() -> str:
    return hashlib.sha256(socket.gethostname().encode("utf-8", "replace")).hexdigest()[:8]


def _leftover_pattern(name: str) -> re.Pattern[str]:
    return re.compile(rf"\.{re.escape(name)}\.tb-([0-9a-f]{{8}})-(\d+)-([0-9a-f]+)\.(writing|new|old)\Z")


def _fsync_file(path: Path) -> None:
    fd = os.open(path, os.O_RDONLY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


def _fsync_dir(path: Path) -> None:
    try:
        _fsync_file(path)
    except OSError:  # some file systems cannot sync a directory; the data files are synced
        pass


def _remove(path: Path) -> None:
    if path.is_dir() and not path.is_symlink():
        shutil.rmtree(path, ignore_errors=True)
    else:
        try:
            path.unlink()
        except FileNotFoundError:
            pass


def _writer_alive(host: str, pid: int, path: Path) -> bool:
    """Whether the process that made a leftover may still be writing it."""
    if host != _host_tag():
        try:
            return time.time() - path.lstat().st_mtime < FOREIGN_LEFTOVER_AGE
        except OSError:
            return False
    if pid == os.getpid():
        return False  # this process is not writing this folder now (saves are not re-entrant)
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    except OSError:
        return False
    return True


def recover_folder(folder: str | Path) -> None:
    """Resolve the leftovers of killed writes of ``folder`` (see the module docstring).

    Best effort: an entry that cannot be removed (read-only place) is left; never raises OSError.
    """
    folder = Path(folder)
    parent, name = folder.parent, folder.name
    pattern = _leftover_pattern(name)
    found: dict[str, list[Path]] = {"writing": [], "new": [], "old": []}
    try:
        with os.scandir(parent) as it:
            for entry in it:
                m = pattern.match(entry.name)
                if m and not _writer_alive(m.group(1), int(m.group(2)), Path(entry.path)):
                    found[m.group(4)].append(Path(entry.path))
    except OSError:
        return
    try:
        for path in found["writing"]:
            _remove(path)
        for state in ("new", "old"):  # a complete new result first, else the old one
            for path in sorted(found[state], key=lambda p: p.lstat().st_mtime, reverse=True):
                if not os.path.lexists(folder) and path.is_dir() and not path.is_symlink():
                    os.rename(path, folder)
                else:
                    _remove(path)
        if folder.is_dir() and not folder.is_symlink():
            with os.scandir(folder) as it:
                for entry in it:
                    if _LEGACY_TMP.match(entry.name) and entry.is_file(follow_symlinks=False):
                        os.unlink(entry.path)
    except OSError:
        pass


def _check_replaceable(folder: Path) -> None:
    """Refuse to replace a folder holding anything but a result and what was derived from it."""
    if not os.path.lexists(folder):
        return
    if folder.is_symlink() or not folder.is_dir():
        raise OutputFolderError(f"result folder {str(folder)!r} exists and is not a folder: not replacing it")
    keep = set(RESULT_FILES) | set(DERIVED_ENTRIES)
    extras = sorted(n for n in os.listdir(folder) if n not in keep)
    if extras:
        raise OutputFolderError(
            f"result folder {str(folder)!r} holds {extras[0]!r}{f' and {len(extras) - 1} more' if len(extras) > 1 else ''}, "
            f"not part of a tb_exudyn result: not replaced (move it away or save elsewhere)")


def _write_file(path: Path, write: Callable[[BinaryIO], object]) -> None:
    """Create ``path`` (it must not exist), fill it with ``write(file)`` and flush it to disk."""
    with open(path, "xb") as fh:
        write(fh)
        fh.flush()
        os.fsync(fh.fileno())


#: a format's check of a folder's contents before they are written: (folder, arrays, meta as JSON gives it back)
FolderCheck = Callable[[Path, Mapping[str, np.ndarray], dict[str, Any]], None]


def check_before_save(folder: Path, arrays: Mapping[str, np.ndarray], text: str, check: FolderCheck) -> None:
    """Run the checks ``load`` would run on ``arrays`` and the metadata ``text`` (as JSON), before
    anything is written: ResultsError naming the file and the key, ending ``[not saved: ...]``."""
    try:
        meta_path = folder / "meta.json"
        size = len(text.encode("utf-8"))
        if size > MAX_JSON_BYTES:
            raise _error(meta_path, f"{size} bytes, more than the {MAX_JSON_BYTES} allowed")
        meta = json.loads(text)
        depth = json_depth(meta)
        if depth > MAX_JSON_DEPTH:
            raise _error(meta_path, f"JSON nested {depth} deep, more than the {MAX_JSON_DEPTH} allowed")
        check(folder, arrays, meta)
    except ResultsError as exc:
        raise ResultsError(f"{exc} [not saved]") from None


def save_result_folder(folder: str | Path, arrays: Mapping[str, np.ndarray], meta: Mapping[str, Any],
                       check: FolderCheck | None = None) -> Path:
    """Write ``arrays.npz`` and ``meta.json`` as the folder ``folder``, whole or not at all.

    ``check``: the format's load-time checks, run first on what would be written (nothing is
    written if they refuse it: :func:`check_before_save`), so that a save never leaves a folder
    that does not load. An existing result folder is replaced (with its figures and report, which
    belong to the old result); a folder holding anything else is refused (OutputFolderError). A
    symbolic link to a folder is followed (the folder it points to is replaced). Returns ``folder``.
    """
    _refuse_objects(arrays)
    arrays = {k: np.asarray(v) for k, v in arrays.items()}
    json_text = _json_text(meta)  # fails on unstorable metadata before anything is written
    if check is not None:
        check_before_save(Path(folder), arrays, json_text, check)
    text = json_text.encode("utf-8")
    given = Path(folder)
    folder = Path(os.path.realpath(given))
    parent, name = folder.parent, folder.name
    try:
        parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise OutputFolderError(f"output folder {str(parent)!r} cannot be created: {exc.strerror or exc}") from None
    recover_folder(folder)
    _check_replaceable(folder)
    stem = f".{name}.tb-{_host_tag()}-{os.getpid()}-{secrets.token_hex(4)}"
    writing, ready, old = parent / f"{stem}.writing", parent / f"{stem}.new", parent / f"{stem}.old"
    moved_old = False
    try:
        os.mkdir(writing)
        _write_file(writing / "arrays.npz", lambda fh: np.savez(fh, **arrays))
        _write_file(writing / "meta.json", lambda fh: fh.write(text))
        _fsync_dir(writing)
        os.rename(writing, ready)  # complete from here on: recover_folder may put it in place
        if os.path.lexists(folder):
            os.rename(folder, old)
            moved_old = True
        os.rename(ready, folder)
        _fsync_dir(parent)
    except BaseException:
        for path in (writing, ready):
            _remove(path)
        if moved_old and not os.path.lexists(folder):
            os.rename(old, folder)
        raise
    if moved_old:
        _remove(old)
    return given


# ============================================================================================ reading
def _error(path: Path | str, what: str) -> ResultsError:
    return ResultsError(f"{path}: {what}")


def load_json(path: str | Path, *, max_bytes: int = MAX_JSON_BYTES, max_depth: int = MAX_JSON_DEPTH) -> dict[str, Any]:
    """A JSON object from a regular file (no symbolic link) of at most ``max_bytes``, nested at most
    ``max_depth`` deep. ResultsError naming the file otherwise."""
    path = Path(path)
    try:
        text = decode_utf8(read_regular(path, max_bytes=max_bytes, follow_symlinks=False))
    except FileNotFoundError:
        raise _error(path, "file not found") from None
    except FileRefused as exc:
        raise _error(path, str(exc)) from None
    try:
        data = json.loads(text)
    except RecursionError:
        raise _error(path, f"JSON nested more than {max_depth} deep") from None
    except ValueError as exc:
        raise _error(path, f"not valid JSON ({exc})") from None
    depth = json_depth(data)
    if depth > max_depth:
        raise _error(path, f"JSON nested {depth} deep, more than the {max_depth} allowed")
    if not isinstance(data, dict):
        raise _error(path, f"holds a JSON {type(data).__name__}, expected an object")
    return data


def json_depth(value: Any) -> int:
    """Nesting depth of parsed JSON (a scalar is 0, ``[]`` is 1), without recursion."""
    depth, stack = 0, [(value, 1)]
    while stack:
        item, level = stack.pop()
        if isinstance(item, dict):
            depth = max(depth, level)
            stack.extend((v, level + 1) for v in item.values())
        elif isinstance(item, list):
            depth = max(depth, level)
            stack.extend((v, level + 1) for v in item)
    return depth


@dataclass(frozen=True)
class ArrayHeader:
    """What an npz member declares: dtype, shape, memory order, and where its data starts."""

    name: str
    dtype: np.dtype
    shape: tuple[int, ...]
    fortran_order: bool
    data_offset: int

    @property
    def nbytes(self) -> int:
        return math.prod(self.shape) * self.dtype.itemsize


class NpzFile:
    """An npz file opened for defensive reading (a context manager).

    On opening, the file must be a regular file (no symbolic link), a zip whose members are
    uncompressed ``<name>.npy`` arrays of a plain numeric or fixed-width string dtype (no objects,
    no records) whose declared shape and dtype account exactly for the member's size. ``headers`` then holds every
    member's :class:`ArrayHeader`; :meth:`read` allocates and reads one array (its CRC checked).
    """

    def __init__(self, path: str | Path) -> None:
        self.path = Path(path)
        try:
            self._fh: BinaryIO = open_regular(self.path, max_bytes=None, follow_symlinks=False)
        except FileNotFoundError:
            raise _error(self.path, "file not found") from None
        except FileRefused as exc:
            raise _error(self.path, str(exc)) from None
        try:
            size = os.fstat(self._fh.fileno()).st_size
            try:
                self._zip = zipfile.ZipFile(self._fh)
            except (zipfile.BadZipFile, zipfile.LargeZipFile, OSError, ValueError, EOFError) as exc:
                raise _error(self.path, f"not an npz (zip) file ({exc})") from None
            infos = self._zip.infolist()
            if len(infos) > MAX_NPZ_MEMBERS:
                raise _error(self.path, f"holds {len(infos)} members, more than the {MAX_NPZ_MEMBERS} allowed")
            self.headers: dict[str, ArrayHeader] = {}
            for info in infos:
                header = self._header(info, size)
                if header.name in self.headers:
                    raise _error(self.path, f"holds the array {header.name!r} twice")
                self.headers[header.name] = header
        except BaseException:
            self._fh.close()
            raise

    def _header(self, info: zipfile.ZipInfo, size: int) -> ArrayHeader:
        if not _MEMBER.match(info.filename):
            raise _error(self.path, f"member {info.filename[:80]!r} is not an array of a plain name (NAME.npy)")
        name = info.filename[:-4]
        if info.compress_type != zipfile.ZIP_STORED:
            raise _error(self.path, f"array {name!r} is compressed; result files hold uncompressed arrays "
                                    "(numpy.savez, not savez_compressed)")
        if info.file_size > size or info.compress_size != info.file_size:
            raise _error(self.path, f"array {name!r} declares {info.file_size} bytes, more than the file holds")
        try:
            with self._zip.open(info) as m:
                version = np.lib.format.read_magic(m)
                if version == (1, 0):
                    shape, fortran, dtype = np.lib.format.read_array_header_1_0(m)
                elif version == (2, 0):
                    shape, fortran, dtype = np.lib.format.read_array_header_2_0(m)
                else:
                    raise ValueError(f"npy format version {version} (1.0 or 2.0 expected)")
                offset = m.tell()
        except (ValueError, OSError, EOFError, zipfile.BadZipFile, SyntaxError, TypeError) as exc:
            raise _error(self.path, f"array {name!r} is damaged or not an npy array ({exc})") from None
        dtype = np.dtype(dtype)
        if dtype.hasobject:
            raise _error(self.path, f"array {name!r} holds Python objects (dtype {dtype}): refused, never unpickled")
        if dtype.fields is not None or dtype.subdtype is not None or dtype.kind not in "biufcSU":
            raise _error(self.path, f"array {name!r} has dtype {dtype}: only plain numbers and strings are read")
        if not all(isinstance(d, int) and d >= 0 for d in shape):
            raise _error(self.path, f"array {name!r} declares the shape {shape!r}")
        header = ArrayHeader(name, dtype, tuple(shape), bool(fortran), offset)
        if offset + header.nbytes != info.file_size:
            raise _error(self.path, f"array {name!r} declares shape {header.shape} of {dtype} ({header.nbytes} bytes) "
                                    f"but the file holds {info.file_size - offset} bytes of data for it")
        return header

    def read(self, name: str) -> np.ndarray:
        """Read one array (its header already checked); ResultsError if its data are damaged."""
        h = self.headers[name]
        shape = h.shape[::-1] if h.fortran_order else h.shape
        out = np.empty(shape, dtype=h.dtype)
        view = memoryview(out.reshape(-1)).cast("B") if out.size else memoryview(bytearray(0))
        try:
            with self._zip.open(f"{name}.npy") as m:
                m.read(h.data_offset)
                pos, chunk = 0, 16 * MIB
                while pos < h.nbytes:
                    piece = m.read(min(chunk, h.nbytes - pos))
                    if not piece:
                        break
                    view[pos:pos + len(piece)] = piece
                    pos += len(piece)
                rest = m.read(1)  # reaching the end checks the CRC
        except (zipfile.BadZipFile, OSError, EOFError, ValueError) as exc:
            raise _error(self.path, f"array {name!r} is damaged ({exc})") from None
        if pos != h.nbytes or rest:
            raise _error(self.path, f"array {name!r} holds {pos} bytes of data, its header declares {h.nbytes}")
        return out.T if h.fortran_order else out

    def read_all(self) -> dict[str, np.ndarray]:
        return {name: self.read(name) for name in self.headers}

    def close(self) -> None:
        self._zip.close()
        self._fh.close()

    def __enter__(self) -> "NpzFile":
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def load_npz(path: str | Path) -> dict[str, np.ndarray]:
    """Every array of an npz file, read defensively (see :class:`NpzFile`; never unpickles)."""
    with NpzFile(path) as npz:
        return npz.read_all()


@dataclass(frozen=True)
class Member:
    """What a result format expects of one npz member: dims (ints, or names bound on first use),
    whether it must be present, whether its values must all be finite, whether they must be >= 0
    (a standard deviation, a PSD, a frequency or a width; NaN, where allowed, is not negative), and
    the largest magnitude of its finite values (:data:`MAX_VALUE`, :data:`MAX_SQUARE`)."""

    dims: tuple[int | str, ...]
    required: bool = True
    finite: bool = True
    nonnegative: bool = False
    max_abs: float = math.inf


def check_members(npz: NpzFile, spec: Mapping[str, Member], sizes: dict[str, int], meaning: Mapping[str, str]) -> None:
    """Check the npz headers against a format's members before any data is read.

    ``sizes`` binds dimension names already known from the metadata (e.g. ``nc``: the number of
    channels); a name not yet bound is bound by the first member that uses it, in ``spec`` order.
    ``meaning`` says where each name comes from, for the message. ResultsError naming the file,
    the array, its shape and the expected one.
    """
    unknown = sorted(set(npz.headers) - set(spec))
    if unknown:
        raise _error(npz.path, f"holds an unexpected array {unknown[0]!r} (expected {', '.join(spec)})")
    for name, member in spec.items():
        h = npz.headers.get(name)
        if h is None:
            if member.required:
                raise _error(npz.path, f"has no array {name!r}")
            continue
        if h.dtype.kind != "f":
            raise _error(npz.path, f"array {name!r} has dtype {h.dtype}, expected floating point numbers")
        if len(h.shape) != len(member.dims):
            raise _error(npz.path, f"array {name!r} has shape {h.shape}, expected {len(member.dims)} dimensions "
                                   f"({', '.join(_dim_text(d, meaning) for d in member.dims)})")
        for axis, (dim, n) in enumerate(zip(member.dims, h.shape)):
            want = dim if isinstance(dim, int) else sizes.setdefault(dim, n)
            if n != want:
                raise _error(npz.path, f"array {name!r} has shape {h.shape}: axis {axis} should be {want} "
                                       f"({_dim_text(dim, meaning)})")


class ArraysInMemory:
    """Arrays about to be saved seen as an opened npz (``path``, ``headers``), so that
    :func:`check_members` checks them as it would check the file."""

    def __init__(self, path: Path, arrays: Mapping[str, np.ndarray]) -> None:
        self.path = path
        self.headers = {name: ArrayHeader(name, a.dtype, tuple(a.shape), False, 0) for name, a in arrays.items()}


def freeze(arrays: Mapping[str, np.ndarray]) -> None:
    """Make loaded arrays read-only: a loaded result is what its files hold (mutate a copy)."""
    for a in arrays.values():
        a.flags.writeable = False


def _dim_text(dim: int | str, meaning: Mapping[str, str]) -> str:
    return str(dim) if isinstance(dim, int) else meaning.get(dim, dim)


def check_values(path: Path, arrays: Mapping[str, np.ndarray], spec: Mapping[str, Member]) -> None:
    """Values that must be finite are finite, values that must be >= 0 are (after reading)."""
    for name, member in spec.items():
        a = arrays.get(name)
        if a is None:
            continue
        if member.finite and not np.all(np.isfinite(a)):
            bad = int(np.size(a) - np.count_nonzero(np.isfinite(a)))
            raise _error(path, f"array {name!r} holds {bad} non-finite value(s) (NaN or inf)")
        # float32 (a kept PSD map) cannot exceed the limits: compared only where the dtype could
        large = (np.isfinite(a) & (np.abs(a) > member.max_abs) if float(np.finfo(a.dtype).max) > member.max_abs
                 else np.zeros(a.shape, dtype=bool))
        if np.any(large):
            first = tuple(int(i) for i in np.argwhere(large)[0])
            raise _error(path, f"array {name!r} holds {int(np.count_nonzero(large))} value(s) of magnitude above "
                               f"{member.max_abs:.0e}, e.g. {float(a[first])!r} at index {first} (allowed: magnitudes "
                               f"<= {member.max_abs:.0e}, so that squares and sums stay finite)")
        if member.nonnegative and np.any(a < 0):
            negative = a < 0
            first = tuple(int(i) for i in np.argwhere(negative)[0])
            raise _error(path, f"array {name!r} holds {int(np.count_nonzero(negative))} negative value(s), e.g. "
                               f"{float(a[first])!r} at index {first} (allowed: values >= 0)")


def check_increasing(path: Path, arrays: Mapping[str, np.ndarray], names: Sequence[str]) -> None:
    """The 1-D arrays ``names`` (those present) are strictly increasing (times, frequencies)."""
    for name in names:
        a = arrays.get(name)
        if a is not None and a.size > 1 and not np.all(np.diff(a) > 0):
            i = int(np.argmax(~(np.diff(a) > 0)))
            raise _error(path, f"array {name!r} is not increasing (element {i + 1} = {float(a[i + 1])!r} after "
                               f"{float(a[i])!r})")


def check_output_times(path: Path, time: np.ndarray) -> None:
    """At least two output times: a result covers a crossing (its output step is at most the crossing's
    duration, :func:`tb_exudyn.execution.resources.check_run_length`), and figures need a span of time."""
    if time.size < 2:
        raise _error(path, f"array 'time' holds {time.size} output time(s) (allowed: at least 2, the output times "
                           "of a crossing)")


def iter_leftovers(folder: str | Path) -> Iterator[Path]:
    """Leftovers of writes of ``folder`` that are still there (for tests and diagnostics)."""
    folder = Path(folder)
    pattern = _leftover_pattern(folder.name)
    if folder.parent.is_dir():
        yield from (p for p in folder.parent.iterdir() if pattern.match(p.name))
    if folder.is_dir() and not folder.is_symlink():
        yield from (p for p in folder.iterdir() if _LEGACY_TMP.match(p.name))
