"""
The pressure process as a referee
=================================

The same scene solved by the exact path (``method = "auto"``) and by 20 000 Monte Carlo walkers
of the pressure process (``method = "markov"``, see the theory section). The walkers' error bars
are two standard errors; the two solutions agree within them at every magnification.
"""

from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

import xpersson

ROOT = Path.cwd().resolve()  # run from anywhere inside the repository (or docs/examples)
while not (ROOT / "examples" / "elastic.toml").is_file() and ROOT != ROOT.parent:
    ROOT = ROOT.parent
scene = xpersson.load_scene(ROOT / "examples" / "elastic.toml")
exact = xpersson.solve(scene, output__pressure_pdf=False)
walkers = xpersson.solve(
    scene,
    output__pressure_pdf=False,
    solver__method="markov",
    solver__walkers=20_000,
    solver__seed=1,
    solver__rtol=0.09,
)
z = (walkers.area_fraction - exact.area_fraction) / walkers.error_estimate.where(
    walkers.error_estimate > 0
)
print("largest difference:", float(np.abs(z).max()), "standard errors")

fig, ax = plt.subplots(figsize=(7, 4), constrained_layout=True)
for p0 in exact.p0.values:
    e, w = exact.sel(p0=p0), walkers.sel(p0=p0)
    (line,) = ax.loglog(e.zeta, e.area_fraction, label=f"p0 = {p0 / 1e3:g} kPa (exact)")
    ax.errorbar(
        w.zeta, w.area_fraction, yerr=2 * w.error_estimate, fmt="o", ms=3, color=line.get_color()
    )
ax.set_xlabel(r"magnification $\zeta$")
ax.set_ylabel("A/A0")
ax.set_title("lines: diffusion equation; points: 20 000 walkers (2 SE bars)")
ax.legend()
