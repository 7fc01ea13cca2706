"""Diagnostics the pipeline adds to every Dataset: resolution of the stored P, theory regime.

* ``P_integral(p0, zeta)``: ``int P dp`` over the stored pressure grid (trapezoidal rule) and
  ``P_resolved(p0, zeta)``: 1 where it equals ``area_fraction`` within
  :data:`P_RTOL`, 0 where the grid does not resolve the distribution (a narrow peak at small
  magnification, or mass beyond the grid's ends). The contact area itself never comes from P.
* regime warnings: the scene lies outside the range where Persson's small-slope, linear-elastic
  theory holds (rms slope far above 1, nominal pressure above the contact modulus).
* ``theory_validity(p0)``: the same per load, as a CF bit field (0: inside the theory's
  regime), from what is already solved (``p0``, ``E_star``, ``rms_slope``, the contact and
  non-contact fractions at the finest magnification): nothing is recomputed.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..plugins import VarSpec
from ._insert import insert_or_set, new_variable, values_of

__all__ = [
    "P_RTOL",
    "SLOPE_LIMIT",
    "DIAGNOSTICS",
    "VALIDITY_FLAGS",
    "pdf_resolution",
    "regime_warnings",
    "theory_validity",
    "validity_flags",
]

P_RTOL = 1e-3
"""Relative agreement of int P dp with A/A0 that counts as resolved."""
SLOPE_LIMIT = 3.0
"""rms slope above which the small-slope theory is reported as left [1]."""

#: bit -> (CF flag meaning, description) of ``theory_validity``
VALIDITY_FLAGS: dict[int, tuple[str, str]] = {
    1: ("p0_above_contact_modulus", "p0 > E*: strains of order 1, outside linear elasticity"),
    2: (
        "rms_slope_above_small_slope_limit",
        f"rms slope > {SLOPE_LIMIT:g}: outside the small-slope theory",
    ),
    4: (
        "full_contact_beyond_float64",
        "1 - A/A0 at zeta_1 below 2^-53: A/A0 rounds to 1 in float64 (read the open area from"
        " non_contact_fraction); gaps there are far below atomic scales",
    ),
    8: (
        "contact_area_underflow",
        "A/A0 at zeta_1 below the smallest normal float64 (2.2e-308): the area is 0 in float64",
    ),
}

DIAGNOSTICS: dict[str, VarSpec] = {
    "P_integral": VarSpec(
        ("p0", "zeta"),
        "1",
        "integral of P over the stored pressure grid",
        description="trapezoidal int P dp; equals area_fraction where P_resolved is 1",
    ),
    "P_resolved": VarSpec(
        ("p0", "zeta"),
        "1",
        "whether the stored P resolves the distribution",
        description=f"1 where |int P dp - A/A0| <= {P_RTOL:g} A/A0 on the stored grid",
        extra={"flag_meanings": "unresolved resolved"},
        valid_min=0,
        valid_max=1,
    ),
    "theory_validity": VarSpec(
        ("p0",),
        "1",
        "where the load lies outside the theory's regime (bit field, 0: inside)",
        description="; ".join(f"{b}: {d}" for b, (_, d) in VALIDITY_FLAGS.items()),
        extra={"flag_meanings": " ".join(m for m, _ in VALIDITY_FLAGS.values())},
        valid_min=0,
        valid_max=sum(VALIDITY_FLAGS),
    ),
}


def pdf_resolution(ds: Any) -> str | None:
    """Add ``P_integral`` and ``P_resolved`` to ``ds`` (when it holds P); return a message
    naming the unresolved zeta points, or ``None`` when every point is resolved."""
    if "P" not in ds or "p" not in ds.dims:
        return None
    var = ds.variables  # plain Variables: no DataArray (with its coordinates) per lookup
    P = var["P"]
    if P.dims != ("p0", "zeta", "p"):
        P = P.transpose("p0", "zeta", "p")
    p = np.asarray(values_of(var["p"]), float)
    integral = _trapezoid(np.asarray(P.values, float), p)
    area = var["area_fraction"]
    if area.dims != ("p0", "zeta"):
        area = area.transpose("p0", "zeta")
    area = np.asarray(area.values, float)
    ok = np.abs(integral - area) <= P_RTOL * np.maximum(area, 1e-300)
    attrs = {name: spec.attrs() for name, spec in DIAGNOSTICS.items() if name.startswith("P_")}
    flags = attrs["P_resolved"]
    flags["flag_values"] = np.array([0, 1], np.int8)
    # CF 2.5: the valid range has the variable's own type
    flags["valid_min"], flags["valid_max"] = np.int8(0), np.int8(1)
    insert_or_set(
        ds,
        {
            "P_integral": new_variable(("p0", "zeta"), integral, attrs["P_integral"]),
            "P_resolved": new_variable(("p0", "zeta"), ok.astype(np.int8), flags),
        },
    )
    zeta = np.asarray(values_of(var["zeta"]), float)
    # at zeta = 1 (tau = 0) P is the initial delta: flagged, but no reason to warn
    ok_or_delta = ok | (np.asarray(var["diffusion_time"].values, float) == 0)[None, :]
    if ok_or_delta.all():
        return None
    bad_z = zeta[~ok_or_delta.all(axis=0)]
    return (
        f"P is not resolved by the stored pressure grid at {int((~ok_or_delta).sum())} of "
        f"{ok.size} "
        f"(p0, zeta) points (zeta {bad_z.min():.4g} .. {bad_z.max():.4g}; see P_resolved, "
        "P_integral): a finer grid (output.p_points, output.p) or a narrower zeta range "
        "resolves them"
    )


def _trapezoid(y: np.ndarray, x: np.ndarray) -> np.ndarray:
    """``np.trapezoid(y, x, axis=-1)`` (bitwise: the same operations, each row reduced alone),
    in blocks of rows whose temporaries stay in cache: the whole-array temporaries of a
    ``(p0, zeta, p)`` P were fresh memory pages at every call (1.8 ms for 2e5 values)."""
    n = y.shape[-1]
    if n < 2 or y.ndim < 1:
        return np.trapezoid(y, x, axis=-1)
    rows = y.reshape(-1, n)
    d = np.diff(x)
    out = np.empty(rows.shape[0])
    block = max(1, 32768 // n)
    buf = np.empty((min(block, rows.shape[0]), n - 1))
    for start in range(0, rows.shape[0], block):
        r = rows[start : start + block]
        b = buf[: r.shape[0]]
        np.add(r[:, 1:], r[:, :-1], out=b)
        np.multiply(d, b, out=b)
        np.divide(b, 2.0, out=b)
        np.add.reduce(b, axis=-1, out=out[start : start + r.shape[0]])
    return out.reshape(y.shape[:-1])


def regime_warnings(ds: Any) -> list[str]:
    """Where the scene leaves the regime of the theory (each a one-line message)."""
    out = []
    var = ds.variables  # plain Variables: no DataArray (with its coordinates) per lookup
    slope = float(var["rms_slope"].values)
    if slope > SLOPE_LIMIT:
        out.append(
            f"rms slope {slope:.3g} is far above 1: Persson's theory assumes small slopes "
            f"(warned above {SLOPE_LIMIT:g})"
        )
    e_star = float(var["E_star"].values)
    p0 = np.asarray(values_of(var["p0"]), float)
    high = p0[p0 > e_star]
    if high.size:
        out.append(
            f"{high.size} load(s) p0 up to {high.max():.4g} Pa exceed the contact modulus "
            f"E* = {e_star:.4g} Pa: strains of order 1 are outside linear elasticity"
        )
    return out


def validity_flags(
    p0: np.ndarray, e_star: float, rms_slope: Any, area: np.ndarray, non: np.ndarray
) -> np.ndarray:
    """The ``theory_validity`` bits (int8, shape of ``area``) of loads ``p0`` [Pa] with the
    contact modulus ``e_star`` [Pa], the rms slope [1] (a scalar, or one per leading row of
    ``area``) and the contact and non-contact fractions [1] at the finest magnification."""
    area = np.asarray(area, float)
    if area.size == 1 and np.size(p0) == 1 and np.ndim(rms_slope) == 0:
        # one load (a single solve): the same four comparisons on Python floats (IEEE, NaN
        # compares false as in numpy), one array made instead of a dozen one-value temporaries
        bits = (
            (float(np.asarray(p0, float).flat[0]) > e_star) * 1
            | (float(rms_slope) > SLOPE_LIMIT) * 2
            | (float(np.asarray(non, float).flat[0]) < 2.0**-53) * 4
            | (float(area.flat[0]) < _TINY) * 8
        )
        return np.full(area.shape, bits, np.int8)
    slope = np.asarray(rms_slope, float).reshape(np.shape(rms_slope) + (1,) * (area.ndim - 1))
    flags = np.zeros(area.shape, np.int8)
    # each bit: a boolean times its int8 value (int8, no int64 temporaries)
    flags |= (np.asarray(p0, float) > e_star) * np.int8(1)
    flags |= (slope > SLOPE_LIMIT) * np.int8(2)
    flags |= (np.asarray(non, float) < 2.0**-53) * np.int8(4)
    flags |= (area < _TINY) * np.int8(8)
    return flags


_TINY = float(np.finfo(float).tiny)  # the smallest normal float64 [1]


def theory_validity(ds: Any) -> None:
    """Add ``theory_validity(p0)`` to ``ds``: a CF bit field of :data:`VALIDITY_FLAGS`.

    Read from the Dataset only (``p0``, ``E_star``, ``rms_slope``, ``area_fraction`` and
    ``non_contact_fraction`` at the last magnification); 0 where the load is inside the regime.
    """
    var = ds.variables  # plain Variables: no DataArray (with its coordinates) per lookup
    p0 = np.atleast_1d(np.asarray(values_of(var["p0"]), float))
    area = _last_zeta(var["area_fraction"])
    non = _last_zeta(var["non_contact_fraction"]) if "non_contact_fraction" in var else 1.0 - area
    flags = validity_flags(
        p0, float(var["E_star"].values), float(var["rms_slope"].values), area, non
    )
    attrs = _validity_attrs()
    # a Variable on xarray's fast path: a (dims, data) tuple makes xarray probe for dask arrays,
    # which imports dask.array (~0.12 s) in a solve that has no use for it
    aligned = ds.sizes.get("p0") == flags.shape[0]  # (the loads' own dimension)
    insert_or_set(ds, {"theory_validity": new_variable(("p0",), flags, attrs)}, aligned)


def _last_zeta(var: Any) -> np.ndarray:
    """The values [1] of a ``(p0, zeta)`` Variable at the last magnification, one per load."""
    if var.dims != ("p0", "zeta"):
        var = var.transpose("p0", "zeta")
    return np.asarray(var.values)[:, -1]


def _validity_attrs() -> dict[str, Any]:
    """The CF attributes of ``theory_validity`` (a fresh dict; the arrays are fresh too)."""
    attrs = dict(_VALIDITY_ATTRS)
    attrs["flag_masks"], attrs["flag_values"] = _VALIDITY_BITS.copy(), _VALIDITY_BITS.copy()
    return attrs


_VALIDITY_BITS = np.array(list(VALIDITY_FLAGS), np.int8)
_VALIDITY_ATTRS = {
    **DIAGNOSTICS["theory_validity"].attrs(),
    "flag_masks": None,  # (the arrays: fresh copies of _VALIDITY_BITS, in this order)
    "flag_values": None,
    # CF 2.5: the valid range has the variable's own type (numpy scalars: immutable, shared)
    "valid_min": np.int8(0),
    "valid_max": np.int8(sum(VALIDITY_FLAGS)),
}
"""The static attributes of ``theory_validity`` (made once: :func:`_validity_attrs`)."""
