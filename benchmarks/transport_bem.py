"""Contact part of xpersson-transport against a boundary-element computation (tamaas).

Barber's analogy makes the constriction conductance ``g = c K`` with one material constant
``c``, so comparing the conductance of the theory with a BEM computation *is* comparing the
incremental contact stiffness ``K = -dp0/du`` on the same spectrum. This script:

1. synthesises ``--seeds`` periodic self-affine surfaces with :func:`xpersson.bem.synthesise`
   (plateau for ``q0 <= q < q1``, ``C ~ q^-2(1+H)`` up to ``q2``; wavevectors in units of
   ``2 pi/L``), each scaled to the rms height ``h_rms``;
2. solves the frictionless, non-adhesive elastic contact (Polonsky-Keer-Rey, rigid rough
   surface on an elastic half-space, E* = 1) at log-spaced nominal pressures, and takes the mean
   gap ``u`` (gap zero on the contact points) and ``K = -p0 / (du/dln p0)`` (central
   differences in ``ln p0``, seeds averaged);
3. solves the conduction problem directly on each BEM contact set (unit potential jump on the
   contact points, no current elsewhere; conjugate gradients with the half-space kernel
   ``(rho_1 + rho_2)/|q|``), which checks Barber's analogy on the rough contact itself;
4. solves the same spectrum (``self_affine`` with ``q_L = 2 pi q0/L``, ``q_r = 2 pi q1/L``,
   ``q_1 = 2 pi q2/L``) with xpersson and the ``electrical_contact`` analysis, reading
   ``contact_stiffness`` and ``electrical_constriction_conductance``, for Persson's area with
   the Persson 2007 correction factor (``s_factor = closure``, ``S = 1``) and with
   Yang-Persson's (``yang_persson``, gamma = 0.42).

Run from the checkout (tamaas installed: ``pip install tamaas``)::

    python benchmarks/transport_bem.py [--n 512] [--seeds 3]

Writes ``benchmarks/results/transport_bem.md``. The BEM conductance is computed with the same
constant (resistivities of copper, E* = 1 Pa: a dimensionless comparison).
"""

from __future__ import annotations

import os

os.environ["OPENBLAS_NUM_THREADS"] = "1"

import argparse  # noqa: E402
import math  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

import xpersson  # noqa: E402

Q0, Q1, Q2, HURST, H_RMS = 2, 8, 64, 0.8, 1e-3  # L = 1 m, E* = 1 Pa
LOADS = np.geomspace(2e-4, 2e-3, 7)  # p0/E*: A/A0 from ~1 % to ~10 %


RHO_SUM = 2 * 1.7e-8  # rho_1 + rho_2 [ohm m] (copper on copper)


def conduction(contact: np.ndarray, rtol: float = 1e-10) -> float:
    """Constriction conductance per area [S m-2] of a periodic contact set (L = 1 m), solved
    directly (:func:`xpersson.bem.conductance_direct`)."""
    from xpersson import bem

    return bem.conductance_direct(contact, 1.0, RHO_SUM, rtol=rtol)


def surface(n: int, seed: int) -> np.ndarray:
    """Periodic map [m] (L = 1 m) of the scene's spectrum, scaled to ``H_RMS``
    (:func:`xpersson.bem.synthesise`: plateau q0..q1, power law to q2, x 2 pi / L)."""
    from xpersson import bem
    from xpersson.physics import SelfAffineRollOff

    two_pi = 2.0 * math.pi
    psd = SelfAffineRollOff.from_h_rms(
        H_RMS, H=HURST, q_L=two_pi * Q0, q_r=two_pi * Q1, q_1=two_pi * Q2
    )
    h = bem.synthesise(psd.C, 1.0, n, seed=seed, q_min=two_pi * Q0, q_max=two_pi * Q2)[0]
    return h * (H_RMS / h.std())


def bem_states(n: int, seed: int) -> list:
    """Converged BEM states (fields kept) at LOADS on one surface (E* = 1 Pa, L = 1 m)."""
    from xpersson import bem

    return bem.solve(surface(n, seed), 1.0, 1.0, LOADS, tol=1e-12, keep_fields=True)


def bem_gaps(n: int, seed: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Mean gap [m], contact fraction and direct conductance [S m-2] at LOADS, one surface."""
    states = bem_states(n, seed)
    u_mean = [s.mean_gap for s in states]
    area = [s.area_fraction for s in states]
    g = [conduction(s.contact) for s in states]
    return np.array(u_mean), np.array(area), np.array(g)


def theory(s_factor: str) -> dict[str, np.ndarray]:
    """Persson's stiffness, mean gap and conductance on the continuum spectrum."""
    two_pi = 2.0 * math.pi
    scene = {
        "spectrum": {"model": "self_affine", "H": HURST, "q_L": f"{two_pi * Q0!r} 1/m",
                     "q_r": f"{two_pi * Q1!r} 1/m", "q_1": f"{two_pi * Q2!r} 1/m",
                     "h_rms": f"{H_RMS!r} m"},
        "material": {"E": "1 Pa", "nu": 0.0},
        "load": {"p0": [f"{float(p)!r} Pa" for p in LOADS]},
        "analyses": {
            "electrical_contact": {"resistivity_1": "1.7e-8 ohm*m",
                                   "resistivity_2": "1.7e-8 ohm*m"},
            "contact_stiffness": {"s_factor": s_factor},
            "mean_gap": {"s_factor": s_factor},
        },
    }  # fmt: skip
    ds = xpersson.solve(scene)
    return {
        "K": ds["contact_stiffness"].values,
        "g": ds["electrical_constriction_conductance"].values,
        "u": ds["mean_gap"].values,
        "A": ds["area_fraction"].isel(zeta=-1).values,
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=512)
    ap.add_argument("--seeds", type=int, default=3)
    args = ap.parse_args()
    runs = [bem_gaps(args.n, seed) for seed in range(1, args.seeds + 1)]
    u = np.mean([r[0] for r in runs], axis=0)
    u_sd = np.std([r[0] for r in runs], axis=0)
    A = np.mean([r[1] for r in runs], axis=0)
    g_direct = np.mean([r[2] for r in runs], axis=0)
    lp = np.log(LOADS)
    K_bem = -LOADS / np.gradient(u, lp)  # central differences inside, one-sided at the ends
    c = 2.0 / (RHO_SUM * 1.0)
    th = {"Persson 2007 (S = 1)": theory("closure"), "Yang-Persson (gamma 0.42)": theory(
        "yang_persson")}  # fmt: skip
    lines = [
        "# Contact conductance (Barber) vs BEM (tamaas PKR): stiffness on the same spectrum",
        "",
        f"`python benchmarks/transport_bem.py --n {args.n} --seeds {args.seeds}`: "
        f"q0, q1, q2 = {Q0}, {Q1}, {Q2} (x 2 pi/L), H = {HURST}, h_rms = {H_RMS} L, E* = 1, "
        f"grid {args.n}^2 (pixel = L/{args.n}: {args.n // Q2} points per shortest wavelength), "
        f"{args.seeds} seeds averaged. g = c K with c = 2/((rho_1 + rho_2) E*) for both.",
        "",
        "g direct: the conduction problem solved on each BEM contact set (unit potential jump on",
        "the contact points, conjugate gradients); c K BEM: Barber's analogy on the BEM loading",
        "curve. Their ratio checks the analogy on the rough contact itself.",
        "",
        "| p0/E* | A BEM | A theory | u BEM / h_rms (sd) | K BEM [E*/h_rms] "
        "| g direct / (c K BEM) | "
        + " | ".join(f"K {k} / K BEM" for k in th)
        + " | u Persson 2007 / u BEM |",
        "|---|---|---|---|---|---|" + "---|" * len(th) + "---|",
    ]
    first = next(iter(th.values()))
    for i, p in enumerate(LOADS):
        ratios = " | ".join(f"{v['K'][i] / K_bem[i]:.3f}" for v in th.values())
        lines.append(
            f"| {p:.3g} | {A[i]:.4f} | {first['A'][i]:.4f} | {u[i] / H_RMS:.4f} "
            f"({u_sd[i] / H_RMS:.4f}) | {K_bem[i] * H_RMS:.4g} | "
            f"{g_direct[i] / (c * K_bem[i]):.3f} | {ratios} | "
            f"{first['u'][i] / u[i]:.3f} |"
        )
    inner = slice(1, -1)
    d = g_direct[inner] / (c * K_bem[inner])
    lines += [
        "",
        f"Analogy on the BEM contact: g direct / (c K BEM) = {d.min():.3f} ... {d.max():.3f}.",
    ]
    for k, v in th.items():
        r = v["K"][inner] / K_bem[inner]
        g_r = v["g"][inner] / g_direct[inner]
        lines.append("")
        lines.append(
            f"{k}: conductance theory / g direct {g_r.min():.3f} ... {g_r.max():.3f} "
            f"(= stiffness ratio {r.min():.3f} ... {r.max():.3f}) on the inner loads."
        )
    out = Path(__file__).resolve().parent / "results" / "transport_bem.md"
    out.write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
