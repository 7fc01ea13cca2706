"""The plugin contract check: :func:`check_plugin` and the per-group unit checks it runs."""

from __future__ import annotations

import copy
import json
import os
import pickle
import subprocess
import sys
from collections.abc import Mapping
from typing import Any

from ..plugins import API_VERSION, Plugin, SpecError, check_plugin_class
from ..specs import caret_units
from ._names import CHECK_NAME, qual
from .fastpaths import check_fast_paths
from .referee import markov_cross_check
from .registry import registry_with
from .scenes import _tiny_context, sample_params, tiny_scene
from .schema import assert_schema

__all__ = ["HEAVY_MODULES", "check_plugin"]

#: Optional heavy libraries a plugin module must not import at module level.
HEAVY_MODULES = ("matplotlib", "dask", "distributed", "tqdm", "pint_xarray", "SurfaceTopography")


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
    instance; determinism and finite values of the group's methods on a tiny scene (a
    boundary's ``walls()`` must leave the instance as it was: nothing passes between plugin
    calls through ``self``); and, with
    ``engine=True``, a solve of :data:`TINY_SCENE` through
    :func:`xpersson.solve` with the plugin injected: finite outputs with the declared
    attributes, :func:`assert_schema`, two runs equal, and for boundaries and coefficients the
    probability balance (``|probability_balance| <= balance_tol``); then every fast path the
    class declares (``fast_paths``) against the plain path on generated scenes, to 1e-12
    relative (:func:`xpersson.testing.fastpaths.check_fast_paths`; with ``engine=False`` only
    the unit checks of shared walls and shared tau).

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
        What was checked (``{"metadata": "ok", "pickle": "ok", ...,
        "fast_paths.shared_walls": "ok ..."}``).

    Raises
    ------
    AssertionError
        A contract violation, with a message naming the class and what failed.
    RuntimeError
        ``engine=True`` but the core pipeline (:func:`xpersson.solve`) is not importable.
    """
    report: dict[str, Any] = {}
    name = qual(cls)
    if not isinstance(cls, type) or not issubclass(cls, Plugin):
        raise AssertionError(f"{cls!r} is not a plugin class (derive from a base in GROUPS)")
    group = cls.group
    report["metadata"] = _check_metadata(cls, name)

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
    report.update(check_fast_paths(cls, values, scene, engine=engine))
    return report


def _check_metadata(cls: type[Plugin], name: str) -> str:
    """The class's declarations (as at definition time), its API version, and
    ``archived_params()`` where a parameter names a file."""
    try:
        check_plugin_class(cls)
    except SpecError as exc:
        raise AssertionError(f"metadata: {exc}") from None
    assert not getattr(cls, "abstract", True), f"{name} is abstract"
    assert cls.api_version <= API_VERSION, f"{name}: api_version {cls.api_version} too new"
    paths = [k for k, spec in cls.parameters.items() if spec.kind == "path"]
    assert not paths or callable(getattr(cls, "archived_params", None)), (
        f"{name}: parameters {paths} name files, so the class must define archived_params() "
        "(the file's table as inline parameters: an archive holds no machine-specific path "
        "and rebuilds the plugin without the file; docs/contracts.md)"
    )
    return "ok"


def _check_import(cls: type, budget: float) -> str:
    module = cls.__module__
    if module == "__main__" or "<locals>" in cls.__qualname__:
        raise AssertionError(
            f"{qual(cls)} must be defined at module level of an importable module "
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
    _equal(psd1.C(q), psd2.C(q), f"{qual(type(inst))}.build().C(q)")
    assert np.all(np.asarray(psd1.C(q)) >= 0), "C(q) must be non-negative"
    return "ok"


def _check_coefficient(inst: Any, clone: Any) -> str:
    import numpy as np

    ctx = _tiny_context()
    who = qual(type(inst))
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

    from ..physics import elastic
    from ..plugins import DiffusionClock

    ctx = _tiny_context()
    who = qual(type(inst))
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
    before = _state(inst)
    for p0 in ctx.p0:
        w1, w2 = inst.walls(ctx, float(p0), clock), clone.walls(ctx, float(p0), clock)
        assert isinstance(w1, tuple) and len(w1) == 2, f"{who}.walls must return (lower, upper)"
        assert w1[0] is not None, f"{who}.walls: the lower wall is required"
        for k, (a, b) in enumerate(zip(w1, w2, strict=True)):
            assert (a is None) == (b is None), f"{who}.walls: two identical calls differ"
            if a is not None:
                _equal(a.at(taus), b.at(taus), f"{who}.walls()[{k}] position")
    changed = _changed(before, _state(inst))
    assert not changed, (
        f"{who}.walls() changed the instance's attributes {changed}: plugin methods are "
        "side-effect free, so nothing may pass from walls() to interpret() through self "
        "(interpret() reads the run's clock as ctx.clock)"
    )
    return "ok"


def _state(inst: Any) -> dict[str, tuple[int, bytes]]:
    """Each attribute of ``inst``: the object bound to it (its id) and its pickled content
    (what :meth:`__getstate__` ships, so that a container filled in place shows too)."""
    shipped = inst.__getstate__()
    if not isinstance(shipped, dict):  # a class with its own state format: compare it whole
        shipped = {"__getstate__()": shipped}
    out = {name: (id(value), b"") for name, value in vars(inst).items()}
    for name, value in shipped.items():
        out[name] = (out.get(name, (id(value), b""))[0], _pickled(value))
    return out


def _pickled(value: Any) -> bytes:
    try:
        return pickle.dumps(value)
    except Exception as exc:  # e.g. a clock's closures: the snapshot still tells it apart
        return f"unpicklable ({type(exc).__name__})".encode()


def _changed(before: dict[str, Any], after: dict[str, Any]) -> list[str]:
    """Names of the attributes added, removed, rebound or modified between two snapshots."""
    return sorted(k for k in before.keys() | after.keys() if before.get(k) != after.get(k))


def _check_analysis(inst: Any, clone: Any) -> str:
    return "ok (checked end to end)"


_GROUP_CHECKS = {
    "spectra": _check_spectrum,
    "coefficients": _check_coefficient,
    "boundaries": _check_boundary,
    "analyses": _check_analysis,
}


def _solver() -> Any:
    try:
        from .. import solve
    except Exception as exc:  # the core pipeline is optional for the metadata checks
        raise RuntimeError(
            "check_plugin: the end-to-end checks need xpersson.solve, which cannot be imported "
            f"({type(exc).__name__}: {exc}); pass engine=False to run only the unit checks"
        ) from exc
    return solve


def _check_engine(
    cls: type[Plugin],
    params: Mapping[str, Any],
    scene: Mapping[str, Any] | None,
    tol: float | None,
) -> str:
    import numpy as np

    solve = _solver()
    who = qual(cls)
    sc = tiny_scene(cls, params, scene)
    if tol is None:
        solver = sc.get("solver", {})
        tol = 10.0 * (float(solver.get("rtol", 1e-6)) + float(solver.get("atol", 1e-12)))
    with registry_with(**{cls.group: {CHECK_NAME: cls}}):
        ds1 = solve(copy.deepcopy(sc))
        ds2 = solve(copy.deepcopy(sc))
    assert_schema(ds1)
    names = list(cls.outputs) + ["area_fraction"]
    for var in names:
        assert var in ds1, f"{who}: declared output {var!r} is missing from the Dataset"
        spec = cls.outputs.get(var)
        if spec is not None:
            got = {k: ds1[var].attrs.get(k) for k in ("units", "long_name")}
            want = {"units": caret_units(spec.units), "long_name": spec.long_name}
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
