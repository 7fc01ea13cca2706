"""The pressure process as a referee: a boundary's engine solution against ``markov`` walkers.

Used by :func:`xpersson.testing.check_plugin` for boundary plugins.  The walls a boundary
supplies on the tiny test scene are solved twice, by the engine's own path (the scene's
``solver.method``, ``"auto"`` by default) and by Monte Carlo walkers of the Markov process the
diffusion equation describes (``method="markov"``), and the area fraction and the probability
absorbed at each wall must agree within ``n_se`` standard errors at every magnification and
load.  Nothing here is specific to a boundary: any wall the engine accepts (fixed, moving,
yield closure) is checked the same way.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Mapping
from typing import Any

from ._names import CHECK_NAME, qual
from .registry import registry_with
from .scenes import sample_params, tiny_scene

__all__ = ["markov_cross_check"]

_QUANTITIES = ("area", "absorbed_lower", "absorbed_upper")


def markov_cross_check(
    cls: type,
    params: Mapping[str, Any] | None = None,
    scene: Mapping[str, Any] | None = None,
    *,
    walkers: int = 40_000,
    seed: int = 0,
    n_se: float = 5.0,
) -> str:
    """Cross-check a boundary plugin's engine solution against the Markov process.

    Parameters
    ----------
    cls : type
        A :class:`~xpersson.plugins.Boundary` subclass.
    params : Mapping, optional
        Its SI parameters (default: declared defaults and ``example`` values).
    scene : Mapping, optional
        Replacements of :data:`~xpersson.testing.TINY_SCENE` sections.
    walkers : int
        Monte Carlo walkers per load (the standard error falls as ``walkers**-0.5``).
    seed : int
        Random seed of the walkers.
    n_se : float
        Allowed difference in standard errors, ``sqrt(v (1 - v) / walkers)`` of the walkers'
        fraction ``v`` plus the engine's own error estimate.

    Returns
    -------
    str
        ``"ok (...)"`` with the largest difference found, in standard errors.

    Raises
    ------
    AssertionError
        A difference larger than ``n_se`` standard errors, naming the load, the magnification
        and the quantity.
    """
    import numpy as np

    from .. import engine
    from ..plugins import DiffusionClock

    who = qual(cls)
    if getattr(cls, "group", None) != "boundaries":
        raise AssertionError(f"{who}: the Markov cross-check applies to boundary plugins")
    rs, ctx = _resolved(cls, params, scene)
    boundary, coef = rs.boundary, rs.coefficient
    try:
        boundary.validate(ctx)
    except ValueError as exc:
        return f"skipped (the tiny scene is outside the plugin's range: {exc})"
    tau = np.asarray(coef.effective_tau(ctx, rs.zeta), dtype=float).reshape(rs.p0.size, -1)
    clock = DiffusionClock(lambda z: coef.tau(ctx, z), lambda z: coef.f(ctx, z), ctx.zeta_max)
    worst, where = 0.0, ""
    for i, p0 in enumerate(rs.p0):
        lower, upper = boundary.walls(ctx, float(p0), clock)
        ref = engine.solve(
            tau[i], float(p0), lower, upper, rtol=rs.rtol, atol=rs.atol, method=rs.method
        )
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            mc = engine.solve(
                tau[i],
                float(p0),
                lower,
                upper,
                rtol=0.09,
                method="markov",
                options={"walkers": int(walkers), "seed": int(seed)},
            )
        load_worst, load_where = _worst_difference(ref, mc, walkers, float(p0), rs.zeta)
        if load_worst > worst:
            worst, where = load_worst, load_where
    if not math.isfinite(worst) or worst > n_se:
        raise AssertionError(
            f"{who}: the engine's solution of the plugin's walls differs from the Markov process "
            f"by {worst:.1f} standard errors (> {n_se:g}) with {walkers} walkers: {where}"
        )
    return f"ok (markov, {walkers} walkers: within {worst:.1f} standard errors)"


def _resolved(
    cls: type, params: Mapping[str, Any] | None, scene: Mapping[str, Any] | None
) -> tuple[Any, Any]:
    """The tiny scene with ``cls`` injected, resolved, and its :class:`SceneContext`."""
    from ..pipeline import scene_context
    from ..scene import Scene

    sc = tiny_scene(cls, sample_params(cls, params), scene)
    with registry_with(boundaries={CHECK_NAME: cls}) as reg:
        rs = Scene(sc).resolve(reg)
    ctx = scene_context(rs)  # the context the pipeline builds for this scene
    return rs, ctx


def _worst_difference(ref: Any, mc: Any, walkers: int, p0: float, zeta: Any) -> tuple[float, str]:
    """Largest engine-walkers difference of one load [standard errors] and where it is."""
    import numpy as np

    worst, where = 0.0, ""
    for name in _QUANTITIES:
        a = np.asarray(getattr(ref, name), dtype=float)
        b = np.asarray(getattr(mc, name), dtype=float)
        se = np.sqrt(np.maximum(b * (1.0 - b), 1.0 / walkers) / walkers)
        z = np.abs(a - b) / (se + np.abs(ref.error_estimate))
        j = int(np.argmax(z))
        if z[j] > worst:
            worst = float(z[j])
            where = (
                f"{name} at p0 = {p0:g} Pa, zeta = {zeta[j]:.4g}: engine "
                f"({ref.method}) {a[j]:.6g}, markov {b[j]:.6g} +- {se[j]:.2g}"
            )
    return worst, where
