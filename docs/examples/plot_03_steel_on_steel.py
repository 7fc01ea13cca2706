"""
Steel on steel: elastoplastic contact
=====================================

``plugins/xpersson-plasticity/examples/steel_on_steel.toml``: constant penetration hardness
3 GPa (boundary ``plastic``: absorbing walls at 0 and sigma_Y). Elastic, plastic and non-contact
area fractions against the magnification; the plastic area tends to p0/sigma_Y (thin lines).
"""

from pathlib import Path

import matplotlib.pyplot as plt

import xpersson

ROOT = Path.cwd().resolve()  # run from anywhere inside the repository (or docs/examples)
while not (ROOT / "examples" / "elastic.toml").is_file() and ROOT != ROOT.parent:
    ROOT = ROOT.parent
ds = xpersson.solve(ROOT / "plugins" / "xpersson-plasticity" / "examples" / "steel_on_steel.toml")
sigma_y = float(ds.yield_stress[0])

fig, ax = plt.subplots(figsize=(7, 4), constrained_layout=True)
styles = ["-", "--", ":"]
for i, p0 in enumerate(ds.p0.values):
    sel = ds.sel(p0=p0)
    ax.loglog(sel.zeta, sel.elastic_area_fraction, styles[i], color="tab:blue")
    ax.loglog(sel.zeta, sel.plastic_area_fraction, styles[i], color="tab:red")
    ax.loglog(sel.zeta, sel.non_contact_area_fraction, styles[i], color="tab:gray")
    ax.axhline(p0 / sigma_y, color="tab:red", lw=0.5)
ax.set_ylim(1e-5, 2)
ax.set_xlabel(r"magnification $\zeta$")
ax.set_ylabel("area fraction")
ax.set_title("elastic (blue), plastic (red), non-contact (grey); p0 = 5, 20, 100 MPa")
