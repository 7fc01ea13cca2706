"""Every fast path a plugin declares, checked against the plain path (:func:`check_fast_paths`).

A plugin's ``fast_paths`` (:class:`xpersson.plugins.FastPaths`) promise that a faster path gives
what the plain path (each load, each sweep point on its own) gives. Each declared path is run
against the plain path on a few generated scenes (the tiny scene with seeded random loads and
roughness exponent) and must agree to :data:`RTOL` relative, element by element, in every
floating-point variable (integer and text variables exactly):

``shared_walls``
    the walls at several loads are at the same positions (relative to the load), and a solve
    with the walls asked once equals one inside :func:`xpersson.sweep.plain_paths`;
``shared_tau``
    every row of ``effective_tau`` equals ``tau(zeta)`` (on an instance that meets the
    declared condition), and a solve equals one inside :func:`~xpersson.sweep.plain_paths`;
``contact_similarity``
    a solve at (E*, loads) equals one at (k E*, k loads) in units of E* (each variable in
    Pa^n divided by k^n), k = 3;
``wall_tables``
    every moving wall the plugin gives (at the tiny context's loads) carries a
    :class:`xpersson.engine.WallTable` whose positions equal its position callable's at times
    across and beyond the table, and a solve equals one inside
    :func:`~xpersson.sweep.plain_paths` (no tables);
``reused``
    a generated scene solved twice (the second solve on the resolution the first made) equals
    its solve inside :func:`~xpersson.sweep.plain_paths` (resolved afresh);
``stacked``
    a sweep over the declared parameters (each at its sample value and a nearby one; the
    spectrum's ``H`` where the plugin declares none) solved through the stacked path equals
    the same sweep inside :func:`~xpersson.sweep.plain_paths`.
"""

from __future__ import annotations

import copy
import zlib
from collections.abc import Iterator, Mapping
from typing import Any

from ..plugins import Plugin, plain_paths
from ._names import CHECK_NAME, SECTION, qual
from .registry import registry_with
from .scenes import _scene_value, _tiny_context, tiny_scene

__all__ = ["RTOL", "check_fast_paths"]

#: Relative tolerance of every fast path against the plain path (rounding only).
RTOL = 1e-12
#: Generated scenes per path.
N_SCENES = 2
#: E* and loads scaled together by this factor in the contact-similarity check.
SIMILARITY_FACTOR = 3.0


def check_fast_paths(
    cls: type[Plugin],
    params: Mapping[str, Any],
    scene: Mapping[str, Any] | None = None,
    *,
    engine: bool = True,
) -> dict[str, str]:
    """Check every fast path ``cls`` declares against the plain path.

    Parameters
    ----------
    cls : type
        The plugin class.
    params : Mapping
        SI parameter values of the instance checked.
    scene : Mapping, optional
        Replacements of the tiny scene's sections (as :func:`~xpersson.testing.check_plugin`).
    engine : bool
        Also compare solves (else only the unit checks of shared walls and shared tau).

    Returns
    -------
    dict
        ``{"fast_paths.<path>": "ok ..."}`` per declared path.

    Raises
    ------
    AssertionError
        Naming the plugin, the path, the variable and the largest relative difference.
    """
    out = {}
    for path in cls.fast_paths.declared():
        check = _CHECKS[path]
        out[f"fast_paths.{path}"] = check(cls, dict(params), scene, engine)
    return out


# -- comparison ------------------------------------------------------------------------------
def _max_rel(a: Any, b: Any, scale: Any = None) -> float:
    """Largest ``|a - b| / max(|a|, |b|, scale)`` (0 where both are equal, NaN included)."""
    import numpy as np

    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    same = (a == b) | (np.isnan(a) & np.isnan(b))
    if np.all(same):
        return 0.0
    ref = np.maximum(np.abs(a), np.abs(b))
    if scale is not None:
        ref = np.maximum(ref, scale)
    with np.errstate(divide="ignore", invalid="ignore"):
        rel = np.where(same, 0.0, np.abs(a - b) / ref)
    rel = np.where(np.isnan(rel), np.inf, rel)  # NaN on one side only
    return float(np.max(rel))


def _fail(cls: type, path: str, var: str, rel: float, where: str) -> AssertionError:
    return AssertionError(
        f"{qual(cls)}: fast path {path!r} differs from the plain path in {var!r}: max relative "
        f"difference {rel:.3g} (> {RTOL:g}) {where}"
    )


def _compare(cls: type, path: str, fast: Any, plain: Any, where: str, power: Any = None) -> None:
    """Every variable of ``plain`` in ``fast``, equal to :data:`RTOL` (``power(name)`` gives
    the factor a variable of ``fast`` is divided by first)."""
    import numpy as np

    for name, var in plain.variables.items():
        if name not in fast.variables:
            raise AssertionError(f"{qual(cls)}: fast path {path!r} lacks variable {name!r} {where}")
        got = fast.variables[name]
        if got.dims != var.dims or got.shape != var.shape:
            raise AssertionError(
                f"{qual(cls)}: fast path {path!r} gives {name!r} dims {got.dims} {got.shape}, "
                f"the plain path {var.dims} {var.shape} {where}"
            )
        a, b = np.asarray(got.values), np.asarray(var.values)
        if b.dtype.kind in "fc":
            if power is not None:
                a = a / power(name)
            rel = _max_rel(a, b)
            if rel > RTOL:
                raise _fail(cls, path, name, rel, where)
        elif not np.array_equal(a, b):
            raise _fail(cls, path, name, float("inf"), where)


def _solve(cls: type, sc: Mapping[str, Any]) -> Any:
    import warnings

    from .. import solve

    with registry_with(**{cls.group: {CHECK_NAME: cls}}), warnings.catch_warnings():
        warnings.simplefilter("ignore")  # validity notes: the same on both paths
        return solve(copy.deepcopy(dict(sc)))


def _both(cls: type, sc: Mapping[str, Any]) -> tuple[Any, Any]:
    """``(fast, plain)``: the scene solved as usual and inside ``plain_paths()``."""
    fast = _solve(cls, sc)
    with plain_paths():
        plain = _solve(cls, sc)
    return fast, plain


# -- generated scenes ------------------------------------------------------------------------
def _pascal(value: Any) -> float:
    """A scene's pressure (a number in Pa, or a quantity) in Pa, by the scene's own converter."""
    if isinstance(value, int | float):
        return float(value)
    from ..units import to_si

    return float(to_si(value, "Pa", "load.p0"))


def _scenes(cls: type, params: Mapping[str, Any], scene: Any) -> Iterator[dict[str, Any]]:
    """:data:`N_SCENES` seeded variants of the check's tiny scene: three loads drawn below the
    scene's largest (factors in [0.5, 1]) and, for a self-affine spectrum that is not the
    plugin under check, ``H`` in [0.7, 0.9]."""
    import numpy as np

    rng = np.random.default_rng(zlib.crc32(qual(cls).encode()))
    base = tiny_scene(cls, params, scene)
    given = base.get("load", {}).get("p0", 1e5)
    top = max(_pascal(p) for p in (given if isinstance(given, list) else [given]))
    for _ in range(N_SCENES):
        sc = copy.deepcopy(base)
        loads = np.sort(top * rng.uniform(0.5, 1.0, 3))
        sc.setdefault("load", {})["p0"] = [f"{float(p)!r} Pa" for p in loads]
        spec = sc.get("spectrum", {})
        if spec.get("model") == "self_affine" and cls.group != "spectra":
            spec["H"] = round(float(rng.uniform(0.7, 0.9)), 6)
        yield sc


# -- the paths -------------------------------------------------------------------------------
def _wall_tables(cls: type, params: dict[str, Any], scene: Any, engine: bool) -> str:
    import numpy as np

    ctx = _tiny_context((1e4, 3e4, 1e5))
    inst = cls(**params)
    try:
        inst.validate(ctx)
    except ValueError:
        return "skipped (the tiny context is outside the plugin's range)"
    tabled = 0
    for p0 in ctx.p0:
        for k, wall in enumerate(inst.walls(ctx, float(p0), _tiny_clock(ctx))):
            if wall is None or wall.is_fixed:
                continue
            tab = wall.table
            if tab is None:
                raise AssertionError(
                    f"{qual(cls)}: declares fast path 'wall_tables' but walls()[{k}] at p0 = "
                    f"{float(p0):g} Pa moves without a table (Wall.absorbing(..., table=...))"
                )
            t = np.concatenate([np.linspace(0.0, 1.5 * tab.t_hi, 301), tab.x, [tab.t_lo]])
            rel = _max_rel(tab.values(t), np.asarray(wall.position(t), dtype=float))
            if rel > RTOL:
                raise _fail(cls, "wall_tables", f"walls()[{k}] table", rel, f"(p0 = {p0:g} Pa)")
            tabled += 1
    unit = f"ok ({tabled} tables)" if tabled else "ok (no moving wall in the tiny context)"
    return unit + _solves(cls, params, scene, engine, "wall_tables")


def _tiny_clock(ctx: Any) -> Any:
    """The diffusion clock of the tiny context (elastic coefficient)."""
    from ..physics import elastic
    from ..plugins import DiffusionClock

    return DiffusionClock(
        lambda z: elastic.diffusion_time(ctx.psd, ctx.E_star, z),
        lambda z: elastic.coefficient_f(ctx.psd, ctx.E_star, z),
        ctx.zeta_max,
    )


def _shared_walls(cls: type, params: dict[str, Any], scene: Any, engine: bool) -> str:
    import numpy as np

    ctx = _tiny_context((1e4, 3e4, 1e5))
    inst = cls(**params)
    try:
        inst.validate(ctx)
    except ValueError:
        unit = "skipped (the tiny context is outside the plugin's range)"
    else:
        clock = _tiny_clock(ctx)
        taus = np.asarray(clock.tau_of_zeta(ctx.zeta), dtype=float)
        first = inst.walls(ctx, float(ctx.p0[0]), clock)
        for p0 in ctx.p0[1:]:
            pair = inst.walls(ctx, float(p0), clock)
            for k, (a, b) in enumerate(zip(first, pair, strict=True)):
                if (a is None) != (b is None) or (a is not None and a.kind != b.kind):
                    raise _fail(cls, "shared_walls", f"walls()[{k}] kind", np.inf, "")
                if a is not None:
                    rel = _max_rel(a.at(taus), b.at(taus), scale=float(p0))
                    if rel > RTOL:
                        where = f"(walls at p0 = {float(ctx.p0[0]):g} and {float(p0):g} Pa)"
                        raise _fail(cls, "shared_walls", f"walls()[{k}] position", rel, where)
        unit = "ok"
    return unit + _solves(cls, params, scene, engine, "shared_walls")


def _shared_tau(cls: type, params: dict[str, Any], scene: Any, engine: bool) -> str:
    from collections.abc import Mapping as _Mapping

    cond = cls.fast_paths.shared_tau
    if isinstance(cond, _Mapping):  # an instance that meets the declared condition
        params = {**params, **cond}
    inst = cls(**params)
    ctx = _tiny_context((1e4, 3e4, 1e5))
    tau = inst.tau(ctx, ctx.zeta)
    eff = inst.effective_tau(ctx, ctx.zeta)
    rel = max(_max_rel(row, tau) for row in eff)
    if rel > RTOL:
        raise _fail(cls, "shared_tau", "effective_tau rows", rel, "(against tau(zeta))")
    return "ok" + _solves(cls, params, scene, engine, "shared_tau")


def _solves(cls: type, params: dict[str, Any], scene: Any, engine: bool, path: str) -> str:
    """A solve of each generated scene against the same solve inside ``plain_paths()``."""
    if not engine:
        return ""
    for i, sc in enumerate(_scenes(cls, params, scene)):
        fast, plain = _both(cls, sc)
        _compare(cls, path, fast, plain, f"(generated scene {i}: {sc['load']['p0']})")
    return f"; {N_SCENES} solves equal the plain path"


def _reused(cls: type, params: dict[str, Any], scene: Any, engine: bool) -> str:
    if not engine:
        return "not checked (engine=False)"
    for i, sc in enumerate(_scenes(cls, params, scene)):
        _solve(cls, sc)  # resolves the scene (kept for the next solve)
        fast, plain = _both(cls, sc)
        _compare(cls, "reused", fast, plain, f"(generated scene {i}, solved again)")
    return f"ok ({N_SCENES} scenes solved twice)"


def _contact_similarity(cls: type, params: dict[str, Any], scene: Any, engine: bool) -> str:
    if not engine:
        return "not checked (engine=False)"
    from ..sweep.batched import pressure_power

    k = SIMILARITY_FACTOR
    for i, sc in enumerate(_scenes(cls, params, scene)):
        ref = _solve(cls, sc)
        scaled = copy.deepcopy(sc)
        mat = scaled.setdefault("material", {})
        mat["E"] = f"{k * _pascal(mat.get('E', '10 MPa'))!r} Pa"
        scaled["load"]["p0"] = [f"{k * _pascal(p)!r} Pa" for p in sc["load"]["p0"]]
        got = _solve(cls, scaled)

        def power(name: str, got: Any = got) -> float:
            return k ** pressure_power(got.variables[name].attrs.get("units"))

        _compare(cls, "contact_similarity", got, ref, f"(generated scene {i}, E* x {k:g})", power)
    return f"ok ({N_SCENES} scenes, E* and loads x {k:g})"


def _nearby(spec: Any, value: float) -> float | None:
    """A second value of a swept parameter: 1.1 or 0.9 times ``value`` within its bounds."""
    for other in (value * 1.1, value * 0.9):
        if other != value and spec.in_bounds(other):
            return other
    return None


def _sweep(cls: type, params: Mapping[str, Any], sc: dict[str, Any]) -> str | None:
    """Put a two-value sweep of each declared stacked parameter into ``sc`` (the spectrum's
    ``H`` where none can be swept); the names swept, or ``None``."""
    names = []
    section = SECTION[cls.group]
    own = sc.setdefault("analyses", {})[CHECK_NAME] if section == "analyses" else sc[section]
    for name in sorted(cls.fast_paths.stacked_params or ()):
        spec, value = cls.parameters[name], params.get(name)
        if spec.kind != "quantity" or spec.array or not spec.sweepable:
            continue
        if not isinstance(value, int | float) or isinstance(value, bool):
            continue
        other = _nearby(spec, float(value))
        if other is not None:
            own[name] = [_scene_value(spec, float(value)), _scene_value(spec, other)]
            names.append(f"{section}.{name}")
    spectrum = sc.get("spectrum", {})
    if not names and cls.group != "spectra" and spectrum.get("model") == "self_affine":
        h = float(spectrum.get("H", 0.8))
        spectrum["H"] = [h, round(h * 0.9, 6)]
        names.append("spectrum.H")
    return ", ".join(names) or None


def _stacked(cls: type, params: dict[str, Any], scene: Any, engine: bool) -> str:
    if not engine:
        return "not checked (engine=False)"
    from ..pipeline import as_scene, stacked
    from ..sweep import expand, resolve_points

    swept = None
    for i, sc in enumerate(_scenes(cls, params, scene)):
        swept = _sweep(cls, params, sc)
        if swept is None:
            return "not checked (no parameter to sweep)"
        with registry_with(**{cls.group: {CHECK_NAME: cls}}):
            points = resolve_points(expand(as_scene(copy.deepcopy(sc))), None)
        why = stacked.stack_reason([points[j] for j in range(len(points))])
        if why is not None:
            return f"not exercised: the generated sweep does not stack ({why})"
        fast, plain = _both(cls, sc)
        _compare(cls, "stacked", fast, plain, f"(generated sweep {i} over {swept})")
    return f"ok ({N_SCENES} sweeps over {swept})"


_CHECKS = {
    "shared_walls": _shared_walls,
    "wall_tables": _wall_tables,
    "shared_tau": _shared_tau,
    "contact_similarity": _contact_similarity,
    "stacked": _stacked,
    "reused": _reused,
}
