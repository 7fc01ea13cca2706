"""Verification of the viscoelastic friction against an independent reference (issue 22).

Outputs checked: ``mu_visc`` and the contact area ``A/A0`` at ``q_1`` of the stand-alone
kernel ``xpersson_viscoelastic.friction_curve`` and of ``xpersson.solve`` (the ``viscoelastic``
coefficient with the ``friction`` analysis, elastic wall, Persson 2001, 20 zeta per decade).

Reference: ``visco_reference.mu_reference`` (in ``plugins/xpersson-viscoelastic/tests``): the
same model written from physics.md §4.2/§4.4/§8.2 with no xpersson code, both q-integrals by
``scipy.integrate.quad`` on explicit breakpoints (a geometric ladder in ``q - q_L``, ``q_r``,
the loss peak and the point where ``G = 1``); the SLS angular closed forms are checked against
quad over ``phi``, and a few points against an adaptive ODE solution (DOP853, rtol 1e-12) of the
same integrals in ``ln(q - q_L)``.

Regime grid: SLS rubber (E_r = 2 MPa, E_g = 2 GPa, tau = 1e-4 s, nu = 0.5), self-affine
spectra with rms slope 0.5, q_L = 2e3 1/m, q_1 = 2e6 1/m, without plateau (q_r = q_L) and with
one (q_r = 10 q_L), H in {0.3, 0.7, 1.0}; v from 1e-9 to 1e3 m/s (13 speeds, one per decade);
T across the WLF law (C1 = 7.84, C2 = 114.75 K, T_ref = 293.15 K: universal constants
re-referenced from T_g = 230 K) in {233.15, 263.15, 293.15, 323.15, 353.15} K, i.e.
a_T from 4e8 to 2e-3; p0 in {0.05, 0.5} MPa. 2 x 3 x 13 x 5 x 2 = 780 points per output.

Run ``python benchmarks/verify_friction.py`` (``--fast`` for a 1-decade-in-3 subset); prints
the worst relative error per output and regime and exits non-zero beyond ``--tol`` (1e-3).
"""

from __future__ import annotations

import argparse
import itertools
import math
import os
import sys
import time
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "plugins" / "xpersson-viscoelastic" / "tests"))

from visco_reference import (  # noqa: E402
    SLS,
    RefSpectrum,
    mu_reference,
    sls_angular_quad,
    wlf_shift,
)

E_R, E_G, TAU, NU = 2e6, 2e9, 1e-4, 0.5
Q_L, Q_1, SLOPE = 2e3, 2e6, 0.5
WLF = (7.84, 114.75, 293.15)
V = np.logspace(-9, 3, 13)
T = np.array([233.15, 263.15, 293.15, 323.15, 353.15])
P0 = np.array([5e4, 5e5])
HURST = (0.3, 0.7, 1.0)
PLATEAU = {"no plateau": 1.0, "plateau q_r = 10 q_L": 10.0}
ZPD = 20
#: (H, q_r, p0, v a_T) where the quad reference is checked against the ODE solution
ODE_POINTS = [
    (0.7, Q_L, 2e5, 1.0),
    (0.7, Q_L, 2e5, 10.0),
    (0.3, 10 * Q_L, 5e4, 1e-3),
    (1.0, Q_L, 5e5, 1e4),
]


def _scene(H: float, q_r: float, v: np.ndarray, T: np.ndarray) -> dict:
    return {
        "spectrum": {
            "model": "self_affine",
            "H": H,
            "q_L": f"{Q_L!r} 1/m",
            "q_r": f"{q_r!r} 1/m",
            "q_1": f"{Q_1!r} 1/m",
            "rms_slope": SLOPE,
        },
        "material": {"E": f"{E_R!r} Pa", "nu": NU},
        "load": {"p0": [f"{float(p)!r} Pa" for p in P0]},
        "coefficient": {
            "model": "viscoelastic",
            "modulus": "sls",
            "E_r": f"{E_R!r} Pa",
            "E_g": f"{E_G!r} Pa",
            "relaxation_time": f"{TAU!r} s",
            "shift": "wlf",
            "C1": WLF[0],
            "C2": f"{WLF[1]!r} K",
            "T_ref": f"{WLF[2]!r} K",
            "velocity": [f"{float(x)!r} m/s" for x in v],
            "temperature": [f"{float(x)!r} K" for x in T],
        },
        "analyses": {"friction": {}},
        "output": {"zeta_per_decade": ZPD},
    }


def references(H: float, q_r: float, v: np.ndarray, T: np.ndarray) -> dict[str, np.ndarray]:
    """Reference mu_visc and A/A0 (n_T, n_v, n_p0)."""
    psd, model = RefSpectrum(H, Q_L, q_r, Q_1, SLOPE), SLS(E_R, E_G, TAU)
    mu = np.empty((T.size, v.size, P0.size))
    area = np.empty_like(mu)
    for (i, t), (j, x), (k, p) in itertools.product(enumerate(T), enumerate(v), enumerate(P0)):
        r = mu_reference(psd, model, NU, float(p), float(x), wlf_shift(float(t), *WLF))
        mu[i, j, k], area[i, j, k] = r["mu_visc"], r["area_fraction"]
    return {"mu_visc": mu, "area_fraction": area}


def kernel(H: float, q_r: float, v: np.ndarray, T: np.ndarray) -> dict[str, np.ndarray]:
    """``friction_curve`` on the grid (n_T, n_v, n_p0)."""
    from xpersson.physics import SelfAffineRollOff
    from xpersson_viscoelastic import WLF as WLFLaw
    from xpersson_viscoelastic import friction_curve, sls

    psd = SelfAffineRollOff.from_rms_slope(SLOPE, H, Q_L, q_r, Q_1)
    aT = WLFLaw(*WLF).aT(T)
    return friction_curve(psd, sls(E_R, E_G, TAU), NU, P0, v, aT)


def pipeline(H: float, q_r: float, v: np.ndarray, T: np.ndarray) -> dict[str, np.ndarray]:
    """``xpersson.solve`` with v and T swept, (n_T, n_v, n_p0)."""
    import xpersson

    ds = xpersson.solve(_scene(H, q_r, v, T))
    mu = ds["mu_visc"].transpose("T", "v", "p0").values
    area = ds["area_fraction"].isel(zeta=-1).transpose("T", "v", "p0").values
    return {"mu_visc": mu, "area_fraction": area}


def check_angular() -> float:
    """Worst relative difference of the SLS angular closed forms vs quad over phi."""
    model, worst = SLS(E_R, E_G, TAU), 0.0
    for w in np.logspace(-3, 12, 31):
        a, b = model.angular(float(w)), sls_angular_quad(model, float(w))
        worst = max(worst, abs(a[0] / b[0] - 1), abs(a[1] / b[1] - 1))
    return worst


def check_ode(points: list[tuple[float, float, float, float]]) -> float:
    """Worst relative difference between the quad reference and an adaptive ODE solution."""
    from scipy.integrate import solve_ivp
    from scipy.special import erf

    worst = 0.0
    model, fnu = SLS(E_R, E_G, TAU), 1.0 - NU * NU
    for H, q_r, p0, s in points:
        psd = RefSpectrum(H, Q_L, q_r, Q_1, SLOPE)
        cG = (math.pi / 4.0) / (fnu * p0) ** 2

        def rhs(u, y, psd=psd, cG=cG, p0=p0, s=s):
            d = math.exp(u)
            q = Q_L + d
            M, Lam = model.angular(q * s)
            P = 1.0 if y[0] <= 0 else float(erf(0.5 / math.sqrt(y[0])))
            c = q**3 * psd.C(q) * d
            return [cG * c * M, c * P * Lam / (2.0 * fnu * p0)]

        u0, u1 = math.log(1e-16 * Q_L), math.log(Q_1 - Q_L)
        sol = solve_ivp(rhs, (u0, u1), [0.0, 0.0], method="DOP853", rtol=1e-12, atol=1e-30)
        ref = mu_reference(psd, model, NU, p0, s)["mu_visc"]
        worst = max(worst, abs(sol.y[1, -1] / ref - 1.0))
    return worst


def cost(repeat: int = 3) -> None:
    """Best-of-``repeat`` wall time of 50 speeds (1e-9..1e3 m/s) on the issue's scene (H = 0.7,
    no plateau, p0 = 0.2 MPa, T_ref): the kernel, and xpersson.solve with friction."""
    import xpersson
    from xpersson.physics import SelfAffineRollOff
    from xpersson_viscoelastic import friction_curve, sls

    v50 = np.logspace(-9, 3, 50)
    psd = SelfAffineRollOff.from_rms_slope(SLOPE, 0.7, Q_L, Q_L, Q_1)
    model = sls(E_R, E_G, TAU)
    scene = _scene(0.7, Q_L, v50, np.array([WLF[2]]))
    scene["load"] = {"p0": "2e5 Pa"}

    def best(fn) -> float:
        fn()
        times = []
        for _ in range(repeat):
            t0 = time.perf_counter()
            fn()
            times.append(time.perf_counter() - t0)
        return min(times)

    t_k = best(lambda: friction_curve(psd, model, NU, [2e5], v50))
    t_s = best(lambda: xpersson.solve(scene))
    print(f"kernel, 50 speeds: {t_k * 1e3:.1f} ms; xpersson.solve, 50 speeds: {t_s:.2f} s")


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--fast", action="store_true", help="v every third decade, T in 3 values")
    ap.add_argument("--tol", type=float, default=1e-3, help="allowed relative error")
    ap.add_argument("--cost", action="store_true", help="only time 50 speeds (kernel, solve)")
    args = ap.parse_args(argv)
    if args.cost:
        cost()
        return 0
    v, temps = (V[::3], T[::2]) if args.fast else (V, T)
    print(f"SLS angular closed forms vs quad over phi: {check_angular():.1e}")
    print(f"quad reference vs adaptive ODE (4 points): {check_ode(ODE_POINTS):.1e}")
    rows, worst_all = [], 0.0
    t_ref = t_ker = t_pipe = 0.0
    for (label, r), H in itertools.product(PLATEAU.items(), HURST):
        t0 = time.perf_counter()
        ref = references(H, r * Q_L, v, temps)
        t1 = time.perf_counter()
        ker = kernel(H, r * Q_L, v, temps)
        t2 = time.perf_counter()
        pipe = pipeline(H, r * Q_L, v, temps)
        t3 = time.perf_counter()
        t_ref, t_ker, t_pipe = t_ref + t1 - t0, t_ker + t2 - t1, t_pipe + t3 - t2
        for path, got in (("friction_curve", ker), ("xpersson.solve", pipe)):
            for out in ("mu_visc", "area_fraction"):
                err = np.abs(got[out] / ref[out] - 1.0)
                i, j, k = np.unravel_index(int(np.argmax(err)), err.shape)
                worst_all = max(worst_all, float(err.max()))
                where = f"v={v[j]:.0e} T={temps[i]:.2f} p0={P0[k]:.0e}"
                rows.append((path, out, f"{label}, H={H}", float(err.max()), where))
    t_list = ", ".join(f"{t:.2f}" for t in temps)
    print(
        f"\nregime grid: v = {v[0]:.0e}..{v[-1]:.0e} m/s ({v.size} speeds), T = {t_list} K (WLF),"
    )
    print(f"p0 = {', '.join(f'{p:.0e}' for p in P0)} Pa; {ZPD} zeta per decade in xpersson.solve\n")
    print(f"{'path':<15} {'output':<14} {'regime':<28} {'worst rel err':>13}  at")
    for path, out, regime, err, where in rows:
        print(f"{path:<15} {out:<14} {regime:<28} {err:13.1e}  {where}")
    print(f"\nworst over all: {worst_all:.1e} (tolerance {args.tol:g})")
    print(f"time: reference {t_ref:.1f} s, kernel {t_ker:.2f} s, xpersson.solve {t_pipe:.1f} s")
    return 0 if worst_all <= args.tol else 1


if __name__ == "__main__":
    raise SystemExit(main())
