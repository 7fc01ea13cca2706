"""Start-up cost: the first solve and the CLI commands, each in a fresh interpreter.

Run from the checkout::

    python benchmarks/startup.py [--rounds 5]

CPU time of each child process (user + system, ``resource.getrusage``; the machine may be
shared), ``OPENBLAS_NUM_THREADS=1``, the best of ``--rounds`` rounds in which the commands are
run alternately. The first solve is ``summary.FIRST_SOLVE`` (the README's one-load elastic
scene, timed inside the child from before ``import xpersson``), against ``import xarray,
pint`` timed the same way; the CLI commands are timed as whole processes (interpreter start
included): ``xpersson --help``, ``validate``, ``run`` and ``info`` on ``examples/elastic.toml``.
"""

from __future__ import annotations

import os

os.environ["OPENBLAS_NUM_THREADS"] = "1"

import argparse  # noqa: E402
import resource  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
from pathlib import Path  # noqa: E402

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from summary import FIRST_SOLVE, IMPORTS  # noqa: E402

CLI = "import sys; from xpersson.cli import main; sys.exit(main(sys.argv[1:]))"


def child_cpu(args: list[str]) -> float:
    """CPU time [s] of one child interpreter running ``python -c CLI args``."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    out = subprocess.run([sys.executable, "-c", CLI, *args], capture_output=True, text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if out.returncode:
        raise RuntimeError(f"xpersson {' '.join(args)} failed: {out.stderr[-500:]}")
    return after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime


def inner_cpu(code: str) -> float:
    """CPU time [s] the child prints (timed inside it)."""
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    return float(out.stdout.strip().splitlines()[-1])


def main(argv: list[str] | None = None) -> dict[str, float]:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=5)
    args = ap.parse_args(argv)
    scene = str(HERE.parent / "examples" / "elastic.toml")
    best: dict[str, float] = {}
    with tempfile.TemporaryDirectory() as tmp:
        nc = str(Path(tmp) / "elastic.nc")
        for _ in range(args.rounds):
            Path(nc).unlink(missing_ok=True)
            times = {
                "import xarray, pint": inner_cpu(IMPORTS),
                "first solve (one load)": inner_cpu(FIRST_SOLVE),
                "xpersson --help": child_cpu(["--help"]),
                "xpersson validate": child_cpu(["validate", scene]),
                "xpersson run": child_cpu(["run", scene, "-o", nc, "--quiet"]),
                "xpersson info": child_cpu(["info", nc]),
            }
            for name, t in times.items():
                best[name] = min(best.get(name, float("inf")), t)
    base = best["import xarray, pint"]
    for name, t in best.items():
        print(f"{name:26s} {t:5.2f} s CPU  ({t / base:.1f}x `import xarray, pint`)")
    return best


if __name__ == "__main__":
    main()
