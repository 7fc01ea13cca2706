"""
Rubber friction: a sweep over sliding speed and temperature
===========================================================

``plugins/xpersson-viscoelastic/examples/tread_on_asphalt.toml``: a synthetic tread compound
(40 Prony modes between 3 MPa and 3 GPa, WLF shift) sliding on an asphalt-like surface.
``velocity`` and ``temperature`` given as lists become the Dataset dimensions ``v`` and ``T``
(one ordinary solve per point, stacked), and the ``friction`` analysis computes the friction
coefficient from each solved contact. The friction peak moves to higher speeds as the rubber
warms, by the shift factor a_T; the contact area shrinks as the rubber stiffens with speed.
"""

from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

import xpersson
import xpersson.plot

ROOT = Path.cwd().resolve()  # run from anywhere inside the repository (or docs/examples)
while not (ROOT / "examples" / "elastic.toml").is_file() and ROOT != ROOT.parent:
    ROOT = ROOT.parent
SCENE = ROOT / "plugins" / "xpersson-viscoelastic" / "examples" / "tread_on_asphalt.toml"

speeds = np.geomspace(1e-8, 1e2, 21)  # m/s
ds = xpersson.solve(
    SCENE,
    coefficient__velocity=[f"{float(v)!r} m/s" for v in speeds],
    coefficient__temperature=["273.15 K", "293.15 K", "313.15 K"],
    load__p0="0.3 MPa",
    output__zeta_per_decade=10,
)
print(ds.mu.dims, ds.mu.shape)

fig, (ax, ax2) = plt.subplots(1, 2, figsize=(10, 4), constrained_layout=True)
for T in ds.T.values:
    line = ax.semilogx(ds.v, ds.mu.sel(T=T), label=f"T = {T - 273.15:.0f} °C")[0]
    ax.semilogx(ds.v, ds.mu_visc.sel(T=T), "--", color=line.get_color())
    ax2.loglog(ds.v, ds.area_fraction.sel(T=T).isel(zeta=-1), color=line.get_color())
ax.set_xlabel("sliding speed v [m/s]")
ax.set_ylabel("friction coefficient mu (dashed: mu_visc)")
ax.legend()
ax2.set_xlabel("sliding speed v [m/s]")
ax2.set_ylabel("A/A0 at q_1")
plt.show()
