"""mu(v) at three temperatures and A/A0 versus v for the tread-on-asphalt example.

Run from this folder (or anywhere): ``python plot_friction.py`` writes
``tread_on_asphalt_friction.png`` in the current directory. matplotlib is imported only here.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
SCENE = HERE / "tread_on_asphalt.toml"
TEMPERATURES = (273.15, 293.15, 313.15)  # K


def friction_curves(
    scene: str | Path = SCENE,
    velocities: np.ndarray | None = None,
    temperatures: tuple[float, ...] = TEMPERATURES,
) -> dict[str, np.ndarray]:
    """Solve the scene over sliding speeds [m/s] and temperatures [K] in one sweep.

    ``velocity`` and ``temperature`` given as lists become the Dataset dimensions ``v`` and
    ``T``. Returns ``v`` [m/s], ``T`` [K], ``p0`` [Pa] and ``mu``, ``mu_visc``, ``area``
    (A/A0 at the largest magnification), each of shape ``(n_T, n_v, n_p0)``.
    """
    import xpersson

    v = np.geomspace(1e-8, 1e2, 31) if velocities is None else np.asarray(velocities, float)
    ds = xpersson.solve(
        str(scene),
        coefficient__velocity=[f"{float(x)!r} m/s" for x in v],
        coefficient__temperature=[f"{float(t)!r} K" for t in temperatures],
    )
    ds = ds.transpose("T", "v", "p0", ...)
    return {
        "v": ds["v"].values,
        "T": ds["T"].values,
        "p0": np.atleast_1d(ds["p0"].values),
        "mu": ds["mu"].values,
        "mu_visc": ds["mu_visc"].values,
        "area": ds["area_fraction"].isel(zeta=-1).values,
    }


def plot_friction(
    scene: str | Path = SCENE,
    out: str | Path = Path("tread_on_asphalt_friction.png"),
    velocities: np.ndarray | None = None,
) -> Path:
    """Plot mu(v) (solid: total, dashed: viscoelastic) and A/A0(v) for the heaviest load."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    r = friction_curves(scene, velocities)
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4), constrained_layout=True)
    for i, T in enumerate(r["T"]):
        line = ax1.semilogx(r["v"], r["mu"][i, :, -1], label=f"T = {T - 273.15:.0f} °C")[0]
        ax1.semilogx(r["v"], r["mu_visc"][i, :, -1], "--", color=line.get_color())
        ax2.loglog(r["v"], r["area"][i, :, -1], color=line.get_color())
    ax1.set(
        xlabel="sliding speed v [m/s]",
        ylabel="friction coefficient μ",
        title=f"p0 = {r['p0'][-1] / 1e6:g} MPa (dashed: μ_visc)",
    )
    ax2.set(xlabel="sliding speed v [m/s]", ylabel="relative contact area A/A0 at q_1")
    ax1.legend()
    out = Path(out)
    fig.savefig(out, dpi=120)
    plt.close(fig)
    return out


if __name__ == "__main__":
    print(plot_friction())
