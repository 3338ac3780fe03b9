"""Packaging guards: the hand-written package list in pyproject.toml covers every sub-package."""

from __future__ import annotations

import re
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def test_every_subpackage_is_listed_in_pyproject():
    listed = set(tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]["packages"])
    on_disk = {
        ".".join(p.parent.relative_to(ROOT).parts) for p in (ROOT / "tb_exudyn").rglob("__init__.py")
    }
    missing = on_disk - listed
    assert not missing, f"add to [tool.setuptools] packages in pyproject.toml: {sorted(missing)}"
    assert "tb_exudyn.models" in listed


def test_only_builder_and_the_exudyn_engine_import_exudyn():
    """Design rule: only tb_exudyn/builder and the Exudyn engine (tb_exudyn/engines/exudyn*.py)
    import Exudyn; every other layer reaches it through them."""
    offenders = []
    for path in (ROOT / "tb_exudyn").rglob("*.py"):
        rel = path.relative_to(ROOT / "tb_exudyn").parts
        if rel[0] == "builder" or (rel[0] == "engines" and rel[-1].startswith("exudyn")):
            continue
        text = path.read_text()
        if re.search(r"^\s*(import|from) exudyn\b", text, re.M):  # the module, not a name such as exudyn_side
            offenders.append(str(path.relative_to(ROOT)))
    assert not offenders, offenders


def test_every_listed_package_exists():
    listed = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]["packages"]
    for name in listed:
        folder = ROOT / "models" if name == "tb_exudyn.models" else ROOT.joinpath(*name.split("."))
        assert folder.is_dir(), f"pyproject lists {name} but {folder} does not exist"
