"""Measured topographies as spectra, and the archived form of file-based spectra.

``spectrum.model = "topography"`` reads a topography file in any format SurfaceTopography reads
(optional extra ``xpersson[topography]``) and computes its isotropic PSD there
(``power_spectrum_from_area``, log-binned; a non-periodic map is windowed by SurfaceTopography).
File-based spectra (this one and ``tabulated``) record the file's SHA-256 and the PSD actually
used (the table, Persson convention, SI) in the resolved scene, so an archive re-solves
(``xpersson reproduce``) after the source file is moved or deleted.
"""

from __future__ import annotations

import hashlib
from pathlib import Path
from typing import Any

import numpy as np

from ..physics.psd import PowerSpectrum
from ..physics.psd import Tabulated as _TabulatedPSD
from ..plugins import ParamSpec, Spectrum

__all__ = [
    "Topography",
    "sha256_of",
    "TABLE_PARAMETERS",
    "ArchivedTable",
    "psd_of_topography",
    "from_surface_topography",
    "is_surface_topography",
]

#: A trailing PSD bin whose share of the mean-square height is below this is FFT round-off of
#: a map without power there (a short-wavelength cutoff, e.g. ``fourier_synthesis``): genuine
#: spectra keep a share above ~1e-12 at the map's finest bin (h^2 ~ q^-2H, H <= 1, <= 6
#: decades), round-off sits near 1e-32.
ZERO_POWER_SHARE = 1e-20

_WAVEVECTOR = dict(unit="1/m", bounds=(0, None), inclusive=(False, True), sweepable=True)

TABLE_PARAMETERS = {
    "q": ParamSpec(
        "1/m",
        default=None,
        array=True,
        description="inline table: wavevectors (instead of a file; archives use it)",
    ),
    "C": ParamSpec(
        "m**4",
        default=None,
        array=True,
        description="inline table: isotropic PSD, Persson convention",
    ),
    "sha256": ParamSpec(
        "1",
        default=None,
        kind="string",
        description="SHA-256 of the source file (recorded by xpersson)",
    ),
    "source": ParamSpec(
        "1",
        default=None,
        kind="string",
        description="what the inline table was computed from (recorded by xpersson for a "
        "SurfaceTopography object or PSD given in a Python scene)",
    ),
}


def sha256_of(path: str | Path) -> str:
    """SHA-256 hex digest of a file."""
    digest = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


class ArchivedTable:
    """Mixin: an inline ``q, C`` table instead of the file, and the archived parameters."""

    _params: dict[str, Any]

    def __init__(self, **params: Any) -> None:
        super().__init__(**params)  # the plugin base: parameters checked and stored
        self._check_source()

    def _check_source(self) -> None:
        p = self._params
        inline = p.get("q") is not None or p.get("C") is not None
        if inline and (p.get("q") is None or p.get("C") is None):
            raise ValueError("give both q [1/m] and C [m^4] for an inline table")
        if not inline and p.get("file") is None:
            raise ValueError("file: required (or an inline table q [1/m], C [m^4])")

    def _inline(self) -> PowerSpectrum | None:
        p = self._params
        if p.get("q") is None:
            return None
        q, C = np.asarray(p["q"], float), np.asarray(p["C"], float)
        convention = p.get("convention") or "persson"
        if p.get("q_unit") not in (None, "1/m") or p.get("C_unit") not in (None, "m**4", "m**3"):
            from ..units import to_si  # e.g. a PSD SurfaceTopography computed in um

            q = q * to_si(f"1 {p['q_unit']}", "1/m", "spectrum.q_unit")
            c_si = "m**3" if convention == "profile_1d" else "m**4"
            C = C * to_si(f"1 {p['C_unit']}", c_si, "spectrum.C_unit")
        return _TabulatedPSD(q, C, convention, q_L=p.get("q_L"), q_1=p.get("q_1"))

    def archived_params(self, psd: Any) -> dict[str, Any]:
        """Parameters that rebuild ``psd`` without the source file (file and checksum kept as
        provenance)."""
        out = {k: v for k, v in self._params.items() if k not in ("q", "C")}
        out["q"] = np.asarray(psd.q_table, float)
        out["C"] = np.asarray(psd.C_table, float)
        out["q_L"], out["q_1"] = float(psd.q_table[0]), float(psd.q_table[-1])
        if "convention" in out:  # the archived table is in the Persson convention, SI
            out["convention"] = "persson"
        out.update({k: v for k, v in (("q_unit", "1/m"), ("C_unit", "m**4")) if k in out})
        file = self._params.get("file")
        if out.get("sha256") is None and file is not None and Path(file).is_file():
            out["sha256"] = sha256_of(file)
        return out


class Topography(ArchivedTable, Spectrum):
    """Isotropic PSD of a measured (or synthetic) topography map [m^4, Persson convention].

    The PSD is SurfaceTopography's ``power_spectrum_from_area`` (isotropic, log-binned, JJP
    convention, divided by (2 pi)^2), truncated to ``[q_L, q_1]`` (default: the reliable
    range of the map) and interpolated log-log between the bins.
    """

    summary = "isotropic PSD of a topography file (SurfaceTopography), log-binned"
    references = ("10.1088/2051-672X/aa51f8", "10.1088/0953-8984/23/21/215004")
    parameters = {
        "file": ParamSpec(
            "1",
            kind="path",
            default=None,
            description="topography file in any format SurfaceTopography reads",
        ),
        "q_L": ParamSpec(
            **_WAVEVECTOR, default=None, description="truncate below (default: smallest reliable q)"
        ),
        "q_1": ParamSpec(
            **_WAVEVECTOR, default=None, description="truncate above (default: largest reliable q)"
        ),
        "points_per_decade": ParamSpec(
            "1",
            default=20,
            kind="int",
            bounds=(2, 1000),
            description="log bins of the PSD per decade of q",
        ),
        "unit": ParamSpec(
            "1",
            default=None,
            kind="string",
            description="height/length unit when the file does not say (e.g. um)",
        ),
        **TABLE_PARAMETERS,
    }

    def build(self) -> PowerSpectrum:
        """Read the map and compute its isotropic PSD (or use the inline table)."""
        inline = self._inline()
        if inline is not None:
            return inline
        p = self._params
        try:
            import SurfaceTopography
        except ImportError:
            raise ValueError(
                "model 'topography' needs SurfaceTopography: pip install 'xpersson[topography]'"
            ) from None
        kwargs = {"unit": p["unit"]} if p["unit"] else {}
        try:
            topo = SurfaceTopography.read_topography(p["file"], **kwargs)
        except OSError as exc:
            raise ValueError(f"file: cannot read {p['file']!r} ({exc})") from None
        unit = topo.unit or p["unit"]
        if unit is None:
            raise ValueError(
                f"unit: the file {p['file']!r} does not give its length unit; "
                "set spectrum.unit (e.g. 'um')"
            )
        from ..units import to_si

        factor = to_si(f"1 {unit}", "m", "spectrum.unit")
        q, C = psd_of_topography(topo, int(p["points_per_decade"]), factor, repr(p["file"]))
        q_L = p["q_L"] if p["q_L"] is not None else float(q[0])
        q_1 = p["q_1"] if p["q_1"] is not None else float(q[-1])
        if not q[0] <= q_L < q_1 <= q[-1]:
            raise ValueError(
                f"q_L, q_1: need {q[0]:g} <= q_L < q_1 <= {q[-1]:g} 1/m (the map's PSD range "
                f"with power); got q_L = {q_L:g}, q_1 = {q_1:g} 1/m"
            )
        return _TabulatedPSD(q, C, "surface_topography", q_L=q_L, q_1=q_1)


def psd_of_topography(
    topo: Any, points_per_decade: int, factor: float, what: str = "the map"
) -> tuple[np.ndarray, np.ndarray]:
    """Isotropic PSD of a SurfaceTopography map, SI (1/m, m^4, JJP convention).

    ``power_spectrum_from_area`` log-binned, bins without data dropped, and a trailing band
    without power (share of the mean-square height below :data:`ZERO_POWER_SHARE`: FFT
    round-off above a short-wavelength cutoff) cut off, so that the default ``q_1`` is the
    largest wavevector that carries roughness. ``factor`` converts the map's length unit to m.
    """
    q, C = topo.power_spectrum_from_area(nb_points_per_decade=int(points_per_decade))
    q = np.ma.filled(np.ma.asarray(q, dtype=float), np.nan) / factor
    C = np.ma.filled(np.ma.asarray(C, dtype=float), np.nan) * factor**4
    ok = np.isfinite(q) & np.isfinite(C) & (q > 0) & (C > 0)
    q, C = q[ok], C[ok]
    if q.size >= 2:
        share = q**2 * C * np.gradient(np.log(q))  # ~ the bins' parts of h^2 (any convention)
        keep = np.flatnonzero(share > ZERO_POWER_SHARE * share.sum())
        q, C = (q[: keep[-1] + 1], C[: keep[-1] + 1]) if keep.size else (q[:0], C[:0])
    if q.size < 2:
        raise ValueError(f"file: {what} gives fewer than two PSD bins with power")
    return q, C


def is_surface_topography(obj: Any) -> bool:
    """A SurfaceTopography topography (2-D map or line scan), by what it can do."""
    return callable(getattr(obj, "power_spectrum_from_area", None)) and hasattr(
        obj, "physical_sizes"
    )


def from_surface_topography(topo: Any, points_per_decade: int = 20, **extra: Any) -> dict:
    """The ``spectrum`` table of a scene for a SurfaceTopography ``Topography`` object.

    The PSD is computed as for a file (:func:`psd_of_topography`); the table (Persson
    convention, SI) is the scene's spectrum, and ``source`` / ``sha256`` record the map
    (grid, sizes, unit, periodicity, SHA-256 of the heights) so the result is reproducible
    from the archive alone and traceable to the map. ``extra`` (``q_L``, ``q_1`` as quantities)
    truncates.
    """
    from ..units import to_si

    unit = getattr(topo, "unit", None)
    if unit is None:
        raise ValueError("spectrum: the SurfaceTopography object has no unit; give it one")
    factor = to_si(f"1 {unit}", "m", "spectrum.unit")
    q, C = psd_of_topography(topo, points_per_decade, factor, "the topography object")
    heights = np.ascontiguousarray(np.asarray(topo.heights(), dtype=float))
    source = (
        f"SurfaceTopography {type(topo).__name__}: nb_grid_pts {tuple(topo.nb_grid_pts)}, "
        f"physical_sizes {tuple(float(x) for x in topo.physical_sizes)} {unit}, "
        f"periodic {bool(getattr(topo, 'is_periodic', False))}; PSD power_spectrum_from_area, "
        f"{int(points_per_decade)} points per decade, bins without power dropped"
    )
    return {
        "model": "topography",
        "q": [f"{float(x)!r} 1/m" for x in q],
        "C": [f"{float(x)!r} m**4" for x in C / (2.0 * np.pi) ** 2],  # JJP -> Persson
        "sha256": hashlib.sha256(heights.tobytes()).hexdigest(),
        "source": source,
        **extra,
    }
