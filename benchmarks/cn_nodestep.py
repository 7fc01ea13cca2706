"""The compiled ``cn`` march's cost per node-step on fixed levels, against the C march (issue 36).

The levels of a scene are recorded once (a spy on ``xpersson.engine._moving.fused_level``: the
level's inputs and start state), then the compiled level (:func:`xpersson.engine._moving_fused.
fused_level`: face coefficients, BLAS product, the march) is timed on them alone, and the C
Thomas march of ``peers/c_march/thomas.c`` on the same levels and steps, in alternated rounds:
ns per node-step of each and their ratio. No error control, no pipeline, no level inputs: what
is left is the cost of a node-step. CPU time (``time.process_time``), ``OPENBLAS_NUM_THREADS=1``,
best of ``--rounds`` rounds, each timed call repeated to ~0.2 s.

Scenes: ``jkr`` (the "engine alone (jkr)" rows of ``summary.py``, rtol 1e-8, on the design's
``roll H=0.30 6dec`` and on the held-out (seed 2026) ``roll H=0.89 3dec``: one load), and
``plastic`` (the worst scene of ``plastic_design.py``, seed 7036, ``roll H=0.40 5dec``: three
loads, a yield wall).

Usage: ``python benchmarks/cn_nodestep.py [--rounds 5] [--scenes jkr30,jkr89,plastic40]``.
To compare two trees, run it with each on ``PYTHONPATH`` (the levels are the same: results are
bitwise equal).
"""

from __future__ import annotations

import os

os.environ["OPENBLAS_NUM_THREADS"] = "1"

import argparse  # noqa: E402
import ctypes  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
import warnings  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

PEERS = Path(os.environ.get("XPERSSON_PEERS", HERE.parents[1] / "shared" / "peers"))


def scenes() -> dict[str, dict]:
    """The named scenes (see the module)."""
    import engine_limit as EL
    import plastic_design as PD
    from summary_design import design, held_out

    return {
        "jkr30": EL.jkr_scene(dict(design(12, 36))["roll H=0.30 6dec"], 1e-8),
        "jkr89": EL.jkr_scene(dict(held_out(12, 2026))["roll H=0.89 3dec"], 1e-8),
        "plastic40": dict(PD.design(32, 7036))[
            "roll H=0.40 5dec Y1=0.44GPa n=0.28 p0/Y1=5e-02-0.45 full"
        ],
    }


def record_levels(scene: dict) -> list:
    """(inputs, start state, stretch) of every level the compiled path marches for ``scene``."""
    import xpersson
    from xpersson.engine import _moving

    got: list = []
    orig = _moving.fused_level

    def spy(fns, inp, r0, stretch):
        got.append((inp, r0.copy(), stretch))
        return orig(fns, inp, r0, stretch)

    _moving.fused_level = spy
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            xpersson.solve(scene)
    finally:
        _moving.fused_level = orig
    return got


def node_steps(levels: list) -> int:
    """Node-steps of the recorded levels (loads x nodes x steps)."""
    return sum(i.p0.shape[0] * i.nodes.x.size * (i.taus.size - 1) for i, _, _ in levels)


def timed(fn, seconds: float = 0.2) -> float:
    """CPU seconds of one call of ``fn``, repeated to about ``seconds``."""
    t, n = time.process_time(), 0
    while time.process_time() - t < seconds or n == 0:
        fn()
        n += 1
    return (time.process_time() - t) / n


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--scenes", default="jkr30,jkr89,plastic40")
    args = ap.parse_args(argv)
    import summary_paths as SP

    from xpersson.engine import _compiled, _moving_fused

    if not _compiled.build():
        print("skip: the compiled march is off or numba is missing")
        return
    lib = SP.c_march_lib(PEERS)
    fns = _compiled.fused()
    dp = ctypes.POINTER(ctypes.c_double)
    table = scenes()
    for name in args.scenes.split(","):
        levels = record_levels(table[name])
        work = node_steps(levels)
        if not work:
            print(f"{name}: no level marched")
            continue

        def engine(levels=levels) -> None:
            for inp, r0, stretch in levels:
                _moving_fused.fused_level(fns, inp, r0, stretch)

        def c_march(levels=levels) -> None:
            for inp, _, _ in levels:
                m, steps = inp.p0.shape[0] * inp.nodes.x.size, inp.taus.size - 1
                r, ws = np.random.default_rng(1).random(m), np.empty(3 * m)
                lib.march(m, steps, r.ctypes.data_as(dp), ws.ctypes.data_as(dp))

        fns_ = {"engine": engine} if lib is None else {"engine": engine, "C": c_march}
        best = dict.fromkeys(fns_, np.inf)
        for _ in range(args.rounds):
            for key, fn in fns_.items():
                best[key] = min(best[key], timed(fn))
        ns = {k: v * 1e9 / work for k, v in best.items()}
        shape = ", ".join(
            f"{i.p0.shape[0]}x{i.nodes.x.size}x{i.taus.size - 1}" for i, _, _ in levels
        )
        line = f"{name}: {work:.3g} node-steps ({shape}); engine {ns['engine']:.2f} ns/node-step"
        if "C" in ns:
            line += f", C {ns['C']:.2f} ns/node-step, ratio {ns['engine'] / ns['C']:.2f}"
        print(line, flush=True)


if __name__ == "__main__":
    main()
