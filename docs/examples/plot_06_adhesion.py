"""
Adhesive contact: ``jkr`` and ``dmt``
=====================================

``plugins/xpersson-adhesion/examples/pdms_on_glass.toml``: a soft PDMS-like elastomer
(E = 1 MPa) on rough glass with a work of adhesion of 0.05 J/m^2, from tensile to compressive
nominal loads. The same scene is solved with the JKR-type detachment wall (``jkr``), with the
attraction integrated over the gaps (``dmt``, 9-3 Lennard-Jones law) and without adhesion
(``elastic``, compressive loads only). Left: the contact area at the finest magnification
against the load. Right: the detachment stress sigma_a(zeta) of ``jkr``; a tensile load is
allowed down to -sigma_a(1), the pull-off stress.
"""

import copy
import tomllib
import warnings
from pathlib import Path

import matplotlib.pyplot as plt

import xpersson

ROOT = Path.cwd().resolve()  # run from anywhere inside the repository (or docs/examples)
while not (ROOT / "examples" / "elastic.toml").is_file() and ROOT != ROOT.parent:
    ROOT = ROOT.parent
SCENE = ROOT / "plugins" / "xpersson-adhesion" / "examples" / "pdms_on_glass.toml"
base = tomllib.loads(SCENE.read_text(encoding="utf-8"))
base["load"]["p0"] = {"start": "-8 kPa", "stop": "40 kPa", "num": 9, "spacing": "linear"}

dmt = copy.deepcopy(base)
dmt["boundary"] = {
    "model": "dmt",
    "law": "lj93",
    **{k: base["boundary"][k] for k in ("work_of_adhesion", "range")},
}
elastic = copy.deepcopy(base)
elastic["boundary"] = {"model": "elastic"}
elastic["load"]["p0"] = {"start": "1 kPa", "stop": "40 kPa", "num": 9, "spacing": "linear"}

results = {}
for name, scene in (("jkr", base), ("dmt", dmt), ("non-adhesive", elastic)):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the Tabor-parameter advice: jkr is the right limit here
        results[name] = xpersson.solve(scene)
jkr = results["jkr"]
print(
    f"jkr: pull-off stress {float(jkr.pull_off_stress) / 1e3:.2f} kPa, "
    f"w_eff = {float(jkr.w_eff):.4f} J/m^2 (sticky: > 0), "
    f"median Tabor parameter {float(jkr.tabor_parameter.median()):.0f}"
)

fig, (ax, ax2) = plt.subplots(1, 2, figsize=(10, 4), constrained_layout=True)
for name, ds in results.items():
    ax.plot(ds.p0 / 1e3, ds.area_fraction.isel(zeta=-1), "o-", ms=3, label=name)
ax.axvline(-float(jkr.pull_off_stress) / 1e3, color="0.6", ls="--", label="jkr: pull-off")
ax.set_xlabel("nominal pressure p0 [kPa] (negative: tensile)")
ax.set_ylabel("A/A0 at zeta_max")
ax.legend()
ax2.loglog(jkr.zeta, jkr.sigma_a / 1e3)
ax2.set_xlabel("magnification zeta")
ax2.set_ylabel("detachment stress sigma_a [kPa]")
plt.show()
