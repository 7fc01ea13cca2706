"""The CF encoding of archives: flags from strings, renamed variables (private)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from ._integrity import _ATTRS_DIGEST, DIGEST, FORMAT_ATTR

if TYPE_CHECKING:
    import xarray as xr

# -- CF encoding ----------------------------------------------------------------------------------
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
    import xarray as xr

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
    """Undo :func:`encode` and :func:`seal` (works on lazily opened Datasets too)."""
    import xarray as xr

    ds.attrs.pop(_ATTRS_DIGEST, None)
    ds.attrs.pop(FORMAT_ATTR, None)
    for name in list(ds.variables):
        ds.variables[name].attrs.pop(DIGEST, None)
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
            # fastpath: a plain object ndarray; the duck-array checks would import dask.array
            ds[name] = xr.Variable(var.dims, strings, attrs, fastpath=True)
        elif how.startswith("renamed_from:"):
            old = how.split(":", 1)[1]
            ds = ds.rename({name: old})
            del ds[old].attrs[_ENCODED]
    return ds
