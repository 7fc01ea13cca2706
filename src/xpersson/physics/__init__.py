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
interface
    Physics of a solved contact shared by analyses and plugins: elastic energy (also of the
    finer scales at full contact), mean gap, stiffness, gap distribution, percolation.
"""

from .closures import (
    CLOSURES,
    DEFAULT_GAMMA,
    GAMMA_DEFAULT,
    closure_S,
    effective_ratio,
    effective_tau,
    variance_factor,
)
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
from .interface import (
    Detachment,
    SolvedContact,
    contact_stiffness,
    critical_magnification,
    detachment,
    elastic_energy,
    full_contact_energy,
    gap_cdf,
    gap_mean,
    gap_pdf,
    mean_gap,
    mean_gap_slope,
    separation_of_detaching_area,
)
from .psd import CONVENTIONS, PowerSpectrum, SelfAffineRollOff, Tabulated, profile_factor

__all__ = [
    "CLOSURES",
    "CONVENTIONS",
    "DEFAULT_GAMMA",
    "Detachment",
    "GAMMA_DEFAULT",
    "KAPPA",
    "G_of_zeta",
    "PowerSpectrum",
    "SelfAffineRollOff",
    "SolvedContact",
    "Tabulated",
    "area_fraction",
    "closure_S",
    "coefficient_f",
    "contact_stiffness",
    "critical_magnification",
    "detachment",
    "diffusion_time",
    "e_star",
    "effective_ratio",
    "effective_tau",
    "elastic_energy",
    "full_contact_energy",
    "gap_cdf",
    "gap_mean",
    "gap_pdf",
    "load_integral",
    "mean_gap",
    "mean_gap_slope",
    "pressure_pdf",
    "profile_factor",
    "second_moment",
    "separation_of_detaching_area",
    "variance_factor",
]
