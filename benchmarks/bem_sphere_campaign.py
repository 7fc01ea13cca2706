"""The rough-sphere campaign: xpersson's finite body against the BEM on a seeded design.

One smooth sphere (``R = 50 mm``, contact modulus ``E* = 1 MPa``) is pressed on rough flats at
two forces, ``F`` (Hertz radius ``a0 = 150 um``) and ``F/4``. The design (a Latin hypercube,
``--seed``) draws per scene:

* Johnson's roughness parameter ``alpha = sigma R / a0^2`` at ``F`` log-uniform in
  0.05-1.2 (``--alpha``; so ``F/4``, ``alpha x 4^(2/3)``, reaches 3);
* the Hurst exponent ``H`` uniform in 0.5-0.9;
* the contact-to-roll-off ratio ``a0 q_L`` log-uniform in 10-20; the spectrum is self-affine on
  ``q_L <= q <= q_1 = 4 q_L`` (no plateau: ``q_r = q_L``, 0.6 decades).

The BEM (:mod:`xpersson.bem.sphere`): ``--realisations`` maps per scene
(:func:`xpersson.bem.synthesise`, seed ``design seed x 1000 + scene``), on a cell of
:data:`xpersson.bem.sphere.CELL_FACTOR` times the theory's nominal radius at ``F`` (closure
``yp08``, the smaller of the two closures' radii; every BEM radius measured is below it), with
``--ppw`` grid points on the shortest wavelength (capped at ``--max-grid``: the number reached
is recorded). Per realisation and force: real area, nominal radius (99 % of the force),
approach and the ring-averaged traction on 40 rings out to half the cell.

Resumable: each finished scene is one JSON line in ``results/bem_sphere_campaign_<name>.jsonl``
(skipped when already there). Even scenes are the calibration half, odd ones held out.
``benchmarks/bem_sphere_report.py`` computes the theory, the bands and their coverage.

Usage::

    OPENBLAS_NUM_THREADS=1 nice -n 10 python benchmarks/bem_sphere_campaign.py --scenes 16
    # more calibration and held-out scenes at the rough end, and a new seed (a test set)
    ... bem_sphere_campaign.py --name cal2 --seed 3 --scenes 8 --alpha 0.3 1.2
    ... bem_sphere_campaign.py --name new --seed 2 --scenes 8
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse  # noqa: E402
import datetime  # noqa: E402
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
A0 = 150e-6  # Hertz radius [m] at FORCE
FORCE = 4.0 * E_STAR * A0**3 / (3.0 * R)  # [N]
FORCES = (FORCE / 4.0, FORCE)
ZETA = 4.0  # q_1 / q_L
RINGS = 40


def design(seed: int, n: int, alpha: tuple[float, float] = (0.05, 1.2)) -> list[dict[str, Any]]:
    """Latin hypercube over (ln alpha, H, ln a0 q_L): ``n`` scenes (``alpha`` at ``F``)."""
    rng = np.random.default_rng(seed)
    u = (np.array([rng.permutation(n) for _ in range(3)]).T + rng.random((n, 3))) / n
    lo, hi = np.log([alpha[0], 1.0, 10.0]), np.log([alpha[1], 1.0, 20.0])
    out = []
    for i, (a, h, q) in enumerate(u):
        alpha = math.exp(lo[0] + a * (hi[0] - lo[0]))
        qa = math.exp(lo[2] + q * (hi[2] - lo[2]))
        out.append({"scene": i, "alpha": alpha, "H": 0.5 + 0.4 * h, "a0_qL": qa,
                    "split": "calibration" if i % 2 == 0 else "held_out"})  # fmt: skip
    return out


def scene(sc: dict[str, Any], closure: str = "persson01") -> dict[str, Any]:
    """The theory's scene of design point ``sc`` (both forces)."""
    q_L = sc["a0_qL"] / A0
    return {
        "coefficient": {"model": "elastic", "closure": closure},
        "geometry": {"model": "sphere", "radius": f"{R!r} m"},
        "load": {"force": [f"{f!r} N" for f in FORCES]},
        "spectrum": {
            "model": "self_affine", "H": sc["H"], "q_L": f"{q_L!r} 1/m", "q_r": f"{q_L!r} 1/m",
            "q_1": f"{ZETA * q_L!r} 1/m", "h_rms": f"{sc['alpha'] * A0 * A0 / R!r} m",
        },
        "material": {"E": f"{0.75 * E_STAR!r} Pa", "nu": 0.5},
    }  # fmt: skip


def cell(sc: dict[str, Any], ppw: float, max_grid: int) -> tuple[float, int, float]:
    """Cell side [m], grid points per side and points per shortest wavelength reached."""
    ds = xpersson.solve(scene(sc, "yp08"))
    L = sphere.CELL_FACTOR * float(ds["nominal_contact_radius"].values.max())
    lam = 2.0 * math.pi / (ZETA * sc["a0_qL"] / A0)
    n = min(max_grid, 16 * math.ceil(ppw * L / lam / 16))
    return L, n, lam / (L / n)


def run_scene(sc: dict[str, Any], realisations: int, seed: int, ppw: float, max_grid: int,
              factor: float = 1.0) -> dict[str, Any]:  # fmt: skip
    """BEM of one design point (every realisation, both forces)."""
    t = time.perf_counter()
    L, n, reached = cell(sc, ppw, max_grid)
    L, n = L * factor, int(n * factor) // 2 * 2
    rs = Scene(scene(sc)).resolve()
    q_L = sc["a0_qL"] / A0
    maps = bem.synthesise(rs.psd.C, L, n, seed=seed * 1000 + sc["scene"],
                          realisations=realisations, q_min=q_L, q_max=ZETA * q_L)  # fmt: skip
    edges = np.linspace(0.0, L / 2, RINGS + 1)
    rows = []
    for h in maps:
        states = sphere.solve_sphere(h, L, R, E_STAR, FORCES, edges)
        rows.append([[s.real_area, s.radius, s.approach, s.profile.tolist(), s.converged]
                     for s in states])  # fmt: skip
    return sc | {
        "L": L, "n": n, "points_per_wavelength": reached, "realisations": realisations,
        "forces": list(FORCES), "edges": edges.tolist(), "bem": rows,
        "seconds": time.perf_counter() - t, "seed": seed,
        "tamaas": bem.tamaas_version(), "xpersson": xpersson.__version__,
        "date": datetime.date.today().isoformat(),
    }  # fmt: skip


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--name", default="cal")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--scenes", type=int, default=16)
    ap.add_argument("--realisations", type=int, default=2)
    ap.add_argument("--ppw", type=float, default=8.0)
    ap.add_argument("--max-grid", type=int, default=1024)
    ap.add_argument("--only", type=int, nargs="*", help="these scenes of the design only")
    ap.add_argument("--factor", type=float, default=1.0, help="cell and grid times this")
    ap.add_argument(
        "--alpha",
        type=float,
        nargs=2,
        default=(0.05, 1.2),
        help="range of Johnson's parameter at F (log-uniform)",
    )
    args = ap.parse_args()
    warnings.simplefilter("ignore", xpersson.XperssonWarning)
    out = HERE / "results" / f"bem_sphere_campaign_{args.name}.jsonl"
    done = set()
    if out.exists():
        done = {json.loads(line)["scene"] for line in out.read_text().splitlines() if line}
    for sc in design(args.seed, args.scenes, tuple(args.alpha)):
        if sc["scene"] in done or (args.only and sc["scene"] not in args.only):
            continue
        rec = run_scene(sc, args.realisations, args.seed, args.ppw, args.max_grid, args.factor)
        with out.open("a") as fh:
            fh.write(json.dumps(rec) + "\n")
        print(f"scene {sc['scene']}: alpha {sc['alpha']:.3g} H {sc['H']:.2f} a0qL "
              f"{sc['a0_qL']:.1f} n {rec['n']} ppw {rec['points_per_wavelength']:.1f} "
              f"{rec['seconds']:.0f} s", flush=True)  # fmt: skip


if __name__ == "__main__":
    main()
