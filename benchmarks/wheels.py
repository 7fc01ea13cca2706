"""Build every distribution as wheel + sdist, check them, install the wheels into a fresh venv and
run the test suite there (issue 26: "never built or installed as wheels").

The six distributions: the core ``xpersson``, the four first-party plugins under ``plugins/`` and
the worked third-party example ``examples/third_party_plugin``. Steps:

1. ``python -m build --wheel --sdist`` of each into ``WORK/dist``;
2. ``twine check`` of every file there;
3. a fresh venv ``WORK/venv`` (``python -m venv``), into which the six *wheels* (not editable, not
   the source tree) are installed with the core's ``test`` extra;
4. a copy of the repository's tracked files (``git ls-files``) without any ``src/`` folder in
   ``WORK/tree``, so only the installed wheels can be imported, and the test suite run there with
   the venv's python (``PYTHONPATH`` cleared). The shared reference data folder ``../shared``
   next to the repository is linked beside the copy when present (tests skip without it).

Usage::

    python benchmarks/wheels.py [WORK [SHARED]]

``WORK`` defaults to a new temporary folder; ``SHARED`` is the reference data folder (default
``../shared`` next to the repository), linked as ``WORK/shared`` so the copy finds it as
``../shared``.

Exit status 0 when every step passes; the summary (files built, twine result, pytest's last
line) is printed at the end.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DISTRIBUTIONS = [
    ".",
    "plugins/xpersson-plasticity",
    "plugins/xpersson-interface",
    "plugins/xpersson-adhesion",
    "plugins/xpersson-viscoelastic",
    "examples/third_party_plugin",
]


def _run(cmd: list[str], **kw: object) -> subprocess.CompletedProcess[str]:
    print("+", " ".join(str(c) for c in cmd), flush=True)
    return subprocess.run(cmd, check=True, text=True, **kw)  # type: ignore[call-overload]


def build_all(dist: Path) -> list[Path]:
    """Build wheel and sdist of every distribution into ``dist``; returns the files."""
    dist.mkdir(parents=True, exist_ok=True)
    for d in DISTRIBUTIONS:
        _run(
            [sys.executable, "-m", "build", "--wheel", "--sdist", "--outdir", str(dist), d],
            cwd=ROOT,
        )
    files = sorted(dist.iterdir())
    wheels = [f for f in files if f.suffix == ".whl"]
    sdists = [f for f in files if f.name.endswith(".tar.gz")]
    if len(wheels) != len(DISTRIBUTIONS) or len(sdists) != len(DISTRIBUTIONS):
        raise SystemExit(f"expected {len(DISTRIBUTIONS)} wheels and sdists, got {files}")
    return files


def fresh_venv(venv: Path, wheels: list[Path]) -> Path:
    """A new venv with the wheels installed (core with its ``test`` extra); returns its python."""
    _run([sys.executable, "-m", "venv", str(venv)])
    py = venv / ("Scripts" if os.name == "nt" else "bin") / "python"
    core = next(w for w in wheels if w.name.startswith("xpersson-"))
    others = [str(w) for w in wheels if w is not core]
    _run([str(py), "-m", "pip", "install", "-q", "--upgrade", "pip"])
    _run([str(py), "-m", "pip", "install", "-q", f"{core}[test]", *others])
    return py


def source_free_tree(tree: Path, shared: Path) -> Path:
    """Copy the tracked files without any ``src/`` folder (tests import the installed wheels)."""
    names = _run(["git", "ls-files"], cwd=ROOT, capture_output=True).stdout.split()
    for name in names:
        parts = Path(name).parts
        if "src" in parts:
            continue
        target = tree / name
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(ROOT / name, target)
    if shared.is_dir() and not (tree.parent / "shared").exists():
        (tree.parent / "shared").symlink_to(shared)
    return tree


def main(argv: list[str]) -> int:
    """Run the four steps in ``argv[0]`` (or a temporary folder); 0 when all pass."""
    work = Path(argv[0]) if argv else Path(tempfile.mkdtemp(prefix="xpersson-wheels-"))
    work.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    files = build_all(work / "dist")
    _run([sys.executable, "-m", "twine", "check", "--strict", *map(str, files)])
    py = fresh_venv(work / "venv", [f for f in files if f.suffix == ".whl"])
    shared = Path(argv[1]) if len(argv) > 1 else ROOT.parent / "shared"
    tree = source_free_tree(work / "repo", shared.resolve())
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    where = _run(
        [
            str(py),
            "-c",
            "import xpersson, xpersson_plasticity as p; print(xpersson.__file__, p.__file__)",
        ],
        cwd=tree,
        env=env,
        capture_output=True,
    ).stdout.strip()
    if str(work / "venv") not in where:
        raise SystemExit(f"the packages are not imported from the venv: {where}")
    tests = subprocess.run(
        [str(py), "-m", "pytest", "-q", "-p", "no:cacheprovider"],
        cwd=tree,
        env=env,
        text=True,
        capture_output=True,
    )
    last = tests.stdout.strip().splitlines()[-1] if tests.stdout.strip() else tests.stderr
    (work / "pytest.log").write_text(tests.stdout + tests.stderr)
    print(f"\nbuilt {len(files)} files in {work / 'dist'}:")
    for f in files:
        print(f"  {f.name}")
    print("twine check --strict: PASSED")
    print(f"imported from: {where}")
    print(f"pytest in the wheel venv: {last}  (log: {work / 'pytest.log'})")
    print(f"total {time.perf_counter() - t0:.0f} s")
    return tests.returncode


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
