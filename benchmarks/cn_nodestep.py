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

Usage: ``python benchmarks/cn_nodestep.py [--rounds 5] [--scenes jkr30,jkr89,plastic40]
[--against OTHER/src]``. ``--against`` also times the compiled level of another checkout (its
``engine/_cnstep.py`` and ``engine/_moving_fused.py``, compiled in this process beside this
tree's, e.g. a ``git worktree`` of an older commit) on the same levels, in the same alternated
rounds: a before/after that the machine's load changes less than two runs would.
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


def other_tree(src: Path) -> tuple:
    """``fused_level`` and its compiled kernels from the checkout whose ``src`` folder is
    ``src`` (its ``_cnstep`` and ``_moving_fused`` with this tree's ``_level``; the helper
    functions it has compiled and bound as ``_compiled`` binds them)."""
    import types

    import numba

    jit = numba.njit(nogil=True, error_model="numpy")  # (the compiled march's options)
    mods = {}
    for name in ("_cnstep", "_moving_fused"):
        text = (src / "xpersson" / "engine" / f"{name}.py").read_text()
        text = text.replace("from ._cnstep import", "from other_cnstep import")
        text = text.replace("from ._level", "from xpersson.engine._level")
        mod = types.ModuleType(f"other{name}")
        sys.modules[f"other{name}"] = mod
        exec(compile(text, f"other{name}", "exec"), mod.__dict__)  # noqa: S102 - a benchmark
        mods[name] = mod
    cn, fu = mods["_cnstep"], mods["_moving_fused"]
    kernels = ("_factor", "_solve_factor") if hasattr(cn, "_factor") else ("_gtsv",)
    scope = {k: jit(getattr(cn, k)) for k in kernels}
    names = ("_diagonals", "_system", "_explicit", "_wall_fluxes", "_record")
    for name in names:  # (in this order: _system may call _diagonals)
        if hasattr(fu, name):
            fn = getattr(fu, name)
            scope[name] = jit(types.FunctionType(fn.__code__, {**vars(fu), **scope}, name))
    level = jit(types.FunctionType(fu.level_march.__code__, {**vars(fu), **scope}, "lm"))
    return fu.fused_level, (level, jit(fu.face_coefficients))


def timed(fn, seconds: float = 0.2) -> float:
    """CPU seconds of one call of ``fn``, repeated to about ``seconds``."""
    t, n = time.process_time(), 0
    while time.process_time() - t < seconds or n == 0:
        fn()
        n += 1
    return (time.process_time() - t) / n


def marches(levels: list, fns: tuple, lib, other: tuple | None) -> dict:
    """The timed calls on ``levels``: ``engine`` (this tree's compiled level ``fns``), ``C``
    (the C march ``lib``, if built) and ``other`` (``--against``'s level, if given)."""
    from xpersson.engine import _moving_fused

    dp = ctypes.POINTER(ctypes.c_double)

    def engine() -> None:
        for inp, r0, stretch in levels:
            _moving_fused.fused_level(fns, inp, r0, stretch)

    def c_march() -> None:
        for inp, _, _ in levels:
            m, steps = inp.p0.shape[0] * inp.nodes.x.size, inp.taus.size - 1
            r, ws = np.random.default_rng(1).random(m), np.empty(3 * m)
            lib.march(m, steps, r.ctypes.data_as(dp), ws.ctypes.data_as(dp))

    def engine_other() -> None:
        for inp, r0, stretch in levels:
            other[0](other[1], inp, r0, stretch)

    out = {"engine": engine}
    if lib is not None:
        out["C"] = c_march
    if other is not None:
        out["other"] = engine_other
    return out


def report(name: str, levels: list, ns: dict) -> str:
    """One line: the levels, ns per node-step of each march and the ratios to C."""
    shape = ", ".join(f"{i.p0.shape[0]}x{i.nodes.x.size}x{i.taus.size - 1}" for i, _, _ in levels)
    line = f"{name}: {node_steps(levels):.3g} node-steps ({shape})"
    for key, label in (("engine", "engine"), ("other", "--against")):
        if key in ns:
            line += f"; {label} {ns[key]:.2f} ns/node-step"
            if "C" in ns:
                line += f" ({ns[key] / ns['C']:.2f} x C)"
    if "C" in ns:
        line += f"; C {ns['C']:.2f} ns/node-step"
    return line


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--scenes", default="jkr30,jkr89,plastic40")
    ap.add_argument("--against", type=Path, default=None, metavar="OTHER_SRC")
    args = ap.parse_args(argv)
    import summary_paths as SP

    from xpersson.engine import _compiled

    if not _compiled.build():
        print("skip: the compiled march is off or numba is missing")
        return
    lib = SP.c_march_lib(PEERS)
    fns = _compiled.built("fused")
    other = other_tree(args.against) if args.against else None
    table = scenes()
    for name in args.scenes.split(","):
        levels = record_levels(table[name])
        if not node_steps(levels):
            print(f"{name}: no level marched")
            continue
        calls = marches(levels, fns, lib, other)
        best = dict.fromkeys(calls, np.inf)
        for _ in range(args.rounds):
            for key, fn in calls.items():
                best[key] = min(best[key], timed(fn))
        ns = {k: v * 1e9 / node_steps(levels) for k, v in best.items()}
        print(report(name, levels, ns), flush=True)


if __name__ == "__main__":
    main()
