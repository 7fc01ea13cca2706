"""numba's on-disk cache of xpersson's compiled kernels, keyed on the sources they depend on.

numba's ``cache=True`` keeps a compiled function on disk next to its source (or in
``NUMBA_CACHE_DIR``) and reuses it while *that function's file* keeps its modification time and
size. It does not look at the functions the kernel calls, nor at the modules whose constants
it froze in: after a change to a callee's module only (a developer's edit, a branch switch, an
upgrade that keeps a file's time and size), the stale machine code would run and give other
numbers than the numpy path it must equal, silently.

:func:`njit` is ``numba.njit`` with that hole closed. Its kernels are compiled under a name
that carries a **source stamp** (:func:`source_stamp`: a SHA-256 digest of the source bytes of
the given modules and of every module of the same packages they import, transitively, function
level imports included), so numba's cache file of a kernel is named by the stamp: after any
change to those sources, the kernel is built afresh and never loaded from a stale file; the
files of other stamps of the same kernel are then removed from numba's cache directory (nothing
is written elsewhere). A source file modified after this module's import (an edit while a
process runs) may no longer be the code the process runs: then the kernels are built without
the disk cache (:func:`edited_since_import`); so are kernels that depend on a module without
Python source. It relies on numba naming a cache file after the function's file and
``__qualname__`` (numba's ``_CacheImpl``, 0.68 and earlier; ``tests/test_numba_cache.py`` fails
if a release stops doing so); the clean-up reads numba's ``Dispatcher.stats.cache_path`` and is
skipped where it is missing.

The cache switch is respected: with ``xpersson.set_options(cache=False)`` (or
``XPERSSON_CACHE=off``) at the time of the build, the kernels are compiled without numba's disk
cache (nothing read, nothing written). Usage, once per process when the kernels are built::

    jit = numba_cache.njit(__name__, nogil=True, error_model="numpy")
    if jit is None:  # numba is not installed
        ...
    fast = jit(kernel)
"""

from __future__ import annotations

import ast
import hashlib
import importlib.util
import re
import sys
import time
import types
from collections.abc import Callable, Iterable
from pathlib import Path
from typing import Any

from .options import cache_enabled

__all__ = [
    "STAMP_LENGTH",
    "edited_since_import",
    "njit",
    "remove_stale",
    "source_files",
    "source_stamp",
]

STAMP_LENGTH = 16
"""Hexadecimal digits of the source stamp in a kernel's compiled name (64 bits)."""

_IMPORTED = time.time()  # [s] since the epoch: files modified later may differ from the code run


def njit(*modules: str | types.ModuleType, **options: Any) -> Callable[[Any], Any] | None:
    """A ``numba.njit(**options)`` decorator whose disk cache is keyed on the sources of
    ``modules`` (names or modules) and of the modules of their packages that they import; None
    when numba is not installed.

    Each decorated function is a copy of the given one (which is left as it is: its numpy
    callers keep using it) named ``<qualname>_<stamp>``; ``cache`` is
    :func:`~xpersson.options.cache_enabled` at the call unless ``options`` sets it.
    """
    try:
        import numba
    except ImportError:
        return None
    try:
        files = source_files(*modules)
        stamp = _stamp(files)
    except (LookupError, OSError):  # a module without readable source: no disk cache at all
        files, stamp, options = [], "nosource", {**options, "cache": False}
    if edited_since_import(files):  # the loaded code may not be the files' (no disk cache)
        options = {**options, "cache": False}
    options = {"cache": cache_enabled(), **options}
    jit = numba.njit(**options)

    def decorate(fn: Any) -> Any:
        copy = types.FunctionType(
            fn.__code__, fn.__globals__, fn.__name__, fn.__defaults__, fn.__closure__
        )
        copy.__kwdefaults__ = fn.__kwdefaults__
        copy.__qualname__ = f"{fn.__qualname__}_{stamp}"
        dispatcher = jit(copy)
        if options["cache"]:
            path = getattr(getattr(dispatcher, "stats", None), "cache_path", None)
            if path is not None:
                remove_stale(Path(path), Path(fn.__code__.co_filename).stem, fn.__qualname__, stamp)
        return dispatcher

    return decorate


def source_stamp(*modules: str | types.ModuleType) -> str:
    """The first :data:`STAMP_LENGTH` hexadecimal digits of the SHA-256 digest of the source
    bytes of :func:`source_files` (each file's bytes with its length, in path order)."""
    return _stamp(source_files(*modules))


def edited_since_import(files: Iterable[Path]) -> list[Path]:
    """The ``files`` modified after this module was imported: the code a process runs may then
    be older than the files' source, and a build stored under their stamp would be stale
    (the kernels are then built without numba's disk cache)."""
    return [path for path in files if path.stat().st_mtime > _IMPORTED]


def _stamp(files: Iterable[Path]) -> str:
    digest = hashlib.sha256()
    for path in files:
        data = path.read_bytes()
        digest.update(f"{path.name}:{len(data)}:".encode())
        digest.update(data)
    return digest.hexdigest()[:STAMP_LENGTH]


def source_files(*modules: str | types.ModuleType) -> list[Path]:
    """The source files of ``modules`` and of every module they import (any import statement,
    function level ones included), transitively, within their top-level packages and
    ``xpersson``; sorted by path. Raises LookupError for such a module without a ``.py``
    source (compiled only), whose changes no stamp could see."""
    names = [m if isinstance(m, str) else m.__name__ for m in modules]
    roots = {"xpersson", *(name.split(".")[0] for name in names)}
    seen: dict[str, Path] = {}
    todo = list(names)
    while todo:
        name = todo.pop()
        if name in seen:
            continue
        origin = _origin(name)
        if origin is None:  # no such module (an attribute of a package, say)
            continue
        if not origin.endswith(".py"):
            raise LookupError(f"module {name} has no Python source ({origin})")
        seen[name] = path = Path(origin)
        package = name if path.name == "__init__.py" else name.rpartition(".")[0]
        todo.extend(n for n in _imported(path, package) if n.split(".")[0] in roots)
    return sorted(set(seen.values()))


def remove_stale(cache_path: Path, module: str, qualname: str, stamp: str) -> list[Path]:
    """Remove numba's cache files (index ``.nbi`` and data ``.nbc``) in ``cache_path`` of the
    function ``qualname`` of the source file ``module`` (its stem) compiled under a stamp other
    than ``stamp`` or under no stamp (``cache=True`` of earlier releases); the removed paths."""
    pattern = re.compile(
        rf"{re.escape(module)}\.{re.escape(qualname)}(_[0-9a-f]{{{STAMP_LENGTH}}})?"
        r"-\d+\.py\d+.*\.nb[ic]"
    )
    keep = f"{module}.{qualname}_{stamp}-"
    removed = []
    for path in _listing(cache_path):
        if pattern.fullmatch(path.name) and not path.name.startswith(keep):
            try:
                path.unlink()
            except OSError:  # another process removed it, or no permission: numba copes
                continue
            removed.append(path)
    return removed


def _listing(directory: Path) -> Iterable[Path]:
    try:
        return list(directory.iterdir())
    except OSError:
        return []


def _origin(name: str) -> str | None:
    """Where the module ``name`` was (or would be) loaded from (``"built-in"``, say, for
    modules without a file), or None: no such module."""
    module = sys.modules.get(name)
    origin = getattr(module, "__file__", None)
    if origin is None:
        try:
            spec = importlib.util.find_spec(name)
        except (ImportError, ValueError):
            return None
        if spec is None:
            return None
        origin = spec.origin or "namespace package"
    return str(origin)


def _imported(path: Path, package: str) -> Iterable[str]:
    """The absolute names of the modules the file ``path`` (of ``package``) imports from: for
    ``from X import a``, ``X.a`` if it is a module, else ``X``."""
    for node in ast.walk(ast.parse(path.read_bytes(), str(path))):
        if isinstance(node, ast.Import):
            yield from (alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = "." * node.level + (node.module or "")
            try:
                base = importlib.util.resolve_name(base, package) if node.level else base
            except (ImportError, ValueError):
                continue
            names = [f"{base}.{alias.name}" for alias in node.names if alias.name != "*"]
            modules = [name for name in names if _origin(name) is not None]
            yield from modules
            if len(modules) < len(node.names):  # some names are the package's own
                yield base
