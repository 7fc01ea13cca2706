"""The cost of one leakage direct call (``Leakage._direct``), fixed part and per load.

Runs whole solves of a design scene with the ``leakage`` analysis (so every per-solve cache is
as fresh as in a user's solve) and times each direct call the solve makes (CPU time), with the
number of loads it computed; ``--parts`` also times the named pieces inside the calls (nested:
they overlap), ``--profile`` profiles the direct calls alone (cProfile, enabled inside the
calls only). The compiled kernels are built first (``set_options(compiled=True)``).

Example (the design's worst scenes of ``summary.py``'s leakage rows)::

    OPENBLAS_NUM_THREADS=1 python benchmarks/leakage_direct_call.py \
        --scene "roll H=0.39 4dec" --loads 100 --solves 15 --parts
    python benchmarks/leakage_direct_call.py --scene "roll H=0.31 5dec" --loads 1000

A fit of ``time = fixed + per_load * loads`` over the calls of several load counts is printed
with ``--fit`` (one-load and ~70-load calls of the same scene, each inside a solve).
"""

from __future__ import annotations

import argparse
import cProfile
import functools
import importlib
import pstats
import sys
import time
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))

from summary_design import design, held_out, load_range, scene  # noqa: E402

import xpersson  # noqa: E402

#: Pieces timed with ``--parts``: (module, attribute, label); a dotted attribute is a method.
PARTS = (
    ("xpersson_interface.plugins", "subset", "subset (rows)"),
    ("xpersson_interface.plugins", "solved_curve", "dense re-solve (solved_curve)"),
    ("xpersson_interface.plugins", "contact_of", "SolvedContact"),
    ("xpersson.physics._solved_contact", "SolvedContact.rows", "SolvedContact.rows (medium's own)"),
    ("xpersson.physics", "critical_magnification", "critical magnification"),
    ("xpersson.physics._solved_contact", "SolvedContact.detachment", "detachment"),
    ("xpersson.physics._phi", "_Phi.__init__", "  Phi init"),
    ("xpersson.physics._curve", "_Curve.dF_weighted", "  Stieltjes sums (dF_weighted)"),
    ("xpersson.physics._phi", "_Phi._table", "  Phi table"),
    ("xpersson.physics._solved_contact", "SolvedContact.separation_at", "separation_at"),
    ("xpersson_interface._leak_direct", "bruggeman_gap", "effective medium (bruggeman_gap)"),
    ("xpersson_interface._leakage", "gap_cdf", "  gap_cdf"),
    ("xpersson_interface._leakage", "_bruggeman_rows", "  Bruggeman rows"),
    ("xpersson_interface._leak_direct", "junction_piece", "junction piece"),
)


def _spec(name: str) -> dict:
    specs = dict(design() + held_out())
    return specs[name]


def _wrap(owner, attr: str, label: str, store: dict) -> None:
    f = getattr(owner, attr)

    @functools.wraps(f)
    def timed(*a, **k):
        t = time.process_time()
        try:
            return f(*a, **k)
        finally:
            store.setdefault(label, []).append(time.process_time() - t)

    setattr(owner, attr, timed)


def _install_parts(store: dict) -> None:
    for mod, attr, label in PARTS:
        owner = importlib.import_module(mod)
        *path, name = attr.split(".")
        for p in path:
            owner = getattr(owner, p)
        _wrap(owner, name, label, store)


def _print_parts(parts: dict[str, list[float]], n: int) -> None:
    for k, v in parts.items():
        print(f"  {k:40s} {1e3 * sum(v) / n:8.3f} ms ({len(v) / n:g} calls)")


def _rows_mode(P, sc, args, calls, prof, parts) -> None:
    """Direct calls of ``args.rows`` loads inside one solve (its Dataset and context), the
    per-solve cache (``plugins.solved``) cleared before each: every call pays its own dense
    re-solve and splines, as a call of the load table does."""
    from xpersson.cache import cache

    solved = cache("plugins.solved")
    compute = P.Leakage.compute

    def timed(self, ctx, ds):
        rows = np.unique(np.linspace(0, len(ctx.p0) - 1, args.rows).round().astype(int))
        for k in range(args.solves + 3):
            solved.clear()
            if k == 3:
                parts.clear()
                if prof is not None:
                    prof.enable()
            t = time.process_time()
            self._direct(ctx, ds, rows)
            if k >= 3:
                calls.append((rows.size, time.process_time() - t))
        if prof is not None:
            prof.disable()
        taken.update({k: list(v) for k, v in parts.items()})
        return compute(self, ctx, ds)

    taken: dict[str, list[float]] = {}
    P.Leakage.compute = timed
    xpersson.solve(sc)
    P.Leakage.compute = compute
    t = np.array([c for _, c in calls])
    print(
        f"{args.scene}: direct calls of {calls[0][0]} loads, ms: median "
        f"{1e3 * np.median(t):.3f}, best {1e3 * t.min():.3f} ({t.size} calls)"
    )
    _print_parts(taken, args.solves)
    if prof is not None:
        pstats.Stats(prof).sort_stats(args.sort).print_stats(45)


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scene", default="roll H=0.39 4dec")
    ap.add_argument("--loads", type=int, default=100)
    ap.add_argument("--solves", type=int, default=15)
    ap.add_argument("--parts", action="store_true")
    ap.add_argument("--profile", action="store_true")
    ap.add_argument("--sort", default="tottime")
    ap.add_argument(
        "--rows",
        type=int,
        default=0,
        help="instead of the solve's own calls: direct calls of this many loads (evenly "
        "spread), --solves of them inside one solve, the per-solve cache cleared before each",
    )
    args = ap.parse_args(argv)
    warnings.simplefilter("ignore")
    from xpersson.engine import _compiled as march
    from xpersson.physics import _compiled as kernels
    from xpersson_interface import plugins as P

    xpersson.set_options(compiled=True)
    kernels.kernel(float("inf"))
    march.build()
    sc = scene(_spec(args.scene), load_range(args.loads), analyses={"leakage": {}})
    calls: list[tuple[int, float]] = []
    parts: dict[str, list[float]] = {}
    prof = cProfile.Profile() if args.profile else None
    direct = P.Leakage._direct

    def timed_direct(self, ctx, ds, rows, *which):
        t = time.process_time()
        if prof is not None:
            prof.enable()
        try:
            return direct(self, ctx, ds, rows, *which)
        finally:
            if prof is not None:
                prof.disable()
            calls.append((int(np.size(rows)), time.process_time() - t))

    if args.parts:
        _install_parts(parts)
    if args.rows:
        _rows_mode(P, sc, args, calls, prof, parts)
        return
    for _ in range(3):  # warm
        xpersson.solve(sc)
    parts.clear()
    P.Leakage._direct = timed_direct
    total = []
    for _ in range(args.solves):
        t = time.process_time()
        xpersson.solve(sc)
        total.append(time.process_time() - t)
    P.Leakage._direct = direct
    per = len(calls) // args.solves
    sizes = [n for n, _ in calls[:per]]
    times = np.array([c for _, c in calls]).reshape(args.solves, per)
    print(f"{args.scene}, {args.loads} loads: solve {1e3 * np.median(total):.2f} ms (median)")
    print(f"direct calls per solve {per}, loads {sizes}")
    print("per call, ms (median):", [round(1e3 * v, 3) for v in np.median(times, axis=0)])
    print(f"direct calls per solve, ms (median): {1e3 * np.median(times.sum(axis=1)):.2f}")
    _print_parts(parts, args.solves)
    if prof is not None:
        pstats.Stats(prof).sort_stats(args.sort).print_stats(45)


if __name__ == "__main__":
    main()
