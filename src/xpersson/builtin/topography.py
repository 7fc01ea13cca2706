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

__all__ = ["Topography", "sha256_of", "TABLE_PARAMETERS", "ArchivedTable"]

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
        return _TabulatedPSD(
            np.asarray(p["q"], float),
            np.asarray(p["C"], float),
            "persson",
            q_L=p.get("q_L"),
            q_1=p.get("q_1"),
        )

    def archived_params(self, psd: Any) -> dict[str, Any]:
        """Parameters that rebuild ``psd`` without the source file (file and checksum kept as
        provenance)."""
        out = {k: v for k, v in self._params.items() if k not in ("q", "C")}
        out["q"] = np.asarray(psd.q_table, float)
        out["C"] = np.asarray(psd.C_table, float)
        out["q_L"], out["q_1"] = float(psd.q_table[0]), float(psd.q_table[-1])
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
        q, C = topo.power_spectrum_from_area(nb_points_per_decade=int(p["points_per_decade"]))
        q = np.ma.filled(np.ma.asarray(q, dtype=float), np.nan) / factor
        C = np.ma.filled(np.ma.asarray(C, dtype=float), np.nan) * factor**4
        ok = np.isfinite(q) & np.isfinite(C) & (q > 0) & (C > 0)
        if np.count_nonzero(ok) < 2:
            raise ValueError(f"file: {p['file']!r} gives fewer than two usable PSD bins")
        q, C = q[ok], C[ok]
        q_L = p["q_L"] if p["q_L"] is not None else float(q[0])
        q_1 = p["q_1"] if p["q_1"] is not None else float(q[-1])
        if not q[0] <= q_L < q_1 <= q[-1]:
            raise ValueError(
                f"q_L, q_1: need {q[0]:g} <= q_L < q_1 <= {q[-1]:g} 1/m (the map's PSD range); "
                f"got q_L = {q_L:g}, q_1 = {q_1:g} 1/m"
            )
        return _TabulatedPSD(q, C, "surface_topography", q_L=q_L, q_1=q_1)
