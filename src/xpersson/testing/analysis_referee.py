"""The analysis-side referee: :func:`check_analysis`, the sibling of :func:`check_plugin`.

An analysis computes downstream quantities from a solved contact. Fuzzing finds NaN and crashes;
it cannot find a finite, plausible, wrong number. :func:`check_analysis` therefore referees an
analysis class the way the boundary referee does a wall: besides the plugin contract it checks
what an analysis must satisfy whatever its physics --

* **per-load independence**: every output with a ``p0`` dimension is the same whether a load is
  solved alone or with others (an analysis that mixes loads -- shared grids, interpolation across
  the batch -- gives answers that depend on the load list);
* **solver-path independence**: the outputs agree when the same scene is solved by another
  engine path (``cn`` finite differences by default, or the ``markov`` walkers), within
  ``path_rtol`` -- an analysis must not amplify the solver's discretisation;
* **regime edges**: a solve at loads spanning the regime (``edge_loads``, e.g. down to
  ``A/A0 ~ 1e-6`` and up to full contact) returns every load; NaN only in variables that declare
  a ``nan_meaning``, never ``inf``;
* **reference**: with ``reference`` (a function of the solved Dataset computed another way:
  adaptive quadrature, mpmath, a closed form, a published table) every output it returns agrees
  within ``rtol``/``atol``; the worst relative error per output is reported.
"""

from __future__ import annotations

import copy
import warnings
from collections.abc import Callable, Mapping, Sequence
from typing import Any

from ._names import CHECK_NAME, qual
from .contracts import check_plugin
from .registry import registry_with
from .scenes import sample_params, tiny_scene

__all__ = ["check_analysis"]


def check_analysis(
    cls: type,
    params: Mapping[str, Any] | None = None,
    *,
    scene: Mapping[str, Any] | None = None,
    reference: Callable[[Any], Mapping[str, Any]] | None = None,
    rtol: float = 1e-3,
    atol: float = 0.0,
    paths: Sequence[str] = ("cn",),
    path_rtol: float = 1e-2,
    load_rtol: float = 1e-6,
    edge_loads: Sequence[str] | None = None,
    contract: bool = True,
) -> dict[str, Any]:
    """Referee an analysis plugin class (see the module docstring for what is checked).

    Parameters
    ----------
    cls : type
        An :class:`~xpersson.plugins.Analysis` subclass.
    params : Mapping, optional
        SI parameter values (default: declared defaults and ``example`` values).
    scene : Mapping, optional
        Replacements of :data:`~xpersson.testing.TINY_SCENE` sections (merged key by key).
    reference : callable, optional
        ``reference(ds) -> {output name: array}``, computed independently from the solved
        Dataset ``ds`` (broadcastable to the output's shape).
    rtol, atol : float
        Tolerance of the reference comparison (relative [1], absolute [output units]).
    paths : sequence of str
        Further engine methods (``solver.method``) the outputs must agree with.
    path_rtol : float
        Relative tolerance between solver paths [1] (plus ``atol``).
    load_rtol : float
        Relative tolerance of a load solved alone against the same load in a batch [1]
        (iterative roots inside an analysis differ at their own tolerance).
    edge_loads : sequence of str, optional
        Loads (quantity strings) of the regime-edge solve; default a decade below the tiny
        scene's loads up to 30 E* (past full contact).
    contract : bool
        Run :func:`check_plugin` first (metadata, pickle, end-to-end determinism).

    Returns
    -------
    dict
        What was checked, with the worst deviations found
        (``{"contract": ..., "loads": ..., "paths": ..., "edges": ..., "reference": ...}``).

    Raises
    ------
    AssertionError
        A violation, naming the class, the output, the load and the size of the deviation.
    """
    import numpy as np

    who = qual(cls)
    if getattr(cls, "group", None) != "analyses":
        raise AssertionError(f"{who}: check_analysis referees analysis plugins (group analyses)")
    report: dict[str, Any] = {}
    if contract:
        report["contract"] = check_plugin(cls, params, scene=scene, markov=0)
    sc = tiny_scene(cls, sample_params(cls, params), scene)
    names = [n for n in cls.outputs]
    base = _solve(cls, sc)

    report["loads"] = _per_load(cls, sc, base, names, load_rtol, who)

    worst, where = 0.0, ""
    for method in paths:
        other = _solve(cls, _with(sc, solver={"method": method}))
        for n in names:
            err = _compare(base[n], other[n], path_rtol, atol, f"{who}: {n!r} with solver {method}")
            if err >= worst:
                worst, where = err, f"{n} ({method})"
    report["paths"] = f"ok (worst {worst:.1e} relative, {where})" if paths else "skipped"

    report["edges"] = _edges(cls, sc, edge_loads, names, who)

    if reference is not None:
        ref = reference(base)
        worst_by = {}
        for n, want in ref.items():
            assert n in base, f"{who}: reference names {n!r}, which the analysis does not output"
            worst_by[n] = _compare(base[n], np.broadcast_to(want, base[n].shape), rtol, atol,
                                   f"{who}: {n!r} against the reference")  # fmt: skip
        report["reference"] = {n: f"ok (worst relative {e:.2e})" for n, e in worst_by.items()}
    return report


def _per_load(
    cls: type, sc: Mapping[str, Any], base: Any, names: list[str], rtol: float, who: str
) -> str:
    """Each load solved alone equals the same load in the batch (within ``rtol``)."""
    import numpy as np

    loads = list(sc["load"]["p0"]) if isinstance(sc["load"]["p0"], list) else [sc["load"]["p0"]]
    worst, shared = 0.0, set()
    for i, p in enumerate(loads):
        alone = _solve(cls, _with(sc, load={"p0": [p]}))
        for n in names:
            if "p0" not in base[n].dims:
                continue
            a, b = base[n].isel(p0=i), alone[n].isel(p0=0)
            if any(not np.array_equal(a[d].values, b[d].values) for d in a.dims if d in a.coords):
                shared.add(n)  # a coordinate sized to the batch (e.g. a gap grid): not comparable
                continue
            err = _compare(a, b, rtol, 0.0, f"{who}: {n!r} at p0 = {p} alone vs in a batch")
            worst = max(worst, err)
    note = f"; coordinates depend on the batch: {sorted(shared)}" if shared else ""
    return f"ok (per-load independent within {worst:.1e}{note})"


def _with(sc: Mapping[str, Any], **sections: Mapping[str, Any]) -> dict[str, Any]:
    out = copy.deepcopy(dict(sc))
    for k, v in sections.items():
        out[k] = {**out.get(k, {}), **v}
    return out


def _solve(cls: type, sc: Mapping[str, Any]) -> Any:
    from .. import solve

    with registry_with(analyses={CHECK_NAME: cls}), warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return solve(copy.deepcopy(dict(sc)))


def _compare(got: Any, want: Any, rtol: float, atol: float, what: str) -> float:
    """Largest relative deviation (NaN must match NaN); raises beyond ``rtol``/``atol``."""
    import numpy as np

    a = np.asarray(getattr(got, "values", got), dtype=float)
    b = np.asarray(getattr(want, "values", want), dtype=float)
    assert a.shape == b.shape, f"{what}: shape {a.shape} vs {b.shape}"
    nan_a, nan_b = np.isnan(a), np.isnan(b)
    assert np.array_equal(nan_a, nan_b), f"{what}: NaN at different places"
    a, b = a[~nan_a], b[~nan_b]
    if a.size == 0:
        return 0.0
    dev = np.abs(a - b)
    bad = dev > atol + rtol * np.abs(b)
    assert not bad.any(), (
        f"{what}: {a[bad][0]:.6g} vs {b[bad][0]:.6g} (|diff| {dev[bad][0]:.3g} > "
        f"atol {atol:g} + rtol {rtol:g} |ref|)"
    )
    scale = np.maximum(np.abs(b), np.finfo(float).tiny)
    return float(np.max(np.where(dev > atol, dev / scale, 0.0)))


def _edges(
    cls: type, sc: Mapping[str, Any], loads: Sequence[str] | None, names: list[str], who: str
) -> str:
    """Every load of a regime-spanning solve comes back; NaN only where declared."""
    import numpy as np

    if loads is None:
        loads = ["1e2 Pa", "1e3 Pa", "1e6 Pa", "1e7 Pa", "1e8 Pa", "4e8 Pa"]
    try:
        ds = _solve(cls, _with(sc, load={"p0": list(loads)}))
    except Exception as exc:  # the pipeline's PluginFailure: one load lost them all
        raise AssertionError(
            f"{who}: the solve at loads {list(loads)} failed, so every load was lost: "
            f"{type(exc).__name__}: {exc}"
        ) from None
    nan_loads = 0
    for n in names:
        v = np.asarray(ds[n].values, dtype=float)
        assert not np.isinf(v).any(), f"{who}: {n!r} has inf at a regime edge"
        if np.isnan(v).any():
            assert cls.outputs[n].nan_meaning, f"{who}: {n!r} is NaN without a nan_meaning"
            nan_loads += int(np.isnan(v).any(axis=tuple(range(1, v.ndim))).sum()) if v.ndim else 1
    return f"ok ({len(loads)} loads from {loads[0]} to {loads[-1]}; {nan_loads} declared NaN)"
