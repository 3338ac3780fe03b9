"""Checkpoints: finished task results on disk that prove what they hold, so that a sweep resumes.

A checkpoint folder holds ``manifest.json`` (the format and the fingerprint of the computation) and
``tasks/<key>.npz``, one file per finished task, written atomically (:func:`tb_exudyn.atomic.write_atomic`).
The fingerprint (:func:`fingerprint`) is a hash of everything that changes a number: the scenario, the
method and its options, the engine and its options, the spectra, the package versions and source
(:func:`tb_exudyn.methods.common.fingerprint_identity`).

A task file is a zip archive (stored, not compressed) of one ``.npy`` member per array and, written
last, ``__checkpoint__.json``: the file format, the computation's fingerprint, the task's key, the
digest of the task's data (:func:`task_digest`) and, per array, its dtype, shape, member size and the
SHA-256 of the member's bytes. Nothing is pickled.

Resume checks every file before it is used, in one streaming pass that keeps no array: a regular file
(not a symbolic link, device or FIFO), a readable archive with exactly the listed members, this run's
fingerprint, key and task digest, and for each member its size, its npy header (dtype and shape as
listed, no Python objects) and its checksum. A file that fails is never used: its task is computed
again (and the file replaced), with a one-line :class:`~tb_exudyn.execution.notices.RunNotice` naming
the file and the reason. A file is checked once more while it is read for the reduction; if it changed
in between (only something outside tb_exudyn can do that: a run locks its output folder),
:class:`~tb_exudyn.errors.CheckpointError` names it.

The manifest says which computation the folder holds: one of another computation is refused on resume
(CheckpointError naming the folder and the remedies); a damaged one is replaced, with a notice (each
task file proves itself, nothing depends on the manifest).
"""

from __future__ import annotations

import hashlib
import json
import math
import os
import zipfile
from pathlib import Path
from typing import Any, BinaryIO, Mapping, Sequence

import numpy as np

from ..atomic import write_atomic
from ..errors import CheckpointError
from ..files import FileRefused, open_regular
from ..storage import check_writable, save_json_atomic
from .notices import notice

#: the format of a task file (its ``__checkpoint__.json``) and of the manifest
TASK_FORMAT = "tb_exudyn.checkpoint_task/2"
MANIFEST_FORMAT = "tb_exudyn.checkpoint/2"
#: the member that describes a task file
META = "__checkpoint__.json"
#: largest description (member) and manifest read
MAX_META_BYTES = 1 << 20
#: bytes read at a time while checking or loading a member
CHUNK = 1 << 24
#: notices about unused files, one each; then one line for the rest
NOTICE_LIMIT = 5


def fingerprint(payload: Mapping[str, Any]) -> str:
    """A stable hash of the JSON form of what defines a computation (scenario text, settings)."""
    text = json.dumps(payload, sort_keys=True, default=str)
    return hashlib.sha256(text.encode("utf-8")).hexdigest()[:16]


def task_digest(data: Any) -> str:
    """A hash of a task's data (its ``repr``: the tasks' frozen dataclasses print every field)."""
    return hashlib.sha256(repr(data).encode("utf-8")).hexdigest()[:16]


class Unusable(Exception):
    """A checkpoint file that cannot be used; the message is the reason (one line)."""


# ------------------------------------------------------------------------------------- reading
def _open_regular(path: Path, limit: int | None = None) -> BinaryIO:
    """Open ``path`` for reading if it is a regular file (no symbolic link, device or FIFO; never
    blocks) of at most ``limit`` bytes (:func:`tb_exudyn.files.open_regular`); Unusable otherwise."""
    try:
        return open_regular(path, max_bytes=limit, follow_symlinks=False)
    except FileRefused as exc:
        raise Unusable(str(exc)) from None
    except OSError as exc:
        raise Unusable(f"cannot be opened ({exc.strerror or exc})") from None


class _Reader:
    """A member's byte stream that hashes what is read and counts it."""

    def __init__(self, fh: BinaryIO) -> None:
        self.fh, self.hash, self.n = fh, hashlib.sha256(), 0

    def read(self, size: int = -1) -> bytes:
        data = self.fh.read(size)
        self.hash.update(data)
        self.n += len(data)
        return data


class _Writer:
    """A member's byte sink that hashes what is written and counts it."""

    def __init__(self, fh: BinaryIO) -> None:
        self.fh, self.hash, self.n = fh, hashlib.sha256(), 0

    def write(self, data: bytes) -> int:
        view = memoryview(data).cast("B")
        self.hash.update(view)
        self.n += view.nbytes
        return self.fh.write(view)


def _header(src: _Reader) -> tuple[tuple[int, ...], bool, np.dtype]:
    version = np.lib.format.read_magic(src)
    if version == (1, 0):
        return np.lib.format.read_array_header_1_0(src)
    if version == (2, 0):
        return np.lib.format.read_array_header_2_0(src)
    raise Unusable(f"npy format {version} not written by tb_exudyn")


def _member(zf: zipfile.ZipFile, info: zipfile.ZipInfo, name: str, spec: Any, load: bool) -> np.ndarray | None:
    """Check one array member against its description (size, header, checksum); return it if ``load``."""
    if not isinstance(spec, dict) or not {"dtype", "shape", "bytes", "sha256"} <= set(spec):
        raise Unusable(f"the description of array {name!r} is incomplete")
    if info.compress_type != zipfile.ZIP_STORED or info.file_size != spec["bytes"]:
        raise Unusable(f"array {name!r} has {info.file_size} bytes, its description says {spec['bytes']}")
    with zf.open(info) as fh:
        src = _Reader(fh)
        shape, fortran, dtype = _header(src)
        if dtype.hasobject:
            raise Unusable(f"array {name!r} holds Python objects")
        if dtype != np.dtype(spec["dtype"]) or list(shape) != list(spec["shape"]):
            raise Unusable(f"array {name!r} is {dtype.str} {tuple(shape)}, its description says "
                           f"{spec['dtype']} {tuple(spec['shape'])}")
        size = math.prod(shape) * dtype.itemsize
        if src.n + size != info.file_size:
            raise Unusable(f"array {name!r}: {info.file_size} bytes do not hold its shape {tuple(shape)}")
        out = None
        if load:
            raw = np.empty(size, dtype=np.uint8)
            view = memoryview(raw)
            for i in range(0, size, CHUNK):
                data = src.read(min(CHUNK, size - i))
                if len(data) != min(CHUNK, size - i):
                    raise Unusable(f"array {name!r} ends early")
                view[i:i + len(data)] = data
            out = raw.view(dtype).reshape(shape, order="F" if fortran else "C")
        while src.read(CHUNK):
            pass
        if src.n != info.file_size or src.hash.hexdigest() != spec["sha256"]:
            raise Unusable(f"the checksum of array {name!r} does not match (the file was changed or damaged)")
    return out


def read_task_file(path: Path, expected: Mapping[str, str], load: bool) -> dict[str, np.ndarray]:
    """Check a task file against ``expected`` (format, fingerprint, key, task digest) and every
    member against its description; return the arrays if ``load`` (else an empty dict).

    Raises :class:`Unusable` with the reason, for any defect (never another exception)."""
    try:
        with _open_regular(path) as fh, zipfile.ZipFile(fh) as zf:
            infos = {i.filename: i for i in zf.infolist()}
            if META not in infos:
                raise Unusable(f"no {META} (not written by this tb_exudyn version, or not finished)")
            if infos[META].file_size > MAX_META_BYTES:
                raise Unusable(f"{META} too large")
            head = json.loads(zf.read(infos[META]).decode("utf-8"))
            if not isinstance(head, dict) or not isinstance(head.get("arrays"), dict):
                raise Unusable(f"{META} is not a task description")
            if head.get("format") != expected["format"]:
                raise Unusable(f"format {head.get('format')!r}, not {expected['format']!r}")
            if head.get("fingerprint") != expected["fingerprint"]:
                raise Unusable(f"a task of another computation (fingerprint {head.get('fingerprint')!r}, this run "
                               f"{expected['fingerprint']!r})")
            if head.get("key") != expected["key"]:
                raise Unusable(f"holds task {head.get('key')!r}, not {expected['key']!r}")
            if head.get("task") != expected["task"]:
                raise Unusable("holds other task data under this key (another frequency or sample split)")
            arrays = head["arrays"]
            if set(infos) != {META} | {f"{n}.npy" for n in arrays}:
                raise Unusable("its members are not those its description lists")
            out = {}
            for name, spec in arrays.items():
                a = _member(zf, infos[f"{name}.npy"], name, spec, load)
                if a is not None:
                    out[name] = a
            return out
    except Unusable:
        raise
    except Exception as exc:  # noqa: BLE001 - any defect of the file means: not usable
        text = " ".join(str(exc).split())[:120]
        raise Unusable(f"unreadable ({type(exc).__name__}{': ' + text if text else ''})") from None


def write_task_file(path: Path, arrays: Mapping[str, Any], head: Mapping[str, str]) -> None:
    """Write a task file atomically: the arrays, then their description (see the module docstring)."""
    arrays = {k: np.asarray(v) for k, v in arrays.items()}
    for name, a in arrays.items():
        if a.dtype.hasobject:
            raise TypeError(f"array {name!r} has dtype object: not storable without pickle")

    def write(fh: BinaryIO) -> None:
        entries = {}
        with zipfile.ZipFile(fh, "w", compression=zipfile.ZIP_STORED, allowZip64=True) as zf:
            for name, a in arrays.items():
                with zf.open(f"{name}.npy", "w", force_zip64=True) as member:
                    sink = _Writer(member)
                    if a.flags.c_contiguous:  # the header, then the data in one piece (np.save's bytes)
                        header = np.lib.format.header_data_from_array_1_0(a)
                        try:
                            np.lib.format.write_array_header_1_0(sink, header)
                        except ValueError:  # a header longer than format 1.0 holds
                            np.lib.format.write_array_header_2_0(sink, header)
                        sink.write(a.reshape(-1).view(np.uint8).data)
                    else:
                        np.lib.format.write_array(sink, a, allow_pickle=False)
                entries[name] = {"dtype": a.dtype.str, "shape": list(a.shape), "bytes": sink.n,
                                 "sha256": sink.hash.hexdigest()}
            zf.writestr(META, json.dumps({**head, "arrays": entries}, sort_keys=True))

    write_atomic(path, write)


def read_manifest(path: Path) -> str | None:
    """The fingerprint a manifest names (None without a manifest); :class:`Unusable` if damaged."""
    if not os.path.lexists(path):
        return None
    try:
        with _open_regular(path, MAX_META_BYTES) as fh:
            data = json.loads(fh.read().decode("utf-8"))
    except Unusable:
        raise
    except Exception as exc:  # noqa: BLE001
        raise Unusable(f"unreadable ({type(exc).__name__})") from None
    if not isinstance(data, dict) or not isinstance(data.get("fingerprint"), str):
        raise Unusable("not a checkpoint manifest")
    return data["fingerprint"]


# ------------------------------------------------------------------------------------- the folder
class Checkpoint:
    """A folder of finished task results: ``manifest.json`` and ``tasks/<key>.npz``.

    Parameters
    ----------
    folder : the checkpoint folder (created)
    fingerprint_ : the computation's fingerprint
    resume : reuse this computation's task files; without it the folder's task files are removed
    remedy : what to tell a user whose folder holds another computation (e.g. the options to use)
    """

    def __init__(self, folder: str | Path, fingerprint_: str, resume: bool,
                 remedy: str = "use another output folder, or start again without resuming") -> None:
        self.folder = check_writable(folder)
        self.tasks = self.folder / "tasks"
        self.fingerprint = fingerprint_
        manifest = self.folder / "manifest.json"
        try:
            old = read_manifest(manifest)
        except Unusable as exc:
            old = None
            if resume:
                notice(f"checkpoint manifest {str(manifest)!r} is damaged ({exc}): replaced; each task file is "
                       "checked on its own")
        if resume and old is not None and old != fingerprint_:
            raise CheckpointError(
                f"checkpoint folder {str(self.folder)!r} holds another computation (fingerprint {old}, this one "
                f"{fingerprint_}): {remedy}")
        if self.tasks.is_dir() and not self.tasks.is_symlink():
            for f in self.tasks.iterdir():  # leftovers of killed writes; all task files without resume
                leftover = f.name.startswith(".") and f.name.endswith(".tmp")
                if (leftover or (not resume and f.suffix == ".npz")) and (f.is_symlink() or f.is_file()):
                    f.unlink()
        elif os.path.lexists(self.tasks):
            self.tasks.unlink()  # not a folder tb_exudyn made
        for f in self.folder.glob(".manifest.json.*.tmp"):
            f.unlink()
        save_json_atomic(manifest, {"format": MANIFEST_FORMAT, "fingerprint": fingerprint_})
        self.tasks.mkdir(exist_ok=True)

    def path(self, key: str) -> Path:
        return self.tasks / f"{key}.npz"

    def _expected(self, key: str, data: Any) -> dict[str, str]:
        return {"format": TASK_FORMAT, "fingerprint": self.fingerprint, "key": key, "task": task_digest(data)}

    def verify(self, tasks: Sequence[Any]) -> list[bool]:
        """Which tasks (``key``, ``data``) have a usable file: each file there is checked in full; a
        file that fails gets a notice naming it and the reason (at most :data:`NOTICE_LIMIT`, then one
        line for the rest), and its task is to be computed again."""
        usable, unused = [], []
        for task in tasks:
            path = self.path(task.key)
            if not os.path.lexists(path):
                usable.append(False)
                continue
            try:
                read_task_file(path, self._expected(task.key, task.data), load=False)
                usable.append(True)
            except Unusable as exc:
                usable.append(False)
                unused.append((path, str(exc)))
        for path, reason in unused[:NOTICE_LIMIT]:
            notice(f"checkpoint file {str(path)!r} not used: {reason}; its task is computed again")
        if len(unused) > NOTICE_LIMIT:
            notice(f"{len(unused) - NOTICE_LIMIT} more checkpoint files in {str(self.tasks)!r} not used; their tasks "
                   "are computed again")
        return usable

    def load(self, task: Any) -> dict[str, np.ndarray]:
        """The arrays of a task's file (checked by :meth:`verify`), checked again as they are read."""
        path = self.path(task.key)
        try:
            return read_task_file(path, self._expected(task.key, task.data), load=True)
        except Unusable as exc:
            raise CheckpointError(
                f"checkpoint file {str(path)!r} changed while this run used it ({exc}): with no other program "
                "writing there, run again with resume") from None

    def save(self, task: Any, result: Mapping[str, Any]) -> None:
        """Write a task's file (replacing a damaged one; a folder in its place is left, with a notice)."""
        path = self.path(task.key)
        if path.is_dir() and not path.is_symlink():
            notice(f"checkpoint file {str(path)!r} not saved: a folder is in its place")
            return
        write_task_file(path, result, self._expected(task.key, task.data))


__all__ = ["Checkpoint", "TASK_FORMAT", "Unusable", "fingerprint", "read_manifest", "read_task_file", "task_digest",
           "write_task_file"]
