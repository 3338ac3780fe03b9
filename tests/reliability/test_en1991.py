"""Hostile inputs of `tb-exudyn check` (tests/reliability/cases_en1991.py): exit status 2, one line
naming the option or file, no traceback, nothing written (the assertions of test_cases.py)."""

from __future__ import annotations

import pytest

from .cases_en1991 import CASES_EN1991
from .test_cases import assert_one_clear_error


@pytest.mark.parametrize("case", CASES_EN1991, ids=[c.id for c in CASES_EN1991])
def test_check_input_is_one_clear_error(case, tmp_path, capsys, monkeypatch):
    assert_one_clear_error(case, tmp_path, capsys, monkeypatch)
