"""``xpersson info``: the summary of an archive (title, status, dimensions, the sweep and the
point shown, variables, plugins, the area fractions at the largest magnification)."""

from __future__ import annotations

import json
from collections.abc import Sequence
from typing import Any

__all__ = ["info", "SHOWN_LOADS"]


def info(ds: Any, archive: str, picks: Sequence[str]) -> None:
    """Print the summary of archive ``ds`` (read from ``archive``); ``picks`` (``DIM=INDEX``)
    choose the sweep point whose area fractions are listed."""
    print(f"{archive}: {ds.attrs.get('title', '')}")
    print(f"  source: {ds.attrs.get('source')}, created {ds.attrs.get('date_created')}")
    print(f"  status: {ds.attrs.get('status')} ({ds.attrs.get('status_message')})")
    print("  dimensions: " + ", ".join(f"{k}={v}" for k, v in ds.sizes.items()))
    swept = _swept(ds)
    if swept:
        print("  sweep: " + ", ".join(f"{d} ({ds.sizes[d]}: {_span(ds[d])})" for d in swept))
    for name, var in {**ds.coords, **ds.data_vars}.items():
        dims = ",".join(var.dims)
        print(
            f"  {name:28s} ({dims}) [{var.attrs.get('units', '?')}] "
            f"{var.attrs.get('long_name', '')}"
        )
    plugins = json.loads(ds.attrs.get("xpersson_plugins", "[]"))
    for p in plugins:
        print(f"  plugin {p['group']}/{p['name']}: {p.get('distribution')} {p.get('version')}")
    shown = _point(ds, swept, picks)
    _print_areas(shown)
    print("\n".join(model_error_lines(shown, SHOWN_LOADS)) or "  model error: none stored")
    if not swept:
        print("\n".join(model_error_reasons(ds)))


def _swept(ds: Any) -> list[str]:
    """The swept dimensions of a sweep's archive (from ``xpersson_sweep``; [] for one scene)."""
    try:
        dims = json.loads(ds.attrs.get("xpersson_sweep", "{}")).get("dims", [])
    except ValueError:
        return []
    return [d for d in dims if d in ds.dims]


def _span(coord: Any) -> str:
    """``0.6 .. 0.8 [1]``: the first and last value of a swept coordinate, with its units."""
    values = coord.values.ravel()
    units = coord.attrs.get("units", "")
    return f"{values[0]:.6g} .. {values[-1]:.6g}" + (f" [{units}]" if units else "")


def _point(ds: Any, swept: list[str], picks: Sequence[str]) -> Any:
    """The sweep point ``info`` prints (``--point DIM=INDEX``, index 0 of the others), said."""
    if not swept:
        return ds
    index = {d: 0 for d in swept}
    for pick in picks:
        dim, _, value = pick.partition("=")
        if dim not in index or not value.strip().lstrip("-").isdigit():
            raise ValueError(f"--point: {pick!r}: expected DIM=INDEX with DIM one of {swept}")
        if not -ds.sizes[dim] <= int(value) < ds.sizes[dim]:
            raise ValueError(f"--point: {dim} index {value} outside 0..{ds.sizes[dim] - 1}")
        index[dim] = int(value)
    sel = ds.isel(index)
    where = ", ".join(f"{d} = {float(sel[d]):.6g} (index {i})" for d, i in index.items())
    print(f"  sweep point shown below: {where}; another: --point DIM=INDEX")
    return sel


SHOWN_LOADS = 10
"""Loads listed by ``xpersson info`` (the rest are counted)."""


def _print_areas(ds: Any) -> None:
    """Every area fraction of the archive (core and boundary) at zeta_max, per load."""
    names = [
        n
        for n, v in ds.data_vars.items()
        if "zeta" in v.dims
        and v.attrs.get("units") == "1"
        and (n.endswith("area_fraction") or n in ("area_fraction", "total_contact_fraction"))
    ]
    if not names or "zeta" not in ds.dims:
        return
    loads = ds["p0"].values.ravel() if "p0" in ds.coords else []
    n_loads = len(loads)
    shown = min(n_loads, SHOWN_LOADS) if n_loads else 1
    print(
        f"  area fractions at zeta_max = {float(ds['zeta'].values[-1]):.6g}"
        + (
            f" (first {shown} of {n_loads} loads; {n_loads - shown} more not shown)"
            if n_loads > shown
            else ""
        )
    )
    if n_loads:
        print(f"    {'p0 [Pa]':28s} " + " ".join(f"{v:.6g}" for v in loads[:shown]))
    for name in names:
        # numpy indexing: xarray's isel would import dask.array (~0.1 s) for one column
        import numpy as np

        var = ds[name]
        values = np.take(var.values, -1, axis=var.dims.index("zeta")).ravel()[:shown]
        label = f"{name}"
        print(
            f"    {label:28s} "
            + " ".join(f"{v:.6g}" for v in values)
            + f"  ({ds[name].attrs.get('long_name', '')})"
        )


def model_error_lines(ds: Any, most: int = 10) -> list[str]:
    """Each output's model-error band per load (the first ``most``), or "not verified"."""
    import numpy as np

    lines = []
    for name in ds.data_vars:
        if name + "_model_error_status" not in ds.variables:
            continue
        lo, hi, ok = (
            np.ravel(ds.variables[name + s].values)[:most]
            for s in ("_exact_low", "_exact_high", "_model_error_status")
        )
        rows = zip(lo, hi, ok, strict=True)
        cells = [_status_cell(a, b, f) for a, b, f in rows]
        lines.append(f"    {name:28s} " + " ".join(cells))
    if lines:
        lines.insert(0, "  model error: interval where exact contact lies (validation campaign)")
    return lines


def _status_cell(low: float, high: float, flag: int) -> str:
    """``[low, high]`` (verified), ``[low, high] extrapolated`` or ``not verified``."""
    if not flag:
        return "not verified"
    return f"[{low:.3g}, {high:.3g}]" + (" extrapolated" if flag == 2 else "")


def model_error_reasons(ds: Any) -> list[str]:
    """Why each output with a model error is verified, extrapolated or not (the scene's decades
    of roughness and H against the campaign's), from the archive's scene; [] if it cannot be
    resolved here (e.g. a plugin or a measured map missing)."""
    names = [n for n in ds.data_vars if n + "_model_error_status" in ds.variables]
    if not names or "xpersson_scene" not in ds.attrs:
        return []
    from .pipeline import as_scene, model_error

    try:
        rs = as_scene(json.loads(ds.attrs["xpersson_scene"])).resolve()
        reasons = model_error.explain(rs, names)
    except Exception:  # noqa: BLE001 - a summary line, never a failure of info
        return []
    return [f"    why {name}: {reasons[name]}" for name in names]
