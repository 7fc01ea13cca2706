"""mu(v) for 50 velocities x 3 temperatures with a 40-mode Prony model: the vectorised kernel
of xpersson-viscoelastic against a direct scipy ``quad`` implementation of the same integrals.

Run with one BLAS thread (``OPENBLAS_NUM_THREADS=1 python benchmarks/viscoelastic_friction.py``);
everything is measured in this one process. The integrals (physics.md §4.2, S = 1):

    G(q)    = (pi/4) / ((1 - nu^2) p0)^2 int_{q_L}^{q} q'^3 C(q') <|E(q' v a_T cos phi)|^2> dq'
    mu_visc = 1 / (2 (1 - nu^2) p0) int_{q_L}^{q_1} q^3 C(q) P(q) int_0^2pi cos phi Im E dphi dq
    P(q)    = erf(1 / (2 sqrt(G(q))))

* kernel: ``xpersson_viscoelastic.friction_curve`` (closed-form angular integrals of the Prony
  series, Gauss-Legendre in ln q with a spectral running integral for G), all 150 points at once;
* quad: ``scipy.integrate.quad`` for the angular integrals (in phi on [0, pi/2]), for G (running,
  incremental between the outer nodes) and for the outer mu integral (in ln q, breakpoint q_r);
  timed on a subset of the points (it takes seconds per point) and scaled to 150 points;
* reference: the kernel with 4x the panels and 2x the nodes (converged to ~1e-14).

Also reports the cost through ``xpersson.solve`` with ``velocity`` and ``temperature`` given as
lists (the core's serial sweep; blocks of (v, T) points stacked in one run, issue 25) against the
kernel with the example's two loads and the point-by-point path (CPU time, interleaved rounds).
"""

from __future__ import annotations

import argparse
import os
import time
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402
from scipy.integrate import quad  # noqa: E402
from scipy.special import erf  # noqa: E402

from xpersson.physics import SelfAffineRollOff  # noqa: E402
from xpersson_viscoelastic import WLF, friction_curve, synthetic_tread  # noqa: E402

HERE = Path(__file__).resolve().parent
NU, P0 = 0.5, 3e5
V = np.geomspace(1e-8, 1e2, 50)
T = np.array([273.15, 293.15, 313.15])
SHIFT = WLF(7.84, 114.75, 293.15)  # universal WLF re-referenced from T_g = 230 K


def _psd() -> SelfAffineRollOff:
    return SelfAffineRollOff.from_h_rms(6e-5, 0.8, 600.0, 3000.0, 1e7)


def quad_mu(psd, model, v: float, aT: float, epsrel: float) -> float:
    """mu_visc at one (v, T) point with scipy.integrate.quad only."""
    f2 = (1.0 - NU**2) ** 2
    tau_k, dE = model.tau, model.delta_E

    def E(omega: float) -> complex:
        x = 1j * omega * tau_k
        return model.E_r + complex(np.sum(dE * x / (1.0 + x)))

    def mean_sq(q: float) -> float:
        w = q * v * aT
        val = quad(
            lambda p: abs(E(w * np.cos(p))) ** 2, 0.0, np.pi / 2, epsabs=0, epsrel=epsrel, limit=200
        )[0]
        return val * 2.0 / np.pi

    def loss(q: float) -> float:
        w = q * v * aT
        val = quad(
            lambda p: np.cos(p) * E(w * np.cos(p)).imag,
            0.0,
            np.pi / 2,
            epsabs=0,
            epsrel=epsrel,
            limit=200,
        )[0]
        return 4.0 * val

    def g_dens(s: float) -> float:  # d tau / d ln q
        q = np.exp(s)
        return q**4 * float(psd.C(q)) * mean_sq(q)

    memo = {np.log(psd.q_L): 0.0}

    def tau(s: float) -> float:  # incremental running integral from the nearest known node
        known = np.array(sorted(memo))
        s0 = known[np.searchsorted(known, s, side="right") - 1]
        pts = [np.log(3000.0)] if s0 < np.log(3000.0) < s else None
        val = memo[s0] + quad(g_dens, s0, s, epsabs=0, epsrel=epsrel, points=pts, limit=200)[0]
        memo[s] = val
        return val

    def mu_dens(s: float) -> float:
        q = np.exp(s)
        G = (np.pi / 4.0) * tau(s) / (f2 * P0**2)
        P = 1.0 if G == 0 else erf(0.5 / np.sqrt(G))
        return q**4 * float(psd.C(q)) * loss(q) * P

    total = quad(
        mu_dens,
        np.log(psd.q_L),
        np.log(psd.q_1),
        epsabs=0,
        epsrel=epsrel,
        points=[np.log(3000.0)],
        limit=200,
    )[0]
    return total / (2.0 * (1.0 - NU**2) * P0)


def _best(fn, repeat: int) -> float:
    best = np.inf
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t)
    return best


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quad-points", type=int, default=6, help="points timed with quad")
    ap.add_argument("--epsrel", type=float, default=1e-8, help="quad relative tolerance")
    ap.add_argument("--rounds", type=int, default=3, help="interleaved timing rounds")
    args = ap.parse_args()
    psd, model = _psd(), synthetic_tread()
    aT = SHIFT.aT(T)

    def run():
        return friction_curve(psd, model, NU, [P0], V, aT)

    run()  # warm-up (imports, caches)
    t_kernel = _best(run, 5)
    mu = run()["mu_visc"][..., 0]  # (n_T, n_v)
    ref = friction_curve(psd, model, NU, [P0], V, aT, nodes=16, panels_per_decade=16)
    mu_ref = ref["mu_visc"][..., 0]
    err_kernel = float(np.max(np.abs(mu / mu_ref - 1.0)))

    idx = np.linspace(0, V.size - 1, args.quad_points).round().astype(int)
    t0 = time.perf_counter()
    mu_q = np.array([quad_mu(psd, model, float(V[i]), float(aT[1]), args.epsrel) for i in idx])
    t_quad_pt = (time.perf_counter() - t0) / idx.size
    err_quad = float(np.max(np.abs(mu_q / mu_ref[1, idx] - 1.0)))
    t_quad = t_quad_pt * V.size * T.size

    sizes, t_solve, t_cpu_kernel, t_pp, t_grid = solve_vs_kernel(args.rounds)

    print(f"OPENBLAS_NUM_THREADS={os.environ['OPENBLAS_NUM_THREADS']}")
    print(f"mu_visc range: {mu.min():.4g} .. {mu.max():.4g}")
    print(f"kernel, 50 v x 3 T x 40 modes: {t_kernel * 1e3:.1f} ms, max rel error {err_kernel:.1e}")
    print(
        f"quad (epsrel={args.epsrel:g}), {idx.size} points: {t_quad_pt:.2f} s/point, "
        f"150 points ~ {t_quad:.0f} s, max rel error {err_quad:.1e}"
    )
    print(f"speed-up of the kernel over quad (150 points): {t_quad / t_kernel:.0f}x")
    print(
        f"xpersson.solve of the example scene with 50 v x 3 T as lists (dims {sizes}, "
        f"friction, blocks of (v, T) points stacked: one kernel call per block), CPU time, "
        f"best of {args.rounds} interleaved rounds: {t_solve * 1e3:.0f} ms = "
        f"{t_solve / t_cpu_kernel:.1f}x the kernel ({t_cpu_kernel * 1e3:.1f} ms CPU, same "
        f"rounds; target <= 10x), {t_solve / t_grid:.1f}x the kernel given the output "
        f"magnifications ({t_grid * 1e3:.1f} ms: mu_visc_cumulative, what the Dataset holds); "
        f"point by point: {t_pp * 1e3:.0f} ms ({t_pp / t_solve:.1f}x the stacked path)"
    )


def solve_vs_kernel(rounds: int) -> tuple[dict, float, float, float, float]:
    """CPU time [s] of mu(v) for 50 v x 3 T through ``xpersson.solve`` (stacked), of the
    kernel, of the point-by-point path and of the kernel given the scene's output
    magnifications, each the best of ``rounds`` interleaved rounds."""
    import warnings

    import xpersson
    from xpersson.sweep import plain_paths

    scene = str(HERE.parent / "plugins/xpersson-viscoelastic/examples/tread_on_asphalt.toml")
    kw = {
        "coefficient__velocity": [f"{float(x)!r} m/s" for x in V],
        "coefficient__temperature": [f"{float(x)!r} K" for x in T],
    }
    psd, model, aT = _psd(), synthetic_tread(), SHIFT.aT(T)
    p0 = [1e5, 3e5]  # the example's two loads

    def point_by_point():
        with plain_paths():
            xpersson.solve(scene, **kw)

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        first = xpersson.solve(scene, **kw)  # warm-up
    sizes, zeta = dict(first.sizes), np.asarray(first["zeta"].values)
    fns = {
        "solve": lambda: xpersson.solve(scene, **kw),
        "kernel": lambda: friction_curve(psd, model, NU, p0, V, aT),
        "grid": lambda: friction_curve(psd, model, NU, p0, V, aT, zeta=zeta),
        "pp": point_by_point,
    }
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        best = {k: np.inf for k in fns}
        for r in range(rounds):
            for k, fn in fns.items():
                if k == "pp" and r:  # seconds: one round is enough for the ratio it shows
                    continue
                t = time.process_time()
                fn()
                best[k] = min(best[k], time.process_time() - t)
    return sizes, best["solve"], best["kernel"], best["pp"], best["grid"]


if __name__ == "__main__":
    main()
