"""Measured topographies as spectra, and the archived form of file-based spectra.

``spectrum.model = "topography"`` reads maps and line scans in any format SurfaceTopography
reads (optional extra ``xpersson[topography]``; :mod:`.surface_maps`) and builds the table that
keeps their own rms height and slope (the ring estimator of :mod:`xpersson.physics.psd`).
File-based spectra (this one and ``tabulated``) record the file's SHA-256 and the PSD actually
used (the table, Persson convention, SI) in the resolved scene, so an archive re-solves
(``xpersson reproduce``) after the source file is moved or deleted.
"""

from __future__ import annotations

import dataclasses
import json
import warnings
from pathlib import Path
from typing import Any

import numpy as np

from ..cache import memoize
from ..errors import XperssonWarning
from ..physics.psd import PowerSpectrum
from ..physics.psd import Tabulated as _TabulatedPSD
from ..plugins import ParamSpec, Spectrum
from .surface_maps import (
    DETREND_MODES,
    MapKeys,
    measured_from_file,
    measured_from_object,
    sha256_of,
    table_of,
)

__all__ = [
    "Topography",
    "sha256_of",
    "TABLE_PARAMETERS",
    "ArchivedTable",
    "from_surface_topography",
    "is_surface_topography",
]

#: The table's h_rms and rms slope may differ from the map's by this much before a warning.
MAP_TOLERANCE = 0.01

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
        """Parameters that rebuild ``psd`` without the source file (the file's name and
        checksum kept as provenance: its name only, as the archive's
        ``xpersson_scene_source``, so that no machine-specific path goes into an archive)."""
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
        for key in ("file", "file2", "file3"):  # (the second and third scans of a map)
            if out.get(key) is not None:
                out[key] = Path(out[key]).name
        return out


_MAP_KEYS = {
    "physical_sizes": ParamSpec(
        "m",
        default=None,
        array=True,
        bounds=(0, None),
        inclusive=(False, True),
        description="physical size per axis when the file does not state it (a text matrix)",
    ),
    "unit": ParamSpec(
        "1",
        default=None,
        kind="string",
        description="height/length unit when the file does not state it (e.g. um)",
    ),
    "height_scale": ParamSpec(
        "1",
        default=None,
        bounds=(0, None),
        inclusive=(False, True),
        description="factor on the heights when the file does not state it",
    ),
    "periodic": ParamSpec(
        "1", default=False, kind="bool", description="the map is periodic (the file may say so)"
    ),
    "detrend": ParamSpec(
        "1",
        default="center",
        kind="choice",
        choices=DETREND_MODES,
        description="SurfaceTopography detrend mode before the spectrum",
    ),
    "tip_radius": ParamSpec(
        "m",
        default=None,
        bounds=(0, None),
        inclusive=(False, True),
        description="probe tip radius: scales it cannot resolve are cut (short-wavelength limit)",
    ),
}

_RECORD = {
    "map_h_rms": ParamSpec(
        "m", default=None, description="the map's own rms height (recorded by xpersson)"
    ),
    "map_rms_slope": ParamSpec(
        "1", default=None, description="the map's own rms 2-D gradient (recorded by xpersson)"
    ),
    "parts": ParamSpec(
        "1",
        default=None,
        kind="string",
        description="JSON: each scan's file, SHA-256, grid, sizes, band (recorded by xpersson)",
    ),
}


class Topography(ArchivedTable, Spectrum):
    """Isotropic PSD of measured maps or line scans [m^4, Persson convention].

    The table keeps the map's own mean-square height and gradient (the ring estimator of
    :mod:`xpersson.physics.psd`); several files of one surface (``file``, ``file_2``,
    ``file_3``) are combined into one table. ``q_L``/``q_1`` and ``tip_radius`` truncate; the
    roughness they drop is recorded and warned about.
    """

    summary = "isotropic PSD of measured maps/line scans (SurfaceTopography), map roughness kept"
    references = ("10.1088/2051-672X/aa51f8", "10.1088/0953-8984/23/21/215004")
    parameters = {
        "file": ParamSpec(
            "1",
            kind="path",
            default=None,
            description="map or line scan in any format SurfaceTopography reads",
        ),
        "file_2": ParamSpec(
            "1", kind="path", default=None, description="a second scan of the same surface"
        ),
        "file_3": ParamSpec(
            "1", kind="path", default=None, description="a third scan of the same surface"
        ),
        "q_L": ParamSpec(
            **_WAVEVECTOR, default=None, description="truncate below (default: 2 pi / L)"
        ),
        "q_1": ParamSpec(
            **_WAVEVECTOR, default=None, description="truncate above (default: the last mode)"
        ),
        "points_per_decade": ParamSpec(
            "1",
            default=20,
            kind="int",
            bounds=(2, 1000),
            description="rings of the PSD per decade of q",
        ),
        **_MAP_KEYS,
        **TABLE_PARAMETERS,
        **_RECORD,
    }

    def build(self) -> PowerSpectrum:
        """Read the maps and build the table that keeps their roughness (or the inline one)."""
        p = self._params
        inline = self._inline()
        if inline is None:
            try:
                import SurfaceTopography  # noqa: F401
            except ImportError:
                raise ValueError(
                    "model 'topography' needs SurfaceTopography: pip install 'xpersson[topography]'"
                ) from None
            files = tuple(p[k] for k in ("file", "file_2", "file_3") if p.get(k))
            digests = tuple(sha256_of(f) if Path(f).is_file() else "" for f in files)
            ppd = int(p["points_per_decade"])
            keys = dataclasses.astuple(map_keys(p))
            q, C, record = _file_table(files, digests, keys, ppd)
            self._params.update(record_params(json.loads(record)))
            what = " and ".join(map(repr, files))
            inline = _truncated(q, C, p["q_L"], p["q_1"], what, int(p["points_per_decade"]))
        return attach_record(inline, self._params)


@memoize("topography.file_table", scope="process", maxsize=8)
def _file_table(
    files: tuple[str, ...], digests: tuple[str, ...], keys: tuple[Any, ...], ppd: int
) -> tuple[np.ndarray, np.ndarray, str]:
    """The table of the files (read once per content: ``digests`` are their SHA-256) and its
    record as JSON; the arrays are read-only (shared by the points of a sweep)."""
    del digests  # part of the key only
    parts = [measured_from_file(f, MapKeys(*keys)) for f in files]
    q, C, record = table_of(parts, ppd)
    q.setflags(write=False)
    C.setflags(write=False)
    return q, C, json.dumps(record)


def map_keys(p: dict[str, Any]) -> MapKeys:
    """The scene's map keys (SI) from a plugin's parameters."""
    sizes = p.get("physical_sizes")
    return MapKeys(
        physical_sizes=None if sizes is None else tuple(float(x) for x in np.ravel(sizes)),
        unit=p.get("unit"),
        height_scale=p.get("height_scale"),
        periodic=bool(p.get("periodic", False)),
        detrend=p.get("detrend") or "center",
        tip_radius=p.get("tip_radius"),
    )


def record_params(record: dict[str, Any]) -> dict[str, Any]:
    """The recorded parameters of a map's table (``map_h_rms``, ``map_rms_slope``, ``parts``)."""
    return {
        "map_h_rms": float(record["map_h_rms"]),
        "map_rms_slope": float(record["map_rms_slope"]),
        "parts": json.dumps(record["parts"], sort_keys=True),
    }


def _truncated(
    q: np.ndarray, C: np.ndarray, q_L: float | None, q_1: float | None, what: str, ppd: int
) -> _TabulatedPSD:
    """The table on ``[q_L, q_1]``: a ``q_1`` within the last ring (the table ends at the
    ring's equal-measure edge, a little below its last mode) is the table's end."""
    lo = float(q[0]) if q_L is None else q_L
    hi = float(q[-1]) if q_1 is None else q_1
    if not lo >= q[0] * (1 - 1e-6):
        raise ValueError(
            f"q_L: {lo:g} 1/m asks for wavelengths up to {2 * np.pi / lo:.4g} m, longer than "
            f"the scan {what} ({2 * np.pi / q[0]:.4g} m; q_L >= {q[0]:g} 1/m)"
        )
    if not hi <= q[-1] * 10 ** (1 / ppd) or not lo < hi:
        raise ValueError(
            f"q_1: need q_L < q_1 <= {q[-1]:g} 1/m (the end of the roughness of {what}); got "
            f"q_L = {lo:g}, q_1 = {hi:g} 1/m"
        )
    return _TabulatedPSD(q, C, "persson", q_L=max(lo, float(q[0])), q_1=min(hi, float(q[-1])))


def attach_record(psd: Any, p: dict[str, Any]) -> Any:
    """Give the table the map's record (for the Dataset) and warn when it misses the map's
    roughness by more than 1 %."""
    if p.get("map_h_rms") is None or p.get("map_rms_slope") is None:
        return psd
    h_map, s_map = float(p["map_h_rms"]), float(p["map_rms_slope"])
    h_tab, s_tab = float(psd.h_rms()), float(psd.rms_slope())
    record = {
        "map_h_rms": h_map,
        "map_rms_slope": s_map,
        "psd_dropped_height": 1.0 - (h_tab / h_map) ** 2,
        "psd_dropped_slope": 1.0 - (s_tab / s_map) ** 2,
    }
    object.__setattr__(psd, "map_record", record)
    off = [
        f"{name} {tab:.4g} of the map's {own:.4g} ({100 * (tab / own - 1):+.2f} %)"
        for name, tab, own in (("h_rms", h_tab, h_map), ("rms slope", s_tab, s_map))
        if abs(tab / own - 1) > MAP_TOLERANCE
    ]
    if off:
        warnings.warn(
            f"spectrum: the table keeps {' and '.join(off)}; q_L, q_1 or tip_radius drop the "
            f"rest (dropped: {100 * record['psd_dropped_height']:.2f} % of the mean-square "
            f"height, {100 * record['psd_dropped_slope']:.2f} % of the mean-square slope)",
            XperssonWarning,
            stacklevel=2,
        )
    return psd


def is_surface_topography(obj: Any) -> bool:
    """A SurfaceTopography topography (2-D map or line scan), by what it can do, or a
    non-empty list of them (scans of one surface)."""
    if isinstance(obj, list | tuple) and obj:
        return all(is_surface_topography(t) for t in obj)
    return callable(getattr(obj, "power_spectrum_from_area", None)) and hasattr(
        obj, "physical_sizes"
    )


def from_surface_topography(topo: Any, points_per_decade: int = 20, **extra: Any) -> dict:
    """The ``spectrum`` table of a scene for a SurfaceTopography object (or a list of them:
    scans of one surface, combined).

    The table is built as for a file (:func:`~xpersson.builtin.surface_maps.table_of`); the
    map keys in ``extra`` (``physical_sizes``, ``unit``, ``height_scale``, ``periodic``,
    ``detrend``, ``tip_radius``, scene values with units) apply as for a file; ``q_L``,
    ``q_1`` truncate. ``source``/``sha256`` (of the heights) and ``parts`` record the maps, so
    the result is reproducible from the archive alone and traceable to the maps.
    """
    keys, rest = _object_keys(extra)
    topos = list(topo) if isinstance(topo, list | tuple) else [topo]
    parts = [measured_from_object(t, keys) for t in topos]
    q, C, record = table_of(parts, int(points_per_decade))
    first = parts[0].provenance
    source = (
        f"SurfaceTopography {first['object']}: nb_grid_pts {tuple(first['nb_grid_pts'])}, "
        f"physical_sizes {tuple(first['physical_sizes_m'])} m, periodic {first['periodic']}, "
        f"detrend {first['detrend']!r}; {len(parts)} scan(s); ring PSD estimator, "
        f"{int(points_per_decade)} rings per decade"
    )
    return {
        "model": "topography",
        "q": [f"{float(x)!r} 1/m" for x in q],
        "C": [f"{float(x)!r} m**4" for x in C],
        "sha256": first["sha256"],
        "source": source,
        **{k: (f"{v!r} m" if k == "map_h_rms" else v) for k, v in record_params(record).items()},
        **rest,
    }


def _object_keys(extra: dict[str, Any]) -> tuple[MapKeys, dict[str, Any]]:
    """The map keys among a Python scene's ``spectrum`` entries (raw values: quantities as
    strings with units or SI numbers), and the rest."""
    from ..units import to_si

    def length(name: str, value: Any) -> float:
        return to_si(value, "m", f"spectrum.{name}") if isinstance(value, str) else float(value)

    rest = dict(extra)
    sizes = rest.pop("physical_sizes", None)
    scale = rest.pop("height_scale", None)
    tip = rest.pop("tip_radius", None)
    detrend = rest.pop("detrend", "center")
    if detrend not in DETREND_MODES:
        raise ValueError(f"detrend: {detrend!r} is not allowed; one of {', '.join(DETREND_MODES)}")
    keys = MapKeys(
        physical_sizes=None
        if sizes is None
        else tuple(length("physical_sizes", v) for v in np.ravel(np.asarray(sizes, dtype=object))),
        unit=rest.pop("unit", None),
        height_scale=None if scale is None else float(scale),
        periodic=bool(rest.pop("periodic", False)),
        detrend=detrend,
        tip_radius=None if tip is None else length("tip_radius", tip),
    )
    return keys, rest
