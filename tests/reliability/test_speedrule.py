"""Hostile inputs of issue 26 item 4 (tests/reliability/cases_speedrule.py): a sweep's key quantity that
matches no channel, a speed whose band the speed rule leaves empty (sweep and run --speed-kmh). Each
ends in exit status 2 with one line naming the option (or the function) and the key, no traceback, and
nothing written, moved or deleted under the scratch folder (the assertions of test_cases.py).

The reference is the error contract of DEVELOPERS.md (one line, the file or option, the key and what
is allowed; exit 2; nothing written).
"""

from __future__ import annotations

import pytest

from .cases_speedrule import CASES_SPEEDRULE
from .test_cases import assert_one_clear_error


@pytest.mark.parametrize("case", CASES_SPEEDRULE, ids=[c.id for c in CASES_SPEEDRULE])
def test_speed_rule_input_is_one_clear_error(case, tmp_path, capsys, monkeypatch):
    assert_one_clear_error(case, tmp_path, capsys, monkeypatch)


def test_the_cases_are_in_their_group():
    assert CASES_SPEEDRULE and {c.group for c in CASES_SPEEDRULE} == {"speedrule"}
    assert len({c.id for c in CASES_SPEEDRULE}) == len(CASES_SPEEDRULE)
