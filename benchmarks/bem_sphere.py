"""A rough sphere: xpersson's finite body against a boundary-element solution (tamaas).

One smooth sphere (radius ``R``) is pressed by one force on rough flats of one spectrum shape
(self-affine, ``H = 0.8``, wavevectors ``q_L <= q <= q_1 = 4 q_L``, ``a0 q_L = 18``) scaled to
four rms heights, so that Johnson's roughness parameter ``alpha = sigma R / a0^2`` (``a0`` the
Hertz radius) runs from 0.05 to 3. For each rms height:

* **theory**: ``xpersson.solve`` of the scene ``[geometry] model = "sphere"`` with
  ``load.force``: ``real_contact_area``, ``nominal_contact_radius`` (the radius holding 99 %
  of the force), ``approach``, and the band of the first two from the rough-sphere campaign
  (``X_exact_low``, ``X_exact_high``, ``X_model_error_status``);
* **BEM**: ``--seeds`` periodic Gaussian maps of the same spectrum
  (:func:`xpersson.bem.synthesise`, band ``[q_L, q_1]``) under the sphere
  (:func:`xpersson.bem.sphere.solve_sphere`): real area, nominal radius, approach referred to
  an isolated half-space.

The cell is :data:`xpersson.bem.sphere.CELL_FACTOR` times the theory's nominal radius (the
BEM's is smaller: its diameter stays below ``L/2``), with 8 points per shortest wavelength up
to ``--max-n`` points per side (the points reached are printed).

The theory is run with Persson's closure (``persson01``, the default) and Yang-Persson's
(``yp08``).

Run: ``python benchmarks/bem_sphere.py [--max-n 1024] [--seeds 3]`` (tamaas installed); prints
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
from typing import Any  # noqa: E402

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
Q_L, Q_1 = 1.2e5, 4.8e5  # [1/m] (a0 q_L = 18, inside the campaign's 6-20)
ALPHAS = (0.05, 0.3, 1.0, 3.0)
#: side of the BEM cell [m] per alpha of the run before this one (q_L = 1.5e5 1/m): used by
#: benchmarks/bem_sphere_profile.py
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


def cell(h_rms: float, max_n: int) -> tuple[float, int]:
    """Cell side [m] (``CELL_FACTOR`` times the theory's radius) and points per side (8 per
    shortest wavelength, at most ``max_n``)."""
    radius = float(xpersson.solve(scene(h_rms))["nominal_contact_radius"])
    L = sphere.CELL_FACTOR * radius
    return L, min(max_n, 16 * math.ceil(8 * L * Q_1 / (2 * math.pi) / 16))


def bem_sphere(h_rms: float, L: float, n: int, seeds: int) -> dict[str, list[float]]:
    """Real areas [m^2], nominal radii [m] and approaches [m] of ``seeds`` realisations on a
    cell of side ``L`` [m] with ``n x n`` points (:func:`xpersson.bem.sphere.solve_sphere`)."""
    rs = Scene(scene(h_rms)).resolve()
    maps = bem.synthesise(rs.psd.C, L, n, seed=39, realisations=seeds, q_min=Q_L, q_max=Q_1)
    states = [sphere.solve_sphere(h, L, R, E_STAR, [FORCE])[0] for h in maps]
    return {k: [getattr(s, k) for s in states] for k in ("real_area", "radius", "approach")}


def bem_rows(max_n: int, seeds: int) -> dict[str, dict[str, Any]]:
    """The BEM's values per alpha, with its cell [m], points per side and time [s]."""
    out = {}
    for alpha in ALPHAS:
        t = time.perf_counter()
        h = alpha * A0 * A0 / R
        L, n = cell(h, max_n)
        out[repr(alpha)] = bem_sphere(h, L, n, seeds) | {
            "L": L, "n": n, "seconds": time.perf_counter() - t
        }  # fmt: skip
        print(f"alpha {alpha}: n {n}, {out[repr(alpha)]['seconds']:.0f} s", flush=True)
    return out


def _band(ds: Any, name: str, bem_value: float) -> str:
    """``in``/``OUT`` of the BEM value against the theory's band, or ``not verified``."""
    if not int(ds[f"{name}_model_error_status"]):
        return "not verified"
    lo, hi = float(ds[f"{name}_exact_low"]), float(ds[f"{name}_exact_high"])
    return f"{'in' if lo <= bem_value <= hi else 'OUT'} [{lo / float(ds[name]):.2f}, " + (
        f"{hi / float(ds[name]):.2f}]"
    )


def table(bem_data: dict, closure: str) -> tuple[list[str], float, float, int]:
    """Markdown rows of one closure, the worst real-area factor, the worst radius error and
    the number of BEM values outside a band (or not verified)."""
    lines = [
        f"Theory with closure `{closure}`:",
        "",
        "| alpha | real area theory [mm^2] | BEM [mm^2] | BEM/theory | band | "
        "radius theory [um] | BEM [um] | theory/BEM - 1 | band | approach theory [um] | "
        "BEM [um] | cell [mm] | n | points per 2pi/q_1 |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    worst_a = worst_r = 0.0
    outside = 0
    for alpha in ALPHAS:
        ds = xpersson.solve(scene(alpha * A0 * A0 / R, closure))
        ta, tr = float(ds["real_contact_area"]), float(ds["nominal_contact_radius"])
        row = bem_data[repr(alpha)]
        areas, radii, appr = (np.asarray(row[k]) for k in ("real_area", "radius", "approach"))
        ba, br, bd = areas.mean(), radii.mean(), appr.mean()
        sa, sr, sd = (v.std(ddof=1) / math.sqrt(v.size) for v in (areas, radii, appr))
        L, n = row["L"], row["n"]
        band_a, band_r = _band(ds, "real_contact_area", ba), _band(ds, "nominal_contact_radius", br)
        outside += sum(not b.startswith("in") for b in (band_a, band_r))
        lines.append(
            f"| {float(ds['johnson_parameter']):.3g} | {ta * 1e6:.4g} | "
            f"{ba * 1e6:.4g} +- {sa * 1e6:.2g} | {ba / ta:.3f} | {band_a} | {tr * 1e6:.4g} | "
            f"{br * 1e6:.4g} +- {sr * 1e6:.2g} | {tr / br - 1:+.3f} | {band_r} | "
            f"{float(ds['approach']) * 1e6:.4g} | {bd * 1e6:.4g} +- {sd * 1e6:.2g} | "
            f"{L * 1e3:.3g} | {n} | {2 * math.pi / Q_1 / (L / n):.1f} |"
        )
        worst_a, worst_r = max(worst_a, ba / ta, ta / ba), max(worst_r, abs(tr / br - 1))
    return lines, worst_a, worst_r, outside


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--max-n", type=int, default=1024)
    ap.add_argument("--seeds", type=int, default=3)
    ap.add_argument("--reuse", action="store_true", help="the BEM of the last run (its JSON)")
    args = ap.parse_args()
    warnings.simplefilter("ignore", xpersson.XperssonWarning)
    store = HERE / "results" / "bem_sphere.json"
    if args.reuse:
        saved = json.loads(store.read_text())
        args.seeds, bem_data = saved["seeds"], saved["bem"]
    else:
        bem_data = bem_rows(args.max_n, args.seeds)
        store.write_text(json.dumps({"seeds": args.seeds, "bem": bem_data}))
    lines = [
        f"Sphere R = {R} m, E* = {E_STAR:g} Pa, F = {FORCE:.4g} N (Hertz radius {A0 * 1e6:g} um); "
        f"spectrum H = 0.8 on [{Q_L:g}, {Q_1:g}] 1/m; BEM {args.seeds} realisations (mean +- "
        f"standard error); BEM time {sum(v['seconds'] for v in bem_data.values()):.0f} s "
        "(nice 10 on a shared machine). Band: the rough-sphere campaign's "
        "(`X_exact_low/high`, factors on the theory's value).",
        "",
    ]
    for closure in CLOSURES:
        rows, worst_a, worst_r, outside = table(bem_data, closure)
        lines += rows + [
            "",
            f"Worst real-area factor {worst_a:.3f} (target within 1.3x); worst nominal radius "
            f"{100 * worst_r:.1f} % (target within 10 %); BEM values outside their band or not "
            f"verified: {outside} of {2 * len(ALPHAS)}.",
            "",
        ]
    text = "\n".join(lines)
    print(text)
    (HERE / "results" / "bem_sphere.md").write_text(
        "# Rough sphere against BEM (benchmarks/bem_sphere.py)\n\n" + text
    )


if __name__ == "__main__":
    main()
