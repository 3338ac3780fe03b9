"""Hostile inputs of `tb-exudyn check --stochastic` (tests/reliability/cases_stochastic.py): exit status 2, one line
naming the option or file, no traceback, nothing written (the assertions of test_cases.py)."""

from __future__ import annotations

import pytest

from .cases_stochastic import CASES_STOCHASTIC
from .test_cases import assert_one_clear_error


@pytest.mark.parametrize("case", CASES_STOCHASTIC, ids=[c.id for c in CASES_STOCHASTIC])
def test_stochastic_input_is_one_clear_error(case, tmp_path, capsys, monkeypatch):
    assert_one_clear_error(case, tmp_path, capsys, monkeypatch)
