"""A rough sphere: xpersson's finite body against a boundary-element solution (tamaas).

One smooth sphere (radius ``R``) is pressed by one force on rough flats of one spectrum shape
(self-affine, ``H = 0.8``, wavevectors ``q_L <= q <= q_1``) scaled to four rms heights, so that
Johnson's roughness parameter ``alpha = sigma R / a0^2`` (``a0`` the Hertz radius) runs from
0.05 to 3. For each rms height:

* **theory**: ``xpersson.solve`` of the scene ``[geometry] model = "sphere"`` with
  ``load.force``: ``real_contact_area`` and ``nominal_contact_radius`` (the radius holding 99 %
  of the force);
* **BEM**: ``--seeds`` periodic Gaussian maps of the same spectrum
  (:func:`xpersson.bem.synthesise`, band ``[q_L, q_1]``) on a square cell of side ``L`` with
  ``n x n`` points, the sphere's cap ``-r^2/(2R)`` added, solved for the frictionless elastic
  contact at the mean pressure ``F/L^2`` (:func:`xpersson.bem.solve`, Polonsky-Keer-Rey); the
  real area is the contact fraction times ``L^2`` and the nominal radius the radius holding
  99 % of the force in the traction map.

The cell (side per alpha in ``CELLS``) holds the BEM's nominal contact with room (its diameter
below ``L/2``); the periodic images of the sphere change the local pressure little at that
distance. The smallest wavelength is resolved by ``(2 pi / q_1) / (L / n)`` points (printed):
the BEM's real area converges from above as it grows, the nominal radius much faster.

Run: ``python benchmarks/bem_sphere.py [--n 1024] [--seeds 3]`` (tamaas installed); prints a
Markdown table and writes ``benchmarks/results/bem_sphere.md``.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse  # noqa: E402
import math  # noqa: E402
import time  # noqa: E402
import warnings  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

import xpersson  # noqa: E402
from xpersson import bem  # noqa: E402
from xpersson.scene import Scene  # noqa: E402

HERE = Path(__file__).resolve().parent
R = 0.05  # sphere radius [m]
E_STAR = 1e6  # contact modulus [Pa] (E = 0.75 MPa, nu = 0.5)
A0 = 150e-6  # Hertz radius [m] at the force below
FORCE = 4.0 * E_STAR * A0**3 / (3.0 * R)  # [N]
Q_L, Q_1 = 1.5e5, 6e5  # [1/m]
ALPHAS = (0.05, 0.3, 1.0, 3.0)
#: side of the BEM cell [m] per alpha: the rougher, the wider the nominal contact
CELLS = {0.05: 1.2e-3, 0.3: 1.2e-3, 1.0: 2.4e-3, 3.0: 2.4e-3}


def scene(h_rms: float) -> dict:
    """The theory's scene at rms height ``h_rms`` [m]."""
    return {
        "geometry": {"model": "sphere", "radius": f"{R} m"},
        "load": {"force": f"{FORCE} N"},
        "spectrum": {
            "model": "self_affine",
            "H": 0.8,
            "q_L": f"{Q_L} 1/m",
            "q_r": f"{Q_L} 1/m",
            "q_1": f"{Q_1} 1/m",
            "h_rms": f"{h_rms} m",
        },  # fmt: skip
        "material": {"E": f"{0.75 * E_STAR} Pa", "nu": 0.5},
    }


def force_radius(pressure: np.ndarray, L: float, fraction: float = 0.99) -> float:
    """Radius [m] about the cell centre holding ``fraction`` of the force of a traction map."""
    n = pressure.shape[0]
    x = (np.arange(n) - n // 2) * (L / n)
    r = np.hypot(*np.meshgrid(x, x, indexing="ij")).ravel()
    order = np.argsort(r)
    cum = np.cumsum(np.clip(pressure.ravel()[order], 0.0, None))
    return float(r[order][np.searchsorted(cum, fraction * cum[-1])])


def bem_sphere(h_rms: float, L: float, n: int, seeds: int) -> tuple[np.ndarray, np.ndarray]:
    """Real areas [m^2] and nominal radii [m] of ``seeds`` realisations on a cell of side
    ``L`` [m] with ``n x n`` points."""
    rs = Scene(scene(h_rms)).resolve()
    maps = bem.synthesise(rs.psd.C, L, n, seed=39, realisations=seeds, q_min=Q_L, q_max=Q_1)
    x = (np.arange(n) - n // 2) * (L / n)
    cap = -(x[:, None] ** 2 + x[None, :] ** 2) / (2.0 * R)
    areas, radii = [], []
    for h in maps:
        (st,) = bem.solve(h + cap, L, E_STAR, [FORCE / L**2], keep_fields=True)
        areas.append(st.area_fraction * L**2)
        radii.append(force_radius(st.pressure, L))
    return np.array(areas), np.array(radii)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=1024)
    ap.add_argument("--seeds", type=int, default=3)
    args = ap.parse_args()
    warnings.simplefilter("ignore", xpersson.XperssonWarning)
    rows = []
    for alpha in ALPHAS:
        h_rms = alpha * A0 * A0 / R
        ds = xpersson.solve(scene(h_rms))
        t = time.perf_counter()
        L = CELLS[alpha]
        areas, radii = bem_sphere(h_rms, L, args.n, args.seeds)
        took = time.perf_counter() - t
        th_area, th_r = float(ds["real_contact_area"]), float(ds["nominal_contact_radius"])
        rows.append(
            (float(ds["johnson_parameter"]), h_rms, th_area, areas.mean(),
             areas.std(ddof=1) / math.sqrt(areas.size), th_r, radii.mean(),
             radii.std(ddof=1) / math.sqrt(radii.size), took, L, 2 * math.pi / Q_1 / (L / args.n))
        )  # fmt: skip
    head = (
        f"Sphere R = {R} m, E* = {E_STAR:g} Pa, F = {FORCE:.4g} N (Hertz radius {A0 * 1e6:g} um); "
        f"spectrum H = 0.8 on [{Q_L:g}, {Q_1:g}] 1/m; BEM n = {args.n} points per side, "
        f"{args.seeds} realisations (mean +- standard error).\n"
    )
    lines = [
        head,
        "| alpha | h_rms [um] | real area theory [mm^2] | BEM [mm^2] | BEM/theory | "
        "radius theory [um] | BEM [um] | theory/BEM - 1 | cell [mm] | points per 2pi/q_1 | "
        "BEM time [s] |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for a, h, ta, ba, sa, tr, br, sr, took, L, ppw in rows:
        lines.append(
            f"| {a:.3g} | {h * 1e6:.4g} | {ta * 1e6:.4g} | {ba * 1e6:.4g} +- {sa * 1e6:.2g} | "
            f"{ba / ta:.3f} | {tr * 1e6:.4g} | {br * 1e6:.4g} +- {sr * 1e6:.2g} | "
            f"{tr / br - 1:+.3f} | {L * 1e3:g} | {ppw:.1f} | {took:.0f} |"
        )
    worst_area = max(max(r[3] / r[2], r[2] / r[3]) for r in rows)
    worst_r = max(abs(r[5] / r[6] - 1) for r in rows)
    lines += [
        "",
        f"Worst real-area factor {worst_area:.3f} (target within 1.3x); worst nominal radius "
        f"{100 * worst_r:.1f} % (target within 10 %).",
    ]
    text = "\n".join(lines)
    print(text)
    (HERE / "results" / "bem_sphere.md").write_text(
        "# Rough sphere against BEM (benchmarks/bem_sphere.py)\n\n" + text + "\n"
    )


if __name__ == "__main__":
    main()
