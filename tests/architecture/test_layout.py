"""The package's layout rules, computed from the source (issue: one solver boundary).

- No import cycle inside tb_exudyn, counting imports at any depth (module level, in functions, under
  TYPE_CHECKING): the strongly connected components of the import graph are single modules.
- Function-level imports of the package's own modules only for lazy loading of the Exudyn-dependent
  parts, at most three, and only where listed here (the command line loads the methods, which build
  Exudyn models, and the report, which imports matplotlib, when a command needs them).
- No module over 600 lines.
- The library does not know its caller (issue 30): no ``"command line"`` string in any module outside
  tb_exudyn/cli/ (the command passes it as the caller's name and names keys as its flags).
- Every registered engine is an Engine subclass with its capabilities declared.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

from .import_graph import ROOT, cycles, edges, modules

#: the allowed function-level imports of the package's own modules: (importing module, imported module)
#: (the modules of compiled functions are loads by name through tb_exudyn.jit.load, which sets Numba's
#: cache directory before their functions are declared)
LAZY_IMPORTS = {("tb_exudyn.cli.lazy", "tb_exudyn.methods"), ("tb_exudyn.cli.results", "tb_exudyn.report")}
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


def test_the_graph_counts_loads_by_name():
    """``importlib.import_module`` of an own module is an edge (the load of plotting by result.plot()
    is one; the engine registry's names are others): a cycle through a load by name is a cycle."""
    by_name = {(e.source, e.target) for e in edges() if e.by_name}
    assert ("tb_exudyn.engines", "tb_exudyn.engines.batched") in by_name
    assert ("tb_exudyn.codes.stochastic", "tb_exudyn.methods.sweep") in by_name
    assert ("tb_exudyn", "tb_exudyn.methods") in by_name
    assert ("tb_exudyn.engines.batched.loop", "tb_exudyn.engines.batched.compiled") in by_name  # jit.load
    assert ("tb_exudyn.methods.pseudo_reduction", "tb_exudyn.methods.compiled_reduction") in by_name


def test_loads_by_name_are_resolved(tmp_path):
    """The forms of a load by name on a small package: a literal, a relative name with ``__name__`` or a
    literal package, and a registry (the name in a variable: every literal naming a module counts)."""
    from .import_graph import by_name

    mods = {n: Path(f"{n.replace('.', '/')}.py") for n in ("p.a", "p.b", "p.c", "p.d", "p.e")}
    mods["p"] = Path("p/__init__.py")
    literal = ("import importlib\nfrom importlib import import_module\n"
               "def f():\n    importlib.import_module('p.b')\n    import_module('.c', __name__)\n"
               "    importlib.import_module('.d', package='p')\n    return 'p.e'\n")
    assert sorted(t for t, _ in by_name("p.a", ast.parse(literal), mods)) == ["p.b", "p.c", "p.d"]
    registry = ("import importlib\nREG = {'x': ('p.e', 'E'), 'y': 'not.a.module'}\n"
                "def g(n):\n    return importlib.import_module(REG[n][0])\n")
    assert [t for t, _ in by_name("p.a", ast.parse(registry), mods)] == ["p.e"]


def test_function_level_imports_only_for_lazy_loading():
    lazy = [(e.source, e.target) for e in edges() if e.in_function and not e.by_name]
    assert len(lazy) <= 3, lazy
    assert set(lazy) <= LAZY_IMPORTS, sorted(set(lazy) - LAZY_IMPORTS)


def test_no_module_over_600_lines():
    long = {name: n for name, path in modules().items()
            if (n := len(path.read_text(encoding="utf-8").splitlines())) > MAX_LINES}
    assert not long, long


#: the caller's name the command line passes as ``where``; only tb_exudyn/cli/ may spell it
CALLER = "command line"


def code_strings(source: str) -> list[ast.Constant]:
    """The code strings of ``source``: its string literals and the literal parts of f-strings, docstrings
    excepted (comments are not in the syntax tree)."""
    tree = ast.parse(source)
    docstrings = set()
    for node in ast.walk(tree):
        if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)) and node.body:
            first = node.body[0]
            if isinstance(first, ast.Expr) and isinstance(first.value, ast.Constant) and isinstance(first.value.value, str):
                docstrings.add(id(first.value))
    return [node for node in ast.walk(tree) if isinstance(node, ast.Constant) and isinstance(node.value, str)
            and id(node) not in docstrings]


def caller_literals(source: str) -> list[int]:
    """Lines of the code strings of ``source`` that spell :data:`CALLER`. A docstring that says what the
    command line does with a function is documentation, not a branch on the caller; a string in code is a
    label the module writes (``where="command line"``) or compares (``where == "command line"``): the
    library then knows its caller."""
    return sorted({node.lineno for node in code_strings(source) if CALLER in node.value})


def test_the_caller_literal_finder_finds_them():
    code = ('"""Module: the command line prints it."""\n'
            'def f(where="command line"):\n    """Called from the "command line"."""\n'
            '    # "command line" in a comment\n'
            '    if where == "command line":\n        return f"command line: {where}"\n    return "other"\n')
    assert caller_literals(code) == [2, 5, 6]


def test_no_command_line_literal_outside_the_cli():
    """The library names its own keys; only the command line knows it is the command line (issue 30)."""
    found = [f"{path.relative_to(ROOT)}:{line}" for name, path in modules().items()
             if not (name == "tb_exudyn.cli" or name.startswith("tb_exudyn.cli."))
             for line in caller_literals(path.read_text(encoding="utf-8"))]
    assert not found, f"{CALLER!r} spelled outside tb_exudyn/cli/: " + ", ".join(found)


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
