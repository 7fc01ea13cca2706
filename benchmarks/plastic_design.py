"""``plastic_scale_dependent`` on a held-out seeded design: ms per load, node-steps, and the
achieved error against a tight reference.

The design (:func:`design`, master seed 7036, never used to tune the step rules; the speed
design of ``summary_design.py`` uses seed 36) draws ``--n`` scenes across the documented
domain: H stratified over 0.05-1, every other scene with a roll-off (knee 10^0.5-10^1 q_L),
3-6 decades of q_1/q_L, q_L 1e2-1e4 1/m, h_rms 1 um, steel (E 210 GPa, nu 0.3); the
hardness ``Y1 zeta^n`` with Y1 0.3-10 GPa and n 0.05-0.5; three loads p0/Y1 log-uniform in
1e-3-0.9; the outputs either the summary's 50 magnifications 1-1e3 or 10 per decade up to
q_1/q_L (alternating).  Default tolerances (rtol 1e-6, atol 1e-12).

Per scene:

* ``ms/load``: CPU time (``time.process_time``) of ``xpersson.solve``, best of ``--rounds``
  after a warm-up, the compiled march on, ``OPENBLAS_NUM_THREADS=1``, over the three loads;
* ``node-steps``: of every grid level the engine marched (``cn_walls.levels_of``);
* ``err/tol``: the achieved error of the elastic area (the engine's ``area``, what its
  control aims at ``rtol |A| + atol``), worst over loads and outputs,
  ``|A - A_ref| / (rtol |A_ref| + atol)``; ``err/est``: the same over the reported error
  estimate plus the reference's own (the comparison resolves no less; honest where <= 1);
  ``plastic``: the plastic area's error over the tolerance of the load identity through
  which it is controlled (``rtol max(p0, Y) / Y``, absolute);
* the reference: the same engine call at rtol 1e-8, atol 1e-14 with raised budgets (3e9 node-steps);
  ``ref est/tol`` is its own error estimate over the tested tolerance (it must be << 1 for
  the comparison to hold).

Usage: ``python benchmarks/plastic_design.py [--n 32] [--rounds 3] [--no-check] [--seed S]
[--out PATH]``; writes ``benchmarks/results/plastic_design.md`` (or ``--out``) unless
``--only`` picks scenes.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse  # noqa: E402
import sys  # noqa: E402
import warnings  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from cn_walls import levels_of  # noqa: E402
from summary_design import ZETA, best  # noqa: E402

import xpersson  # noqa: E402

SEED = 7036


def design(n: int = 32, seed: int = SEED) -> list[tuple[str, dict]]:
    """``n`` labelled ``plastic_scale_dependent`` scenes (seeded, H stratified)."""
    rng = np.random.default_rng(seed)
    hs = 0.05 + 0.95 * (np.arange(n) + rng.random(n)) / n
    rng.shuffle(hs)
    out = []
    for k, H in enumerate(hs):
        roll, decades, q_L = bool(k % 2), int(rng.integers(3, 7)), 10 ** rng.uniform(2, 4)
        knee = 10 ** rng.uniform(0.5, 1.0) if roll else 1.0
        y1, hard = 10 ** rng.uniform(8.5, 10.0), rng.uniform(0.05, 0.5)
        frac = np.sort(10 ** rng.uniform(-3.0, np.log10(0.9), 3))
        full = bool((k // 2) % 2)
        sc = {
            "spectrum": {
                "model": "self_affine",
                "H": round(float(H), 4),
                "q_L": f"{float(q_L)!r} 1/m",
                "q_r": f"{float(q_L * knee)!r} 1/m",
                "q_1": f"{float(q_L * 10**decades)!r} 1/m",
                "h_rms": "1 um",
            },
            "material": {"E": "210 GPa", "nu": 0.3},
            "load": {"p0": [f"{float(y1 * f)!r} Pa" for f in frac]},
            "boundary": {
                "model": "plastic_scale_dependent",
                "Y1": f"{float(y1)!r} Pa",
                "n": round(float(hard), 3),
            },
            "output": {"zeta_per_decade": 10} if full else {"zeta": ZETA},
        }
        label = (
            f"{'roll' if roll else 'flat'} H={H:.2f} {decades}dec Y1={y1 / 1e9:.2g}GPa "
            f"n={hard:.2f} p0/Y1={frac[0]:.0e}-{frac[-1]:.2g} {'full' if full else '1e3'}"
        )
        out.append((label, sc))
    return out


def engine_call(sc: dict) -> tuple[tuple, dict, object]:
    """The engine batch call of the scene's solve: (args, keywords, result)."""
    from xpersson import engine

    seen: list = []
    orig = engine.solve_batch

    def spy(*args, **kw):
        res = orig(*args, **kw)
        seen.append((args, kw, res))
        return res

    engine.solve_batch = spy
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            xpersson.solve(sc)
    finally:
        engine.solve_batch = orig
    return seen[0]


def accuracy(sc: dict, rtol: float = 1e-8, atol: float = 1e-14) -> dict:
    """The achieved error of the scene's engine call against the same call at ``rtol``,
    ``atol`` with raised budgets (see the module): ``err_tol``, ``err_est``, ``plastic``,
    ``ref_est`` (the reference's estimate over the tested tolerance) and ``ref_status``."""
    from xpersson import engine

    args, kw, res = engine_call(sc)
    tight = dict(kw, rtol=rtol, atol=atol, max_steps=20_000_000)
    tight["options"] = {**(kw.get("options") or {}), "max_work": 3e9, "levels": 80}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ref = engine.solve_batch(*args, **tight)
    area, a_ref = np.asarray(res.area), np.asarray(ref.area)
    est = np.asarray(res.error_estimate)
    marched = est > 0
    # the comparison resolves no less than the reference's own estimate (its round-off at
    # outputs where A = 1 otherwise reads as err/est > 1)
    est = est + np.asarray(ref.error_estimate)
    tol = kw["rtol"] * np.abs(a_ref) + kw["atol"]
    err = np.abs(area - a_ref)
    y = np.asarray(res.wall_upper)
    p0 = np.asarray(args[1], dtype=float).reshape(-1, 1)
    scale = np.maximum(np.abs(p0), np.abs(y)) / np.abs(y)
    err_pl = np.abs(np.asarray(res.absorbed_upper) - np.asarray(ref.absorbed_upper))
    return {
        "err_tol": float(np.max(err / tol)),
        "err_est": float(np.max(np.where(marched, err / np.where(marched, est, 1.0), 0.0))),
        "plastic": float(np.max(err_pl / (kw["rtol"] * scale))),
        "ref_est": float(np.max(np.asarray(ref.error_estimate) / tol)),
        "ref_status": sorted({str(s) for s in np.atleast_1d(ref.status)}),
        "status": sorted({str(s) for s in np.atleast_1d(res.status)}),
    }


def cost(sc: dict, rounds: int) -> dict:
    """Levels, node-steps and CPU ms per load of ``sc``."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        levels = levels_of(sc)
    t = best({"s": lambda: xpersson.solve(sc)}, rounds)["s"]
    return {
        "levels": len(levels),
        "node_steps": sum(a * b * c for a, b, c in levels),
        "ms_per_load": t / len(sc["load"]["p0"]) * 1e3,
    }


HEAD = (
    "| scene | levels | node-steps | ms/load | status | err/tol | err/est | plastic | "
    "ref est/tol |\n|---|---:|---:|---:|---|---:|---:|---:|---:|"
)


def row(label: str, c: dict, a: dict | None) -> str:
    """One line of the table."""
    if a is None:
        acc = "- | - | - | - | -"
    else:
        acc = (
            f"{', '.join(a['status'])} | {a['err_tol']:.3g} | {a['err_est']:.3g} | "
            f"{a['plastic']:.3g} | {a['ref_est']:.2g} ({', '.join(a['ref_status'])})"
        )
    return f"| {label} | {c['levels']} | {c['node_steps']:.3g} | {c['ms_per_load']:.1f} | {acc} |"


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=32)
    ap.add_argument("--seed", type=int, default=SEED)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--no-check", action="store_true", help="no reference (speed only)")
    ap.add_argument("--only", default="", help="scenes whose label contains this")
    ap.add_argument("--out", default=str(HERE / "results" / "plastic_design.md"))
    args = ap.parse_args(argv)
    xpersson.set_options(compiled=True)
    from xpersson.engine import _compiled

    _compiled.build()  # in force from the first scene (else after ~0.4 s of numpy marching)
    lines = [HEAD]
    print(HEAD, flush=True)
    worst = {"ms": (0.0, ""), "err_tol": (0.0, ""), "err_est": (0.0, "")}
    marching = 0
    for label, sc in design(args.n, args.seed):
        if args.only not in label:
            continue
        c = cost(sc, args.rounds)
        a = None if args.no_check or not c["levels"] else accuracy(sc)
        marching += bool(c["levels"])
        worst["ms"] = max(worst["ms"], (c["ms_per_load"], label))
        if a is not None:
            worst["err_tol"] = max(worst["err_tol"], (a["err_tol"], label))
            worst["err_est"] = max(worst["err_est"], (a["err_est"], label))
        line = row(label, c, a)
        print(line, flush=True)
        lines.append(line)
    summary = (
        f"\n\n{marching} of {len(lines) - 1} scenes march. Worst ms/load {worst['ms'][0]:.1f} "
        f"({worst['ms'][1]}); worst err/tol {worst['err_tol'][0]:.3g} ({worst['err_tol'][1]}); "
        f"worst err/est {worst['err_est'][0]:.3g} ({worst['err_est'][1]})."
    )
    text = "\n".join(lines) + summary
    print(summary)
    if args.only:
        return
    out = Path(args.out)
    out.parent.mkdir(exist_ok=True)
    out.write_text(
        "# `plastic_scale_dependent` on a held-out design: ms per load, node-steps, error\n\n"
        f"`python benchmarks/plastic_design.py --n {args.n} --rounds {args.rounds}` "
        f"(seed {args.seed}). CPU time, best of {args.rounds} rounds, compiled march, "
        "OPENBLAS_NUM_THREADS=1; shared 2-core machine. rtol 1e-6, atol 1e-12; reference: "
        "the engine at rtol 1e-8, atol 1e-14.\n\n" + text + "\n"
    )


if __name__ == "__main__":
    main()
