"""
A third-party boundary: the offset (adhesive) wall
==================================================

The worked plugin of ``examples/third_party_plugin`` (distribution ``xpersson-example``,
boundary ``offset_wall``): an absorbing wall at p = -s, a constant detachment stress. It is
selected by name in a scene like any first-party plugin; its exact area is
erf((p0 + s) / (2 sqrt(tau))), and it keeps more area in contact than the elastic wall.
"""

import matplotlib.pyplot as plt
import numpy as np

import xpersson
from xpersson.testing import constant_wall_area

scene = {
    "spectrum": {
        "model": "self_affine",
        "H": 0.8,
        "q_L": "1e3 1/m",
        "q_r": "1e4 1/m",
        "q_1": "1e8 1/m",
        "h_rms": "1 um",
    },
    "material": {"E": "10 MPa", "nu": 0.5},
    "load": {"p0": "100 kPa"},
    "output": {"zeta_per_decade": 8},
}
elastic = xpersson.solve(scene)
fig, ax = plt.subplots(figsize=(7, 4), constrained_layout=True)
ax.loglog(elastic.zeta, elastic.area_fraction, "k", label="elastic wall p = 0")
for s in (10e3, 30e3, 100e3):
    ds = xpersson.solve({**scene, "boundary": {"model": "offset_wall", "s": f"{s} Pa"}})
    exact = constant_wall_area(1e5, s, ds.diffusion_time.values)
    print(f"s = {s:g} Pa: max |A - exact| = {np.max(np.abs(ds.area_fraction - exact)):.1e}")
    ax.loglog(ds.zeta, ds.area_fraction, label=f"offset_wall, s = {s / 1e3:g} kPa")
ax.set_xlabel(r"magnification $\zeta$")
ax.set_ylabel("A/A0")
ax.legend()
