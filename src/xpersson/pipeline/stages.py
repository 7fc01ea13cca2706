"""The checked plugin calls of a run before the engine: the plugins' own validation, the
coefficient's arrays and the walls of every load (each result checked, each failure naming its
plugin)."""

from __future__ import annotations

from typing import Any

import numpy as np

from .. import checks
from ..cache import Cache
from ..plugins import Analysis, Boundary, Coefficient, SceneContext, fast_paths_on
from ..scene import ResolvedScene, SceneError

__all__ = ["coefficient_arrays", "declares_shared_tau", "load_walls", "shared_tau", "validate"]


def validate(rs: ResolvedScene, ctx: SceneContext, boundary: Any, analyses: list[Any]) -> None:
    """Run the boundary's and the analyses' ``validate(ctx)`` before any solving.

    ``boundary`` and ``analyses`` are the plugin labels (one per entry of ``rs.analyses``);
    a ``ValueError`` becomes a :class:`SceneError` naming the section and the plugin.
    """
    if type(rs.boundary).validate is not Boundary.validate:  # the base class checks nothing
        try:
            with checks.calling(boundary, "validate()", passthrough=(ValueError,)):
                rs.boundary.validate(ctx)
        except ValueError as exc:
            raise SceneError(f"boundary: {exc} [{boundary}]") from None
    for (name, analysis), label in zip(rs.analyses, analyses, strict=True):
        if type(analysis).validate is Analysis.validate:
            continue
        try:
            with checks.calling(label, "validate()", passthrough=(ValueError,)):
                analysis.validate(ctx)
        except ValueError as exc:
            raise SceneError(f"analyses.{name}: {exc} [{label}]") from None


def load_walls(rs: ResolvedScene, ctx: SceneContext, clock: Any, who: Any) -> list[Any]:
    """The checked (lower, upper) walls of every load (asked once when the boundary declares
    walls that do not depend on the load, ``fast_paths.shared_walls``, outside
    :func:`~xpersson.plugins.plain_paths`)."""
    if not (type(rs.boundary).fast_paths.shared_walls and fast_paths_on()):
        walls = []
        for p0 in rs.p0:
            with checks.calling(who, f"walls() for p0 = {float(p0):g} Pa"):
                pair = rs.boundary.walls(ctx, float(p0), clock)
            walls.append(checks.check_walls(pair, float(p0), who))
        return walls
    return [_shared_walls(rs, ctx, clock, who)] * rs.p0.size


def _shared_walls(rs: ResolvedScene, ctx: SceneContext, clock: Any, who: Any) -> tuple:
    """The walls of a boundary whose walls do not depend on the load, checked for every load.

    Asked once (at the first load) and checked as :func:`xpersson.checks.check_walls` checks each
    load, with the positions at ``tau = 0`` compared with all loads at once; the first load
    left outside (if any) is reported exactly as the per-load check reports it.
    """
    p_first = float(rs.p0[0])
    with checks.calling(who, f"walls() for p0 = {p_first:g} Pa"):
        pair = rs.boundary.walls(ctx, p_first, clock)
    pair = checks.check_walls(pair, p_first, who)
    if rs.p0.size > 1:
        lower, upper = pair
        zero = np.zeros(1)
        inside = rs.p0 > float(np.asarray(lower.at(zero), float)[0])
        if upper is not None:
            inside &= rs.p0 < float(np.asarray(upper.at(zero), float)[0])
        outside = np.flatnonzero(~inside)
        if outside.size:  # raises the per-load check's message for that load
            checks.check_walls(pair, float(rs.p0[outside[0]]), who)
    return pair


def coefficient_arrays(
    coef: Any, ctx: SceneContext, who: Any, key: Any = None
) -> tuple[np.ndarray, np.ndarray, np.ndarray, bool]:
    """tau(zeta), f(zeta) and the per-load effective tau [Pa^2], each checked; and whether
    every load's effective tau is tau(zeta) (then returned as a read-only broadcast).

    ``key``: the run's clock key (:attr:`~xpersson.plugins.DiffusionClock.key`, a content key
    of ``coef.tau`` and ``coef.f``): the checked tau and f on this grid are then computed once
    for later solves (copies returned: they become the Dataset's data).
    """
    nz, nl = ctx.zeta.size, ctx.p0.size
    if key is None:
        tau_c, f_z = _tau_and_f(coef, ctx, who)
    else:
        kept = _TAU_F.get((key, ctx.zeta), lambda: _tau_and_f(coef, ctx, who))
        tau_c, f_z = kept[0].copy(), kept[1].copy()
    if shared_tau(coef):  # effective tau only broadcasts tau(zeta): nothing to ask
        return tau_c, f_z, _rows(tau_c, nl), True
    with checks.calling(who, "effective_tau(zeta)"):
        tau_eff = coef.effective_tau(ctx, ctx.zeta)
    shared = _equals_rows(tau_eff, tau_c, (nl, nz))
    if shared:  # every row is the checked tau(zeta): the same checks hold, nothing to repeat
        tau_eff = _rows(tau_c, nl)
    else:
        tau_eff = checks.check_array(
            tau_eff,
            who,
            "effective_tau(zeta)",
            (nl, nz),
            nonnegative=True,
            nondecreasing_axis=1,
            unit="Pa2",
        )
    return tau_c, f_z, tau_eff, shared


def _rows(row: np.ndarray, n: int) -> np.ndarray:
    """``np.broadcast_to(row, (n, row.size))``: ``n`` read-only rows of ``row`` without a copy
    (one load: a view, without broadcast_to's ~2.5 us)."""
    if n != 1:
        return np.broadcast_to(row, (n, row.size))
    view = row[None, :]
    view.flags.writeable = False
    return view


_TAU_F = Cache(
    "pipeline.tau_f",
    scope="spectrum",
    maxsize=64,
    doc="a coefficient's checked tau(zeta) and f(zeta) [Pa^2] by its clock key and the grid",
)


def _tau_and_f(coef: Any, ctx: SceneContext, who: Any) -> tuple[np.ndarray, np.ndarray]:
    """The coefficient's tau(zeta) and f(zeta) [Pa^2] on the output grid, checked."""
    nz = ctx.zeta.size
    with checks.calling(who, "tau(zeta)"):
        tau_c = coef.tau(ctx, ctx.zeta)
    tau_c = checks.check_array(
        tau_c, who, "tau(zeta)", (nz,), nonnegative=True, nondecreasing_axis=0, unit="Pa2"
    )
    with checks.calling(who, "f(zeta)"):
        f_z = coef.f(ctx, ctx.zeta)
    f_z = checks.check_array(f_z, who, "f(zeta)", (nz,), nonnegative=True, unit="Pa2")
    return tau_c, f_z


def shared_tau(coef: Any) -> bool:
    """Whether ``coef``'s effective tau is tau(zeta) for every load, taken from its declaration
    (:func:`declares_shared_tau`); ``False`` inside :func:`~xpersson.plugins.plain_paths`
    (then every load is asked)."""
    return fast_paths_on() and declares_shared_tau(coef)


def declares_shared_tau(coef: Any) -> bool:
    """Whether ``coef``'s class inherits :meth:`Coefficient.effective_tau` (which broadcasts
    tau(zeta)) or declares it shared (``fast_paths.shared_tau``, for this instance's
    parameters). The Dataset has ``effective_diffusion_time`` exactly where this is False,
    also where its values happen to equal tau(zeta): a scene's variables follow from its
    plugins and parameters, never from its values, so the points of a sweep, the parts of a
    sweep folder and the sweep's fast and plain paths hold the same variables."""
    cls = type(coef)
    if cls.effective_tau is Coefficient.effective_tau:
        return True
    return bool(cls.fast_paths.tau_shared(coef.params))


def _equals_rows(value: Any, row: np.ndarray, shape: tuple[int, int]) -> bool:
    """Whether ``value`` is a ``shape`` float array whose every row equals ``row`` exactly."""
    if not isinstance(value, np.ndarray) or value.shape != shape or value.dtype != float:
        return False
    return bool(np.array_equal(value, np.broadcast_to(row, shape)))
