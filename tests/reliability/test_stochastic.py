"""Hostile inputs of `tb-exudyn check --stochastic` (tests/reliability/cases_stochastic.py): exit status 2, one line
naming the option or file, no traceback, nothing written (the assertions of test_cases.py)."""

from __future__ import annotations

import pytest

from .cases import snapshot
from .cases_stochastic import CASES_STOCHASTIC
from .test_cases import run_case


@pytest.mark.parametrize("case", CASES_STOCHASTIC, ids=[c.id for c in CASES_STOCHASTIC])
def test_stochastic_input_is_one_clear_error(case, tmp_path, capsys, monkeypatch):
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
