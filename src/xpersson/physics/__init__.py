"""Pure-numpy physics layer of xpersson (SI floats and numpy arrays, no units/xarray).

Submodules
----------
psd
    Isotropic roughness power spectra with exact moments (:class:`SelfAffineRollOff`,
    :class:`Tabulated`).
elastic
    Persson (2001) elastic theory closed forms (diffusion time, area, pressure PDF).
closures
    Correction-factor closures (Persson01, YP08, WM17, Xu24) as effective diffusion times.
"""

from .closures import CLOSURES, DEFAULT_GAMMA, closure_S, effective_ratio, effective_tau
from .elastic import (
    KAPPA,
    G_of_zeta,
    area_fraction,
    coefficient_f,
    diffusion_time,
    e_star,
    load_integral,
    pressure_pdf,
    second_moment,
)
from .psd import CONVENTIONS, PowerSpectrum, SelfAffineRollOff, Tabulated, profile_factor

__all__ = [
    "CLOSURES",
    "CONVENTIONS",
    "DEFAULT_GAMMA",
    "KAPPA",
    "G_of_zeta",
    "PowerSpectrum",
    "SelfAffineRollOff",
    "Tabulated",
    "area_fraction",
    "closure_S",
    "coefficient_f",
    "diffusion_time",
    "e_star",
    "effective_ratio",
    "effective_tau",
    "load_integral",
    "pressure_pdf",
    "profile_factor",
    "second_moment",
]
