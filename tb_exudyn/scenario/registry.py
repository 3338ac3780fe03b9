"""The library of named models: the TOML files under models/ (vehicles, bridges, scenarios, limits, tracks).

A name is a file's stem: ``models/scenarios/li_zhu_2011.toml`` is the scenario ``li_zhu_2011``.
The folder is found inside the installed package (``tb_exudyn/models``), next to the package in a
source checkout, or where the environment variable ``TB_EXUDYN_MODELS`` points.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

from ..errors import SettingError, one_of
from .errors import ScenarioError
from .toml_io import read_toml

CATEGORIES = ("vehicles", "bridges", "scenarios", "limits", "tracks")


def models_dir() -> Path:
    """The folder holding vehicles/, bridges/, scenarios/ and limits/.

    Raises SettingError (key ``TB_EXUDYN_MODELS``) when the environment variable names no such
    folder, or when it is unset and the package's own folder is missing.
    """
    allowed = "a folder holding vehicles/, bridges/ and scenarios/ (tb_exudyn's models/ folder)"
    env = os.environ.get("TB_EXUDYN_MODELS")
    if env:
        path = Path(env)
        if not path.is_dir():
            reason = "not a folder" if path.exists() else "no such folder"
            raise SettingError("environment", "TB_EXUDYN_MODELS", env, allowed, reason)
        if not (path / "scenarios").is_dir():
            raise SettingError("environment", "TB_EXUDYN_MODELS", env, allowed, "the folder holds no scenarios/")
        return path
    package = Path(__file__).resolve().parent.parent
    for candidate in (package / "models", package.parent / "models"):
        if (candidate / "scenarios").is_dir():
            return candidate
    raise SettingError("environment", "TB_EXUDYN_MODELS", None, allowed,
                       "unset, and tb_exudyn's models/ folder was not found in the package or next to it")


def model_files(category: str) -> dict[str, Path]:
    """Name -> file for one category (vehicles, bridges, scenarios, limits or tracks), sorted by name."""
    if category not in CATEGORIES:
        raise ValueError(f"category must be one of {CATEGORIES}, not {category!r}")
    folder = models_dir() / category
    return {p.stem: p for p in sorted(folder.glob("*.toml"))}


def model_path(category: str, name: str, referrer: str | None = None, key: str = "") -> Path:
    """The file of a named model, or a ScenarioError listing the names that exist."""
    files = model_files(category)
    if name not in files:
        raise ScenarioError(
            referrer, key or category, name, one_of(files, name, tail=" or a .toml path"),
            f"unknown {category[:-1]} name",
        )
    return files[name]


@dataclass(frozen=True)
class ModelEntry:
    """One line of ``tb-exudyn list``."""

    category: str
    name: str
    description: str
    path: Path


def list_models() -> list[ModelEntry]:
    """Every named model with its one-line description (read from the file, not validated)."""
    out = []
    for category in CATEGORIES:
        for name, path in model_files(category).items():
            try:
                description = str(read_toml(path).get("description", ""))
            except ScenarioError as exc:
                description = f"(unreadable: {exc})"
            out.append(ModelEntry(category, name, description, path))
    return out
