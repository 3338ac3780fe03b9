"""Results declare what they are (issue 48): no module outside tb_exudyn/methods/ compares a result's
method string; they ask its kind (``result.kind.gaussian``, ``.sampled``, ``.random``, ...:
tb_exudyn/results/kinds.py).

Found in the syntax tree of every module: a comparison (==, !=, in, not in) one of whose sides is an
attribute ``.method``, ``getattr(x, "method", ...)`` or ``x["method"]``, and a call of a string method on
``x.method`` (``.startswith``). ``args.method`` is the command line's --method option, not a result's.
"""

from __future__ import annotations

import ast

from tb_exudyn.results import RandomResponse, TimeHistory
from tb_exudyn.results.kinds import DETERMINISTIC, RANDOM_KINDS

from .import_graph import ROOT, modules

#: the command line's parsed options (``args.method``: the --method flag)
OPTIONS = "args"


def _is_method_string(node: ast.AST) -> bool:
    if isinstance(node, ast.Attribute) and node.attr == "method":
        return not (isinstance(node.value, ast.Name) and node.value.id == OPTIONS)
    if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id == "getattr":
        return len(node.args) >= 2 and isinstance(node.args[1], ast.Constant) and node.args[1].value == "method"
    if isinstance(node, ast.Subscript):
        return isinstance(node.slice, ast.Constant) and node.slice.value == "method"
    return False


def method_comparisons(source: str) -> list[int]:
    """The lines of ``source`` that compare a result's method string (the module docstring)."""
    out = set()
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Compare) and any(_is_method_string(x) for x in (node.left, *node.comparators)):
            out.add(node.lineno)
        elif (isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute)
              and _is_method_string(node.func.value)):
            out.add(node.lineno)
    return sorted(out)


def test_the_finder_finds_every_form():
    code = ('if r.method == "pem":\n    pass\n'
            'x = "pem" != result.method\n'
            'y = getattr(r, "method", "") in ("pem",)\n'
            'z = r.method.startswith("monte_carlo")\n'
            'w = meta["method"] == "pem"\n'
            'ok = args.method == "det" or r.kind.gaussian or st.method(1) == 2 or f(method="poisson")\n')
    assert method_comparisons(code) == [1, 3, 4, 5, 6]


def test_no_module_outside_methods_compares_a_result_method_string():
    found = [f"{path.relative_to(ROOT)}:{line}" for name, path in modules().items()
             if not name.startswith("tb_exudyn.methods")
             for line in method_comparisons(path.read_text(encoding="utf-8"))]
    assert not found, "a result's method string compared outside tb_exudyn/methods/ (ask result.kind): " + ", ".join(found)


def test_every_kind_is_declared_once():
    """Each method a RandomResponse may record has its kind; a TimeHistory is the deterministic run; their
    folders are the output folder's (pem, mc, mc_linear, det)."""
    from tb_exudyn.results.random_response import METHODS

    assert tuple(RANDOM_KINDS) == METHODS and TimeHistory.kind is DETERMINISTIC
    assert [k.folder for k in RANDOM_KINDS.values()] + [DETERMINISTIC.folder] == ["pem", "mc", "mc_linear", "det"]
    assert [(k.gaussian, k.sampled) for k in RANDOM_KINDS.values()] == [(True, False), (False, True), (False, True)]
    assert all(k.random for k in RANDOM_KINDS.values()) and not DETERMINISTIC.random
    assert isinstance(RandomResponse.kind, property)
