"""
Thermal and electrical contact of an aluminium heat sink
========================================================

``plugins/xpersson-transport/examples/heat_sink.toml``: analyses ``thermal_contact`` and
``electrical_contact`` (Barber's stiffness-conductance analogy on Persson's contact stiffness,
air in the gaps with its temperature-jump length, radiation) for an aluminium heat sink on an
aluminium base in air, 25 nominal pressures. Right: Holm's non-interacting spots seen at the
finest magnification overestimate the conductance by orders of magnitude (the spots interact).
"""

from pathlib import Path

import matplotlib.pyplot as plt

import xpersson

ROOT = Path.cwd().resolve()  # run from anywhere inside the repository (or docs/examples)
while not (ROOT / "examples" / "elastic.toml").is_file() and ROOT != ROOT.parent:
    ROOT = ROOT.parent
ds = xpersson.solve(ROOT / "plugins" / "xpersson-transport" / "examples" / "heat_sink.toml")
p0 = ds.p0.values / 1e6

fig, (ax, ax2) = plt.subplots(1, 2, figsize=(10, 4), constrained_layout=True)
for name, style, label in (
    ("thermal_contact_conductance", "k-", "total"),
    ("thermal_solid_conductance", "o-", "solid contact (Barber)"),
    ("thermal_gas_conductance", "s-", "air in the gaps"),
):
    ax.loglog(p0, ds[name].values, style, ms=3, label=label)
ax.set_xlabel("nominal pressure p0 [MPa]")
ax.set_ylabel("thermal contact conductance [W m$^{-2}$ K$^{-1}$]")
ax.legend()
ax2.loglog(p0, ds.electrical_constriction_conductance.values, "o-", ms=3, label="Barber")
ax2.loglog(p0, ds.holm_conductance.isel(zeta=-1).values, "--", label=r"Holm spots at $\zeta_1$")
g_holm = ds.electrical_constriction_conductance.values * ds.holm_ratio.values
ax2.loglog(p0, g_holm, "-.", label=r"Holm spots at $\zeta_H$ (roll-off)")
ax2.set_xlabel("nominal pressure p0 [MPa]")
ax2.set_ylabel("electrical contact conductance [S m$^{-2}$]")
ax2.legend()
