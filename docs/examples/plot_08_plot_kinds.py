"""
Every plot kind from every bundled example
==========================================

``xpersson plot ARCHIVE --kind KIND -o FIGURE`` and :mod:`xpersson.plot` draw six kinds of
figure straight from a Dataset. Below, each kind that a bundled example provides, exactly as
the command line writes it (:func:`xpersson.plot.save`: the scene's title above, human units,
legends outside the axes). A kind whose variable an example lacks is refused with a message
naming the analysis or output option that provides it (printed below).
"""

import warnings
from pathlib import Path

import matplotlib.pyplot as plt

import xpersson
import xpersson.plot

ROOT = Path.cwd().resolve()
while not (ROOT / "examples" / "elastic.toml").is_file() and ROOT != ROOT.parent:
    ROOT = ROOT.parent
PLUGINS = ROOT / "plugins"
EXAMPLES = {
    "elastic": (ROOT / "examples" / "elastic.toml", {}),
    "sweep": (ROOT / "examples" / "sweep.toml", {}),
    "steel on steel": (PLUGINS / "xpersson-plasticity" / "examples" / "steel_on_steel.toml", {}),
    "pdms on glass": (PLUGINS / "xpersson-adhesion" / "examples" / "pdms_on_glass.toml", {}),
    # the seal with the gap distribution and the elastic energy requested as well
    "rubber seal": (
        PLUGINS / "xpersson-interface" / "examples" / "rubber_seal.toml",
        {"analyses__gap_pdf": {}, "analyses__elastic_energy": {}},
    ),
    "tread on asphalt": (
        PLUGINS / "xpersson-viscoelastic" / "examples" / "tread_on_asphalt.toml",
        {},
    ),
}


def draw(name: str) -> None:
    """Solve one example and draw every kind it provides (a figure each)."""
    path, overrides = EXAMPLES[name]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ds = xpersson.solve(path, **overrides)
    for kind in xpersson.plot.KINDS:
        try:
            ax = xpersson.plot.plot(ds, kind)
        except ValueError as exc:
            print(f"{name}, {kind}: {exc}")
            continue
        # the archive's title, swept values and --set overrides, as `xpersson plot` writes them
        ax.figure.suptitle(f"{xpersson.plot.suptitle(ds)}\n(kind {kind!r})", fontsize="large")


# %%
# The flagship example: contact area and pressure distribution
draw("elastic")

# %%
# A sweep (2 moduli x 3 Hurst exponents): colour for H, line style and markers for E, so the
# curves that coincide (E doubles where the surface's slope halves) stay visible.
draw("sweep")

# %%
# Elastoplastic steel: the total contact area and its elastic and plastic parts; at the largest
# magnifications all contact is plastic and A/A0 = p0 / sigma_Y.
draw("steel on steel")

# %%
# Adhesion: loads from tensile to compressive, the area against the load.
draw("pdms on glass")

# %%
# A seal: area, gap distribution (a colour bar for the 40 loads), both leakage theories with the
# sealed range, and the elastic energy.
draw("rubber seal")

# %%
# Rubber friction: the archive holds one sliding speed and one temperature; the friction kind
# re-solves its scene over 17 speeds at 0, 20 and 40 °C and marks the stored point (star).
draw("tread on asphalt")
plt.show()
