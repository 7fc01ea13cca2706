"""The analyses integrated over a finite body: numbers and the docs' figure.

Solves the two examples (a steel ball's contact conductance, an O-ring's leak rate), prints the
body's values per force with their error estimates, checks the estimates against the same
scenes on a pressure grid four times denser (32 per decade), and draws
``docs/user_guide/figures/geometry_body_quantities.png`` (conductance against force with Holm's
smooth ball; leak rate against force).

    OPENBLAS_NUM_THREADS=1 python benchmarks/body_quantities.py [--no-figure]
"""

from __future__ import annotations

import argparse
import warnings
from pathlib import Path

import numpy as np

import xpersson
import xpersson.scene._geometry as geometry

ROOT = Path(__file__).resolve().parents[1]
BALL = ROOT / "plugins" / "xpersson-transport" / "examples" / "ball_conductance.toml"
ORING = ROOT / "plugins" / "xpersson-interface" / "examples" / "oring.toml"
FIGURE = ROOT / "docs" / "user_guide" / "figures" / "geometry_body_quantities.png"
RHO = 2 * 1.7e-7  # rho_1 + rho_2 of the ball example [ohm m]


def _solve(path: Path, per_decade: int) -> object:
    default = geometry.PER_DECADE
    geometry.PER_DECADE = per_decade
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return xpersson.solve(path)
    finally:
        geometry.PER_DECADE = default


def _table(ds: object, dense: object, names: list[str]) -> None:
    print(f"{'force [N]':>10}" + "".join(f"{n:>30}" for n in names))
    for k, f in enumerate(ds["force"].values):  # type: ignore[index]
        row = f"{f:10.3g}"
        for n in names:
            v = float(ds[n].values[k])  # type: ignore[index]
            est = float(ds[f"{n}_grid_error"].values[k])  # type: ignore[index]
            act = abs(v / float(dense[n].values[k]) - 1)  # type: ignore[index]
            row += f"{v:12.4g} (est {est:.1e}, 32/dec {act:.1e})"
        print(row)


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--no-figure", action="store_true")
    args = ap.parse_args(argv)
    ball, ball32 = _solve(BALL, 8), _solve(BALL, 32)
    ring, ring32 = _solve(ORING, 8), _solve(ORING, 32)
    print("steel ball on a rough steel flat (est: the grid error reported; 32/dec: the change")
    print("on a pressure grid of 32 per decade)")
    _table(ball, ball32, ["body_electrical_conductance", "body_thermal_conductance"])
    holm = 4 * ball["hertz_radius"].values / RHO  # type: ignore[index]
    G = ball["body_electrical_conductance"].values  # type: ignore[index]
    print("G / Holm of the smooth ball:", np.array2string(G / holm, precision=3))
    print("Johnson's parameter:", np.array2string(ball["johnson_parameter"].values, precision=3))  # type: ignore[index]
    print("\nO-ring on a rough steel counterface")
    _table(ring, ring32, ["body_leak_rate", "body_leak_rate_emt", "body_elastic_energy"])
    if args.no_figure:
        return
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(8.0, 3.4), layout="constrained")
    F = ball["force"].values  # type: ignore[index]
    ax1.loglog(F, G, "o-", label="rough flat (body_electrical_conductance)")
    ax1.loglog(F, holm, "k:", label="smooth ball, Holm 4a/(rho1+rho2)")
    ax1.set(xlabel="force [N]", ylabel="electrical conductance [S]", title="steel ball, R = 5 mm")
    ax1.legend(fontsize=8)
    Fr = ring["force"].values  # type: ignore[index]
    for name, label in (("body_leak_rate", "critical junction"), ("body_leak_rate_emt", "EMT")):
        ax2.loglog(Fr, ring[name].values, "o-", label=label)  # type: ignore[index]
    ax2.set(xlabel="force [N]", ylabel="leak rate [m$^3$/s]", title="NBR O-ring, water at 1 bar")
    ax2.legend(fontsize=8)
    fig.savefig(FIGURE, dpi=110)
    print(f"\nwrote {FIGURE.relative_to(ROOT)}")


if __name__ == "__main__":
    main()
