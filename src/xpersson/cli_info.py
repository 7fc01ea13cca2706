"""``xpersson info``: the summary of an archive (title, status, dimensions, the sweep and the
point shown, variables, plugins, the area fractions at the largest magnification)."""

from __future__ import annotations

import json
import math
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


def model_error_reasons(ds: Any, table: dict[str, Any] | None = None) -> list[str]:
    """Why each output with a model error is verified, extrapolated or not (the scene's decades
    of roughness ``log10(q_1/q_r)`` and ``H`` against the campaign's), read from the archive's
    scene and the packaged table without resolving the scene (no solver import); [] for a
    sweep or a spectrum without ``H``, ``q_1`` in 1/m."""
    names = [n for n in ds.data_vars if n + "_model_error_status" in ds.variables]
    try:
        scene = json.loads(ds.attrs["xpersson_scene"])
        feats = _spectrum_numbers(scene.get("spectrum", {}))
    except (KeyError, ValueError, TypeError):
        return []
    if not names or feats is None:
        return []
    import numpy as np

    if table is None:
        from importlib import resources

        text = resources.files("xpersson").joinpath("data", "model_error.json").read_text("utf-8")
        table = json.loads(text)
    fixed = {
        "boundary": scene.get("boundary", {}).get("model"),
        "closure": scene.get("coefficient", {}).get("closure"),
    }
    out = []
    for name in names:
        entries = [
            e
            for e in table["bands"]
            if e["variable"] == name
            and all(e.get("match", {}).get(k, v) == v for k, v in fixed.items())
        ]
        flags = {int(f) for f in np.ravel(ds.variables[name + "_model_error_status"].values)}
        out.append(f"    why {name}: " + reason(feats, entries, flags))
    return out


def _spectrum_numbers(spectrum: dict[str, Any]) -> dict[str, float] | None:
    """``hurst`` and ``decades`` of a stored self-affine spectrum (``"<value> 1/m"`` strings)."""

    def per_m(key: str) -> float | None:
        value = spectrum.get(key)
        if not isinstance(value, str) or not value.strip().endswith(" 1/m"):
            return None
        return float(value.split()[0])

    q_l, q_1 = per_m("q_L"), per_m("q_1")
    q_r = per_m("q_r") or q_l
    hurst = spectrum.get("H")
    if not isinstance(hurst, (int, float)) or None in (q_l, q_1, q_r):
        return None
    return {"hurst": float(hurst), "decades": math.log10(q_1 / q_r)}


def reason(feats: dict[str, Any], entries: list[dict[str, Any]], flags: set[int]) -> str:
    """One line: the scene's decades and ``H`` against the ``entries`` of its output (those of
    its boundary and closure), consistent with the output's status ``flags`` per load."""
    if not entries:
        return "not verified: the campaign did not test this boundary or closure"
    d, hurst = feats["decades"], feats["hurst"]
    cells = [e["ranges"]["decades"] for e in entries if e.get("status", 1) == 1]
    lo, hi = min(c[0] for c in cells), max(c[1] for c in cells)
    ext = max((e["ranges"]["decades"][1] for e in entries if e.get("status") == 2), default=hi)
    h_lo, h_hi = entries[0]["ranges"].get("hurst", (-math.inf, math.inf))
    text = f"{d:.2f} decades of roughness log10(q_1/q_r), H = {hurst:.3g}; campaign cells "
    text += f"{lo:.2f}-{hi:.2f} decades" + (f", extrapolated to {ext:.2f}" if ext > hi else "")
    if 2 in flags:
        return text + ": extrapolated (band along the measured trend, widened)"
    if 1 in flags:
        return text + ": verified where the load's regime has a band"
    if not h_lo <= hurst < h_hi:
        return text + f": not verified (H outside {h_lo:.3g}-{h_hi:.3g})"
    if d < lo:
        return text + ": not verified (fewer decades than the campaign's cells)"
    if d >= ext:
        limit = "the extrapolation limit" if ext > hi else "no extrapolation passed for it"
        return text + f": not verified (beyond the cells; {limit})"
    return text + ": not verified (the loads' regime or the options lie outside the campaign's)"
