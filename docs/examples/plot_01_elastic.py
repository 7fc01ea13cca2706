"""
Tutorial: what xpersson computes, on the flagship example
=========================================================

The README's main job, ``examples/elastic.toml``: a rubber block (E = 10 MPa, nu = 0.5) squeezed
against a self-affine rough surface (Hurst exponent H = 0.8, rms height 1 um) at three nominal
pressures. Before any option, this page explains the four quantities every result carries: the
magnification zeta, the contact area A/A0, Persson's G and the pressure distribution P(p).
"""

# %%
# Solve the scene
# ---------------
# :func:`xpersson.solve` reads the scene file and returns an :class:`xarray.Dataset`; every
# variable carries its unit and a long name. The flagship example runs without any warning
# (here any xpersson warning would stop the build).

import warnings
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
from scipy.special import erf

import xpersson
import xpersson.plot

ROOT = Path.cwd().resolve()  # run from anywhere inside the repository (or docs/examples)
while not (ROOT / "examples" / "elastic.toml").is_file() and ROOT != ROOT.parent:
    ROOT = ROOT.parent
with warnings.catch_warnings():
    warnings.simplefilter("error", xpersson.XperssonWarning)
    ds = xpersson.solve(ROOT / "examples" / "elastic.toml")
print(ds.attrs["status"], "-", ds.attrs["status_message"])
print(dict(ds.sizes))

# %%
# The magnification zeta
# ----------------------
# Looked at with a microscope of magnification :math:`\zeta = q/q_L`, the surface shows only its
# roughness with wavevectors between :math:`q_L` (the largest wavelength, here
# :math:`2\pi/q_L` = 6.3 mm) and :math:`q = \zeta q_L`. At :math:`\zeta = 1` the surface looks
# flat; at the largest magnification :math:`\zeta_1 = q_1/q_L` (here :math:`10^5`, wavelengths
# down to 63 nm) all of it is resolved. The power spectrum :math:`C(q)` says how much roughness
# each wavevector carries: flat below the roll-off :math:`q_r`, a power law
# :math:`q^{-2(1+H)}` above it.

fig, ax = plt.subplots(figsize=(6.4, 3.6), layout="constrained")
ax.loglog(ds["q_psd"], ds["psd_C"], "o-")
ax.set_xlabel("wavevector q [1/m]")
ax.set_ylabel("power spectrum C(q) [m$^4$]")
ax.set_title("the spectrum's nodes (roll-off at $q_r$, power law above)")

# %%
# The contact area A/A0
# ---------------------
# At each magnification a fraction :math:`A(\zeta)/A_0` of the nominal area is still in contact:
# 1 at :math:`\zeta = 1`, falling as finer roughness is resolved, because the stress at some
# points drops to zero and they lose contact. The value at :math:`\zeta_1` is *the* contact area
# of the surface; at small loads it is proportional to the load (here 10x the load gives about
# 10x the area, until the contact becomes nearly complete at 1 MPa).

ax = xpersson.plot.area(ds)
print(ds["area_fraction"].isel(zeta=-1).to_series())

# %%
# Persson's G
# -----------
# The roughness resolved up to :math:`\zeta` widens the stress distribution. Its variance grows by
# :math:`2 f(\zeta) d\zeta`, with :math:`f = \tfrac{\pi}{4} E^{*2} q_L q^3 C(q)`; the accumulated
# "diffusion time" :math:`\tau(\zeta) = \int_1^\zeta f\, d\zeta'` [Pa²] divided by
# :math:`p_0^2` is Persson's dimensionless :math:`G(\zeta)`. For the elastic theory the area
# depends on G only: :math:`A/A_0 = \mathrm{erf}\big(1/(2\sqrt{G})\big)`, so G is the one number
# that says how "rough" a surface looks to a solid under a given load.

fig, ax = plt.subplots(figsize=(6.4, 3.6), layout="constrained")
for p0, style in zip(ds["p0"].values, ["-", "--", ":"], strict=True):
    sel = ds.sel(p0=p0)
    ax.loglog(sel["G"], sel["area_fraction"], style, lw=2, label=f"p0 = {p0 / 1e3:g} kPa")
g = np.geomspace(1e-3, 1e5, 200)
ax.loglog(g, erf(1 / (2 * np.sqrt(g))), "k", lw=0.8, label=r"erf$(1/2\sqrt{G})$")
ax.set_xlabel("G = tau / p0²")
ax.set_ylabel("A/A0")
ax.set_ylim(1e-3, 1.5)
ax.legend(frameon=False)

# %%
# The pressure distribution P(p)
# ------------------------------
# :math:`P(p, \zeta)\, dp` is the fraction of the nominal area whose local pressure lies between
# p and p + dp. It starts as a delta at the nominal pressure :math:`p_0`, spreads as roughness is
# resolved, and vanishes at p = 0 (points that reach zero pressure leave the contact). Its
# integral is the contact area, and its mean over the contact area is the mean contact
# pressure: :math:`\int_0^\infty p P\, dp = p_0` (load balance). The scene asks for it with
# ``output.pressure_pdf = true`` on a pressure grid fine enough to resolve it at every stored
# magnification (``P_resolved`` says so per point).

ax = xpersson.plot.pressure_pdf(ds)
p = ds["p"].values
load = np.trapezoid(ds["P"].isel(zeta=-1).values * p, p, axis=-1)
print("int p P dp / p0 at zeta_1:", load / ds["p0"].values)

# %%
# The options
# -----------
# Everything above came from the scene file; each section picks a plugin or sets a grid:
#
# * ``[spectrum]``: the roughness (``self_affine``, a table, or a measured topography);
# * ``[material]``: E and nu (the contact modulus :math:`E^* = E/(1-\nu^2)`);
# * ``[load]``: the nominal pressures (a value, a list or a range);
# * ``[coefficient]`` and ``[boundary]``: the physics of f and of the wall at p = 0 (elastic
#   here; viscoelastic, plastic and adhesive ones come with the plugins);
# * ``[output]``: the stored magnifications and the pressure grid of P;
# * ``[analyses.*]``: what to compute from the solved contact.
#
# The user guide (:doc:`../user_guide/index`) covers each of them; the next examples use the
# plugins.

print((ROOT / "examples" / "elastic.toml").read_text())
