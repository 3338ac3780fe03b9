"""Hostile inputs (tests/reliability/cases.py): every one ends in exit status 2 with one line that
names the file (or the option or environment variable), no traceback, and nothing written.

Cases that would block (a FIFO) or read without end (/dev/zero) if their defence failed run in a
subprocess limited to 2 GB of address space and 60 s; the others call ``tb_exudyn.cli.main`` (or
the Python function) in this process.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from tb_exudyn.cli import main
from tb_exudyn.errors import UserError

from .cases import CASES, Run, snapshot, subprocess_command

ROOT = Path(__file__).resolve().parents[2]

#: the terminal's line width for every command (issue 49), not counting the paths the user typed
LINE_MAX = 200


def run_case(run: Run, cwd: Path, capsys: pytest.CaptureFixture, monkeypatch: pytest.MonkeyPatch) -> tuple[int, str]:
    """Exit status and stderr of a case (in this process, or isolated in a limited subprocess)."""
    if run.isolate:
        env = {**os.environ, **run.env, "PYTHONPATH": str(ROOT), "MPLBACKEND": "Agg", "OMP_NUM_THREADS": "1",
               "OPENBLAS_NUM_THREADS": "1"}
        proc = subprocess.run(subprocess_command(run, sys.executable), capture_output=True, text=True, timeout=300,
                              env=env, cwd=cwd)
        return proc.returncode, proc.stderr
    for key, value in run.env.items():
        monkeypatch.setenv(key, value)
    if run.argv:
        code = main(list(run.argv))
        return code, capsys.readouterr().err
    try:
        exec(compile(run.code, "<case>", "exec"), {})
    except UserError as exc:
        return 2, f"error: {exc}\n"
    return 0, ""


def assert_one_clear_error(case, tmp_path: Path, capsys: pytest.CaptureFixture,
                           monkeypatch: pytest.MonkeyPatch) -> str:
    """The contract every hostile case is held to (every cases_<topic>.py list uses it): exit 2, no
    traceback, one line holding the case's expected texts (the file or option, the key), and nothing
    under the scratch folder written, moved or deleted. Returns the line."""
    work, cwd = tmp_path / "work", tmp_path / "cwd"
    work.mkdir()
    cwd.mkdir()
    monkeypatch.chdir(cwd)
    run = case.build(work)
    before = snapshot(tmp_path)
    code, err = run_case(run, cwd, capsys, monkeypatch)
    assert code == 2, f"exit {code}: {err}"
    assert "Traceback" not in err, err
    assert len(err.strip().splitlines()) == 1, err
    for text in run.expect:
        assert text in err, f"{text!r} not in {err!r}"
    assert snapshot(tmp_path) == before, "something was written, moved or deleted"
    shown = err.strip().replace(str(tmp_path), "T")  # the width a user sees, less the paths they typed
    assert len(shown) <= LINE_MAX, f"{len(shown)} characters (at most {LINE_MAX}): {shown}"
    return err


@pytest.mark.parametrize("case", CASES, ids=[c.id for c in CASES])
def test_hostile_input_is_one_clear_error(case, tmp_path, capsys, monkeypatch):
    assert_one_clear_error(case, tmp_path, capsys, monkeypatch)
