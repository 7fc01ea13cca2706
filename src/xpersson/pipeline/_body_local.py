"""The analyses' local quantities integrated over a finite body's nominal pressure.

An analysis declares ``body_quantities`` (:class:`xpersson.plugins.BodyQuantity`): an output
of its own on the pressure grid ``p0`` that is a quantity per nominal area (or per square) at
the local nominal pressure, and how it combines over the body. Here, for every force, that
output is read at the nominal pressure of each cell of the body's solution (interpolated on
the grid the flat was solved at: no new solve) and combined (:func:`combine`). The error
estimate ``<name>_grid_error`` is the larger relative change of two coarsenings: the body on
half the cells, and the local value interpolated on every other pressure of the grid.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
import xarray as xr
from numpy.typing import NDArray

from .. import checks
from ..errors import XperssonWarning
from ..physics.body import BodySolution, kernel
from ..plugins import BodyQuantity
from ..specs import VarSpec

__all__ = ["combine", "interpolate", "local_outputs"]

FloatArray = NDArray[np.float64]
_QUALITY = {"coverage_content_type": "qualityInformation"}


def interpolate(p_grid: FloatArray, q_grid: FloatArray, p: FloatArray) -> FloatArray:
    """``q`` at pressures ``p`` [Pa] from its values on the increasing grid ``p_grid`` [Pa].

    Piecewise linear in ``(ln p, ln q)`` where both ends are positive and finite (linear in
    ``q`` where an end is 0, in ``1/q`` where an end is ``inf``: an unbounded conductance); below
    the grid the power law of the first interval (``q -> 0`` or ``inf`` at ``p = 0`` as its
    exponent is positive or negative; held where an end is 0 or ``inf``); above the grid the last
    value.
    """
    x, p = np.log(p_grid), np.asarray(p, float)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        s = np.log(p)
        lq = np.log(q_grid)
        j = np.clip(np.searchsorted(x, s) - 1, 0, x.size - 2)
        t = np.clip((s - x[j]) / (x[j + 1] - x[j]), 0.0, 1.0)
        pos = (q_grid[j] > 0) & (q_grid[j + 1] > 0)
        inner = np.where(
            pos,
            np.exp(lq[j] + t * (lq[j + 1] - lq[j])),
            q_grid[j] + t * (q_grid[j + 1] - q_grid[j]),
        )
        unbounded = np.isinf(q_grid[j]) | np.isinf(q_grid[j + 1])
        if unbounded.any():  # linear in the resistance 1/q (0 at an unbounded end)
            harmonic = 1.0 / ((1.0 - t) / q_grid[j] + t / q_grid[j + 1])
            inner = np.where(unbounded, harmonic, inner)
        ends = q_grid[:2]
        k = (lq[1] - lq[0]) / (x[1] - x[0]) if np.all((ends > 0) & np.isfinite(ends)) else 0.0
        below = q_grid[0] * np.power(p / p_grid[0], k)
    return np.where(p < p_grid[0], below, inner)


def combine(
    how: str, q: FloatArray, sols: Sequence[BodySolution], symmetry: str, *,
    bulk: float = 0.0, datum: float = 1.0,
) -> FloatArray:  # fmt: skip
    """The body's value of the local ``q`` (per cell, ``(n_force, n)``), one per solution.

    ``"area"``: ``sum q dA`` (rings [m^2]; a line contact per length [m]). ``"series"``: a line
    contact's ``1 / sum(dx / q)`` per length (NaN for an axisymmetric body). ``"constriction"``:
    the flux through the interface of conductance ``q`` per area in series with the bodies'
    spreading, ``b`` (``bulk``) times the half-space Green's function of the elastic solve, at a
    unit potential difference (a line contact: referred to the distance ``datum`` [m], as its
    approach).
    """
    cell = np.array([sol.cell for sol in sols])
    if how == "area":
        return np.sum(q * cell, axis=1)
    if how == "series":
        if symmetry != "plane":
            return np.full(len(sols), np.nan)
        with np.errstate(divide="ignore"):
            resistance = np.sum(np.where(np.isinf(q), 0.0, cell / q), axis=1)
            return 1.0 / resistance
    n = cell.shape[1]
    h = np.array([sol.edges[1] - sol.edges[0] for sol in sols])
    M = kernel(symmetry, n)[None, :, :] * h[:, None, None]
    if symmetry == "plane":
        M = M - (4.0 / math.pi) * (h * np.log(h / datum))[:, None, None]
    if bulk > 0:  # an interface 1e15 times the bulk's conductance is perfect: no overflow
        q = np.minimum(q, 1e15 / (bulk * h[:, None]))
    A = np.eye(n)[None, :, :] + bulk * q[:, :, None] * M
    j = np.linalg.solve(A, q[:, :, None])[:, :, 0]
    return np.sum(j * cell, axis=1)


def _evaluate(
    bq: BodyQuantity, q_grid: FloatArray, p_grid: FloatArray, sols: Sequence[BodySolution],
    symmetry: str, constants: Mapping[str, float],
) -> FloatArray:  # fmt: skip
    """``combine`` of the local value interpolated at the cells of ``sols``."""
    p = np.array([sol.p for sol in sols])
    return combine(bq.combine, interpolate(p_grid, q_grid, p), sols, symmetry, **constants)


def _relative(a: FloatArray, b: FloatArray) -> FloatArray:
    """``|a - b| / |b|``; 1 where ``b`` is 0 and ``a`` is not (the value vanishes on one grid
    alone, e.g. a seal sealing on it: an error as large as the other value, not inf); 0 where
    they are equal (also both 0 or inf)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        d = np.abs(a - b) / np.abs(b)
    d = np.where(b == 0, 1.0, d)
    return np.where(a == b, 0.0, d)


def local_outputs(
    rs: Any, ds: xr.Dataset, full: Sequence[BodySolution], half: Sequence[BodySolution],
    length: float,
) -> dict[str, xr.Variable]:  # fmt: skip
    """The declared local quantities of the scene's analyses over the body, per force.

    ``full``/``half``: the body's solutions on the result's grid and on half its cells;
    ``length``: the cylinder's length [m] (1 for an axisymmetric body). Each quantity ``X``
    gives ``X`` and ``X_grid_error`` [1] (dimension ``force``).
    """
    geo = rs.geometry
    out: dict[str, xr.Variable] = {}
    undefined = []  # series quantities of an axisymmetric body
    for name, analysis in rs.analyses:
        label = rs.labels[f"analyses.{name}"]
        for bname, bq in type(analysis).body_quantities.items():
            if {bname, f"{bname}_grid_error"} & (set(ds.variables) | set(out)):
                raise checks.PluginFailure(
                    f"{label}: body quantity {bname!r} is already a variable of the body's "
                    "Dataset (declared twice, or a core output's name)",
                    plugin=label,
                )
            with checks.calling(label, f"body_quantities[{bname!r}]"):
                values = np.asarray(ds[bq.local].values, float)
                if bq.unbounded is not None:  # NaN by full contact: no interface resistance
                    rigid = bq.unbounded_where(type(analysis).outputs, ds[bq.unbounded].values)
                    values = np.where(rigid & np.isnan(values), np.inf, values)
                q = bq.local_values(analysis.params, values, np.asarray(rs.p0, float))
                bulk = 0.0 if bq.bulk is None else float(bq.bulk(analysis.params))
            value, err = _integrated(bq, q, rs, (full, half), bulk)
            out[bname] = xr.Variable(("force",), value * length, bq.spec().attrs())
            out[f"{bname}_grid_error"] = xr.Variable(("force",), err, _error_spec(bname).attrs())
            if bq.combine == "series" and geo.symmetry != "plane":
                undefined.append(bname)
    if undefined:
        warnings.warn(
            f"{', '.join(undefined)}: a series across the contact (a seal) needs a line "
            f"contact (geometry cylinder); NaN for the {type(geo).__name__.lower()}",
            XperssonWarning,
            stacklevel=4,
        )
    return out


def _integrated(
    bq: BodyQuantity, q: FloatArray, rs: Any, grids: tuple[Sequence[BodySolution], ...],
    bulk: float,
) -> tuple[FloatArray, FloatArray]:  # fmt: skip
    """The body's value (per length of a line contact) and its error estimate [1]: the larger
    relative change on half the cells (``grids[1]``) and from every other grid pressure."""
    geo, p_grid = rs.geometry, np.asarray(rs.p0, float)
    consts = {"bulk": bulk, "datum": float(geo.params.get("radius", 1.0))}
    full, half = grids
    value = _evaluate(bq, q, p_grid, full, geo.symmetry, consts)
    err = _relative(_evaluate(bq, q, p_grid, half, geo.symmetry, consts), value)
    coarse = _evaluate(bq, q[::2], p_grid[::2], full, geo.symmetry, consts)
    return value, np.maximum(err, _relative(coarse, value))


def _error_spec(name: str) -> VarSpec:
    return VarSpec(
        ("force",), "1", f"estimated relative integration error of {name}",
        description="the larger relative change from half the body's cells and from every "
        "other pressure of the grid the local value is interpolated on; 1 where the value is 0 "
        "and a coarser one is not (e.g. a seal that seals on the finer grid only)",
        extra=_QUALITY, nan_meaning="the quantity is NaN",
    )  # fmt: skip
