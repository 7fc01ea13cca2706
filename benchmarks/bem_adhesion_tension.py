"""The tensile-branch candidates of ``docs/adhesion_bem.md``, reproduced from the stored BEM data.

Reads ``results/bem_adhesion.json`` (no BEM solve) and prints:

* ``k = p_att/p_rep`` of the BEM's retraction paths against the contact area (``p_rep`` from
  each surface's own non-adhesive ``A(p)``, power-law extrapolated below the lightest load;
  surface means), beside the unscaled mean field at the Persson-equivalent area ``A/1.45``;
* the mean field (scaled 0.85 and unscaled) on each surface's realised spectrum (its Fourier
  power binned in 10 log shells): small-load ratio and pull-off per surface;
* the rigid rough bump: the surface smoothed at ``zeta_c q_L`` as a sphere, the finer band's
  mean field as an effective traction-gap law of the mean gap, Derjaguin's pull-off
  ``2 pi R W_eff / L^2``;
* the single smooth bump with Persson-Tosatti's ``gamma_eff`` (``adhesive``'s floor before
  its constant ``BUMPS``).

Usage (from the repository root; about a minute)::

    OPENBLAS_NUM_THREADS=1 python benchmarks/bem_adhesion_tension.py
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import bem_adhesion as B
import numpy as np
from scipy.special import erf, erfc

HERE = Path(__file__).resolve().parent
E_STAR = B.E_STAR
L = B.L_CELL
Q_L = 2.0 * math.pi / L
AREAS = (0.003, 0.005, 0.01, 0.02, 0.03, 0.05)


def mean_field(psd: Any, work: float, rng: float, scale: float, zmax: float) -> Any:
    """``adhesive``'s tabulated mean field (``_meanfield.MeanField``) on a spectrum."""
    from xpersson.physics import diffusion_time
    from xpersson_adhesion._curves import curve_grid, increasing
    from xpersson_adhesion._meanfield import MeanField, attraction_curve

    z = curve_grid(np.geomspace(1.0, zmax, 41), per_decade=8)
    z = np.concatenate((z[:1], z[1:][z[1:] - 1.0 >= 1e-5]))
    tau = np.asarray(diffusion_time(psd, E_STAR, z), float)
    z, tau = increasing(z, tau)
    s = math.sqrt(tau[-1])

    def evaluate(p: np.ndarray) -> np.ndarray:
        return scale * attraction_curve(psd, E_STAR, z, tau, "exponential", work, rng, p)

    return MeanField(evaluate, s, 10.0 * s)


def k_of_area(entry: dict[str, Any], elastic: list[list[float]], loads: np.ndarray) -> np.ndarray:
    """Surface-mean ``k(A)`` of the BEM's retraction paths at :data:`AREAS`."""
    rows = []
    for seed, path in enumerate(entry["paths"]):
        el = np.array(elastic[seed])
        a = np.array([s["area"] for s in path["retract"]])
        p = np.array([s["p"] for s in path["retract"]]) * E_STAR
        slope = np.polyfit(np.log(el[:2]), np.log(loads[:2]), 1)
        ok = a > 0
        prep = np.full(a.shape, np.nan)
        prep[ok] = np.exp(np.interp(np.log(a[ok]), np.log(el), np.log(loads)))
        low = ok & (a < el[0])
        prep[low] = np.exp(np.polyval(slope, np.log(a[low])))
        k = (prep - p) / prep
        o = np.argsort(a)
        keep = np.isfinite(k[o]) & (a[o] > 0)
        rows.append(np.interp(AREAS, a[o][keep], k[o][keep], left=np.nan, right=np.nan))
    return np.nanmean(np.array(rows), axis=0)


def realised_psd(H: float, seed: int, shells: int = 10) -> Any:
    """The Persson PSD of one BEM surface: its Fourier power in log shells of ``|k|``."""
    from xpersson.physics import Tabulated

    n = 256
    f = np.fft.fft2(B.surface(H, seed, n) * L) / n**2
    k = np.fft.fftfreq(n, d=1.0 / n)
    kk = np.hypot(*np.meshgrid(k, k, indexing="ij"))
    edges = np.geomspace(1.0, B.RATIO + 1e-4, shells + 1)
    q, c = [], []
    for a, b in zip(edges[:-1], edges[1:], strict=True):
        shell = (kk >= a) & (kk < b)
        q.append(math.sqrt(a * b) * Q_L)
        c.append(float(np.sum(np.abs(f[shell]) ** 2)) / (math.pi * (b * b - a * a) * Q_L**2))
    slope = -2.0 * (1.0 + H)
    qa = np.concatenate(([Q_L], q, [B.RATIO * Q_L]))
    ca = np.concatenate(
        ([c[0] * (Q_L / q[0]) ** slope], c, [c[-1] * (B.RATIO * Q_L / q[-1]) ** slope])
    )
    return Tabulated(qa, ca, q_L=Q_L, q_1=B.RATIO * Q_L)


def rigid_bump(psd: Any, H: float, zeta_c: float, work: float, rng: float) -> float:
    """Derjaguin pull-off [Pa] of the bump smoothed at ``zeta_c``, the finer band's mean field
    (scaled 0.85) as its traction-gap law of the mean gap, per cell."""
    from xpersson.physics import SelfAffineRollOff, diffusion_time, mean_gap
    from xpersson_adhesion._curves import curve_grid
    from xpersson_adhesion._meanfield import attraction_curve

    qc = zeta_c * Q_L
    radius = 1.0 / math.sqrt(2.0 * math.pi * float(psd.running_moment(5.0, qc)))
    band = SelfAffineRollOff(float(psd.C(np.array([qc]))[0]), H, qc, qc, float(psd.q_1))
    z = curve_grid(np.geomspace(1.0, float(band.q_1) / qc, 20), per_decade=8)
    tau = np.asarray(diffusion_time(band, E_STAR, z), float)
    s = math.sqrt(tau[-1])
    p = np.geomspace(1e-3 * s, 10.0 * s, 100)
    with np.errstate(divide="ignore", invalid="ignore"):
        x = p[:, None] / (2.0 * np.sqrt(tau[None, :]))
    u = np.asarray(mean_gap(band, E_STAR, p, z, erf(x), non_area=erfc(x)), float)
    att = 0.85 * attraction_curve(band, E_STAR, z, tau, "exponential", work, rng, p)
    o = np.argsort(u)
    u, f, pp = u[o], (att - p)[o], p[o]
    tail = f[-1] * (u[-1] - u[-2]) / max(math.log(pp[-2] / pp[-1]), 1e-9)  # exponential tail
    cum = np.concatenate((np.cumsum((0.5 * (f[1:] + f[:-1]) * np.diff(u))[::-1])[::-1], [0.0]))
    return 2.0 * math.pi * radius * max(float(np.max(cum + tail)), 0.0) / L**2


def single_bump(psd: Any, work: float) -> float:
    """One smooth bump with Persson-Tosatti's ``gamma_eff`` at the best scale [Pa per cell]."""
    from xpersson_adhesion._bump import BUMPS, Bump

    return Bump(psd, E_STAR, work, L).pull_off / BUMPS


def main() -> None:
    """Print the four evidence tables."""
    bem = json.loads((HERE / "results" / "bem_adhesion.json").read_text())
    loads = np.array([x for x in B.LOADS if x > 0]) * B.SLOPE * E_STAR
    for name, sp in bem["spectra"].items():
        H = sp["H"]
        psd = B.continuum_psd(H)
        rng = B.range_of(H)
        for entry in sp["works"]:
            if entry["tabor"] > 2.0 or not entry["paths"]:
                continue
            w, mu = entry["work_J_m2"], entry["tabor"]
            pulls = entry["pull_off_Pa"]
            print(f"{name} mu_T {mu}: BEM pull-off mean {np.mean(pulls):.1f} Pa {np.round(pulls)}")
            kb = k_of_area(entry, sp["elastic_area"], loads)
            mf = mean_field(psd, w, rng, 1.0, B.RATIO)
            km = np.interp(np.array(AREAS) / 1.45, erf(mf.p / (2.0 * mf.scale)), mf.k)
            print(
                "  k(A) BEM / mean field: "
                + "  ".join(
                    f"{a:g}: {x:.2f}/{y:.2f}" for a, x, y in zip(AREAS, kb, km, strict=True)
                )
            )
            per = []
            for seed in range(len(pulls)):
                real = realised_psd(H, seed)
                m85 = mean_field(real, w, rng, 0.85, B.RATIO)
                m1 = mean_field(real, w, rng, 1.0, B.RATIO)
                per.append((m85.small_load_ratio, m85.pull_off(), m1.pull_off()))
            print(
                "  realised spectra k0 / pull-off 0.85 / 1.0: "
                + "; ".join(f"{a:.2f} {b:.0f} {c:.0f}" for a, b, c in per)
            )
            rigid = {zc: rigid_bump(psd, H, zc, w, rng) for zc in (4.0, 8.0, 12.0, 16.0)}
            print(
                "  rigid rough bump: "
                + ", ".join(f"zeta_c {k:g}: {v:.1f}" for k, v in rigid.items())
            )
            print(f"  single smooth bump (gamma_eff): {single_bump(psd, w):.1f} Pa")


if __name__ == "__main__":
    main()
