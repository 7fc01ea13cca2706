"""The figure's suptitle, from the archive's own metadata: its title, the swept parameters with
the values the archive holds, and the ``--set`` overrides its history records (so a title
written for the scene file does not go stale after ``xpersson run ... --set``)."""

from __future__ import annotations

import json
import re
import shlex
import textwrap

import numpy as np
import xarray as xr

from ._units import text

__all__ = ["suptitle"]

_SHOWN = 4  # more swept values than this: the range and the count instead of every value


def _values(ds: xr.Dataset, dim: str) -> str:
    """The values of swept dimension ``dim`` in human units (a range for many)."""
    units = ds[dim].attrs.get("units", "1")
    vals = np.asarray(ds[dim].values).ravel()
    if vals.dtype.kind not in "fiu":
        return ", ".join(str(v) for v in vals[:_SHOWN]) + ("..." if vals.size > _SHOWN else "")
    if vals.size <= _SHOWN:
        return ", ".join(text(float(v), units) for v in vals)
    return (
        f"{vals.size} values, {text(float(vals.min()), units)} to {text(float(vals.max()), units)}"
    )


def sweep_line(ds: xr.Dataset) -> str:
    """``sweep: H = 0.6, 0.7, 0.8; E = 5 MPa, 10 MPa`` from ``xpersson_sweep`` ("" if none)."""
    try:
        dims = json.loads(ds.attrs.get("xpersson_sweep", "{}")).get("dims", [])
    except (TypeError, ValueError):
        return ""
    dims = [d for d in dims if d in ds.coords]
    return ("sweep: " + "; ".join(f"{d} = {_values(ds, d)}" for d in dims)) if dims else ""


def overrides(ds: xr.Dataset) -> list[str]:
    """The ``--set KEY=VALUE`` overrides of the command recorded in the archive's history."""
    found = re.search(r"\((xpersson .*)\)\s*$", str(ds.attrs.get("history", "")))
    if not found:
        return []
    try:
        words = shlex.split(found.group(1))
    except ValueError:
        return []
    out = []
    for i, word in enumerate(words):
        if word == "--set" and i + 1 < len(words):
            out.append(words[i + 1])
        elif word.startswith("--set="):
            out.append(word[len("--set=") :])
    return out


def suptitle(ds: xr.Dataset, width: int = 70) -> str:
    """The archive's title (wrapped), then its sweep and ``--set`` overrides, one line each."""
    parts = [textwrap.fill(str(ds.attrs.get("title", "")), width)]
    parts.append(sweep_line(ds))
    sets = overrides(ds)
    if sets:
        parts.append("with --set " + ", ".join(sets))
    return "\n".join(p for p in parts if p)
