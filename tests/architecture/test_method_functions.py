"""Every function in tb_exudyn/methods/ is at most 80 lines (issue 30: one driver).

A method's run is the driver's skeleton (tb_exudyn/methods/driver.py) plus the method's own plan,
reduce and finish; a function that grows past 80 lines is a second driver growing back. Measured
from the source with ``ast`` (no module is imported): a function's length is its last line minus its
first, decorators excluded, nested functions counted inside their parent (and on their own).
"""

from __future__ import annotations

import ast
from pathlib import Path

from .import_graph import ROOT

METHODS = ROOT / "tb_exudyn" / "methods"
MAX_FUNCTION_LINES = 80


def long_functions(source: str, limit: int = MAX_FUNCTION_LINES) -> list[tuple[str, int]]:
    """(name, lines) of every function (methods and nested functions included) of ``source`` longer
    than ``limit`` lines."""
    out = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            n = node.end_lineno - node.lineno + 1  # type: ignore[operator]
            if n > limit:
                out.append((node.name, n))
    return out


def test_the_measure_finds_a_long_function():
    """An 81-line function is found, an 80-line one and a long class body of short methods are not
    (so that the test below can fail, and fails only on functions)."""
    body = "\n".join(f"    x{i} = {i}" for i in range(79))
    assert long_functions(f"def f():\n{body}\n    return 0\n") == [("f", 81)]
    assert long_functions(f"def f():\n{body}\n") == []
    methods = "\n".join(f"    def m{i}(self):\n        return {i}" for i in range(60))
    assert long_functions(f"class C:\n{methods}\n") == []
    nested = f"def outer():\n    def inner():\n{body.replace('    ', '        ')}\n        return 1\n    return inner\n"
    assert [name for name, _ in long_functions(nested)] == ["outer", "inner"]


def test_no_function_in_methods_over_80_lines():
    files = sorted(METHODS.rglob("*.py"))
    assert any(p.parent.name == "pem" for p in files)  # the PEM package is seen
    long = {f"{p.relative_to(ROOT)}:{name}": n for p in files
            for name, n in long_functions(p.read_text(encoding="utf-8"))}
    assert not long, long
