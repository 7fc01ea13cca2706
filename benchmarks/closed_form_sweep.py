"""How long does a 500-load x 200-zeta A/A0 map take with the closed form?

Run:  python benchmarks/closed_form_sweep.py
Prints the median time of (a) the whole `xpersson.solve` pipeline (scene resolution, closed
form through the engine's exact path, Dataset assembly) and (b) the bare closed-form kernel
`erf(p0 / (2 sqrt(tau)))` on the same grid, for the physics.md §1.4 surface.
"""

from __future__ import annotations

import statistics
import time

import xpersson
from xpersson.physics import elastic

SCENE = {
    "spectrum": {
        "model": "self_affine",
        "H": 0.8,
        "q_L": "1e3 1/m",
        "q_r": "1e4 1/m",
        "q_1": "1e8 1/m",
        "h_rms": "1 um",
    },
    "material": {"E": "10 MPa", "nu": 0.5},
    "load": {"p0": {"start": "1 Pa", "stop": "10 MPa", "num": 500}},
    "output": {"zeta_per_decade": 40},
}


def _median(fn, repeats: int = 5) -> tuple[object, float]:
    times, out = [], None
    for _ in range(repeats):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return out, statistics.median(times)


def main() -> None:
    xpersson.solve(SCENE)  # warm-up: imports, entry points
    for closure in ("persson01", "yp08"):
        scene = dict(SCENE, coefficient={"closure": closure})
        ds, t = _median(lambda s=scene: xpersson.solve(s))
        print(
            f"xpersson.solve, closure={closure}: {ds.area_fraction.shape} A/A0 values "
            f"in {t * 1e3:.1f} ms (median of 5)"
        )
    rs = xpersson.Scene(SCENE).resolve()
    tau = elastic.diffusion_time(rs.psd, rs.E_star, rs.zeta)
    _, t = _median(lambda: elastic.area_fraction(rs.p0[:, None], tau[None, :]))
    print(
        f"closed-form kernel erf(p0/(2 sqrt(tau))): {rs.p0.size} x {rs.zeta.size} "
        f"in {t * 1e3:.2f} ms"
    )


if __name__ == "__main__":
    main()
