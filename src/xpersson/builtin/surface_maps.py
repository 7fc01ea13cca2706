"""Measured maps and line scans as SurfaceTopography reads them, with what a format lacks
given in the scene, checked before any work, turned into the table that keeps their roughness.

The rule for metadata: **what the file (or object) states wins**; the scene fills in what it
lacks (``physical_sizes``, ``unit``, ``height_scale``, ``periodic``); a scene value that
contradicts the file's is refused, naming both. The same keys apply to a file and to a
SurfaceTopography object.
"""

from __future__ import annotations

import hashlib
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ..physics import psd as _psd
from ..units import to_si

__all__ = [
    "DETREND_MODES",
    "MapKeys",
    "Measured",
    "measured_from_file",
    "measured_from_object",
    "sha256_of",
    "table_of",
]

#: SurfaceTopography's detrend modes (``Topography.detrend``).
DETREND_MODES = ("center", "mean", "median", "height", "slope", "curvature")


@dataclass(frozen=True)
class MapKeys:
    """What the scene gives about a map (SI): each ``None`` when the scene does not say."""

    physical_sizes: tuple[float, ...] | None = None  # [m]
    unit: str | None = None
    height_scale: float | None = None  # [1]
    periodic: bool = False
    detrend: str = "center"
    tip_radius: float | None = None  # [m]


@dataclass
class Measured:
    """One map or line scan, in m, ready for its spectrum.

    Attributes
    ----------
    heights : ndarray
        Detrended heights [m], ``(nx, ny)`` or ``(n,)``.
    sizes : tuple of float
        Physical sizes [m].
    periodic : bool
        Whether the map is periodic (the exact ring estimator), else Hann-windowed.
    h2, s2 : float
        The map's own mean-square height [m^2] and mean-square 2-D gradient [1] (the spectral
        derivative for a periodic map; SurfaceTopography's ``rms_gradient`` (finite
        differences) otherwise; twice the profile's for a line scan).
    q_reliable : float or None
        The short-wavelength limit from the tip radius [1/m] (``2 pi / lambda_c``).
    provenance : dict
        ``file``, ``sha256``, ``nb_grid_pts``, ``physical_sizes_m``, ``pixel_size_m``, ...
    """

    heights: np.ndarray
    sizes: tuple[float, ...]
    periodic: bool
    h2: float
    s2: float
    what: str
    q_reliable: float | None = None
    provenance: dict[str, Any] = field(default_factory=dict)


def sha256_of(path: str | Path) -> str:
    """SHA-256 hex digest of a file."""
    digest = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def _factor(unit: str, what: str) -> float:
    return to_si(f"1 {unit}", "m", f"spectrum.unit of {what}")


def _contradiction(key: str, what: str, stated: Any, given: Any) -> ValueError:
    return ValueError(
        f"{key}: {what} states {stated!r}; the scene gives {given!r}. What the file (or "
        f"object) states wins: remove spectrum.{key} (or give the same value)"
    )


def _fill(channel: Any, keys: MapKeys, what: str) -> dict[str, Any]:
    """Keyword arguments for ``reader.topography``: the scene's values the file lacks."""
    kw: dict[str, Any] = {}
    unit = getattr(channel, "unit", None)
    if keys.unit is not None:
        if unit is None:
            kw["unit"] = keys.unit
        elif not math.isclose(_factor(unit, what), _factor(keys.unit, what), rel_tol=1e-9):
            raise _contradiction("unit", what, unit, keys.unit)
    sizes = getattr(channel, "physical_sizes", None)
    if sizes is not None and keys.physical_sizes is not None:
        factor = _factor(kw.get("unit") or unit or "m", what)
        own = tuple(float(x) * factor for x in sizes)
        if len(own) != len(keys.physical_sizes) or not np.allclose(
            own, keys.physical_sizes, rtol=1e-6
        ):
            raise _contradiction("physical_sizes", what, own, keys.physical_sizes)
    if sizes is None:
        if keys.physical_sizes is None:
            raise ValueError(
                f"physical_sizes: {what} does not state its physical size; give "
                'spectrum.physical_sizes (e.g. ["10 um", "10 um"], one value per axis)'
            )
        if len(keys.physical_sizes) != channel.dim:
            raise ValueError(
                f"physical_sizes: {what} has {channel.dim} axes; the scene gives "
                f"{len(keys.physical_sizes)} sizes"
            )
        factor = _factor(kw.get("unit") or unit or "m", what) if (kw.get("unit") or unit) else 1
        kw["physical_sizes"] = tuple(s / factor for s in keys.physical_sizes)
        if not (kw.get("unit") or unit):
            kw["unit"] = "m"  # sizes given in m, heights then in m too (unless unit says)
    if keys.height_scale is not None:
        fixed = getattr(channel, "height_scale_factor", None)
        if fixed is None:
            kw["height_scale_factor"] = keys.height_scale
        elif not math.isclose(float(fixed), keys.height_scale, rel_tol=1e-9):
            raise _contradiction("height_scale", what, fixed, keys.height_scale)
    if keys.periodic:
        kw["periodic"] = True
    return kw


def measured_from_file(path: str, keys: MapKeys) -> Measured:
    """Read a map or line scan in any format SurfaceTopography reads."""
    import SurfaceTopography as ST
    from SurfaceTopography.Exceptions import ReadFileError

    what = f"the file {path!r}"
    try:
        reader = ST.open_topography(path)
        channel = reader.channels[0]
        kw = _fill(channel, keys, what)
        topo = reader.topography(**kw)
    except (OSError, ReadFileError) as exc:
        raise ValueError(f"file: cannot read {path!r} ({type(exc).__name__}: {exc})") from None
    except ValueError as exc:
        if str(exc).split(":", 1)[0] in ("unit", "physical_sizes", "height_scale"):
            raise
        raise ValueError(f"file: {what}: {exc}") from None
    return _measured(topo, keys, what, {"file": str(path), "sha256": sha256_of(path)})


def measured_from_object(topo: Any, keys: MapKeys) -> Measured:
    """A SurfaceTopography object, the scene's keys applied as for a file."""
    what = f"the SurfaceTopography {type(topo).__name__}"
    unit = getattr(topo, "unit", None)
    if unit is None:
        if keys.unit is None:
            raise ValueError(f"unit: {what} has no unit; give spectrum.unit (e.g. 'um')")
        unit = keys.unit
    elif keys.unit is not None and not math.isclose(
        _factor(unit, what), _factor(keys.unit, what), rel_tol=1e-9
    ):
        raise _contradiction("unit", what, unit, keys.unit)
    if keys.physical_sizes is not None:
        own = tuple(float(s) * _factor(unit, what) for s in topo.physical_sizes)
        if not np.allclose(own, keys.physical_sizes, rtol=1e-6):
            raise _contradiction("physical_sizes", what, own, keys.physical_sizes)
    heights = np.ascontiguousarray(np.asarray(topo.heights(), dtype=float))
    digest = hashlib.sha256(heights.tobytes()).hexdigest()
    if keys.height_scale is not None:
        topo = topo.scale(keys.height_scale)
    return _measured(topo, keys, what, {"object": type(topo).__name__, "sha256": digest}, unit)


def _check_heights(topo: Any, what: str) -> np.ndarray:
    if not getattr(topo, "is_uniform", True):
        raise ValueError(
            f"file: {what} is a non-uniform line scan (unequal x spacing); resample it to a "
            "uniform grid (SurfaceTopography: .to_uniform(n, 0))"
        )
    raw = topo.heights()
    heights = np.ma.filled(np.ma.asarray(raw, dtype=float), np.nan)  # masked: undefined
    bad = int(np.count_nonzero(~np.isfinite(heights)))
    if bad:
        raise ValueError(
            f"file: {what} has {bad} undefined (NaN or infinite) heights of {heights.size}; "
            "fill or crop them before use (SurfaceTopography: .interpolate_undefined_data())"
        )
    if np.ptp(heights) == 0:
        raise ValueError(f"file: {what} has constant heights (no roughness)")
    return heights


def _measured(
    topo: Any, keys: MapKeys, what: str, prov: dict[str, Any], unit: str | None = None
) -> Measured:
    unit = unit or getattr(topo, "unit", None)
    if unit is None:
        raise ValueError(f"unit: {what} does not state its length unit; set spectrum.unit")
    _check_heights(topo, what)
    periodic = bool(getattr(topo, "is_periodic", False)) or keys.periodic
    detrended = topo.detrend(keys.detrend)
    heights = _check_heights(detrended, what)
    factor = _factor(unit, what)
    sizes = tuple(float(s) * factor for s in topo.physical_sizes)
    if detrended.dim == 1:  # twice the profile's (forward differences, as SurfaceTopography)
        dx = float(topo.physical_sizes[0]) / heights.size
        s2 = 2.0 * float(np.mean((np.diff(heights) / dx) ** 2))
    else:
        s2 = float(detrended.rms_gradient()) ** 2
    measured = Measured(
        heights * factor, sizes, periodic and keys.detrend in ("center", "mean", "median"),
        float(np.var(heights)) * factor**2, s2, what,
    )  # fmt: skip
    if keys.tip_radius is not None:
        cutoff = detrended.scanning_probe_reliability_cutoff(keys.tip_radius / factor)
        if cutoff is not None:
            measured.q_reliable = 2 * math.pi / (float(cutoff) * factor)
    n = tuple(int(x) for x in topo.nb_grid_pts)
    prov.update(
        nb_grid_pts=list(n),
        physical_sizes_m=list(sizes),
        pixel_size_m=[s / k for s, k in zip(sizes, n, strict=True)],
        unit=str(unit),
        periodic=measured.periodic,
        detrend=keys.detrend,
    )
    measured.provenance = prov
    return measured


def _rings(m: Measured, ppd: int) -> _psd.Rings:
    """The map's rings: exact for a periodic map, Hann-windowed otherwise (totals the map's)."""
    h = m.heights
    if not m.periodic:
        w = np.ones_like(h)
        for axis, n in enumerate(h.shape):
            shape = [1] * h.ndim
            shape[axis] = n
            w = w * np.hanning(n).reshape(shape)
        h = (h - h.mean()) * w / math.sqrt(float(np.mean(w**2)))
    if h.ndim == 1:
        r = _psd.profile_rings(h, m.sizes[0], ppd)
    else:
        r = _psd.map_rings(h, (m.sizes[0], m.sizes[1]), ppd)
    if m.periodic:
        m.s2 = r.s2  # a periodic map's own gradient: the spectral derivative
    return _psd.Rings(r.edges, r.var, r.modes, m.h2, m.s2, r.centre)


def table_of(parts: list[Measured], ppd: int) -> tuple[np.ndarray, np.ndarray, dict[str, Any]]:
    """The table (Persson, SI) of one or several scans of one surface, and its record.

    Returns
    -------
    q, C : ndarray
        Nodes [1/m] and values [m^4].
    record : dict
        ``map_h_rms`` [m], ``map_rms_slope`` [1] (of the one map; of the combination's table
        for several), ``parts`` (each scan's provenance and band).
    """
    tables = []
    finest = min(
        parts, key=lambda m: min(s / k for s, k in zip(m.sizes, m.heights.shape, strict=True))
    )
    for m in parts:
        rings = _rings(m, ppd)
        q, C = _psd.table_from_rings(rings, low_end=m.heights.ndim == 1)
        weight = np.concatenate(([rings.modes[0]], rings.modes, [rings.modes[-1]]))
        if m.q_reliable is not None and m.q_reliable < q[-1]:  # the tip's limit
            m.provenance["tip_limit_1_per_m"] = m.q_reliable
            if not m.q_reliable > q[0]:
                raise ValueError(
                    f"tip_radius: {m.what} is unreliable at every scale (the tip's limit "
                    f"2 pi / lambda_c = {m.q_reliable:.4g} 1/m is below the scan's {q[0]:.4g} 1/m)"
                )
            cut = _psd.Tabulated(q, C, q_1=m.q_reliable)
            weight = np.append(weight[: cut.q_table.size - 1], weight[cut.q_table.size - 1])
            q, C = cut.q_table, cut.C_table
        tables.append((q, C, np.maximum(weight, 1).astype(float)))
        nyquist = math.pi * min(k / s for s, k in zip(m.sizes, m.heights.shape, strict=True))
        if len(parts) > 1 and m is not finest and nyquist < q[-1]:
            # beyond its Nyquist wavevector a scan's rings are incomplete (the FFT grid's
            # corners): there the finer scans speak
            cut = _psd.Tabulated(q, C, q_1=nyquist)
            weight = np.append(weight[: cut.q_table.size - 1], weight[cut.q_table.size - 1])
            q, C = cut.q_table, cut.C_table
        m.provenance["band_1_per_m"] = [float(q[0]), float(q[-1])]
    if len(parts) == 1:
        q, C = tables[0][0], tables[0][1]
        h2, s2 = parts[0].h2, parts[0].s2
    else:
        q, C = _psd.combine_tables(tables, ppd)
        table = _psd.Tabulated(q, C)
        h2, s2 = table.h_rms() ** 2, table.rms_slope() ** 2
    record = {
        "map_h_rms": math.sqrt(h2),
        "map_rms_slope": math.sqrt(s2),
        "parts": [m.provenance for m in parts],
    }
    return q, C, record
