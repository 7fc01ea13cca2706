"""
Elastic rubber on a self-affine surface
=======================================

The README's main job: ``examples/elastic.toml`` (the reference parameter set of physics.md
§1.4: E = 10 MPa, nu = 0.5, H = 0.8, h_rms = 1 um, three loads). Left: the contact area A/A0
against the magnification; right: the pressure distribution P(p) at the largest magnification.
"""

from pathlib import Path

import matplotlib.pyplot as plt

import xpersson

ROOT = Path.cwd().resolve()  # run from anywhere inside the repository (or docs/examples)
while not (ROOT / "examples" / "elastic.toml").is_file() and ROOT != ROOT.parent:
    ROOT = ROOT.parent
ds = xpersson.solve(ROOT / "examples" / "elastic.toml")
print(ds.attrs["status"], "-", ds.attrs["status_message"])

fig, (ax, ax2) = plt.subplots(1, 2, figsize=(10, 4), constrained_layout=True)
for p0 in ds.p0.values:
    sel = ds.sel(p0=p0)
    ax.loglog(sel.zeta, sel.area_fraction, label=f"p0 = {p0 / 1e3:g} kPa")
    ax2.plot(ds.p / 1e6, sel.P.isel(zeta=-1) * 1e6, label=f"p0 = {p0 / 1e3:g} kPa")
ax.set_xlabel(r"magnification $\zeta$")
ax.set_ylabel("A/A0")
ax.legend()
ax2.set_xlabel("p [MPa]")
ax2.set_ylabel("P [1/MPa]")
ax2.set_title(rf"$\zeta$ = {float(ds.zeta[-1]):.3g}")
ax2.set_xlim(0, 2)
ax2.legend()
