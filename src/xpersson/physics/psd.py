"""Isotropic surface-roughness power spectra (pure numpy, SI units).

All spectra are stored internally in **Persson's isotropic convention**
(:cite:p:`jacobs2017,persson2005`):

.. math::

    C(q) = (2\\pi)^{-2} \\int d^2x \\, \\langle h(x) h(0) \\rangle e^{-i q\\cdot x}
    \\quad [\\mathrm{m^4}], \\qquad
    \\langle h^2 \\rangle = 2\\pi \\int q C(q)\\, dq .

Every spectrum in this module is *piecewise power law* between its breakpoints
(:meth:`PowerSpectrum.nodes`), so all moments
:math:`m_k = \\int q^k C(q)\\, dq` and the running slope integral
:math:`I_3(q) = \\int_{q_L}^{q} q'^3 C(q')\\, dq'` are evaluated **exactly** as sums of analytic
segment integrals (the logarithmic case, segment exponent :math:`k + e = -1`, is handled
continuously through :math:`\\mathrm{expm1}(x)/x`).

Wavevectors ``q`` are in rad/m (written 1/m).
"""

from __future__ import annotations

from ._map_spectrum import Rings, combine_tables, map_rings, profile_rings, table_from_rings
from ._psd_fit import SelfAffineFit, fit_self_affine
from ._self_affine import SelfAffineRollOff
from ._spectrum import CONVENTIONS, PowerSpectrum, profile_factor, stacked_C
from ._stored import StoredSpectrum, segment_exponents
from ._tabulated import Convention, Tabulated

__all__ = [
    "CONVENTIONS",
    "Convention",
    "PowerSpectrum",
    "Rings",
    "SelfAffineFit",
    "SelfAffineRollOff",
    "StoredSpectrum",
    "Tabulated",
    "profile_factor",
    "stacked_C",
    "segment_exponents",
    "map_rings",
    "profile_rings",
    "table_from_rings",
    "combine_tables",
    "fit_self_affine",
]
