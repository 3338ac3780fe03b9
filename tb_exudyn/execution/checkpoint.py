"""Checkpoints: finished task results on disk, so that an interrupted sweep resumes.

A checkpoint folder holds ``manifest.json`` (the fingerprint of the computation) and
``tasks/<key>.npz`` (one file per finished task, written atomically). ``resume=True`` reuses the
files of a folder with the same fingerprint; a folder with another fingerprint is refused on resume
and cleared otherwise. The fingerprint (:func:`fingerprint`) is a hash of everything that changes a
number: the scenario, the method and its options, the engine and its options, the package versions.
"""

from __future__ import annotations

import hashlib
import json
from pathlib import Path
from typing import Any, Mapping

import numpy as np

from ..errors import CheckpointError
from ..results.storage import check_writable, load_json, load_npz, save_json_atomic, save_npz_atomic


def fingerprint(payload: Mapping[str, Any]) -> str:
    """A stable hash of the JSON form of what defines a computation (scenario text, settings)."""
    text = json.dumps(payload, sort_keys=True, default=str)
    return hashlib.sha256(text.encode("utf-8")).hexdigest()[:16]


class Checkpoint:
    """A folder of finished task results: ``manifest.json`` (fingerprint) and ``tasks/<key>.npz``."""

    def __init__(self, folder: str | Path, fingerprint_: str, resume: bool):
        self.folder = check_writable(folder)
        self.tasks = self.folder / "tasks"
        manifest = self.folder / "manifest.json"
        if manifest.exists():
            old = load_json(manifest).get("fingerprint")
            if old != fingerprint_:
                if resume:
                    raise CheckpointError(
                        f"checkpoint folder {str(self.folder)!r} holds another computation (fingerprint {old}, "
                        f"this one {fingerprint_}): use another --out folder or drop --resume"
                    )
            if not resume:
                for f in self.tasks.glob("*.npz"):
                    f.unlink()
        save_json_atomic(manifest, {"fingerprint": fingerprint_})
        self.tasks.mkdir(exist_ok=True)

    def path(self, key: str) -> Path:
        return self.tasks / f"{key}.npz"

    def done(self, key: str) -> bool:
        return self.path(key).exists()

    def load(self, key: str) -> dict[str, np.ndarray]:
        return load_npz(self.path(key))

    def save(self, key: str, result: Mapping[str, np.ndarray]) -> None:
        save_npz_atomic(self.path(key), result)
