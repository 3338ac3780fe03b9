"""Issue 30, item 2: library errors about arguments the user gave as flags are printed with the flag.

Every case of cases_flags.py is held to the hostile-input contract of test_cases.py (exit 2, one line
holding the expected texts, no traceback, nothing under the scratch folder written, moved or
deleted).
"""

from __future__ import annotations

import pytest

from .cases_flags import CASES_FLAGS, GROUP
from .test_cases import assert_one_clear_error


@pytest.mark.parametrize("case", CASES_FLAGS, ids=[c.id for c in CASES_FLAGS])
def test_library_error_is_printed_with_the_flag(case, tmp_path, capsys, monkeypatch):
    assert_one_clear_error(case, tmp_path, capsys, monkeypatch)


def test_cases_are_in_the_flags_group():
    assert CASES_FLAGS and {c.group for c in CASES_FLAGS} == {GROUP}
    assert len({c.id for c in CASES_FLAGS}) == len(CASES_FLAGS)
