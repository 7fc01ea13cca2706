"""CF encoding of archives: what is written differs from the in-memory Dataset only where
CF-1.11 requires it, and :func:`decode` undoes it, so an archive re-opens identical.

- Coordinate variables carry no ``_FillValue`` (CF §2.5.1).
- String status variables (``solver_status``) are stored as ``int8`` flags with numeric
  ``flag_values`` and ``flag_meanings`` (CF §3.5); decoded back to strings on reading.
- ``flag_values`` are stored with the variable's own type.
- The pressure PDF ``P`` is stored as ``pressure_pdf``: CF forbids variable names that differ
  only by case, and ``p`` is the pressure coordinate. The stored variable says so in its
  ``xpersson_name`` attribute; :func:`decode` restores ``P``.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import xarray as xr

__all__ = ["encode", "decode", "RENAMED"]

RENAMED = {"P": "pressure_pdf"}
_ENCODED = "xpersson_encoding"


def _flag_codes(var: xr.DataArray) -> tuple[list[str], np.ndarray]:
    meanings = str(var.attrs.get("flag_meanings", "")).split()
    values = np.asarray(var.values, dtype=object)
    extra = sorted({str(v) for v in values.ravel()} - set(meanings) - {""})
    meanings = meanings + extra + ["not_solved"]
    index = {m: i for i, m in enumerate(meanings)}
    index[""] = len(meanings) - 1
    codes = (
        np.vectorize(lambda v: index[str(v)], otypes=[np.int8])(values)
        if values.size
        else (np.zeros(values.shape, np.int8))
    )
    return meanings, codes


def encode(ds: xr.Dataset) -> tuple[xr.Dataset, dict[str, dict[str, Any]]]:
    """The Dataset as written (a shallow copy) and its netCDF ``encoding``."""
    out = ds.copy(deep=False)
    encoding: dict[str, dict[str, Any]] = {}
    for name in list(out.data_vars):
        var = out[name]
        if var.dtype.kind in "OUS" and "flag_meanings" in var.attrs:
            n_declared = len(str(var.attrs["flag_meanings"]).split())
            meanings, codes = _flag_codes(var)
            attrs = dict(var.attrs)
            attrs.update(
                {
                    "flag_values": np.arange(len(meanings), dtype=np.int8),
                    "flag_meanings": " ".join(meanings),
                    _ENCODED: f"flags_from_strings:{n_declared}",
                }
            )
            out[name] = xr.DataArray(codes, dims=var.dims, attrs=attrs)
        elif "flag_values" in var.attrs:
            kind = np.int8 if var.dtype.kind == "b" else var.dtype
            vals = var.attrs["flag_values"]
            if isinstance(vals, str):
                vals = vals.split()
            out[name].attrs["flag_values"] = np.asarray(vals, dtype=float).astype(kind)
    for old, new in RENAMED.items():
        if old in out.variables and new not in out.variables:
            out = out.rename({old: new})
            out[new].attrs[_ENCODED] = f"renamed_from:{old}"
    for name in out.coords:
        encoding[name] = {"_FillValue": None}
    for name in out.data_vars:
        if out[name].dtype.kind in "iub":
            encoding[name] = {"_FillValue": None}
    return out, encoding


def decode(ds: xr.Dataset) -> xr.Dataset:
    """Undo :func:`encode` (works on lazily opened Datasets too)."""
    for name in list(ds.variables):
        how = ds[name].attrs.get(_ENCODED)
        if how is None:
            continue
        if how.startswith("flags_from_strings:"):
            var = ds[name]
            n_declared = int(how.split(":", 1)[1])
            meanings = np.array(str(var.attrs["flag_meanings"]).split(), dtype=object)
            codes = np.asarray(var.values)
            strings = meanings[codes.ravel()].reshape(codes.shape)
            strings[codes == len(meanings) - 1] = ""
            attrs = {k: v for k, v in var.attrs.items() if k not in ("flag_values", _ENCODED)}
            attrs["flag_meanings"] = " ".join(meanings[:n_declared])
            ds[name] = xr.DataArray(strings, dims=var.dims, attrs=attrs)
        elif how.startswith("renamed_from:"):
            old = how.split(":", 1)[1]
            ds = ds.rename({name: old})
            del ds[old].attrs[_ENCODED]
    return ds
