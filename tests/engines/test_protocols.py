"""The interfaces between methods and engines (tb_exudyn/engines/protocols.py) and who implements them.

Exact problem: each class the protocols' docstring names as an implementation has the protocol's
members (``isinstance`` on a ``runtime_checkable`` Protocol checks their presence), and an object
lacking one is refused (so that the checks can fail). No number is computed: there is no tolerance.
"""

from __future__ import annotations

import numpy as np
import pytest

from tb_exudyn.engines.protocols import ColumnEngine, ColumnSource, Reducer


def test_the_reducers_implement_the_reducer_protocol():
    from tb_exudyn.engines.batched.mean import _MeanRecorder
    from tb_exudyn.methods.monte_carlo import SampleReducer
    from tb_exudyn.methods.pem import PsdReducer

    for cls in (PsdReducer, SampleReducer, _MeanRecorder):
        assert callable(getattr(cls, "record", None)) and callable(getattr(cls, "result", None)), cls
    assert isinstance(_MeanRecorder(3, 2), Reducer)

    class NoResult:
        def record(self, i, Y, ext):  # noqa: ANN001
            pass

    assert not isinstance(NoResult(), Reducer)


def test_the_column_sources_implement_the_source_protocol():
    from tb_exudyn.system.columns import StaticLoadColumns

    source = StaticLoadColumns(static=np.zeros(2), row_force=np.zeros(1), force=np.zeros(2))
    assert isinstance(source, ColumnSource) and source.width == 1
    assert not isinstance(object(), ColumnSource)


@pytest.mark.exudyn
def test_every_registered_engine_implements_the_engine_protocol():
    pytest.importorskip("exudyn")
    from tb_exudyn.engines import ENGINES, engine_class

    for name in ENGINES:
        cls = engine_class(name)
        for member in ("integrate", "integrate_estimate", "mean", "describe", "fs", "name", "full_model",
                       "single_columns"):
            assert hasattr(cls, member), (name, member)
    assert not isinstance(object(), ColumnEngine)
