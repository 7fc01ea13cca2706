"""Leak rate of a rubber seal versus squeezing pressure (critical junction and Bruggeman EMT).

Solves ``rubber_seal.toml`` with :func:`xpersson.solve` and writes ``leak_rate.png`` in the
current directory (never into the source tree). Requires xpersson and xpersson-interface
installed (``pip install -e``) and matplotlib.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import xpersson  # noqa: E402

HERE = Path(__file__).resolve().parent


def main(out: Path = Path("leak_rate.png")) -> Path:
    """Solve the example scene and plot the leak rates [m^3/s] versus p0 [MPa]."""
    ds = xpersson.solve(HERE / "rubber_seal.toml")
    p0 = ds["p0"].values / 1e6
    q_cj = ds["leak_rate"].values
    q_emt = ds["leak_rate_emt"].values
    sealed = ds["leak_sealed"].values.astype(bool)
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(10, 4))
    ok = q_cj > 0
    ax.loglog(p0[ok], q_cj[ok] * 1e9 * 3600, "o-", label="critical junction ($a_c$ = 0.42)")
    ok2 = q_emt > 0
    ax.loglog(p0[ok2], q_emt[ok2] * 1e9 * 3600, "s--", label="Bruggeman EMT")
    if sealed.any():
        ax.axvline(p0[sealed][0], color="k", lw=0.8, ls=":")
        ax.text(p0[sealed][0], 1e-10, " sealed (CJ)", rotation=90, va="bottom")
    ax.set_xlim(p0.min(), p0.max())
    ax.set_ylim(bottom=1e-12)
    ax.set_xlabel("squeezing pressure $p_0$ [MPa]")
    ax.set_ylabel("leak rate [mm$^3$/h]")
    ax.set_title("water, 1 bar, $L_x$ = 2 mm, $L_y$ = 50 mm")
    ax.legend()
    ax2.semilogx(p0, ds["mean_gap"].values * 1e6, label=r"mean gap $\bar u$")
    ax2.semilogx(p0, ds["leak_u1"].values * 1e6, label="critical gap $u_1(\\zeta_c)$")
    ax2.set_xlabel("squeezing pressure $p_0$ [MPa]")
    ax2.set_ylabel("separation [$\\mu$m]")
    ax2.legend()
    fig.suptitle("Rubber (E = 10 MPa) on steel, $h_{rms}$ = 2 $\\mu$m, H = 0.8")
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    plt.close(fig)
    print(
        f"wrote {out}; leak rate at the lowest load {q_cj[0]:.3e} m^3/s, "
        f"sealed above {p0[sealed][0] if sealed.any() else np.nan:.3g} MPa"
    )
    return out


if __name__ == "__main__":
    main()
