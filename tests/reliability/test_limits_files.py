"""Broken limit files (tests/reliability/cases_limits.py, issue 27): every one ends in exit status 2 with
one line naming the file (or TB_EXUDYN_MODELS), the key and what is allowed, no traceback, and nothing
written, moved or deleted under the scratch folder (so a refused run makes no --out folder and writes
no result): the assertions of tests/reliability/test_cases.py, with its runner.
"""

from __future__ import annotations

import pytest

from .cases_limits import CASES_LIMITS
from .test_cases import assert_one_clear_error


def test_the_cases_are_the_limits_group():
    assert CASES_LIMITS and {c.group for c in CASES_LIMITS} == {"limits"}
    assert len({c.id for c in CASES_LIMITS}) == len(CASES_LIMITS)


@pytest.mark.parametrize("case", CASES_LIMITS, ids=[c.id for c in CASES_LIMITS])
def test_broken_limit_file_is_one_clear_error_before_any_work(case, tmp_path, capsys, monkeypatch):
    assert_one_clear_error(case, tmp_path, capsys, monkeypatch)
