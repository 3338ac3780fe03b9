"""The import graph of tb_exudyn, computed from the source (no module is imported).

Every ``import`` and ``from ... import`` statement of a module under tb_exudyn/ is an edge, at any
depth (module level, inside functions, under ``if TYPE_CHECKING``), resolved to the package's own
modules: ``from . import x`` is an edge to the sub-module ``x`` when it exists, else to the package.
A package's ``__init__`` is a node of its own. The parents that Python initialises before a
sub-module (``a`` and ``a.b`` before ``a.b.c``) are not edges: they are the package structure, not a
dependency of the importing module's code.
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
    fl = [e for e in es if e.in_function]
    print(len(fl), "function-level imports of own modules:")
    for e in fl:
        print(f"  {e.source}:{e.line} -> {e.target}")
