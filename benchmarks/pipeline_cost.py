"""The whole pipeline at the cost of its kernels: ratios measured in one process.

Measures, with CPU time of this process (the machine may be shared) and one BLAS thread
(``OPENBLAS_NUM_THREADS=1`` is set before numpy is imported):

1. ``xpersson.solve`` of 1000 loads x 51 magnifications (elastic, closed form) against a bare
   numpy/scipy kernel written here, ``erf(p0 / (2 sqrt(tau)))`` on the same grid (target:
   within 10x);
2. a single-load ``xpersson.solve`` (target: <= 1 ms) and its parts;
3. ``plastic_scale_dependent`` with a yield wall that is never reached against the elastic
   solve of the same scene (target: within 2x).

Every quantity is the median CPU time of ``--calls`` calls in each of ``--rounds`` rounds (the
quantities of a ratio interleaved call by call); the table gives the smallest round median of
each (the machine may be shared: the least disturbed round) and the ratios of those.

Run: ``python benchmarks/pipeline_cost.py [--rounds N] [--profile]``; prints a Markdown table
and writes it to ``benchmarks/results/pipeline_cost.md``. ``--profile`` (needs
``pyinstrument``) prints instead a profile of 200 calls of each of the three user paths
(1000 loads, one load, the unreached yield wall). Where numba's kernels run, pyinstrument
charges a compiled call's time to the stack of the next Python event (2026-12-02: 0.47 ms
per solve to an ``os.environ.get`` of 5 us): time those steps with ``solve_stages.py``
(a CPU-time counter around each stage) or sample them with ``py-spy``.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse  # noqa: E402
import statistics  # noqa: E402
import time  # noqa: E402
import warnings  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402
from scipy.special import erf  # noqa: E402

import xpersson  # noqa: E402
from xpersson.physics import elastic  # noqa: E402

HERE = Path(__file__).resolve().parent
SPECTRUM = {
    "model": "self_affine",
    "H": 0.8,
    "q_L": "1e3 1/m",
    "q_r": "1e4 1/m",
    "q_1": "1e8 1/m",
    "h_rms": "1 um",
}
LOADS_1000 = {
    "spectrum": SPECTRUM,
    "material": {"E": "10 MPa", "nu": 0.5},
    "load": {"p0": {"start": "1 kPa", "stop": "1 MPa", "num": 1000}},
    "output": {"zeta_per_decade": 10},
}
SINGLE = {"spectrum": SPECTRUM, "material": {"E": "10 MPa", "nu": 0.5}, "load": {"p0": "0.1 MPa"}}
STEEL = {
    "spectrum": SPECTRUM,
    "material": {"E": "210 GPa", "nu": 0.3},
    "load": {"p0": ["1 kPa", "1 MPa"]},
    "output": {"zeta_per_decade": 10},
}
UNREACHED = dict(STEEL, boundary={"model": "plastic_scale_dependent", "Y1": "30 GPa", "n": 0.2})


def _engine_calls() -> tuple:
    """The walls and the engine call (what run() asks the boundary and hands the engine) for
    both scenes; a fresh clock each call, as in a solve (no inverse cached)."""
    from xpersson import engine
    from xpersson.plugins import DiffusionClock, SceneContext

    out = []
    for scene in (STEEL, UNREACHED):
        rs = xpersson.Scene(scene).resolve()
        ctx = SceneContext(
            psd=rs.psd,
            E=rs.E,
            nu=rs.nu,
            E_star=rs.E_star,
            p0=rs.p0,
            zeta=rs.zeta,
            rtol=rs.rtol,
            atol=rs.atol,
        )
        coef = rs.coefficient
        tau = np.asarray(coef.tau(ctx, rs.zeta))

        def call(rs=rs, ctx=ctx, coef=coef, tau=tau) -> None:
            clock = DiffusionClock(
                lambda z: coef.tau(ctx, z), lambda z: coef.f(ctx, z), ctx.zeta_max
            )
            walls = rs.boundary.walls(ctx, float(rs.p0[0]), clock)
            engine.solve_batch(tau, rs.p0, walls, rtol=rs.rtol, atol=rs.atol)

        out.append(call)
    return tuple(out)


def _measure(p0: np.ndarray, tau: np.ndarray, calls: int) -> dict[str, float]:
    """One round: every quantity ``calls`` times, median CPU seconds of each. The quantities
    compared with one another are interleaved call by call (so that a change of the machine's
    load hits both alike): the bare kernel with the 1000 loads, the elastic with the plastic
    solve; the single load runs in its own loop (a steady state, as a user's loop of single
    solves; after a 1000-load solve its first call runs with cold CPU caches)."""

    def bare() -> np.ndarray:
        with np.errstate(divide="ignore"):
            return erf(p0[:, None] / (2.0 * np.sqrt(tau[None, :])))

    engine_elastic, engine_unreached = _engine_calls()
    groups = [
        {"bare": bare, "many": lambda: xpersson.solve(LOADS_1000)},
        {
            "single": lambda: xpersson.solve(SINGLE),
            "resolve": lambda: xpersson.Scene(SINGLE).resolve(),
        },
        {
            "elastic": lambda: xpersson.solve(STEEL),
            "unreached": lambda: xpersson.solve(UNREACHED),
            "engine_elastic": engine_elastic,
            "engine_unreached": engine_unreached,
        },
    ]
    out: dict[str, float] = {}
    for fns in groups:
        times: dict[str, list[float]] = {k: [] for k in fns}
        for fn in fns.values():  # warm-up
            fn()
        for _ in range(calls):
            for name, fn in fns.items():
                t0 = time.process_time_ns()
                fn()
                times[name].append((time.process_time_ns() - t0) * 1e-9)
        out.update({k: statistics.median(v) for k, v in times.items()})
    return out


def _profile() -> None:
    """pyinstrument profiles of the three user paths (200 calls each after 5 warm-ups)."""
    from pyinstrument import Profiler

    for label, scene in (
        ("1000 loads x 51 zeta", LOADS_1000),
        ("one load", SINGLE),
        ("yield wall never reached (2 loads)", UNREACHED),
    ):
        for _ in range(5):
            xpersson.solve(scene)
        prof = Profiler(interval=1e-4)
        prof.start()
        for _ in range(200):
            xpersson.solve(scene)
        prof.stop()
        print(f"## {label}: 200 solves")
        print(prof.output_text(unicode=False, color=False))


def main(argv: list[str] | None = None) -> list[str]:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=5, help="measurement rounds (default 5)")
    ap.add_argument("--calls", type=int, default=60, help="calls of each per round (60)")
    ap.add_argument("--profile", action="store_true", help="print pyinstrument profiles")
    args = ap.parse_args(argv)
    warnings.simplefilter("ignore")  # P-resolution notes of the solves are not measured here
    if args.profile:
        _profile()
        return []
    rs = xpersson.Scene(LOADS_1000).resolve()
    tau = np.asarray(elastic.diffusion_time(rs.psd, rs.E_star, rs.zeta))
    p0 = rs.p0
    with np.errstate(divide="ignore"):
        ref = erf(p0[:, None] / (2.0 * np.sqrt(tau[None, :])))
    assert np.allclose(ref, xpersson.solve(LOADS_1000).area_fraction.values, rtol=1e-14)
    rounds = [_measure(p0, tau, args.calls) for _ in range(max(1, args.rounds))]
    t = {k: min(r[k] for r in rounds) for k in rounds[0]}
    ms = {k: v * 1e3 for k, v in t.items()}
    rows = [
        "| measurement | CPU time | ratio | target |",
        "|---|---:|---:|---|",
        f"| bare kernel erf(p0/(2 sqrt tau)), 1000 x {tau.size} | {ms['bare']:.3f} ms | 1 | |",
        f"| xpersson.solve, 1000 loads x {tau.size} zeta | {ms['many']:.3f} ms | "
        f"{t['many'] / t['bare']:.1f}x bare | <= 10x |",
        f"| xpersson.solve, one load | {ms['single']:.3f} ms | | <= 1 ms |",
        f"| of which Scene.resolve (parse, plugins, PSD) | {ms['resolve']:.3f} ms | | |",
        f"| elastic solve, 2 loads (steel) | {ms['elastic']:.3f} ms | 1 | |",
        f"| plastic_scale_dependent, wall never reached | {ms['unreached']:.3f} ms | "
        f"{t['unreached'] / t['elastic']:.2f}x elastic | <= 2x |",
        f"| walls + engine only: elastic, 2 loads | {ms['engine_elastic']:.3f} ms | 1 | |",
        f"| walls + engine only: yield wall never reached, 2 loads | "
        f"{ms['engine_unreached']:.3f} ms | "
        f"{t['engine_unreached'] / t['engine_elastic']:.2f}x elastic | |",
    ]
    r_many = [r["many"] / r["bare"] for r in rounds]
    r_plastic = [r["unreached"] / r["elastic"] for r in rounds]
    note = (
        f"\n{len(rounds)} rounds of {args.calls} calls in one process (the two sides of a "
        "ratio interleaved call by call); each entry is the smallest round median (the "
        "machine is shared: the least disturbed round), the ratios are those of these "
        f"entries. Ratios within each round: 1000 "
        f"loads {min(r_many):.1f}-{max(r_many):.1f}x bare, unreached wall "
        f"{min(r_plastic):.2f}-{max(r_plastic):.2f}x elastic.\n"
    )
    text = "\n".join(rows)
    print(text + "\n" + note)
    out = HERE / "results"
    out.mkdir(exist_ok=True)
    (out / "pipeline_cost.md").write_text(
        "# Pipeline cost (CPU time, one process, OPENBLAS_NUM_THREADS=1)\n\n" + text + "\n" + note
    )
    return rows


if __name__ == "__main__":
    main()
