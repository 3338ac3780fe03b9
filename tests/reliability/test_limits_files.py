"""Broken limit files (tests/reliability/cases_limits.py, issue 27): every one ends in exit status 2 with
one line naming the file (or TB_EXUDYN_MODELS), the key and what is allowed, no traceback, and nothing
written, moved or deleted under the scratch folder (so a refused run makes no --out folder and writes
no result): the assertions of tests/reliability/test_cases.py, with its runner.
"""

from __future__ import annotations

import pytest

from .cases import snapshot
from .cases_limits import CASES_LIMITS
from .test_cases import run_case


def test_the_cases_are_the_limits_group():
    assert CASES_LIMITS and {c.group for c in CASES_LIMITS} == {"limits"}
    assert len({c.id for c in CASES_LIMITS}) == len(CASES_LIMITS)


@pytest.mark.parametrize("case", CASES_LIMITS, ids=[c.id for c in CASES_LIMITS])
def test_broken_limit_file_is_one_clear_error_before_any_work(case, tmp_path, capsys, monkeypatch):
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
