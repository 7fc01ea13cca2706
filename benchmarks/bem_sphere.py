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

The theory is run with Persson's closure (``persson01``) and Yang-Persson's (``yp08``).

Run: ``python benchmarks/bem_sphere.py [--n 1024] [--seeds 3]`` (tamaas installed); prints
Markdown tables and writes ``benchmarks/results/bem_sphere.md`` and the BEM's numbers to
``bem_sphere.json`` (``--reuse`` recomputes only the theory against them).
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse  # noqa: E402
import json  # noqa: E402
import math  # noqa: E402
import time  # noqa: E402
import warnings  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

import xpersson  # noqa: E402
from xpersson import bem  # noqa: E402
from xpersson.bem import sphere  # noqa: E402
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


CLOSURES = ("persson01", "yp08")  # the theory's closures compared (Persson 2001; Yang-Persson)


def scene(h_rms: float, closure: str = "persson01") -> dict:
    """The theory's scene at rms height ``h_rms`` [m]."""
    return {
        "coefficient": {"model": "elastic", "closure": closure},
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


def bem_sphere(h_rms: float, L: float, n: int, seeds: int) -> tuple[np.ndarray, ...]:
    """Real areas [m^2], nominal radii [m] and approaches [m] of ``seeds`` realisations on a
    cell of side ``L`` [m] with ``n x n`` points (:func:`xpersson.bem.sphere.solve_sphere`)."""
    rs = Scene(scene(h_rms)).resolve()
    maps = bem.synthesise(rs.psd.C, L, n, seed=39, realisations=seeds, q_min=Q_L, q_max=Q_1)
    states = [sphere.solve_sphere(h, L, R, E_STAR, [FORCE])[0] for h in maps]
    return tuple(
        np.array([getattr(s, k) for s in states]) for k in ("real_area", "radius", "approach")
    )


def bem_rows(n: int, seeds: int) -> dict[str, list[list[float]]]:
    """BEM real areas [m^2] and nominal radii [m] per alpha (and the time [s], cell [m])."""
    out = {}
    for alpha in ALPHAS:
        t = time.perf_counter()
        areas, radii = bem_sphere(alpha * A0 * A0 / R, CELLS[alpha], n, seeds)
        out[repr(alpha)] = [areas.tolist(), radii.tolist(), [time.perf_counter() - t]]
    return out


def table(bem_data: dict, n: int, closure: str) -> tuple[list[str], float, float]:
    """Markdown rows of one closure, the worst real-area factor and the worst radius error."""
    lines = [
        f"Theory with closure `{closure}`:",
        "",
        "| alpha | h_rms [um] | real area theory [mm^2] | BEM [mm^2] | BEM/theory | "
        "radius theory [um] | BEM [um] | theory/BEM - 1 | cell [mm] | points per 2pi/q_1 |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    worst_a = worst_r = 0.0
    for alpha in ALPHAS:
        h = alpha * A0 * A0 / R
        ds = xpersson.solve(scene(h, closure))
        ta, tr = float(ds["real_contact_area"]), float(ds["nominal_contact_radius"])
        areas, radii, _ = (np.asarray(v) for v in bem_data[repr(alpha)])
        ba, br = areas.mean(), radii.mean()
        sa, sr = (v.std(ddof=1) / math.sqrt(v.size) for v in (areas, radii))
        L = CELLS[alpha]
        lines.append(
            f"| {float(ds['johnson_parameter']):.3g} | {h * 1e6:.4g} | {ta * 1e6:.4g} | "
            f"{ba * 1e6:.4g} +- {sa * 1e6:.2g} | {ba / ta:.3f} | {tr * 1e6:.4g} | "
            f"{br * 1e6:.4g} +- {sr * 1e6:.2g} | {tr / br - 1:+.3f} | {L * 1e3:g} | "
            f"{2 * math.pi / Q_1 / (L / n):.1f} |"
        )
        worst_a, worst_r = max(worst_a, ba / ta, ta / ba), max(worst_r, abs(tr / br - 1))
    return lines, worst_a, worst_r


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=1024)
    ap.add_argument("--seeds", type=int, default=3)
    ap.add_argument("--reuse", action="store_true", help="the BEM of the last run (its JSON)")
    args = ap.parse_args()
    warnings.simplefilter("ignore", xpersson.XperssonWarning)
    store = HERE / "results" / "bem_sphere.json"
    if args.reuse:
        saved = json.loads(store.read_text())
        args.n, args.seeds, bem_data = saved["n"], saved["seeds"], saved["bem"]
    else:
        bem_data = bem_rows(args.n, args.seeds)
        store.write_text(json.dumps({"n": args.n, "seeds": args.seeds, "bem": bem_data}))
    lines = [
        f"Sphere R = {R} m, E* = {E_STAR:g} Pa, F = {FORCE:.4g} N (Hertz radius {A0 * 1e6:g} um); "
        f"spectrum H = 0.8 on [{Q_L:g}, {Q_1:g}] 1/m; BEM n = {args.n} points per side, "
        f"{args.seeds} realisations (mean +- standard error); BEM time "
        f"{sum(v[2][0] for v in bem_data.values()):.0f} s.",
        "",
    ]
    for closure in CLOSURES:
        rows, worst_a, worst_r = table(bem_data, args.n, closure)
        lines += rows + [
            "",
            f"Worst real-area factor {worst_a:.3f} (target within 1.3x); worst nominal radius "
            f"{100 * worst_r:.1f} % (target within 10 %).",
            "",
        ]
    text = "\n".join(lines)
    print(text)
    (HERE / "results" / "bem_sphere.md").write_text(
        "# Rough sphere against BEM (benchmarks/bem_sphere.py)\n\n" + text
    )


if __name__ == "__main__":
    main()
