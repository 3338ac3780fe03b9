"""The package's layout rules, computed from the source (issue: one solver boundary).

- No import cycle inside tb_exudyn, counting imports at any depth (module level, in functions, under
  TYPE_CHECKING): the strongly connected components of the import graph are single modules.
- Function-level imports of the package's own modules only for lazy loading of the Exudyn-dependent
  parts, at most three, and only where listed here (the command line loads the methods, which build
  Exudyn models, and the report, which imports matplotlib, when a command needs them).
- No module over 600 lines.
- Every registered engine is an Engine subclass with its capabilities declared.
"""

from __future__ import annotations

import pytest

from .import_graph import ROOT, cycles, edges, modules

#: the allowed function-level imports of the package's own modules: (importing module, imported module)
LAZY_IMPORTS = {("tb_exudyn.cli", "tb_exudyn.methods"), ("tb_exudyn.cli", "tb_exudyn.report")}
MAX_LINES = 600


def test_the_import_graph_sees_the_package():
    """The graph is not empty and has the edges everyone knows (a broken parser would pass the
    other tests vacuously)."""
    es = edges()
    pairs = {(e.source, e.target) for e in es}
    assert len(modules()) > 60
    assert ("tb_exudyn.engines.batched", "tb_exudyn.engines.base") in pairs
    assert ("tb_exudyn.methods.pem.method", "tb_exudyn.engines") in pairs
    assert ("tb_exudyn.report", "tb_exudyn.plotting.files") in pairs


def test_no_import_cycle():
    found = cycles(edges())
    assert not found, "import cycles: " + "; ".join(" <-> ".join(c) for c in found)


def test_cycle_detection_finds_a_cycle():
    """The cycle finder on a graph with a known cycle (so that the test above can fail)."""
    from .import_graph import Edge

    es = [Edge("a", "b", 1, False), Edge("b", "c", 1, False), Edge("c", "a", 1, True), Edge("c", "d", 1, False)]
    assert cycles(es) == [["a", "b", "c"]]


def test_function_level_imports_only_for_lazy_loading():
    lazy = [(e.source, e.target) for e in edges() if e.in_function]
    assert len(lazy) <= 3, lazy
    assert set(lazy) <= LAZY_IMPORTS, sorted(set(lazy) - LAZY_IMPORTS)


def test_no_module_over_600_lines():
    long = {name: n for name, path in modules().items()
            if (n := len(path.read_text(encoding="utf-8").splitlines())) > MAX_LINES}
    assert not long, long


@pytest.mark.exudyn
def test_every_registered_engine_declares_its_capabilities():
    pytest.importorskip("exudyn")
    from tb_exudyn.engines import ENGINES, engine_class
    from tb_exudyn.engines.base import Engine

    assert set(ENGINES) >= {"exudyn", "batched", "dense"}
    for name in ENGINES:
        cls = engine_class(name)
        assert issubclass(cls, Engine) and cls.name == name
        assert isinstance(cls.full_model, bool) and isinstance(cls.single_columns, bool)
        assert set(cls.linearizations) <= {"rest", "static"} and cls.linearizations
    assert (ROOT / "tb_exudyn" / "engines" / "dense.py").exists()
