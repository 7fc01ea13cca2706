"""Elastic, plastic and non-contact area fractions versus magnification for steel on steel.

Solves ``steel_on_steel.toml`` (next to this script) with :func:`xpersson.solve` and plots the
three area fractions against the magnification zeta (log axis), one line style per load, to
``steel_on_steel_areas.png`` in the current directory.

Usage::

    python plot_areas.py [scene.toml] [out.png]
"""

from __future__ import annotations

import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent


def plot_areas(scene: str | Path, out: str | Path) -> Path:
    """Solve ``scene`` and write the area-fraction plot to ``out`` (PNG); returns the path."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    import xpersson

    ds = xpersson.solve(str(scene))
    if "p0" not in ds.dims:
        ds = ds.expand_dims("p0")
    fractions = {
        "elastic_area_fraction": ("elastic $A_{el}/A_0$", "tab:blue"),
        "plastic_area_fraction": ("plastic $A_{pl}/A_0$", "tab:red"),
        "non_contact_area_fraction": ("non-contact $A_{non}/A_0$", "tab:gray"),
    }
    styles = ["-", "--", ":", "-."]
    sigma_y = float(ds["yield_stress"].values[0])
    fig, ax = plt.subplots(figsize=(7.5, 4.8), constrained_layout=True)
    for i, p0 in enumerate(ds["p0"].values):
        sel = ds.sel(p0=p0)
        for name, (_, color) in fractions.items():
            ax.plot(sel["zeta"], sel[name], styles[i % len(styles)], color=color)
        ax.axhline(p0 / sigma_y, color="tab:red", lw=0.6, alpha=0.4)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_ylim(1e-5, 2.0)
    ax.set_xlabel(r"magnification $\zeta = q/q_L$")
    ax.set_ylabel("area fraction")
    ax.set_title(
        f"{ds.attrs.get('title', 'plastic contact')}\n"
        r"thin lines: $p_0/\sigma_Y$ (limit of $A_{pl}/A_0$ as $\zeta \to \infty$)",
        fontsize=10,
    )
    handles = [plt.Line2D([], [], color=c, label=lab) for lab, c in fractions.values()] + [
        plt.Line2D([], [], color="k", ls=styles[i % len(styles)], label=f"$p_0$ = {p / 1e6:g} MPa")
        for i, p in enumerate(ds["p0"].values)
    ]
    ax.legend(handles=handles, fontsize=8, loc="lower right", ncol=2)
    out = Path(out)
    fig.savefig(out, dpi=130)
    plt.close(fig)
    return out


if __name__ == "__main__":
    scene = sys.argv[1] if len(sys.argv) > 1 else HERE / "steel_on_steel.toml"
    out = sys.argv[2] if len(sys.argv) > 2 else Path("steel_on_steel_areas.png")
    print(plot_areas(scene, out))
