"""The import graph of tb_exudyn, computed from the source (no module is imported).

Every ``import`` and ``from ... import`` statement of a module under tb_exudyn/ is an edge, at any
depth (module level, inside functions, under ``if TYPE_CHECKING``), resolved to the package's own
modules: ``from . import x`` is an edge to the sub-module ``x`` when it exists, else to the package.
A package's ``__init__`` is a node of its own. The parents that Python initialises before a
sub-module (``a`` and ``a.b`` before ``a.b.c``) are not edges: they are the package structure, not a
dependency of the importing module's code.

A load by name is an edge too (``by_name``): ``importlib.import_module("tb_exudyn.x")`` (or
``import_module``, or ``jit.load``, which imports a module of compiled functions), ``importlib.import_module(".x", __name__)`` / ``(".x", "tb_exudyn.pkg")`` resolved
against its package; and where the name is not a literal (a registry: ``import_module(module)``),
every string literal of that module that names one of the package's modules, since any of them may
be what it loads (an over-count is safe for a test that allows no cycle). Such a dependency is as
real as an import statement: it only runs later.
"""

from __future__ import annotations

import ast
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
PACKAGE = "tb_exudyn"


@dataclass(frozen=True)
class Edge:
    source: str
    target: str
    line: int
    in_function: bool
    by_name: bool = False


def module_name(path: Path) -> str:
    rel = path.relative_to(ROOT).with_suffix("")
    parts = list(rel.parts)
    if parts[-1] == "__init__":
        parts = parts[:-1]
    return ".".join(parts)


def modules() -> dict[str, Path]:
    return {module_name(p): p for p in sorted((ROOT / PACKAGE).rglob("*.py"))}


def _is_package(name: str, mods: dict[str, Path]) -> bool:
    return name in mods and mods[name].name == "__init__.py"


def _resolve(current: str, level: int, module: str | None, mods: dict[str, Path]) -> str:
    if level == 0:
        return module or ""
    base = current.split(".")
    if not _is_package(current, mods):
        base = base[:-1]
    base = base[: len(base) - (level - 1)]
    return ".".join(base + ([module] if module else []))


def _is_import_module(node: ast.AST) -> bool:
    """``importlib.import_module(...)``, ``import_module(...)`` or ``jit.load(...)`` (tb_exudyn.jit's
    loader of compiled modules)."""
    if not isinstance(node, ast.Call):
        return False
    f = node.func
    return (isinstance(f, ast.Attribute) and isinstance(f.value, ast.Name)
            and (f.attr, f.value.id) in {("import_module", "importlib"), ("load", "jit")}) or (
        isinstance(f, ast.Name) and f.id == "import_module")


def _string(node: ast.AST | None) -> str | None:
    return node.value if isinstance(node, ast.Constant) and isinstance(node.value, str) else None


def by_name(name: str, tree: ast.AST, mods: dict[str, Path]) -> list[tuple[str, int]]:
    """(target, line) of every load by name in the module ``name`` (see the module docstring)."""
    out: list[tuple[str, int]] = []
    dynamic: list[int] = []
    for node in ast.walk(tree):
        if not _is_import_module(node) or not node.args:
            continue
        target = _string(node.args[0])
        if target is None:
            dynamic.append(node.lineno)
            continue
        if target.startswith("."):
            package_arg = node.args[1] if len(node.args) > 1 else next(
                (k.value for k in node.keywords if k.arg == "package"), None)
            package = _string(package_arg)
            if package is None:  # __name__ or __package__: this module's own package context
                package = name if _is_package(name, mods) else name.rpartition(".")[0]
            level = len(target) - len(target.lstrip("."))
            base = package.split(".")
            base = base[: len(base) - (level - 1)]
            target = ".".join(base + ([target.lstrip(".")] if target.lstrip(".") else []))
        out.append((target, node.lineno))
    if dynamic:
        names = {n.value for n in ast.walk(tree) if isinstance(n, ast.Constant) and isinstance(n.value, str)}
        out += [(n.partition(":")[0], dynamic[0]) for n in sorted(names) if n.partition(":")[0] in mods]
    return out


def edges() -> list[Edge]:
    mods = modules()
    out: list[Edge] = []
    for name, path in mods.items():
        tree = ast.parse(path.read_text(encoding="utf-8"))
        func_lines: set[int] = set()
        for node in ast.walk(tree):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                for sub in ast.walk(node):
                    if isinstance(sub, (ast.Import, ast.ImportFrom)):
                        func_lines.add(sub.lineno)
        for node in ast.walk(tree):
            targets: list[str] = []
            if isinstance(node, ast.Import):
                targets = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom):
                base = _resolve(name, node.level, node.module, mods)
                subs = [f"{base}.{alias.name}" for alias in node.names]
                targets = [t for t in subs if t in mods]
                if len(targets) < len(subs):  # a name defined in the module or package itself
                    targets.append(base)
            for target in targets:
                if target in mods and target != name and (target == PACKAGE or target.startswith(PACKAGE + ".")):
                    out.append(Edge(name, target, node.lineno, node.lineno in func_lines))
        for target, line in by_name(name, tree, mods):
            if target in mods and target != name:
                out.append(Edge(name, target, line, True, by_name=True))
    return out


def cycles(graph_edges: list[Edge]) -> list[list[str]]:
    """The strongly connected components with more than one module (Tarjan)."""
    graph: dict[str, set[str]] = {}
    for e in graph_edges:
        graph.setdefault(e.source, set()).add(e.target)
        graph.setdefault(e.target, set())
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on: set[str] = set()
    found: list[list[str]] = []
    counter = [0]

    def visit(v: str) -> None:
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in sorted(graph[v]):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                found.append(sorted(comp))

    import sys

    sys.setrecursionlimit(10000)
    for v in sorted(graph):
        if v not in index:
            visit(v)
    return found


if __name__ == "__main__":
    es = edges()
    for c in cycles(es):
        print("cycle:", " <-> ".join(c))
    fl = [e for e in es if e.in_function and not e.by_name]
    print(len(fl), "function-level imports of own modules:")
    for e in fl:
        print(f"  {e.source}:{e.line} -> {e.target}")
    bn = [e for e in es if e.by_name]
    print(len(bn), "loads by name of own modules:")
    for e in bn:
        print(f"  {e.source}:{e.line} -> {e.target}")
