"""numba's disk cache of the compiled kernels is keyed on their sources (``xpersson.numba_cache``).

numba's own ``cache=True`` reuses a kernel's machine code while the kernel's *file* keeps its
time and size: a change to a callee's module alone ran stale code (measured on the engine's
``level_march`` after an edit of ``_cnstep._gtsv``). These tests build a kernel whose callee
lives in another module of a temporary package, change only the callee, and rebuild in a fresh
process.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from xpersson import numba_cache

KERNEL = """\
from .helper import helper, SCALE


def kernel(x):
    return helper(x) * SCALE
"""

RUN = """\
import types
from stalepkg import kern
from xpersson import numba_cache

jit = numba_cache.njit("stalepkg.kern")
scope = {**vars(kern), "helper": jit(kern.helper)}
fast = jit(types.FunctionType(kern.kernel.__code__, scope, "kernel"))
print(fast(1.0))
"""


@pytest.fixture(autouse=True)
def _forget_stalepkg():
    """``find_spec`` imports a module's parent package: each test's ``stalepkg`` is its own."""
    yield
    for name in [n for n in sys.modules if n == "stalepkg" or n.startswith("stalepkg.")]:
        del sys.modules[name]


def _package(root: Path, offset: str, scale: str = "2.0") -> None:
    pkg = root / "stalepkg"
    pkg.mkdir(exist_ok=True)
    (pkg / "__init__.py").write_text("")
    (pkg / "kern.py").write_text(KERNEL)
    (pkg / "consts.py").write_text(f"SCALE = {scale}\n")
    (pkg / "helper.py").write_text(
        f"from .consts import SCALE\n\n\ndef helper(x):\n    return x + {offset}\n"
    )


def _run(root: Path, cache: str) -> float:
    paths = [str(root), str(Path(numba_cache.__file__).parents[1]), os.environ.get("PYTHONPATH")]
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(p for p in paths if p)}
    env["XPERSSON_CACHE"] = cache
    done = subprocess.run(
        [sys.executable, "-c", RUN], env=env, capture_output=True, text=True, timeout=120
    )
    assert done.returncode == 0, done.stderr
    return float(done.stdout.split()[-1])


def _cache_files(root: Path) -> list[str]:
    return sorted(p.name for p in (root / "stalepkg" / "__pycache__").glob("*.nb[ic]"))


def test_a_callee_change_alone_rebuilds_the_kernel(tmp_path):
    """The kernel's file is untouched; only the callee's module changes (same size): a fresh
    process computes with the new source, and the files of the old stamp are gone (numba's own
    ``cache=True`` returned the stale 4.0). Two processes, each importing numba: ~2 s."""
    pytest.importorskip("numba")
    _package(tmp_path, "1.0")
    assert _run(tmp_path, "on") == 4.0
    first = _cache_files(tmp_path)
    assert any(name.startswith("kern.kernel_") for name in first)
    _package(tmp_path, "2.0")
    assert _run(tmp_path, "on") == 6.0
    assert not set(first) & set(_cache_files(tmp_path))


def test_the_cache_switch_keeps_numba_off_the_disk(tmp_path):
    """``XPERSSON_CACHE=off``: the kernels are compiled without numba's disk cache."""
    pytest.importorskip("numba")
    _package(tmp_path, "1.0")
    assert _run(tmp_path, "off") == 4.0
    assert not (tmp_path / "stalepkg" / "__pycache__").exists() or not _cache_files(tmp_path)


def test_the_stamp_covers_the_imports_transitively(tmp_path, monkeypatch):
    """The stamp changes with a module two imports away and not with an unrelated one."""
    monkeypatch.syspath_prepend(str(tmp_path))
    _package(tmp_path, "1.0")
    (tmp_path / "stalepkg" / "other.py").write_text("X = 1\n")
    names = {p.name for p in numba_cache.source_files("stalepkg.kern")}
    assert names == {"kern.py", "helper.py", "consts.py"}
    before = numba_cache.source_stamp("stalepkg.kern")
    (tmp_path / "stalepkg" / "other.py").write_text("X = 2\n")
    assert numba_cache.source_stamp("stalepkg.kern") == before
    _package(tmp_path, "1.0", scale="2.5")
    after = numba_cache.source_stamp("stalepkg.kern")
    assert after != before and len(after) == numba_cache.STAMP_LENGTH


def test_remove_stale_removes_only_the_kernels_other_stamps(tmp_path):
    stamp, old = "0123456789abcdef", "fedcba9876543210"
    names = [
        f"kern.kernel_{stamp}-4.py311.nbi",  # kept: the current stamp
        f"kern.kernel_{stamp}-4.py311.1.nbc",
        f"kern.kernel_{old}-4.py311.nbi",  # removed: another stamp
        f"kern.kernel_{old}-4.py311.2.nbc",
        "kern.kernel-4.py311.nbi",  # removed: numba's cache=True without a stamp
        f"kern.kernel_rows_{old}-9.py311.nbi",  # kept: another function
        f"other.kernel_{old}-4.py311.nbi",  # kept: another file
    ]
    for name in names:
        (tmp_path / name).write_bytes(b"")
    removed = numba_cache.remove_stale(tmp_path, "kern", "kernel", stamp)
    assert sorted(p.name for p in removed) == sorted(names[2:5])
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(names[:2] + names[5:])


def test_a_module_without_source_is_refused(tmp_path, monkeypatch):
    """A kernel's dependency installed as bytecode only: no stamp can see its changes, so
    ``source_files`` refuses it (and :func:`~xpersson.numba_cache.njit` keeps numba's disk cache
    off for those kernels)."""
    import py_compile

    monkeypatch.syspath_prepend(str(tmp_path))
    pkg = tmp_path / "nosrcpkg"
    pkg.mkdir()
    (pkg / "__init__.py").write_text("")
    (pkg / "kern.py").write_text("from .dep import X\n")
    (pkg / "dep.py").write_text("X = 1\n")
    py_compile.compile(str(pkg / "dep.py"), cfile=str(pkg / "dep.pyc"))
    (pkg / "dep.py").unlink()
    with pytest.raises(LookupError, match="nosrcpkg.dep"):
        numba_cache.source_files("nosrcpkg.kern")


def test_a_file_edited_after_import_is_seen(tmp_path, monkeypatch):
    """An edit while a process runs: its loaded code may be older than the file, so a build
    must not be stored under the new file's stamp."""
    import time

    monkeypatch.syspath_prepend(str(tmp_path))
    _package(tmp_path, "1.0")
    files = numba_cache.source_files("stalepkg.kern")
    monkeypatch.setattr(numba_cache, "_IMPORTED", time.time() + 1.0)  # imported after writing
    assert numba_cache.edited_since_import(files) == []
    later = time.time() + 10.0
    os.utime(tmp_path / "stalepkg" / "helper.py", (later, later))
    assert numba_cache.edited_since_import(files) == [tmp_path / "stalepkg" / "helper.py"]
