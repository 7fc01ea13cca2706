"""The user guide's finite-body figure (``docs/user_guide/figures/geometry_sphere.png``).

Left: the nominal pressure ``p(r)`` of ``examples/sphere.toml`` at two forces against Hertz's
(the smooth ball, closed form). Right: the real contact area, the Hertz disk and the nominal
disk (99 % of the force) against the force. Every curve is read from the solved Dataset.

Usage::

    OPENBLAS_NUM_THREADS=1 python benchmarks/figure_geometry_sphere.py
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import xpersson  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "docs" / "user_guide" / "figures" / "geometry_sphere.png"


def main() -> None:
    ds = xpersson.solve(str(ROOT / "examples" / "sphere.toml"))
    r = ds["r"].values
    force = ds["force"].values
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(10, 3.8))
    for i, style in ((0, "-"), (3, "--")):
        a = float(ds["hertz_radius"][i])
        p_max = 3 * force[i] / (2 * np.pi * a**2)  # Hertz's peak pressure
        hertz = p_max * np.sqrt(np.clip(1 - (r / a) ** 2, 0, None))
        alpha = float(ds["johnson_parameter"][i])
        label = f"F = {force[i] * 1e3:.3g} mN, alpha = {alpha:.2g}"
        ax.plot(r * 1e3, hertz / 1e3, "k" + style, label=f"smooth (Hertz), {label}")
        ax.plot(r * 1e3, ds["nominal_pressure"][i] / 1e3, "C3" + style, label=f"rough, {label}")
    ax.set(xlabel="r [mm]", ylabel="nominal pressure p(r) [kPa]", xlim=(0, 0.45))
    ax.legend(fontsize=7)
    mm2 = 1e6
    bx.loglog(force, ds["real_contact_area"] * mm2, "C3o-", label="real contact area (rough)")
    bx.loglog(force, np.pi * ds["hertz_radius"] ** 2 * mm2, "k--", label="Hertz disk pi a0^2")
    bx.loglog(
        force, np.pi * ds["nominal_contact_radius"] ** 2 * mm2, "C0:",
        label="nominal disk (99 % of the force)",
    )  # fmt: skip
    bx.set(xlabel="force F [N]", ylabel="area [mm^2]")
    bx.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(OUT, dpi=100)
    print(f"wrote {OUT.relative_to(ROOT)}")


if __name__ == "__main__":
    main()
