"""The whole pipeline at the cost of its kernels: ratios measured in one process.

Measures, with CPU time of this process (the machine may be shared) and one BLAS thread
(``OPENBLAS_NUM_THREADS=1`` is set before numpy is imported):

1. ``xpersson.solve`` of 1000 loads x 51 magnifications (elastic, closed form) against a bare
   numpy/scipy kernel written here, ``erf(p0 / (2 sqrt(tau)))`` on the same grid (target:
   within 10x);
2. a single-load ``xpersson.solve`` (target: <= 1 ms) and its parts;
3. ``plastic_scale_dependent`` with a yield wall that is never reached against the elastic
   solve of the same scene (target: within 2x).

Run: ``python benchmarks/pipeline_cost.py``; prints a Markdown table and writes it to
``benchmarks/results/pipeline_cost.md``.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import statistics  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402
from scipy.special import erf  # noqa: E402

import xpersson  # noqa: E402
from xpersson.physics import elastic  # noqa: E402

HERE = Path(__file__).resolve().parent
SPECTRUM = {"model": "self_affine", "H": 0.8, "q_L": "1e3 1/m", "q_r": "1e4 1/m",
            "q_1": "1e8 1/m", "h_rms": "1 um"}
LOADS_1000 = {"spectrum": SPECTRUM, "material": {"E": "10 MPa", "nu": 0.5},
              "load": {"p0": {"start": "1 kPa", "stop": "1 MPa", "num": 1000}},
              "output": {"zeta_per_decade": 10}}
SINGLE = {"spectrum": SPECTRUM, "material": {"E": "10 MPa", "nu": 0.5},
          "load": {"p0": "0.1 MPa"}}
STEEL = {"spectrum": SPECTRUM, "material": {"E": "210 GPa", "nu": 0.3},
         "load": {"p0": ["1 kPa", "1 MPa"]}, "output": {"zeta_per_decade": 10}}
UNREACHED = dict(STEEL, boundary={"model": "plastic_scale_dependent", "Y1": "30 GPa", "n": 0.2})


def cpu(fn, repeats: int = 30) -> float:
    """Median CPU seconds of ``fn()`` (one warm-up call)."""
    fn()
    times = []
    for _ in range(repeats):
        t0 = time.process_time_ns()
        fn()
        times.append((time.process_time_ns() - t0) * 1e-9)
    return statistics.median(times)


def _engine_parts() -> tuple[float, float]:
    """CPU time of the engine call alone (what run() hands the engine) for both scenes."""
    from xpersson import engine
    from xpersson.plugins import DiffusionClock, SceneContext

    out = []
    for scene in (STEEL, UNREACHED):
        rs = xpersson.Scene(scene).resolve()
        ctx = SceneContext(psd=rs.psd, E=rs.E, nu=rs.nu, E_star=rs.E_star, p0=rs.p0,
                           zeta=rs.zeta, rtol=rs.rtol, atol=rs.atol)
        coef = rs.coefficient
        tau = np.asarray(coef.tau(ctx, rs.zeta))
        clock = DiffusionClock(lambda z, c=coef, x=ctx: c.tau(x, z),
                               lambda z, c=coef, x=ctx: c.f(x, z), ctx.zeta_max)
        walls = rs.boundary.walls(ctx, float(rs.p0[0]), clock)
        out.append(cpu(lambda w=walls, t=tau, p=rs.p0, r=rs.rtol, a=rs.atol: engine.solve_batch(
            t, p, w, rtol=r, atol=a), 30))
    return out[0], out[1]


def main() -> list[str]:
    rs = xpersson.Scene(LOADS_1000).resolve()
    tau = np.asarray(elastic.diffusion_time(rs.psd, rs.E_star, rs.zeta))
    p0 = rs.p0

    def bare() -> np.ndarray:
        return erf(p0[:, None] / (2.0 * np.sqrt(tau[None, :])))

    assert np.allclose(bare(), xpersson.solve(LOADS_1000).area_fraction.values, rtol=1e-14)
    t_bare = cpu(bare, 100)
    t_many = cpu(lambda: xpersson.solve(LOADS_1000), 20)
    t_single = cpu(lambda: xpersson.solve(SINGLE), 100)
    t_resolve = cpu(lambda: xpersson.Scene(SINGLE).resolve(), 100)
    t_elastic = cpu(lambda: xpersson.solve(STEEL), 30)
    t_unreached = cpu(lambda: xpersson.solve(UNREACHED), 30)
    e_el, e_un = _engine_parts()
    rows = [
        "| measurement | CPU time | ratio | target |",
        "|---|---:|---:|---|",
        f"| bare kernel erf(p0/(2 sqrt tau)), 1000 x {tau.size} | {t_bare * 1e3:.3f} ms | 1 | |",
        f"| xpersson.solve, 1000 loads x {tau.size} zeta | {t_many * 1e3:.3f} ms | "
        f"{t_many / t_bare:.1f}x bare | <= 10x |",
        f"| xpersson.solve, one load | {t_single * 1e3:.3f} ms | | <= 1 ms |",
        f"| of which Scene.resolve (parse, plugins, PSD) | {t_resolve * 1e3:.3f} ms | | |",
        f"| elastic solve, 2 loads (steel) | {t_elastic * 1e3:.3f} ms | 1 | |",
        f"| plastic_scale_dependent, wall never reached | {t_unreached * 1e3:.3f} ms | "
        f"{t_unreached / t_elastic:.2f}x elastic | <= 2x |",
        f"| engine only: elastic walls, 2 loads | {e_el * 1e3:.3f} ms | 1 | |",
        f"| engine only: yield wall never reached, 2 loads | {e_un * 1e3:.3f} ms | "
        f"{e_un / e_el:.2f}x elastic | <= 2x |",
    ]
    text = "\n".join(rows)
    print(text)
    out = HERE / "results"
    out.mkdir(exist_ok=True)
    (out / "pipeline_cost.md").write_text(
        "# Pipeline cost (CPU time, one process, OPENBLAS_NUM_THREADS=1)\n\n" + text + "\n")
    return rows


if __name__ == "__main__":
    main()
