"""Hostile inputs of issue 29, the imported modal bridge (tests/reliability/cases_modal.py): each ends in
exit status 2 with one line naming the file (or the option) and the column or key, no traceback, and
nothing written, moved or deleted under the scratch folder (the assertions of test_cases.py, on these
cases). The reference is the error contract of DEVELOPERS.md (one line, the file or option, the key and
what is allowed; exit 2; nothing written).
"""

from __future__ import annotations

import pytest

from .cases_modal import CASES_MODAL
from .test_cases import assert_one_clear_error


@pytest.mark.parametrize("case", CASES_MODAL, ids=[c.id for c in CASES_MODAL])
def test_modal_table_input_is_one_clear_error(case, tmp_path, capsys, monkeypatch):
    assert_one_clear_error(case, tmp_path, capsys, monkeypatch)


def test_the_cases_are_in_their_group():
    assert CASES_MODAL and {c.group for c in CASES_MODAL} == {"modal"}
    assert len({c.id for c in CASES_MODAL}) == len(CASES_MODAL)


def test_the_good_tables_of_the_cases_run(tmp_path, capsys):
    """The cases' tables without their defect are a valid bridge: `tb-exudyn show` reads them (exit 0)
    and names the bridge's frequencies, so each case fails for its defect alone."""
    from tb_exudyn.cli import main

    from .cases_modal import _bridge, _scenario

    _bridge(tmp_path)
    assert main(["show", str(_scenario(tmp_path))]) == 0
    out = capsys.readouterr().out
    assert "bridge f1, f3 vertical" in out and "5, -" in out
