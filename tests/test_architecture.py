"""The layout's habits as tests (issue 21): no import cycle, small modules, short functions, faces.

`lint-imports` (.importlinter, run by .ci/run) checks the layers and the private-module rule; these
tests check what it does not: cycles between single modules (function-level imports included),
module and function sizes, and that no ``_private`` name is imported across a package border.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[1] / "src" / "xpersson"
MAX_MODULE_LINES = 500
MAX_FUNCTION_LINES = 100
# The closed forms stay in one page so that each formula sits next to its siblings (the image
# sums, the sine series and the linear wall share their helpers); see the module docstring.
LONG_MODULES_ALLOWED = {"engine/exact.py"}


def _modules() -> dict[str, Path]:
    mods = {}
    for path in sorted(SRC.rglob("*.py")):
        parts = list(path.relative_to(SRC.parent).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts = parts[:-1]
        mods[".".join(parts)] = path
    return mods


def _package_of(module: str, path: Path) -> str:
    return module if path.name == "__init__.py" else module.rpartition(".")[0]


def _imports(module: str, path: Path, known: dict[str, Path]):
    """(target module, imported names) of every import statement, at any depth of the file."""
    package = _package_of(module, path)
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                base = base[: len(base) - (node.level - 1)]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            for alias in node.names:
                sub = f"{target}.{alias.name}"
                if sub in known:
                    yield sub, None
                else:
                    yield target, alias.name
        elif isinstance(node, ast.Import):
            for alias in node.names:
                yield alias.name, None


def _graph() -> dict[str, set[str]]:
    mods = _modules()
    graph: dict[str, set[str]] = {m: set() for m in mods}
    for module, path in mods.items():
        for target, _ in _imports(module, path, mods):
            if target in mods and target != module:
                graph[module].add(target)
    return graph


def _cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components with more than one module (Tarjan, iterative)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    found = []
    counter = 0
    for root in graph:
        if root in index:
            continue
        work = [(root, iter(sorted(graph[root])))]
        index[root] = low[root] = counter
        counter += 1
        stack.append(root)
        on_stack.add(root)
        while work:
            node, children = work[-1]
            child = next(children, None)
            if child is not None:
                if child not in index:
                    index[child] = low[child] = counter
                    counter += 1
                    stack.append(child)
                    on_stack.add(child)
                    work.append((child, iter(sorted(graph[child]))))
                elif child in on_stack:
                    low[node] = min(low[node], index[child])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[node])
            if low[node] == index[node]:
                component = []
                while True:
                    member = stack.pop()
                    on_stack.discard(member)
                    component.append(member)
                    if member == node:
                        break
                if len(component) > 1:
                    found.append(sorted(component))
    return found


def test_cycle_finder_finds_a_planted_cycle():
    graph = {"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}, "e": set()}
    assert _cycles(graph) == [["a", "b", "c"]]


def test_no_import_cycle_between_modules():
    assert _cycles(_graph()) == []


def test_modules_are_small():
    too_long = {
        str(path.relative_to(SRC)): n
        for path in SRC.rglob("*.py")
        if (n := len(path.read_text().splitlines())) > MAX_MODULE_LINES
        and str(path.relative_to(SRC)) not in LONG_MODULES_ALLOWED
    }
    assert too_long == {}


def test_functions_are_short():
    too_long = {}
    for path in SRC.rglob("*.py"):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
                n = node.end_lineno - node.lineno + 1
                if n > MAX_FUNCTION_LINES:
                    too_long[f"{path.relative_to(SRC)}:{node.name}"] = n
    assert too_long == {}


def _top_package(module: str) -> str:
    parts = module.split(".")
    return ".".join(parts[:2])


@pytest.mark.parametrize("plugins_root", [SRC.parents[1] / "plugins"])
def test_plugins_use_public_core_names_only(plugins_root):
    """First-party plugins reach the core through public names only (as a third party must)."""
    offenders = []
    for path in plugins_root.glob("*/src/**/*.py"):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom) and (node.module or "").startswith("xpersson."):
                if any(p.startswith("_") for p in node.module.split(".")) or any(
                    a.name.startswith("_") for a in node.names
                ):
                    offenders.append(f"{path.relative_to(plugins_root)}:{node.lineno}")
    assert offenders == []


def test_no_private_name_crosses_a_package_border():
    """``from xpersson.a import _x`` is allowed only inside package ``xpersson.a``'s own tree."""
    mods = _modules()
    offenders = []
    for module, path in mods.items():
        for target, name in _imports(module, path, mods):
            if not target.startswith("xpersson") or name is None or not name.startswith("_"):
                continue
            if name.startswith("__"):
                continue
            if _top_package(target) != _top_package(module):
                offenders.append(f"{module} imports {target}.{name}")
    assert offenders == []
