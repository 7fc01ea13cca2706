"""Where a cross-check's surfaces come from, checked before any work.

* **Synthesis** from the scene's spectrum ``C(q)``: a ``self_affine`` spectrum, a
  ``tabulated`` one, or the table of a ``topography`` spectrum that has no single 2-D map (a
  line scan, several scans combined, an inline table). The cell is ``2 pi / q_L``.
* **The measured map itself** (``topography`` with one 2-D map): read and detrended as the
  spectrum was (the scene's ``detrend``, ``unit``, ``physical_sizes``, ``height_scale``), in
  m. A periodic map is the cell as it is; a non-periodic one is **mirrored** (even reflection
  across two edges) into a periodic cell twice its side, which keeps every height (so the
  height distribution and ``h_rms``), the magnitude of every slope, and adds no step at the
  edges (the step a plain periodisation adds is spurious short-wavelength roughness in
  contact). The fold lines are creases where the slope changes sign.

The heights a BEM solves on an ``n x n`` grid are the map's Fourier modes in the band
(:func:`band_limited`): exact interpolation of a periodic band-limited map, no mode outside
the band.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from ._errors import refuse as _refuse
from .synthesis import wavenumbers

__all__ = ["Source", "source_of", "band_limited", "mirrored", "TABLE_SPECTRA"]

#: Spectrum models whose ``psd`` is a table (``q_table``, ``C_table``), synthesised from it.
TABLE_SPECTRA = ("tabulated", "topography")


@dataclass
class Source:
    """The surfaces of a cross-check (SI).

    Attributes
    ----------
    kind : str
        ``"synthesis"`` (every realisation synthesised from the spectrum) or ``"map"``
        (realisation 0 is the measured map; the others, if any, are synthesised from the
        map's spectrum table on the same cell and band).
    q_L : float
        The cell's fundamental wavevector [1/m]: the cell's side is ``2 pi / q_L``.
    top : float
        The spectrum's largest wavevector [1/m] (``q_1``; for a map, its largest mode, or the
        scene's truncation ``q_1``/``tip_radius``).
    q_min : float or None
        Lowest synthesised wavevector [1/m] (``None``: the cell's ``2 pi / L``).
    q_cut : float or None
        The scene's own low truncation ``q_L`` applied to the map [1/m] (``None``: every mode
        of the map is kept).
    heights : ndarray or None
        The periodic cell of the measured map [m] (mirrored when not periodic), its own grid.
    description : str
        What the surfaces are (the Dataset's ``surfaces`` attribute).
    notes : list of str
        Lines for stderr and the Dataset's ``notes``.
    reads_files : bool
        The scene reads scans with SurfaceTopography (imported: its memory counts).
    """

    kind: str
    q_L: float
    top: float
    q_min: float | None
    q_cut: float | None = None
    heights: np.ndarray | None = None
    description: str = ""
    notes: list[str] = field(default_factory=list)
    reads_files: bool = False  # SurfaceTopography is imported (its memory is in the estimate)

    @property
    def L(self) -> float:
        """Side of the periodic cell [m]."""
        return 2 * math.pi / self.q_L

    def text(self, realisations: int) -> str:
        """What the ``realisations`` surfaces are (the Dataset's ``surfaces`` attribute)."""
        if self.kind == "map" and realisations > 1:
            return self.description + (
                "; realisations 1.. are Gaussian periodic maps of the map's spectrum table on "
                "the same cell and band, realisation i seeded numpy default_rng([seed, i])"
            )
        return self.description

    def flags(self, realisations: int) -> xr.Variable:
        """``bem_surface``: which realisation is the measured map (CF flags)."""
        flags = np.zeros(realisations, dtype="i1")
        flags[0] = self.kind == "map"
        return xr.Variable(
            ("realisation",),
            flags,
            {
                "units": "1",
                "long_name": "surface of each realisation",
                "flag_values": np.array([0, 1], dtype="i1"),
                "flag_meanings": "synthesised_from_the_spectrum measured_map",
            },
        )


_SYNTHESISED = (
    "Gaussian periodic maps of the scene's spectrum (Persson's C(q), (2 pi / L)^2 per mode), "
    "realisation i seeded numpy default_rng([seed, i])"
)


def source_of(rs: Any) -> Source:
    """The surfaces of the resolved scene ``rs`` (a refusal for a spectrum it cannot use)."""
    spec = rs.plugin_names["spectrum"]
    psd = rs.psd
    if spec == "self_affine":
        q_L = float(psd.q_L)
        return Source("synthesis", q_L, float(psd.q_1), q_L, None, None, _SYNTHESISED)
    if spec not in TABLE_SPECTRA:
        raise _refuse(
            f"spectrum model {spec!r}: the cross-check synthesises 'self_affine' and table "
            "spectra ('tabulated', 'topography') and solves measured maps; this one has no "
            "table to synthesise from"
        )
    params = dict(getattr(rs.spectrum, "params", {}) or {})
    files = [params[k] for k in ("file", "file_2", "file_3") if params.get(k)]
    reads = spec == "topography" and bool(files) and params.get("q") is None
    found = _map_source(files[0], params, psd) if reads and len(files) == 1 else None
    found = found or _table_source(spec, files if reads else [], psd)
    found.reads_files = reads
    return found


def _table_source(spec: str, files: list[str], psd: Any) -> Source:
    """Synthesis from the table; ``files`` are the scans read (empty: an inline table)."""
    q_L = float(psd.q_L)
    src = Source("synthesis", q_L, float(psd.q_1), q_L, None, None, _SYNTHESISED)
    if spec == "topography":
        if not files:
            why = "an inline table (no map read)"
        elif len(files) > 1:
            why = f"{len(files)} scans combined (no one map holds the whole band)"
        else:
            why = "a line scan (1-D: its heights are no 2-D map)"
        src.notes.append(
            f"the spectrum is {why}: the BEM solves Gaussian syntheses of its isotropic 2-D "
            "table, not measured heights"
        )
        src.description = _SYNTHESISED.replace("scene's spectrum", f"scene's table ({why})")
    return src


def _map_source(file: str, params: dict[str, Any], psd: Any) -> Source | None:
    """The measured map as the BEM's cell (``None`` for a line scan)."""
    from ..builtin.surface_maps import measured_from_file
    from ..builtin.topography import map_keys

    m = measured_from_file(file, map_keys(params))
    if m.heights.ndim != 2:
        return None
    (nx, ny), (lx, ly) = m.heights.shape, m.sizes
    if nx != ny or not math.isclose(lx, ly, rel_tol=1e-6):
        raise _refuse(
            f"the measured map {Path(file).name!r} is {nx} x {ny} points over {lx:.4g} x "
            f"{ly:.4g} m: the BEM cell is square with square pixels (crop the map to a square)"
        )
    h = m.heights - m.heights.mean()
    detrend = m.provenance["detrend"]
    what = f"the measured map {Path(file).name!r} ({nx}^2 points, {lx:.4g} m, detrend {detrend!r})"
    if m.periodic:
        cell, L, how = h, lx, "periodic: the cell as it is"
    else:
        cell, L = mirrored(h), 2 * lx
        how = (
            "not periodic: mirrored into a periodic cell of twice its side (every height and "
            "slope magnitude kept, no step at the edges; creases along the fold lines)"
        )
    q_cut = params.get("q_L")
    cut_above = params.get("q_1") is not None or params.get("tip_radius") is not None
    top = float(psd.q_1) if cut_above else _top_mode(cell, L)
    src = Source("map", 2 * math.pi / L, top, q_cut, q_cut, cell, f"realisation 0: {what}, {how}")
    src.notes.append(f"the BEM solves {what}, {how}")
    return src


def _top_mode(h: np.ndarray, L: float) -> float:
    """The largest wavevector [1/m] with power of a periodic map (its table ends a little
    below it, at the last ring's equal-measure edge: the map's own band is kept whole)."""
    power = np.abs(np.fft.fft2(h - h.mean())) ** 2
    qq = wavenumbers(L, h.shape[0])
    return float(qq[power > 1e-20 * power.sum()].max())


def mirrored(h: np.ndarray) -> np.ndarray:
    """The even (half-sample) reflection of a map across its last row and column: a periodic
    ``2n x 2n`` map [m] whose every quadrant is the map or its mirror image."""
    top = np.concatenate([h, h[:, ::-1]], axis=1)
    return np.concatenate([top, top[::-1, :]], axis=0)


def _embed(f: np.ndarray, n: int, axis: int) -> np.ndarray:
    """Fourier amplitudes ``f`` (FFT order along ``axis``, ``m`` modes) placed on ``n`` modes:
    zero-padded (``n > m``, the Nyquist mode split between +-m/2 so the map stays real and
    keeps its values at the old nodes) or truncated (``n < m``)."""
    m = f.shape[axis]
    if n == m:
        return f
    g = np.moveaxis(f, axis, 0)
    out = np.zeros((n, *g.shape[1:]), dtype=complex)
    half = min(m, n) // 2
    out[:half] = g[:half]
    out[n - half + 1 :] = g[m - half + 1 :]
    if n > m:
        out[half] = out[n - half] = 0.5 * g[half]
    return np.moveaxis(out, 0, axis)


def band_limited(
    h: np.ndarray, n: int, L: float, lo: float | None = None, hi: float | None = None
) -> np.ndarray:
    """A periodic map [m] on an ``n x n`` grid of the same cell ``L`` [m], keeping only its
    Fourier modes with ``lo <= |q| <= hi`` [1/m] (``None``: no bound; the mean is removed).

    For a map whose modes all lie in the band and below both grids' Nyquist wavevector this
    is exact interpolation: the same continuous surface, sampled on the new grid.
    """
    m = h.shape[0]
    f = np.fft.fft2(np.asarray(h, dtype=float)) / m**2
    f = _embed(_embed(f, n, 0), n, 1)
    qq = wavenumbers(L, n)
    keep = qq > 0
    if lo is not None:
        keep &= qq >= lo * (1 - 1e-12)
    if hi is not None:
        keep &= qq <= hi * (1 + 1e-12)
    return np.fft.ifft2(np.where(keep, f, 0)).real * n * n
