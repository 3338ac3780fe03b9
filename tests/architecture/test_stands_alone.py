"""The repository stands alone (issue 30, item 5): no tracked file cites a file of the shared folder.

The shared folder (its reference notes and its design page) exists on the developers' machine, not in
a clone of the repository. What the code, the data and the docs cite must be in the repository
(docs/references.md gives the primary sources) or a public source. The test reads every file that
``git ls-files`` lists and looks for the shared folder's path and its files' names: ``shared/`` as a
path, ``DESIGN.md`` and the reference notes (``code_limits.md``, ``seed_paper.md``, ``bridges.md``,
``vehicles.md``, ``track_spectra.md``, ``validation_cases.md``, ``en1991_dynamic.md``).

Every tracked file must be clean, the package's docstrings and messages included.
"""

from __future__ import annotations

import re
import subprocess
from pathlib import Path

import pytest

from .import_graph import ROOT

#: the shared folder's notes, cited by file name in the old docstrings and model files
SHARED_FILES = ("code_limits", "seed_paper", "bridges", "vehicles", "track_spectra", "validation_cases",
                "en1991_dynamic", "DESIGN")
#: a citation of the shared folder: its path (``shared/``, not ``..._shared/`` or ``.shared/``) or one of
#: its files by name (``bridges.md``, not ``my_bridges.md``)
CITATION = re.compile(r"(?<![\w.-])shared/|(?<![\w-])(?:" + "|".join(SHARED_FILES) + r")\.md\b")
#: this file names the patterns it looks for
THIS = Path(__file__).resolve().relative_to(ROOT).as_posix()


def tracked_files() -> list[str]:
    """The repository's tracked files (``git ls-files``), relative to its root."""
    try:
        out = subprocess.run(["git", "ls-files", "-z"], cwd=ROOT, capture_output=True, check=True).stdout
    except (OSError, subprocess.CalledProcessError) as exc:  # an unpacked sdist: no repository to read
        pytest.skip(f"not a git checkout ({exc})")
    return [p for p in out.decode("utf-8").split("\0") if p]


def citations(paths: list[str]) -> list[str]:
    """``path:line: text`` of every line of ``paths`` that cites the shared folder."""
    found = []
    for rel in paths:
        path = ROOT / rel
        if rel == THIS or not path.is_file():  # a file deleted in the work tree but not yet in the index
            continue
        text = path.read_bytes().decode("utf-8", errors="replace")
        for n, line in enumerate(text.splitlines(), 1):
            if CITATION.search(line):
                found.append(f"{rel}:{n}: {line.strip()[:120]}")
    return found


def test_the_files_are_listed():
    """The listing sees the repository (a broken listing would pass the tests below vacuously)."""
    files = tracked_files()
    assert len(files) > 100
    assert {"README.md", "docs/references.md", "models/scenarios/li_zhu_2011.toml", THIS} <= set(files)


@pytest.mark.parametrize("line", [
    "Li & Zhu (`shared/reference/seed_paper.md`)", "as in /work/shared/reference/bridges.md", "see DESIGN.md",
    "(code_limits.md: 3.5 m/s^2)", "vehicles.md values", "track_spectra.md conventions",
    "validation_cases.md section 3", "en1991_dynamic.md", "shared/hooks",
])
def test_the_pattern_finds_a_citation(line):
    assert CITATION.search(line), line


@pytest.mark.parametrize("line", [
    "docs/references.md, code limits", "shared libraries count once per process", "the mean is shared",
    "models/bridges/li_zhu_2011_bridge.toml", "my_vehicles.md", "the_shared/ folder", "docs/models.md",
])
def test_the_pattern_spares_other_text(line):
    assert not CITATION.search(line), line


def test_no_file_outside_the_package_cites_the_shared_folder():
    found = citations([p for p in tracked_files() if not p.startswith("tb_exudyn/")])
    assert not found, "cite the primary source (docs/references.md) instead:\n" + "\n".join(found)


def test_no_package_file_cites_the_shared_folder():
    found = citations([p for p in tracked_files() if p.startswith("tb_exudyn/")])
    assert not found, "cite the primary source (docs/references.md) instead:\n" + "\n".join(found)
