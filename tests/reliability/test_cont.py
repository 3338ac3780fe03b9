"""Hostile continuous girders of issue 29 (tests/reliability/cases_cont.py): each ends in exit
status 2 with one line naming the file (or the function) and the key, no traceback, and nothing
written, moved or deleted under the scratch folder (the assertions of test_cases.py, on these cases).

The reference is the error contract of DEVELOPERS.md (one line, the file or option, the key and what
is allowed; exit 2; nothing written).
"""

from __future__ import annotations

import pytest

from .cases import snapshot
from .cases_cont import CASES_CONT
from .test_cases import run_case


@pytest.mark.parametrize("case", CASES_CONT, ids=[c.id for c in CASES_CONT])
def test_bad_continuous_girder_is_one_clear_error(case, tmp_path, capsys, monkeypatch):
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


def test_the_cases_are_in_their_group():
    assert CASES_CONT and {c.group for c in CASES_CONT} == {"continuous"}
    assert len({c.id for c in CASES_CONT}) == len(CASES_CONT)
