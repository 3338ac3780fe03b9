"""The linear engines import no Exudyn (issue 30): only tb_exudyn/builder and tb_exudyn/engines/exudyn*.py
do, and a linear engine given the parent's LinearModel builds no model.

Exact problem: importing the batched and the dense engine in a fresh interpreter leaves ``exudyn``
and ``tb_exudyn.builder`` out of ``sys.modules`` (a module-level import anywhere in their import
chain would put them there); a batched engine on a LinearModel built once (as the methods build it
in the parent, :func:`tb_exudyn.engines.exudyn_runs.linear_model`) integrates a PEM column and runs
its linear mean without building the Exudyn model (its ``_model`` stays None), and gives the same
outputs, bitwise, as an engine that made its own LinearModel (the same computation: no tolerance).
"""

from __future__ import annotations

import pickle
import subprocess
import sys

import numpy as np
import pytest

from .import_graph import ROOT


def test_the_linear_engines_import_no_exudyn():
    code = ("import sys, tb_exudyn.engines.batched, tb_exudyn.engines.dense\n"
            "print('exudyn' in sys.modules, 'tb_exudyn.builder' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, check=True)
    assert out.stdout.split() == ["False", "False"], out.stdout + out.stderr


@pytest.mark.exudyn
def test_a_batched_engine_on_the_parents_system_builds_no_model():
    pytest.importorskip("exudyn")
    import tb_exudyn as tbx
    from tb_exudyn.builder import build_model
    from tb_exudyn.engines.batched import BatchedEngine
    from tb_exudyn.engines.exudyn_runs import linear_model
    from tb_exudyn.methods.common import analysis_setup
    from tb_exudyn.methods.pem import PsdReducer, column_frequencies, harmonic_columns, pem_tasks
    from tb_exudyn.methods.reduction import engine_plan

    sc = tbx.load_scenario("quick")
    system = pickle.loads(pickle.dumps(linear_model(build_model(sc, warn=False), mean=True)))  # as sent
    given, own = BatchedEngine(sc, system=system), BatchedEngine(sc)
    ptasks = pem_tasks(sc, analysis_setup(sc, warn=False).grid)[:2]
    results = []
    for engine in (given, own):
        cols = harmonic_columns(ptasks, sc)
        reducer = PsdReducer(cols, engine_plan(engine), column_frequencies(ptasks, cols), engine.steps.n_outputs,
                             len(sc.track.irregularities), 1.0 / engine.fs, False)
        results.append((engine.integrate(cols, reducer)["var_z"], engine.mean()["mean"]))
    assert given._model is None  # neither the columns nor the linear mean built the model
    assert np.array_equal(results[0][0], results[1][0]) and np.array_equal(results[0][1], results[1][1])
