"""Contact conductance of an aluminium heat sink versus nominal pressure (thermal and electric).

Solves ``heat_sink.toml`` with :func:`xpersson.solve` and writes ``heat_sink_conductance.png``
in the current directory (never into the source tree). Requires xpersson,
xpersson-interface and xpersson-transport installed (``pip install -e``) and matplotlib.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import xpersson  # noqa: E402

HERE = Path(__file__).resolve().parent


def main(out: Path = Path("heat_sink_conductance.png")) -> Path:
    """Solve the example scene and plot the conductances [W/(m^2 K), S/m^2] versus p0 [MPa]."""
    ds = xpersson.solve(HERE / "heat_sink.toml")
    p0 = ds["p0"].values / 1e6
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(11, 4.3))
    parts = {
        "thermal_contact_conductance": ("total", "k-", 2.0),
        "thermal_solid_conductance": ("solid contact (Barber)", "C0o-", 1.2),
        "thermal_gas_conductance": ("air in the gaps", "C1s-", 1.2),
        "thermal_radiation_conductance": ("radiation ($\\varepsilon$ = 0.1)", "C2:", 1.2),
    }
    for name, (label, style, lw) in parts.items():
        ax.loglog(p0, ds[name].values, style, lw=lw, ms=3, label=label)
    ax.set_xlabel("nominal pressure $p_0$ [MPa]")
    ax.set_ylabel("thermal contact conductance [W m$^{-2}$ K$^{-1}$]")
    ax.set_title("Al 6061 / Al 6061 in air, $h_{rms}$ = 1 $\\mu$m")
    ax.grid(True, which="both", lw=0.3)
    ax.legend()
    g_b = ds["electrical_constriction_conductance"].values
    g_h = ds["holm_conductance"].isel(zeta=-1).values
    ax2.loglog(p0, g_b, "C0o-", ms=3, label="Barber: $2K/((\\rho_1+\\rho_2)E^*)$")
    ax2.loglog(p0, g_h, "C3--", label="Holm, non-interacting spots at $\\zeta_1$")
    z_h = float(np.median(ds["holm_magnification"].values))
    ax2.loglog(p0, g_b * ds["holm_ratio"].values, "C2-.",
               label=f"Holm, spots at $\\zeta_H \\approx$ {z_h:.3g} ($q_r/q_L$ = 10)")  # fmt: skip
    ax2.set_xlabel("nominal pressure $p_0$ [MPa]")
    ax2.set_ylabel("electrical contact conductance [S m$^{-2}$]")
    r = ds["electrical_contact_resistance"].values
    ax2.set_title(
        f"R(16 cm$^2$) = {r[0] * 1e6:.3g} $\\mu\\Omega$ ... {r[-1] * 1e6:.3g} $\\mu\\Omega$"
    )
    ax2.grid(True, which="both", lw=0.3)
    ax2.legend()
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    plt.close(fig)
    h = ds["thermal_contact_conductance"].values
    print(f"wrote {out}; h = {h[0]:.3g} ... {h[-1]:.3g} W/(m^2 K) for p0 = "
          f"{p0[0]:.3g} ... {p0[-1]:.3g} MPa")  # fmt: skip
    return out


if __name__ == "__main__":
    main()
