"""A/A0 versus nominal load, tensile to compressive: jkr vs dmt vs non-adhesive contact.

Solves ``pdms_on_glass.toml`` (PDMS-like elastomer on rough glass) three times -- the JKR-type
detachment wall ``jkr``, the attraction in the gaps ``dmt`` (9-3 Lennard-Jones law, same work
of adhesion) and the elastic (non-adhesive) boundary, which takes compressive loads only -- and
plots the contact area at the finest magnification against the nominal load.

Usage (from ``plugins/xpersson-adhesion``)::

    python examples/plot_area_vs_load.py [output.png]

Writes ``pdms_area_vs_load.png`` in the current directory by default (never into the
source tree).
"""

from __future__ import annotations

import copy
import sys
import tomllib
import warnings
from pathlib import Path

import numpy as np

import xpersson

HERE = Path(__file__).resolve().parent


def scenes() -> dict[str, dict]:
    """The example scene with the three boundaries."""
    base = tomllib.loads((HERE / "pdms_on_glass.toml").read_text())
    jkr = copy.deepcopy(base)
    dmt = copy.deepcopy(base)
    dmt["boundary"] = {
        "model": "dmt",
        "work_of_adhesion": base["boundary"]["work_of_adhesion"],
        "range": base["boundary"]["range"],
        "law": "lj93",
    }
    elastic = copy.deepcopy(base)
    elastic["boundary"] = {"model": "elastic"}
    elastic["load"]["p0"] = {"start": "1 kPa", "stop": "40 kPa", "num": 13, "spacing": "linear"}
    return {"jkr": jkr, "dmt": dmt, "non-adhesive": elastic}


def main(argv: list[str] | None = None) -> Path:
    argv = sys.argv[1:] if argv is None else argv
    out = Path(argv[0]) if argv else Path("pdms_area_vs_load.png")
    results = {}
    for name, scene in scenes().items():
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # the Tabor-parameter advice is printed below
            ds = xpersson.solve(scene)
        results[name] = ds
        area = ds["area_fraction"].isel(zeta=-1).values
        print(
            f"{name:13s} status={ds.attrs['status']:8s} p0 [kPa] = "
            f"{np.array2string(ds['p0'].values / 1e3, precision=1)}"
        )
        print(f"{'':13s} A/A0 = {np.array2string(area, precision=4)}")
    dmt = results["dmt"]
    print(
        f"dmt: p_att = {np.array2string(dmt['p_att'].values / 1e3, precision=0)} kPa "
        f"(discretisation check {float(dmt['p_att_discretization_error'].max()):.1e})"
    )
    jkr = results["jkr"]
    print(
        f"jkr: sigma_a(1) = {jkr['sigma_a'].values[0] / 1e3:.2f} kPa, pull-off stress = "
        f"{float(jkr['pull_off_stress']) / 1e3:.2f} kPa, w_eff = {float(jkr['w_eff']):.4f} J/m^2,"
        f" median Tabor parameter = {np.median(jkr['tabor_parameter'].values):.3g}"
    )

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 4))
    for name, ds in results.items():
        ax.plot(ds["p0"].values / 1e3, ds["area_fraction"].isel(zeta=-1).values, "o-", label=name)
    ax.axvline(-jkr["sigma_a"].values[0] / 1e3, color="0.6", ls="--", label="jkr: -sigma_a(zeta=1)")
    ax.set_xlabel("nominal pressure p0 [kPa] (negative: tensile)")
    ax.set_ylabel("contact area A/A0 at zeta_max")
    ax.set_title("PDMS-like elastomer on rough glass")
    ax.legend()
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    print(f"wrote {out}")
    return out


if __name__ == "__main__":
    main()
