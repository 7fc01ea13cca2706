"""The layout's habits as tests (issues 21, 33): no import cycle, small modules, short functions,
faces, for the core and for each first-party plugin package alike.

`lint-imports` (.importlinter, run by .ci/run) checks the layers, the private-module rule, the
plugins' independence and that the core never imports a plugin; these tests check what it does
not: cycles between single modules (function-level imports included), module and function sizes,
that no ``_private`` name is imported across a package border, that the plugins use public core
names only, and, once more in plain Python, that plugins and core stay apart.

Every check runs over ``src/xpersson`` and each ``plugins/xpersson-*/src/xpersson_*``. A limit
that fails is a prompt to split a module or a function by its jobs, never to fold lines.
"""

from __future__ import annotations

import ast
import configparser
from collections.abc import Iterator
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
SRC = ROOT / "src" / "xpersson"
PLUGINS = sorted(ROOT.glob("plugins/xpersson-*/src/xpersson_*"))
PACKAGES = [SRC, *PLUGINS]
FIRST_PARTY = {"adhesion", "interface", "plasticity", "transport", "viscoelastic"}
MAX_MODULE_LINES = 500
MAX_FUNCTION_LINES = 100
# The closed forms stay in one page so that each formula sits next to its siblings (the image
# sums, the sine series and the linear wall share their helpers); see the module docstring.
LONG_MODULES_ALLOWED = {"xpersson/engine/exact.py"}

every_package = pytest.mark.parametrize("package", PACKAGES, ids=lambda p: p.name)
every_plugin = pytest.mark.parametrize("package", PLUGINS, ids=lambda p: p.name)


def _modules(package: Path) -> dict[str, Path]:
    """Dotted module name -> file, for every module of ``package`` (a source directory)."""
    mods = {}
    for path in sorted(package.rglob("*.py")):
        parts = list(path.relative_to(package.parent).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts = parts[:-1]
        mods[".".join(parts)] = path
    return mods


def _package_of(module: str, path: Path) -> str:
    return module if path.name == "__init__.py" else module.rpartition(".")[0]


def _imports(module: str, path: Path, known: dict[str, Path]) -> Iterator[tuple[str, str | None]]:
    """(target module, imported name or None) of every import statement, at any depth of the
    file (function-level imports included)."""
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


def _graph(package: Path) -> dict[str, set[str]]:
    mods = _modules(package)
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


def test_every_first_party_plugin_is_covered():
    assert {p.name.removeprefix("xpersson_") for p in PLUGINS} == FIRST_PARTY


def test_the_import_contract_covers_every_package():
    """.importlinter's root packages, faces, acyclic and independence contracts name the core
    and every first-party plugin package found here."""
    config = configparser.ConfigParser()
    config.read(ROOT / ".importlinter")
    plugins = {p.name for p in PLUGINS}
    listed = {
        "root_packages": config["importlinter"]["root_packages"],
        "faces": config["importlinter:contract:faces"]["packages_with_private_modules"],
        "acyclic": config["importlinter:contract:acyclic"]["ancestors"],
    }
    for key, value in listed.items():
        assert set(value.split()) == {"xpersson"} | plugins, key
    independent = config["importlinter:contract:plugins-independent"]["modules"]
    assert set(independent.split()) == plugins
    forbidden = config["importlinter:contract:core-names-no-plugin"]["forbidden_modules"]
    assert set(forbidden.split()) == plugins


def test_cycle_finder_finds_a_planted_cycle():
    graph = {"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}, "e": set()}
    assert _cycles(graph) == [["a", "b", "c"]]


def test_cycle_finder_sees_a_function_level_import(tmp_path):
    pkg = tmp_path / "pkg"
    pkg.mkdir()
    (pkg / "__init__.py").write_text("")
    (pkg / "a.py").write_text("from .b import g\n")
    (pkg / "b.py").write_text("def g():\n    from .a import f\n")
    assert _cycles(_graph(pkg)) == [["pkg.a", "pkg.b"]]


@every_package
def test_no_import_cycle_between_modules(package):
    assert _cycles(_graph(package)) == []


@every_package
def test_modules_are_small(package):
    too_long = {}
    for path in package.rglob("*.py"):
        name = str(path.relative_to(package.parent))
        n = len(path.read_text().splitlines())
        if n > MAX_MODULE_LINES and name not in LONG_MODULES_ALLOWED:
            too_long[name] = n
    assert too_long == {}


@every_package
def test_functions_are_short(package):
    too_long = {}
    for path in package.rglob("*.py"):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
                n = node.end_lineno - node.lineno + 1
                if n > MAX_FUNCTION_LINES:
                    too_long[f"{path.relative_to(package.parent)}:{node.name}"] = n
    assert too_long == {}


def _border(module: str) -> str:
    """The package whose private names ``module`` may import: a sub-package (or top-level module)
    of the core, or the whole of a (flat) plugin package."""
    parts = module.split(".")
    return ".".join(parts[:2]) if parts[0] == "xpersson" else parts[0]


@every_package
def test_no_private_name_crosses_a_package_border(package):
    """``from xpersson.a import _x`` is allowed only inside package ``xpersson.a``'s own tree."""
    mods = _modules(package)
    offenders = []
    for module, path in mods.items():
        for target, name in _imports(module, path, mods):
            if not target.startswith("xpersson") or name is None or not name.startswith("_"):
                continue
            if name.startswith("__"):
                continue
            if _border(target) != _border(module):
                offenders.append(f"{module} imports {target}.{name}")
    assert offenders == []


@every_plugin
def test_plugins_use_public_core_names_only(package):
    """First-party plugins reach the core through public names only (as a third party must):
    no ``_private`` module of ``xpersson`` and no ``_private`` name imported from it."""
    mods = _modules(package)
    offenders = []
    for module, path in mods.items():
        for target, name in _imports(module, path, mods):
            if target != "xpersson" and not target.startswith("xpersson."):
                continue
            private_module = any(p.startswith("_") for p in target.split("."))
            if private_module or (name or "").startswith("_"):
                offenders.append(f"{module} imports {target}" + (f".{name}" if name else ""))
    assert offenders == []


def _foreign(package: Path) -> list[str]:
    """Imports in ``package`` of a ``xpersson_*`` package other than itself."""
    mods = _modules(package)
    hits = []
    for module, path in mods.items():
        for target, name in _imports(module, path, mods):
            top = target.split(".")[0]
            if top.startswith("xpersson_") and top != package.name:
                hits.append(f"{module} imports {target}" + (f".{name}" if name else ""))
    return hits


@every_plugin
def test_plugins_never_import_each_other(package):
    """No exception: what two plugins need lives in the core (``xpersson.plugins.solved``)."""
    assert _foreign(package) == []


def test_the_independence_contract_ignores_no_import():
    """.importlinter's independence contract has no ``ignore_imports``: no edge is excused."""
    config = configparser.ConfigParser()
    config.read(ROOT / ".importlinter")
    assert "ignore_imports" not in config["importlinter:contract:plugins-independent"]


def test_import_finder_sees_a_plugin_importing_another(tmp_path):
    pkg = tmp_path / "xpersson_a"
    pkg.mkdir()
    (pkg / "__init__.py").write_text("")
    (pkg / "m.py").write_text("def f():\n    from xpersson_b.c import g\n")
    assert _foreign(pkg) == ["xpersson_a.m imports xpersson_b.c.g"]


def test_core_never_imports_a_plugin():
    """The core finds plugins through entry points only; it never names a plugin package."""
    assert _foreign(SRC) == []
