"""Hostile two-track data of issue 29 (tests/reliability/cases_tracks.py): each ends in exit status 2
with one line naming the file (or the function) and the key, no traceback, and nothing written, moved
or deleted under the scratch folder (the assertions of test_cases.py, on these cases).

The reference is the error contract of DEVELOPERS.md (one line, the file or option, the key and what
is allowed; exit 2; nothing written).
"""

from __future__ import annotations

import pytest

from .cases_tracks import CASES_TRACKS
from .test_cases import assert_one_clear_error


@pytest.mark.parametrize("case", CASES_TRACKS, ids=[c.id for c in CASES_TRACKS])
def test_bad_tracks_are_one_clear_error(case, tmp_path, capsys, monkeypatch):
    assert_one_clear_error(case, tmp_path, capsys, monkeypatch)


def test_the_cases_are_in_their_group():
    assert CASES_TRACKS and {c.group for c in CASES_TRACKS} == {"tracks"}
    assert len({c.id for c in CASES_TRACKS}) == len(CASES_TRACKS)
