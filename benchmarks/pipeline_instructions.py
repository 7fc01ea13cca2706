"""The pipeline's fixed cost per solve in instructions (deterministic on a shared machine).

CPU time on a machine shared by several processes moves by 20-50 % from run to run; the number
of instructions a solve executes does not. This counts, with valgrind's callgrind, the
instructions of ``xpersson.solve`` of one load with the engine's result canned (the engine
call returns the result it gave once: the pipeline alone, around the engine), per solve, on
scenes of the speed design (``summary_design.py``): a ``jkr`` load (the row "jkr, one load vs
C march") and an elastic closed-form load (the row "one closed-form load vs its kernel").

Collection is switched on only inside ``eval`` (``--toggle-collect=builtin_eval``), which runs
the measured solves after a warm-up, so imports and first solves are not counted. Each scene
runs in its own process under valgrind (about 1-2 minutes each, mostly the imports at ~50x).

Run: ``python benchmarks/pipeline_instructions.py [--solves N] [--scenes NAME ...]``
(needs ``valgrind``; prints a Markdown table, writes nothing). ``--tree PATH`` measures the
source tree at PATH instead (e.g. an export of another commit: ``git archive <rev> | tar -x -C
PATH``), for an A/B of two commits on the same scenes.
"""

from __future__ import annotations

import argparse
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
PLUGINS = ("adhesion", "interface", "plasticity", "transport", "viscoelastic")
DEFAULT_SCENES = ("roll H=0.39 4dec", "flat H=0.89 5dec", "roll H=0.89 3dec")

CHILD = r"""
import sys, warnings
sys.path.insert(0, {bench!r})
warnings.simplefilter("ignore")
import xpersson
from xpersson import engine
from cn_walls import engine_call_of
from summary_design import design, held_out
from summary_paths import _march_cases, scene
spec = (dict(design()) | dict(held_out()))[{name!r}]
sc = scene(spec, "100 kPa") if {elastic!r} else _march_cases(spec)["jkr, one load vs C march"][0]
res = engine_call_of(sc)()
engine.solve_batch = lambda *a, **k: res  # the pipeline alone: the engine's result canned
for _ in range(10):
    xpersson.solve(sc)
eval("[xpersson.solve(sc) for _ in range({n})]")
"""


def instructions(tree: Path, name: str, elastic: bool, n: int) -> float:
    """Instructions per solve [1] of scene ``name`` (jkr or elastic), source tree ``tree``."""
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1", PYTHONHASHSEED="0")  # the same dict layouts
    paths = [tree / "src", *(tree / "plugins" / f"xpersson-{p}" / "src" for p in PLUGINS)]
    env["PYTHONPATH"] = os.pathsep.join(str(p) for p in paths)
    code = CHILD.format(bench=str(HERE), name=name, elastic=elastic, n=n)
    cmd = [
        "valgrind",
        "--tool=callgrind",
        "--toggle-collect=builtin_eval",
        "--callgrind-out-file=/dev/null",
        sys.executable,
        "-c",
        code,
    ]
    out = subprocess.run(cmd, env=env, capture_output=True, text=True, check=True, cwd=tree)
    found = re.search(r"Collected : (\d+)", out.stderr)
    if found is None:
        raise RuntimeError(f"no instruction count in valgrind's output: {out.stderr[-400:]}")
    return int(found.group(1)) / n


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--solves", type=int, default=50, help="measured solves per scene")
    ap.add_argument("--scenes", nargs="+", default=list(DEFAULT_SCENES))
    ap.add_argument("--tree", type=Path, default=HERE.parent, help="source tree to measure")
    args = ap.parse_args()
    if shutil.which("valgrind") is None:
        sys.exit("valgrind is not installed: nothing measured")
    print("| scene | jkr, one load [M instr/solve] | closed form, one load [M instr/solve] |")
    print("|---|---|---|")
    for name in args.scenes:
        jkr, el = (instructions(args.tree, name, e, args.solves) / 1e6 for e in (False, True))
        print(f"| {name} | {jkr:.3f} | {el:.3f} |", flush=True)


if __name__ == "__main__":
    main()
