"""
Leakage of a rubber seal
========================

``plugins/xpersson-interface/examples/rubber_seal.toml``: analyses ``mean_gap`` and ``leakage``
(critical-junction theory and the Bruggeman effective medium) for a rubber seal squeezed
against rough steel, 40 squeezing pressures.
"""

from pathlib import Path

import matplotlib.pyplot as plt

import xpersson

ROOT = Path.cwd().resolve()  # run from anywhere inside the repository (or docs/examples)
while not (ROOT / "examples" / "elastic.toml").is_file() and ROOT != ROOT.parent:
    ROOT = ROOT.parent
ds = xpersson.solve(ROOT / "plugins" / "xpersson-interface" / "examples" / "rubber_seal.toml")
p0 = ds.p0.values / 1e6

fig, (ax, ax2) = plt.subplots(1, 2, figsize=(10, 4), constrained_layout=True)
for name, style, label in (
    ("leak_rate", "o-", "critical junction"),
    ("leak_rate_emt", "s--", "Bruggeman EMT"),
):
    q = ds[name].values * 1e9 * 3600  # m^3/s -> mm^3/h
    ok = q > 0
    ax.loglog(p0[ok], q[ok], style, ms=3, label=label)
ax.set_xlabel("squeezing pressure p0 [MPa]")
ax.set_ylabel("leak rate [mm$^3$/h]")
ax.legend()
ax2.semilogx(p0, ds.mean_gap.values * 1e6)
ax2.set_xlabel("squeezing pressure p0 [MPa]")
ax2.set_ylabel(r"mean gap $\bar u$ [$\mu$m]")
