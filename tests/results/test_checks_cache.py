"""The checks of a result are computed once per result and arguments (results.checks.cached_checks):
``result.checks()``, the terminal's verdict lines and the report read the same table.

The problem: the synthetic time history of tests/plotting/synthetic_results.py (the 'quick'
scenario's channels, no solver run) checked against the shipped limits. The count of calls of the
checks function is exact (no tolerance): equal arguments must not compute again, other arguments
or another result must.
"""

from __future__ import annotations

import dataclasses
import importlib.util
from pathlib import Path

from tb_exudyn.results import checks as checks_module
from tb_exudyn.results.checks import default_limits, verdict_lines

_spec = importlib.util.spec_from_file_location(
    "synthetic_results", Path(__file__).resolve().parents[1] / "plotting" / "synthetic_results.py")
synthetic = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(synthetic)


def test_the_checks_are_computed_once_per_result_and_arguments(monkeypatch):
    calls = []
    real = checks_module.checks

    def counted(result, limits=None, **options):
        calls.append(options)
        return real(result, limits, **options)

    monkeypatch.setattr(checks_module, "checks", counted)
    th = synthetic.time_history()
    table = th.checks()
    assert table.rows and len(calls) == 1
    assert th.checks() is table and th.checks(default_limits()) is table  # None and the default limits: one key
    verdict_lines(th)
    assert len(calls) == 1
    assert th.checks(probability=1e-3) is not table and len(calls) == 2
    other = dataclasses.replace(th)  # another result (of the same values): its own table
    assert other.checks() is not table and len(calls) == 3
    assert [r.verdict for r in other.checks().rows] == [r.verdict for r in table.rows]
