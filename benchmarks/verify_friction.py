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
from typing import Any

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "plugins" / "xpersson-viscoelastic" / "tests"))

from visco_reference import (  # noqa: E402
    SLS,
    AngularTable,
    PronyRef,
    RefSpectrum,
    arrhenius_shift,
    mu_reference,
    prony_angular_quad,
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
#: second regime: a 3-mode Prony series with an Arrhenius shift (H = 0.7, one load)
PRONY_DE, PRONY_TAU = (5e8, 1e9, 5e8), (1e-6, 1e-4, 1e-2)
E_A, T_ARR, P0_ARR = 1e5, np.array([273.15, 313.15]), np.array([2e5])
#: (H, q_r, p0, v a_T) where the quad reference is checked against the ODE solution
ODE_POINTS = [
    (0.7, Q_L, 2e5, 1.0),
    (0.7, Q_L, 2e5, 10.0),
    (0.3, 10 * Q_L, 5e4, 1e-3),
    (1.0, Q_L, 5e5, 1e4),
]


#: the contact term: tau_f0 exp(-c log10(a_T v / v*)^2), area at zeta_c between output points
TAU_F0, C_LAW, V_STAR, ZETA_C = 3e5, 0.1, 1e-2, 300.0
DIMS = ("T", "v", "p0")
#: outputs of xpersson.solve compared (scalars per point, then profiles along zeta)
SCALARS = ("mu_visc", "mu_contact", "mu", "contact_area_cutoff", "area_fraction", "shift_factor")
PROFILES = (
    "area_fraction",
    "G",
    "mu_visc_cumulative",
    "loss_integral",
    "effective_modulus",
    "loss_angular_integral",
)


def _sls_wlf() -> dict:
    return {
        "modulus": "sls",
        "E_r": f"{E_R!r} Pa",
        "E_g": f"{E_G!r} Pa",
        "relaxation_time": f"{TAU!r} s",
        "shift": "wlf",
        "C1": WLF[0],
        "C2": f"{WLF[1]!r} K",
        "T_ref": f"{WLF[2]!r} K",
    }


def _prony_arrhenius() -> dict:
    return {
        "modulus": "prony",
        "E_r": f"{E_R!r} Pa",
        "delta_E": [f"{x!r} Pa" for x in PRONY_DE],
        "relaxation_times": [f"{x!r} s" for x in PRONY_TAU],
        "shift": "arrhenius",
        "activation_energy": f"{E_A!r} J/mol",
        "T_ref": f"{WLF[2]!r} K",
    }


def _scene(H: float, q_r: float, v: np.ndarray, T: np.ndarray, coef: dict | None = None) -> dict:
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
            **(coef or _sls_wlf()),
            "velocity": [f"{float(x)!r} m/s" for x in v],
            "temperature": [f"{float(x)!r} K" for x in T],
        },
        "analyses": {
            "friction": {
                "tau_f": f"{TAU_F0!r} Pa",
                "shear_law": "velocity",
                "c": C_LAW,
                "v_star": f"{V_STAR!r} m/s",
                "zeta_c": ZETA_C,
            }
        },
        "output": {"zeta_per_decade": ZPD},
    }


def references(
    H: float,
    q_r: float,
    v: np.ndarray,
    T: np.ndarray,
    zeta: np.ndarray,
    model: Any = None,
    shift: Any = None,
    p0s: np.ndarray = P0,
) -> dict[str, np.ndarray]:
    """Reference outputs on the grid: scalars (n_T, n_v, n_p0), ``<name>(zeta)`` profiles
    (n_T, n_v, n_p0, n_zeta). Default: the SLS with WLF."""
    psd = RefSpectrum(H, Q_L, q_r, Q_1, SLOPE)
    model = SLS(E_R, E_G, TAU) if model is None else model
    shift = (lambda t: wlf_shift(t, *WLF)) if shift is None else shift
    shape = (T.size, v.size, p0s.size)
    out = {k: np.empty(shape) for k in SCALARS}
    out.update({f"{k}(zeta)": np.empty(shape + zeta.shape) for k in PROFILES})
    zs = np.concatenate([zeta, [ZETA_C]])
    for (i, t), (j, x), (k, p) in itertools.product(enumerate(T), enumerate(v), enumerate(p0s)):
        aT = shift(float(t))
        r = mu_reference(psd, model, NU, float(p), float(x), aT, zeta=zs)
        prof = r["profiles"]
        law = math.log10(aT * float(x) / V_STAR)
        tau_f = TAU_F0 * math.exp(-C_LAW * law * law)
        A_c = float(prof["area_fraction"][-1])
        vals = {
            "mu_visc": r["mu_visc"],
            "area_fraction": r["area_fraction"],
            "contact_area_cutoff": A_c,
            "mu_contact": tau_f * A_c / float(p),
            "mu": r["mu_visc"] + tau_f * A_c / float(p),
            "shift_factor": aT,
        }
        for name, val in vals.items():
            out[name][i, j, k] = val
        for name in PROFILES:
            out[f"{name}(zeta)"][i, j, k] = prof[name][:-1]
    return out


def kernel(
    H: float, q_r: float, v: np.ndarray, T: np.ndarray, prony: bool = False
) -> dict[str, np.ndarray]:
    """``friction_curve`` on the grid (n_T, n_v, n_p0): SLS/WLF, or Prony/Arrhenius."""
    from xpersson.physics import SelfAffineRollOff
    from xpersson_viscoelastic import WLF as WLFLaw
    from xpersson_viscoelastic import Arrhenius, Prony, friction_curve, sls

    psd = SelfAffineRollOff.from_rms_slope(SLOPE, H, Q_L, q_r, Q_1)
    if prony:
        model = Prony(E_R, np.array(PRONY_DE), np.array(PRONY_TAU))
        return friction_curve(psd, model, NU, P0_ARR, v, Arrhenius(E_A, WLF[2]).aT(T))
    return friction_curve(psd, sls(E_R, E_G, TAU), NU, P0, v, WLFLaw(*WLF).aT(T))


def pipeline(
    H: float, q_r: float, v: np.ndarray, T: np.ndarray, prony: bool = False
) -> dict[str, np.ndarray]:
    """``xpersson.solve`` with v and T swept: the outputs as :func:`references`, and zeta."""
    import xpersson

    if prony:
        scene = _scene(H, q_r, v, T, _prony_arrhenius())
        scene["load"] = {"p0": [f"{float(p)!r} Pa" for p in P0_ARR]}
    else:
        scene = _scene(H, q_r, v, T)
    ds = xpersson.solve(scene)

    def arr(name: str, zeta: bool) -> np.ndarray:
        da = ds[name]
        want = DIMS + (("zeta",) if zeta else ())
        if not zeta and "zeta" in da.dims:
            da = da.isel(zeta=-1)
        da = da.expand_dims({d: ds.sizes[d] for d in want if d not in da.dims})
        return np.asarray(da.transpose(*want).values, dtype=float)

    out = {k: arr(k, False) for k in SCALARS}
    out.update({f"{k}(zeta)": arr(k, True) for k in PROFILES})
    out["zeta"] = np.asarray(ds["zeta"].values, dtype=float)
    return out


def error(name: str, got: np.ndarray, ref: np.ndarray, ref_all: dict) -> np.ndarray:
    """Relative error; the running friction relative to the total ``mu_visc``; entries where
    the reference is exactly 0 (``L``, ``mu`` running and ``G`` at ``zeta = 1``) are skipped."""
    if name == "mu_visc_cumulative(zeta)":
        return np.abs(got - ref) / ref_all["mu_visc"][..., None]
    with np.errstate(divide="ignore", invalid="ignore"):
        err = np.abs(got / ref - 1.0)
    return np.where(ref == 0.0, np.where(got == 0.0, 0.0, np.inf), err) * (ref != 0.0)


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


def cost(repeat: int = 7) -> None:
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


def _regimes() -> list[tuple[str, float, float, bool]]:
    """(label, q_r / q_L, H, Prony?) of every regime of the grid."""
    regimes = [
        (f"{'plateau' if r > 1 else 'no plateau'}, H={H}", r, H, False)
        for r, H in itertools.product(PLATEAU.values(), HURST)
    ]
    regimes += [(f"Prony+Arrhenius, {lab}", r, 0.7, True) for lab, r in PLATEAU.items()]
    return regimes


def measure(fast: bool) -> tuple[dict, list, np.ndarray, np.ndarray, tuple[float, float, float]]:
    """Worst relative error per (path, output) and regime, against the quad reference.

    Returns the table ``{(path, output): [(error, where) per regime]}``, the regimes, the speeds
    and temperatures used, and the times (reference, kernel, xpersson.solve) in seconds.
    """
    v, temps = (V[::3], T[::2]) if fast else (V, T)
    regimes = _regimes()
    prony_ref = PronyRef(E_R, PRONY_DE, PRONY_TAU)
    aTs = [arrhenius_shift(float(t), E_A, WLF[2]) for t in T_ARR]
    table_ref = AngularTable(prony_ref, Q_L * v[0] * min(aTs), Q_1 * v[-1] * max(aTs))
    table: dict[tuple[str, str], list[tuple[float, str]]] = {}
    t_ref = t_ker = t_pipe = 0.0
    for _label, r, H, prony in regimes:
        tt, p0s = (T_ARR, P0_ARR) if prony else (temps, P0)
        t0 = time.perf_counter()
        ker = kernel(H, r * Q_L, v, tt, prony)
        t1 = time.perf_counter()
        pipe = pipeline(H, r * Q_L, v, tt, prony)
        t2 = time.perf_counter()
        zeta = pipe.pop("zeta")
        if prony:
            shift = lambda t: arrhenius_shift(t, E_A, WLF[2])  # noqa: E731
            ref = references(H, r * Q_L, v, tt, zeta, table_ref, shift, p0s)
        else:
            ref = references(H, r * Q_L, v, tt, zeta)
        t3 = time.perf_counter()
        t_ker, t_pipe, t_ref = t_ker + t1 - t0, t_pipe + t2 - t1, t_ref + t3 - t2
        for path, got in (("friction_curve", ker), ("xpersson.solve", pipe)):
            for out in got:
                err = error(out, got[out], ref[out], ref)
                idx = np.unravel_index(int(np.argmax(err)), err.shape)
                where = f"v={v[idx[1]]:.0e} T={tt[idx[0]]:.0f} p0={p0s[idx[2]]:.0e}"
                table.setdefault((path, out), []).append((float(err.max()), where))
    return table, regimes, v, temps, (t_ref, t_ker, t_pipe)


def rows(fast: bool) -> list[dict]:
    """The friction rows of the verification matrix (``benchmarks/verify.py``)."""
    table, regimes, v, temps, _ = measure(fast)
    grid = (
        f"v {v[0]:.0e}..{v[-1]:.0e} m/s ({v.size}), T {temps.min():.0f}..{temps.max():.0f} K "
        f"(WLF), H 0.3/0.7/1, with and without plateau; Prony+Arrhenius ({len(regimes)} regimes)"
    )
    out = []
    for (path, name), cells in table.items():
        worst, where = max(cells)
        out.append(
            {
                "output": f"{name} ({path})",
                "regime": grid,
                "reference": "nested scipy quad with explicit breakpoints (visco_reference.py)",
                "worst": worst,
                "measure": "relative error",
                "note": f"worst at {where}",
            }
        )
    return out


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--fast", action="store_true", help="v every third decade, T in 3 values")
    ap.add_argument("--tol", type=float, default=1e-3, help="allowed relative error")
    ap.add_argument("--cost", action="store_true", help="only time 50 speeds (kernel, solve)")
    args = ap.parse_args(argv)
    if args.cost:
        cost()
        return 0
    print(f"SLS angular closed forms vs quad over phi: {check_angular():.1e}")
    print(f"quad reference vs adaptive ODE (4 points): {check_ode(ODE_POINTS):.1e}")
    prony_ref = PronyRef(E_R, PRONY_DE, PRONY_TAU)
    worst_phi = max(
        abs(a / b - 1.0)
        for w in np.logspace(-3, 12, 16)
        for a, b in zip(prony_ref.angular(w), prony_angular_quad(prony_ref, w), strict=True)
    )
    print(f"Prony angular rule vs quad over phi: {worst_phi:.1e}")
    table, regimes, v, temps, (t_ref, t_ker, t_pipe) = measure(args.fast)
    t_list = ", ".join(f"{t:.2f}" for t in temps)
    speeds = f"v = {v[0]:.0e}..{v[-1]:.0e} m/s ({v.size} speeds)"
    print(f"\nregime grid: {speeds}, T = {t_list} K (WLF),")
    print(f"p0 = {', '.join(f'{p:.0e}' for p in P0)} Pa; {ZPD} zeta per decade in xpersson.solve;")
    print(f"contact term: tau_f0 = {TAU_F0:g} Pa, velocity law, zeta_c = {ZETA_C:g}\n")
    print("| path | output | " + " | ".join(r[0] for r in regimes) + " | worst at |")
    print("|---|---|" + "---:|" * len(regimes) + "---|")
    worst_all = 0.0
    for (path, out), cells in table.items():
        worst = max(cells)
        worst_all = max(worst_all, worst[0])
        row = " | ".join(f"{e:.1e}" for e, _ in cells)
        print(f"| {path} | {out} | {row} | {worst[1]} |")
    print(f"\nworst over all: {worst_all:.1e} (tolerance {args.tol:g})")
    print(f"time: reference {t_ref:.1f} s, kernel {t_ker:.2f} s, xpersson.solve {t_pipe:.1f} s")
    return 0 if worst_all <= args.tol else 1


if __name__ == "__main__":
    raise SystemExit(main())
