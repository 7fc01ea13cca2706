"""Built-in spectrum plugins: self-affine with roll-off, and tabulated (q, C) files."""

from __future__ import annotations

from typing import Any

from ..cache import memoize
from ..physics.psd import PowerSpectrum, SelfAffineRollOff
from ..physics.psd import Tabulated as _TabulatedPSD
from ..plugins import FastPaths, ParamSpec, Spectrum
from .topography import TABLE_PARAMETERS, ArchivedTable

__all__ = ["SelfAffine", "Tabulated"]

_WAVEVECTOR = dict(unit="1/m", bounds=(1e-12, 1e15), inclusive=(True, True), sweepable=True)
"""Wavevectors from 2 pi / (6e9 km) to 2 pi / (6 fm): everything outside is a typo."""


class SelfAffine(Spectrum):
    """Self-affine isotropic PSD with a roll-off plateau (Persson convention).

    C(q) = C_r for q_L <= q < q_r and C_r (q/q_r)^(-2(1+H)) for q_r <= q <= q_1 [m^4]. The
    amplitude is set by exactly one of ``h_rms`` [m], ``rms_slope`` (2-D gradient, [1]) or
    ``C_r`` [m^4].
    """

    summary = "self-affine isotropic PSD with roll-off, C(q) = C_r (q/q_r)^(-2(1+H))"
    references = ("10.1088/2051-672X/aa51f8", "10.1063/1.1388626")
    parameters = {
        "H": ParamSpec(
            "1",
            bounds=(0, 1),
            inclusive=(False, True),
            sweepable=True,
            description="Hurst exponent",
        ),
        "q_L": ParamSpec(**_WAVEVECTOR, description="lower cut-off wavevector (2 pi / L)"),
        "q_r": ParamSpec(
            **_WAVEVECTOR, default=None, description="roll-off wavevector (default q_L: no plateau)"
        ),
        "q_1": ParamSpec(**_WAVEVECTOR, description="upper cut-off wavevector"),
        "h_rms": ParamSpec(
            "m",
            default=None,
            sweepable=True,
            bounds=(0, 1e6),
            inclusive=(False, True),
            description="rms height (give one of h_rms, rms_slope, C_r)",
        ),
        "rms_slope": ParamSpec(
            "1",
            default=None,
            sweepable=True,
            bounds=(0, 1e6),
            inclusive=(False, True),
            description="rms 2-D gradient (give one of h_rms, rms_slope, C_r)",
        ),
        "C_r": ParamSpec(
            "m**4",
            default=None,
            sweepable=True,
            bounds=(0, 1e60),
            inclusive=(False, True),
            description="plateau PSD value (give one of h_rms, rms_slope, C_r)",
        ),
    }
    #: points of a sweep block may differ in the exponent and the amplitude (one spectrum each,
    #: the same q nodes and output grid)
    fast_paths = FastPaths(
        stacked_params=frozenset({"H", "h_rms", "rms_slope", "C_r"}), reused=True
    )

    def __init__(self, **params: Any) -> None:
        super().__init__(**params)
        p = self._params
        given = [k for k in ("h_rms", "rms_slope", "C_r") if p[k] is not None]
        if len(given) != 1:
            raise ValueError(
                "give exactly one of h_rms [m], rms_slope [1] or C_r [m^4] to set the amplitude"
                + (f" (got {', '.join(given)})" if given else "")
            )
        q_r = p["q_L"] if p["q_r"] is None else p["q_r"]
        if not p["q_L"] <= q_r:
            raise ValueError(f"q_r = {q_r:g} 1/m must satisfy q_L <= q_r (q_L = {p['q_L']:g} 1/m)")
        if not q_r < p["q_1"]:
            raise ValueError(
                f"q_1 = {p['q_1']:g} 1/m must satisfy q_r < q_1 (q_r = {q_r:g} 1/m, q_L = "
                f"{p['q_L']:g} 1/m)"
            )

    def build(self) -> PowerSpectrum:
        """The numerical spectrum (SI): frozen, and shared by every build with equal parameters
        (a scene solved again, the points of a sweep that do not change the spectrum)."""
        p = self._params
        q_r = p["q_L"] if p["q_r"] is None else p["q_r"]
        return _self_affine(p["h_rms"], p["rms_slope"], p["C_r"], p["H"], p["q_L"], q_r, p["q_1"])


#: 256 as ``checks.spectrum``: a sweep over more H values than the bound (64 before) missed on
#: every point at every solve (least recently used dropped first), ~8 ms of a 100 x 100 E x H sweep
@memoize("spectra.self_affine", scope="process", maxsize=256)
def _self_affine(
    h_rms: float | None,
    rms_slope: float | None,
    C_r: float | None,
    H: float,
    q_L: float,
    q_r: float,
    q_1: float,
) -> SelfAffineRollOff:
    """The frozen spectrum of these SI parameters (one of h_rms [m], rms_slope, C_r [m^4])."""
    geo = dict(H=H, q_L=q_L, q_r=q_r, q_1=q_1)
    if h_rms is not None:
        psd = SelfAffineRollOff.from_h_rms(h_rms, **geo)
    elif rms_slope is not None:
        psd = SelfAffineRollOff.from_rms_slope(rms_slope, **geo)
    else:
        psd = SelfAffineRollOff(C_r, **geo)
    psd.freeze()
    return psd


class Tabulated(ArchivedTable, Spectrum):
    """PSD read from a two-column text/CSV file (q, C), interpolated log-log.

    Conventions: ``persson`` (isotropic, m^4), ``surface_topography`` (isotropic JJP /
    SurfaceTopography convention, equal to (2 pi)^2 times Persson's) or ``profile_1d`` (1-D
    line-scan PSD in the JJP convention, m^3; converted with a local power-law factor).
    """

    summary = "tabulated isotropic or 1-D PSD from a (q, C) file, log-log interpolated"
    #: the table is read from its file (a ``kind="path"`` parameter) or given inline at each build
    fast_paths = FastPaths(reused=True)
    references = ("10.1088/2051-672X/aa51f8",)
    parameters = {
        "file": ParamSpec(
            "1", kind="path", default=None, description="two-column text/CSV file: q, C"
        ),
        "q_unit": ParamSpec(
            "1", default="1/m", kind="string", description="unit of the q column (pint syntax)"
        ),
        "C_unit": ParamSpec(
            "1",
            default="m**4",
            kind="string",
            description="unit of the C column (m**4 isotropic, m**3 for 1-D)",
        ),
        "convention": ParamSpec(
            "1",
            default="persson",
            kind="choice",
            choices=("persson", "surface_topography", "profile_1d"),
            description="PSD convention of the file",
        ),
        "q_L": ParamSpec(
            **_WAVEVECTOR, default=None, description="truncate below (default: first table point)"
        ),
        "q_1": ParamSpec(
            **_WAVEVECTOR, default=None, description="truncate above (default: last table point)"
        ),
        **TABLE_PARAMETERS,
    }

    def build(self) -> PowerSpectrum:
        """Read, convert to SI and the Persson convention."""
        from ..units import to_si

        inline = self._inline()
        if inline is not None:
            return inline
        p = self._params
        iso = p["convention"] != "profile_1d"
        c_si = "m**4" if iso else "m**3"
        q_factor = to_si(f"1 {p['q_unit']}", "1/m", "spectrum.q_unit")
        c_factor = to_si(f"1 {p['C_unit']}", c_si, "spectrum.C_unit")
        try:
            return _TabulatedPSD.from_file(
                p["file"], q_factor, c_factor, p["convention"], q_L=p["q_L"], q_1=p["q_1"]
            )
        except OSError as exc:
            raise ValueError(f"file: cannot read {p['file']!r} ({exc.strerror})") from None
        except ValueError as exc:
            if str(exc).startswith(str(p["file"])):  # errors of the file's content
                raise ValueError(f"file: {exc}") from None
            raise
