"""The plugin-author kit: contract checks, an injectable registry, schema checks and oracles.

Typical use in a plugin's own test-suite::

    from xpersson.testing import check_plugin, registry_with

    def test_contract():
        check_plugin(MyWall)                       # metadata, pickle, determinism, engine

    def test_from_a_scene():
        with registry_with(boundaries={"mywall": MyWall}):
            ds = xpersson.solve({..., "boundary": {"model": "mywall", "s": "1 kPa"}})

The closed-form oracles (:func:`mirrored_gaussian_area`, :func:`constant_wall_area`,
:func:`linear_wall_area`, :func:`two_wall_areas`, ...) are plain functions; when pytest is
installed the module also defines the fixtures ``xpersson_oracles`` and ``xpersson_tiny_scene``
(enable them with ``pytest_plugins = ["xpersson.testing"]`` in a ``conftest.py``).

Importing this module imports neither numpy-heavy libraries nor the core pipeline; they are
imported by the checks that need them.
"""

from __future__ import annotations

import contextlib
import copy
import json
import math
import os
import pickle
import re
import subprocess
import sys
from collections.abc import Iterator, Mapping
from types import SimpleNamespace
from typing import Any

from ._crosscheck import markov_cross_check
from .plugins import (
    API_VERSION,
    REQUIRED,
    Plugin,
    Registry,
    SpecError,
    check_plugin_class,
    normalize_group,
    using_registry,
)

__all__ = [
    "HEAVY_MODULES",
    "KNOWN_DIMS",
    "TINY_SCENE",
    "assert_schema",
    "check_plugin",
    "constant_wall_area",
    "constant_wall_load",
    "linear_wall_area",
    "linear_wall_load",
    "markov_cross_check",
    "mirrored_gaussian_area",
    "oracles",
    "registry_with",
    "sample_params",
    "two_wall_areas",
]

#: Optional heavy libraries a plugin module must not import at module level.
HEAVY_MODULES = ("matplotlib", "dask", "distributed", "tqdm", "pint_xarray", "SurfaceTopography")

#: Dimensions of the core Dataset (sweep dimensions are accepted when they have a coordinate).
KNOWN_DIMS = ("p0", "zeta", "p", "q_psd")

#: The tiny scene of the checks (about 10 zeta points, two loads; solves in milliseconds).
TINY_SCENE: dict[str, Any] = {
    "title": "xpersson.testing tiny scene",
    "spectrum": {
        "model": "self_affine",
        "H": 0.8,
        "q_L": "1e3 1/m",
        "q_r": "1e4 1/m",
        "q_1": "1e7 1/m",
        "h_rms": "1 um",
    },
    "material": {"E": "10 MPa", "nu": 0.5},
    "load": {"p0": ["1e4 Pa", "1e5 Pa"]},
    "coefficient": {"model": "elastic"},
    "boundary": {"model": "elastic"},
    "output": {"zeta_per_decade": 3},
    "solver": {"rtol": 1e-6},
}

_SECTION = {
    "spectra": "spectrum",
    "coefficients": "coefficient",
    "boundaries": "boundary",
    "analyses": "analyses",
}
_CHECK_NAME = "plugin_under_check"


# -- registry injection ------------------------------------------------------------------------
@contextlib.contextmanager
def registry_with(autoload: bool | None = None, **groups: Mapping[str, type]) -> Iterator[Registry]:
    """Make plugins available by name without installing them.

    Builds a :class:`~xpersson.plugins.Registry` with ``extra=groups`` (installed entry points
    stay visible unless ``autoload=False``) and installs it as the default registry for the
    duration of the ``with`` block (also usable as a decorator).

    Parameters
    ----------
    autoload : bool, optional
        Passed to :class:`~xpersson.plugins.Registry` (``False``: built-ins only).
    **groups
        ``spectra=``, ``coefficients=``, ``boundaries=``, ``analyses=`` (singular forms are
        accepted): mappings name -> plugin class.

    Examples
    --------
    >>> with registry_with(boundaries={"mywall": MyWall}) as reg:  # doctest: +SKIP
    ...     ds = xpersson.solve(scene_using_mywall)
    """
    extra = {normalize_group(g): dict(v) for g, v in groups.items()}
    with using_registry(Registry(autoload=autoload, extra=extra)) as reg:
        yield reg


# -- parameters --------------------------------------------------------------------------------
def sample_params(cls: type[Plugin], params: Mapping[str, Any] | None = None) -> dict[str, Any]:
    """SI parameters for an instance: ``params``, else each spec's default or ``example``.

    Raises
    ------
    AssertionError
        A required parameter has no ``example`` and is not in ``params``.
    """
    out = dict(params or {})
    for name, spec in cls.parameters.items():
        if name in out:
            continue
        value = spec.sample
        if value is REQUIRED:
            raise AssertionError(
                f"{_qual(cls)}: parameter {name!r} is required; pass params={{{name!r}: ...}} "
                f"to check_plugin or declare ParamSpec(example=...)"
            )
        out[name] = value
    return out


def _scene_value(spec: Any, value: Any) -> Any:
    """An SI value written the way a scene gives it (quantity strings with units)."""
    if spec.kind != "quantity" or value is None:
        return value
    if spec.array:
        from .units import ureg

        return ureg().Quantity(list(value), spec.unit)
    if spec.unit in ("1", ""):
        return float(value)
    return f"{float(value)!r} {spec.unit}"


def _scene_params(cls: type[Plugin], params: Mapping[str, Any]) -> dict[str, Any]:
    return {
        k: _scene_value(cls.parameters[k], v)
        for k, v in params.items()
        if cls.parameters[k].required or v != cls.parameters[k].default
    }


# -- check_plugin ------------------------------------------------------------------------------
def check_plugin(
    cls: type[Plugin],
    params: Mapping[str, Any] | None = None,
    *,
    scene: Mapping[str, Any] | None = None,
    engine: bool = True,
    cheap_import: bool = True,
    import_budget: float = 3.0,
    balance_tol: float | None = None,
    markov: int = 40_000,
) -> dict[str, Any]:
    """Check a plugin class against the xpersson plugin contract.

    Checks, in order: class metadata (as at class definition, plus the API version); a cheap
    module import in a fresh interpreter (no :data:`HEAVY_MODULES`, within ``import_budget``
    seconds of CPU time, so a loaded machine does not fail it); pickle round trip of an
    instance; determinism and finite values of the group's methods on a tiny scene; and, with
    ``engine=True``, a solve of :data:`TINY_SCENE` through
    :func:`xpersson.solve` with the plugin injected: finite outputs with the declared
    attributes, :func:`assert_schema`, two runs equal, and for boundaries and coefficients the
    probability balance (``|probability_balance| <= balance_tol``).

    Parameters
    ----------
    cls : type
        The plugin class.
    params : Mapping, optional
        SI parameter values (default: declared defaults and ``example`` values).
    scene : Mapping, optional
        Replacements of :data:`TINY_SCENE` sections (merged key by key), e.g. a load below a
        yield stress: ``{"load": {"p0": "1 MPa"}}``.
    engine : bool
        Run the end-to-end checks through :func:`xpersson.solve`.
    cheap_import : bool
        Import the plugin's module in a subprocess and time it.
    import_budget : float
        Allowed import time [s].
    balance_tol : float, optional
        Allowed probability-balance residual [1]. Default: the engine's own acceptance
        criterion for the tiny scene's tolerances, ``10 (rtol + atol)``.
    markov : int
        Boundaries only (with ``engine=True``): walkers of the cross-check against the Markov
        process, :func:`markov_cross_check` (within 5 standard errors); 0 skips it.

    Returns
    -------
    dict
        What was checked (``{"metadata": "ok", "pickle": "ok", ...}``).

    Raises
    ------
    AssertionError
        A contract violation, with a message naming the class and what failed.
    RuntimeError
        ``engine=True`` but the core pipeline (:func:`xpersson.solve`) is not importable.
    """
    report: dict[str, Any] = {}
    name = _qual(cls)
    if not isinstance(cls, type) or not issubclass(cls, Plugin):
        raise AssertionError(f"{cls!r} is not a plugin class (derive from a base in GROUPS)")
    group = cls.group
    try:
        check_plugin_class(cls)
    except SpecError as exc:
        raise AssertionError(f"metadata: {exc}") from None
    assert not getattr(cls, "abstract", True), f"{name} is abstract"
    assert cls.api_version <= API_VERSION, f"{name}: api_version {cls.api_version} too new"
    report["metadata"] = "ok"

    if cheap_import:
        report["import"] = _check_import(cls, import_budget)

    values = sample_params(cls, params)
    inst = cls(**values)
    try:
        clone = pickle.loads(pickle.dumps(inst))
    except Exception as exc:
        raise AssertionError(
            f"{name}: instances must pickle (dask ships them to workers): "
            f"{type(exc).__name__}: {exc}"
        ) from None
    assert type(clone) is cls, f"{name}: unpickled instance has type {type(clone)}"
    assert clone == inst, f"{name}: pickle round trip changed the parameters: {clone!r}"
    report["pickle"] = "ok"

    report["methods"] = _GROUP_CHECKS[group](inst, clone)

    if engine:
        report["engine"] = _check_engine(cls, values, scene, balance_tol)
        if markov and group == "boundaries":
            report["markov"] = markov_cross_check(cls, values, scene, walkers=markov)
    return report


def _qual(cls: Any) -> str:
    return f"{getattr(cls, '__module__', '?')}.{getattr(cls, '__qualname__', repr(cls))}"


def _check_import(cls: type, budget: float) -> str:
    module = cls.__module__
    if module == "__main__" or "<locals>" in cls.__qualname__:
        raise AssertionError(
            f"{_qual(cls)} must be defined at module level of an importable module "
            "(entry points and pickling need it)"
        )
    code = (
        "import json, sys, time\n"
        f"t = time.process_time(); import {module}; t = time.process_time() - t\n"
        f"heavy = [m for m in {HEAVY_MODULES!r} if m in sys.modules]\n"
        "print(json.dumps({'t': t, 'heavy': heavy}))\n"
    )
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(p for p in sys.path if p)
    proc = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=120
    )
    if proc.returncode != 0:
        tail = proc.stderr.strip().splitlines()[-1:] or ["?"]
        raise AssertionError(f"importing {module} in a fresh interpreter failed: {tail[0]}")
    res = json.loads(proc.stdout.strip().splitlines()[-1])
    assert not res["heavy"], (
        f"importing {module} imports {res['heavy']} at module level; import optional heavy "
        "libraries inside the methods that need them"
    )
    assert res["t"] <= budget, f"importing {module} took {res['t']:.2f} s (> {budget} s)"
    return f"ok ({res['t'] * 1e3:.0f} ms)"


def _tiny_context(p0: tuple[float, ...] = (1e5, 1e6)) -> Any:
    import numpy as np

    from .physics.psd import SelfAffineRollOff
    from .plugins import SceneContext

    psd = SelfAffineRollOff.from_h_rms(1e-6, 0.8, 1e3, 1e4, 1e6)
    E, nu = 1e7, 0.5
    return SceneContext(
        psd=psd,
        E=E,
        nu=nu,
        E_star=E / (1 - nu**2),
        p0=np.asarray(p0, dtype=float),
        zeta=np.geomspace(1.0, 1e3, 10),
    )


def _equal(a: Any, b: Any, what: str) -> None:
    import numpy as np

    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    assert a.shape == b.shape, f"{what}: shapes differ between two calls ({a.shape}, {b.shape})"
    assert np.array_equal(a, b, equal_nan=True), f"{what}: two identical calls differ"
    assert np.all(np.isfinite(a)), f"{what}: non-finite values {a}"


def _check_spectrum(inst: Any, clone: Any) -> str:
    import numpy as np

    psd1, psd2 = inst.build(), clone.build()
    q = np.geomspace(float(psd1.q_L), float(psd1.q_1), 40)
    _equal(psd1.C(q), psd2.C(q), f"{_qual(type(inst))}.build().C(q)")
    assert np.all(np.asarray(psd1.C(q)) >= 0), "C(q) must be non-negative"
    return "ok"


def _check_coefficient(inst: Any, clone: Any) -> str:
    import numpy as np

    ctx = _tiny_context()
    who = _qual(type(inst))
    f1, f2 = inst.f(ctx, ctx.zeta), clone.f(ctx, ctx.zeta)
    _equal(f1, f2, f"{who}.f")
    assert np.all(np.asarray(f1) >= 0), f"{who}.f: the diffusion coefficient must be >= 0"
    t1, t2 = inst.tau(ctx, ctx.zeta), clone.tau(ctx, ctx.zeta)
    _equal(t1, t2, f"{who}.tau")
    t1 = np.asarray(t1, dtype=float)
    assert abs(t1[0]) <= 1e-12 * max(1.0, float(np.max(np.abs(t1)))), f"{who}: tau(1) != 0"
    assert np.all(np.diff(t1) >= 0), f"{who}: tau(zeta) must be non-decreasing"
    e1, e2 = inst.effective_tau(ctx, ctx.zeta), clone.effective_tau(ctx, ctx.zeta)
    _equal(e1, e2, f"{who}.effective_tau")
    shape = (ctx.p0.size, ctx.zeta.size)
    assert np.shape(e1) == shape, f"{who}.effective_tau: shape {np.shape(e1)}, expected {shape}"
    return "ok"


def _check_boundary(inst: Any, clone: Any) -> str:
    import numpy as np

    from .physics import elastic
    from .plugins import DiffusionClock

    ctx = _tiny_context()
    who = _qual(type(inst))
    try:
        inst.validate(ctx)
    except ValueError as exc:
        return f"skipped (the tiny scene is outside the plugin's range: {exc})"
    clock = DiffusionClock(
        lambda z: elastic.diffusion_time(ctx.psd, ctx.E_star, z),
        lambda z: elastic.coefficient_f(ctx.psd, ctx.E_star, z),
        ctx.zeta_max,
    )
    taus = np.asarray(clock.tau_of_zeta(ctx.zeta), dtype=float)
    for p0 in ctx.p0:
        w1, w2 = inst.walls(ctx, float(p0), clock), clone.walls(ctx, float(p0), clock)
        assert isinstance(w1, tuple) and len(w1) == 2, f"{who}.walls must return (lower, upper)"
        assert w1[0] is not None, f"{who}.walls: the lower wall is required"
        for k, (a, b) in enumerate(zip(w1, w2, strict=True)):
            assert (a is None) == (b is None), f"{who}.walls: two identical calls differ"
            if a is not None:
                _equal(a.at(taus), b.at(taus), f"{who}.walls()[{k}] position")
    return "ok"


def _check_analysis(inst: Any, clone: Any) -> str:
    return "ok (checked end to end)"


_GROUP_CHECKS = {
    "spectra": _check_spectrum,
    "coefficients": _check_coefficient,
    "boundaries": _check_boundary,
    "analyses": _check_analysis,
}


def _merge(base: dict[str, Any], over: Mapping[str, Any]) -> dict[str, Any]:
    out = copy.deepcopy(base)
    for key, val in over.items():
        if isinstance(val, Mapping) and isinstance(out.get(key), dict):
            out[key] = _merge(out[key], val)
        else:
            out[key] = copy.deepcopy(val)
    return out


def _solver() -> Any:
    try:
        from . import solve
    except Exception as exc:  # the core pipeline is optional for the metadata checks
        raise RuntimeError(
            "check_plugin: the end-to-end checks need xpersson.solve, which cannot be imported "
            f"({type(exc).__name__}: {exc}); pass engine=False to run only the unit checks"
        ) from exc
    return solve


def tiny_scene(
    cls: type[Plugin] | None = None,
    params: Mapping[str, Any] | None = None,
    scene: Mapping[str, Any] | None = None,
) -> dict[str, Any]:
    """:data:`TINY_SCENE` with ``scene`` merged in and ``cls`` selected as ``plugin_under_check``.

    ``params`` are SI values; they are written as quantity strings in the declared units.
    """
    sc = _merge(TINY_SCENE, scene or {})
    if cls is not None:
        section = _SECTION[cls.group]
        raw = _scene_params(cls, params or {})
        if section == "analyses":
            sc.setdefault("analyses", {})[_CHECK_NAME] = raw
        else:
            sc[section] = {"model": _CHECK_NAME, **raw}
    return sc


def _check_engine(
    cls: type[Plugin],
    params: Mapping[str, Any],
    scene: Mapping[str, Any] | None,
    tol: float | None,
) -> str:
    import numpy as np

    solve = _solver()
    who = _qual(cls)
    sc = tiny_scene(cls, params, scene)
    if tol is None:
        solver = sc.get("solver", {})
        tol = 10.0 * (float(solver.get("rtol", 1e-6)) + float(solver.get("atol", 1e-12)))
    with registry_with(**{cls.group: {_CHECK_NAME: cls}}):
        ds1 = solve(copy.deepcopy(sc))
        ds2 = solve(copy.deepcopy(sc))
    assert_schema(ds1)
    names = list(cls.outputs) + ["area_fraction"]
    for var in names:
        assert var in ds1, f"{who}: declared output {var!r} is missing from the Dataset"
        spec = cls.outputs.get(var)
        if spec is not None:
            got = {k: ds1[var].attrs.get(k) for k in ("units", "long_name")}
            want = {"units": spec.units, "long_name": spec.long_name}
            assert got == want, f"{who}: {var!r} has attrs {got}, declared {want}"
        a1, a2 = np.asarray(ds1[var].values), np.asarray(ds2[var].values)
        if a1.dtype.kind in "fc":
            assert np.all(np.isfinite(a1)), f"{who}: {var!r} has non-finite values"
            if spec is not None:
                lo, hi = spec.valid_min, spec.valid_max
                assert lo is None or np.all(a1 >= lo), f"{who}: {var!r} below valid_min {lo}"
                assert hi is None or np.all(a1 <= hi), f"{who}: {var!r} above valid_max {hi}"
        assert np.array_equal(a1, a2), f"{who}: {var!r} differs between two identical solves"
    area = np.asarray(ds1["area_fraction"].values)
    assert np.all((area >= -tol) & (area <= 1 + tol)), f"{who}: area_fraction outside [0, 1]"
    if cls.group in ("boundaries", "coefficients") and "probability_balance" in ds1:
        worst = float(np.nanmax(np.abs(ds1["probability_balance"].values)))
        assert worst <= tol, f"{who}: probability balance violated by {worst:.3g} (> {tol:g})"
        return f"ok (probability balance {worst:.1e})"
    return "ok"


# -- schema ------------------------------------------------------------------------------------
_UNIT_TOKEN = re.compile(r"([A-Za-z_]+)(-?\d+)")


def _to_pint(units: str) -> str:
    try:
        from .units import udunits_to_pint
    except Exception:  # pragma: no cover - the units module is part of the core
        if units in ("1", ""):
            return "dimensionless"
        return "*".join(_UNIT_TOKEN.sub(r"\1**\2", units.strip()).split())
    return udunits_to_pint(units)


def _unit_parser() -> Any:
    try:
        from .units import ureg

        return ureg()
    except Exception:  # pint missing: units are not checkable
        return None


def assert_schema(ds: Any, extra_dims: tuple[str, ...] = ()) -> None:
    """Assert the CF conventions of an xpersson Dataset.

    Every variable and coordinate has non-empty ``units`` and ``long_name`` attributes; every
    dimension is one of :data:`KNOWN_DIMS` (plus ``extra_dims``) or a sweep dimension with its
    own coordinate; units parse as UDUNITS strings (checked through pint when available).

    Raises
    ------
    AssertionError
        Listing every problem found.
    """
    problems: list[str] = []
    reg = _unit_parser()
    for name in list(ds.variables):
        var = ds[name]
        attrs = var.attrs
        for key in ("units", "long_name"):
            val = attrs.get(key)
            if not isinstance(val, str) or not val.strip():
                problems.append(f"{name}: missing {key!r} attribute")
        for dim in var.dims:
            if dim not in KNOWN_DIMS and dim not in extra_dims and dim not in ds.coords:
                problems.append(f"{name}: unknown dimension {dim!r} (no coordinate)")
        units = attrs.get("units")
        if reg is not None and isinstance(units, str) and units.strip():
            try:
                reg.Unit(_to_pint(units))
            except Exception as exc:
                problems.append(f"{name}: units {units!r} do not parse ({type(exc).__name__})")
    if problems:
        raise AssertionError("Dataset schema problems:\n  " + "\n  ".join(problems))


# -- closed-form oracles -----------------------------------------------------------------------
def _erf(x: Any) -> Any:
    from scipy.special import erf

    return erf(x)


def mirrored_gaussian_area(p0: Any, tau: Any) -> Any:
    """Elastic contact area A/A0 = erf(p0 / (2 sqrt(tau))) (physics.md §1.2).

    Parameters
    ----------
    p0 : float or array
        Nominal pressure [Pa].
    tau : float or array
        Diffusion time [Pa^2] (tau = G p0^2).
    """
    import numpy as np

    t = np.asarray(tau, dtype=float)
    with np.errstate(divide="ignore"):
        return _erf(np.asarray(p0, dtype=float) / (2.0 * np.sqrt(t)))


def constant_wall_area(p0: Any, s: Any, tau: Any) -> Any:
    """Area with an absorbing wall at p = -s: erf((p0 + s) / (2 sqrt(tau))) (§2.2).

    ``s`` [Pa] is a constant adhesive stress sigma_a; ``s = 0`` is the elastic case.
    """
    return mirrored_gaussian_area(_add(p0, s), tau)


def constant_wall_load(p0: Any, s: Any, tau: Any) -> Any:
    """Load in the domain, int p P dp = p0 + s (1 - A) [Pa], for the wall at p = -s (§2.2)."""
    import numpy as np

    return np.asarray(p0, dtype=float) + np.asarray(s, dtype=float) * (
        1.0 - constant_wall_area(p0, s, tau)
    )


def _add(a: Any, b: Any) -> Any:
    import numpy as np

    return np.asarray(a, dtype=float) + np.asarray(b, dtype=float)


def _linear_wall_terms(p0: Any, s0: Any, c: Any, tau: Any) -> tuple[Any, ...]:
    import numpy as np

    p0, s0, c, tau = (np.asarray(v, dtype=float) for v in (p0, s0, c, tau))
    y0 = p0 + s0
    sig = np.sqrt(2.0 * tau)
    a1 = (y0 + c * tau) / sig
    a2 = (c * tau - y0) / sig
    return p0, s0, c, tau, y0, sig, a1, a2, np.exp(-c * y0)


def linear_wall_area(p0: Any, s0: Any, c: Any, tau: Any) -> Any:
    """Exact area for the absorbing wall p_w(tau) = -(s0 + c tau) (physics.md §2.2).

    A/A0 = Phi((y0 + c tau)/sqrt(2 tau)) - exp(-c y0) Phi((c tau - y0)/sqrt(2 tau)),
    y0 = p0 + s0. Units: p0, s0 [Pa], c [1/Pa], tau [Pa^2].
    """
    from scipy.special import ndtr

    *_, a1, a2, k = _linear_wall_terms(p0, s0, c, tau)
    return ndtr(a1) - k * ndtr(a2)


def linear_wall_load(p0: Any, s0: Any, c: Any, tau: Any) -> Any:
    """Exact load in the domain, int p P dp [Pa], for the linearly moving wall (§2.2)."""
    import numpy as np
    from scipy.special import ndtr

    p0, s0, c, tau, y0, sig, a1, a2, k = _linear_wall_terms(p0, s0, c, tau)
    phi = lambda x: np.exp(-0.5 * x * x) / math.sqrt(2.0 * math.pi)  # noqa: E731
    return p0 * ndtr(a1) + sig * phi(a1) - k * ((-p0 - 2.0 * s0) * ndtr(a2) + sig * phi(a2))


def two_wall_areas(p0: float, sigma_y: float, tau: Any) -> tuple[Any, Any]:
    """Elastic and plastic area for fixed walls at 0 and sigma_y (physics.md §3.1).

    Sine series ``A_el = sum_odd 4/(n pi) sin(n pi p0/sY) exp(-(n pi/sY)^2 tau)`` and
    ``A_pl = p0/sY - sum_n 2/(n pi) (-1)^(n+1) sin(n pi p0/sY) exp(-(n pi/sY)^2 tau)`` (image
    series at small tau), from :mod:`xpersson.engine.exact`, their one home. Units: p0, sigma_y
    [Pa], tau [Pa^2].

    Returns
    -------
    (A_el, A_pl) : arrays shaped like ``tau``
    """
    import numpy as np

    from .engine import exact  # the one home of the two-wall series

    t = np.asarray(tau, dtype=float)
    a_el, _, a_pl = exact.two_wall(t, float(p0), 0.0, float(sigma_y))
    return np.asarray(a_el).reshape(np.shape(tau)), np.asarray(a_pl).reshape(np.shape(tau))


def oracles() -> SimpleNamespace:
    """The closed forms as one namespace (what the ``xpersson_oracles`` fixture returns)."""
    return SimpleNamespace(
        mirrored_gaussian_area=mirrored_gaussian_area,
        constant_wall_area=constant_wall_area,
        constant_wall_load=constant_wall_load,
        linear_wall_area=linear_wall_area,
        linear_wall_load=linear_wall_load,
        two_wall_areas=two_wall_areas,
    )


# -- pytest fixtures (only when pytest is installed) -------------------------------------------
try:  # pragma: no cover - exercised through pytest itself
    import pytest as _pytest
except ImportError:  # pragma: no cover
    _pytest = None

if _pytest is not None:

    @_pytest.fixture
    def xpersson_oracles() -> SimpleNamespace:
        """Closed-form oracles (:func:`oracles`)."""
        return oracles()

    @_pytest.fixture
    def xpersson_tiny_scene() -> dict[str, Any]:
        """A fresh copy of :data:`TINY_SCENE`."""
        return copy.deepcopy(TINY_SCENE)
