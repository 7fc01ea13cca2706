"""The fast-path contract: what a plugin class declares so that the pipeline may take a faster
path than solving each load and each sweep point on its own.

A plugin declares its fast paths in one place, ``fast_paths = FastPaths(...)`` on its class;
everything else is the plain path (each load asked, each sweep point solved alone). The
declaration is checked when the class is created (:func:`settle`, called by
:meth:`xpersson.plugins.Plugin.__init_subclass__`), and :func:`xpersson.testing.check_plugin`
runs every declared path against the plain path (:mod:`xpersson.testing.fastpaths`).

The declaration is **not inherited**: a subclass may change the physics a promise rests on, so
a class without its own ``fast_paths`` gets :data:`NO_FAST_PATHS` (every path plain) and
declares its paths again where they still hold.

:func:`plain_paths` (a ``with`` block) and the option ``fast_paths``
(``xpersson.set_options(fast_paths=False)``, ``XPERSSON_FAST_PATHS=off``) send everything down
the plain path (tests and :func:`~xpersson.testing.check_plugin` compare the two).
"""

from __future__ import annotations

import contextlib
import dataclasses
import difflib
import threading
import types
from collections.abc import Iterator, Mapping
from typing import Any

from ..options import fast_paths_enabled
from ..specs import SpecError

__all__ = ["FastPaths", "NO_FAST_PATHS", "fast_paths_on", "plain_paths", "settle"]


@dataclasses.dataclass(frozen=True)
class FastPaths:
    """The fast paths a plugin class declares (``fast_paths = FastPaths(...)``).

    Parameters
    ----------
    contact_similarity : bool
        Coefficients, boundaries, analyses. Promise: the plugin's outputs depend on the
        material only through E*, and are unchanged in units of E* when E* and every load
        scale together (an output in Pa^n scales as E*^n). Path: a sweep over
        ``material.E`` / ``material.nu`` is solved as one batch of equivalent loads
        (:mod:`xpersson.sweep.batched`), used when every plugin of the scene declares it.
        Check: a solve at (E*, p0) equals one at (k E*, k p0) in units of E* (1e-12 relative).
    stacked_params : frozenset of str or None
        Every group. ``None``: no stacked path. A set (possibly empty) of the class's own
        parameter names that may differ between the points of a sweep block solved as one run
        (:mod:`xpersson.pipeline.stacked`): the plugin accepts a block stacked over a point axis
        through its ``*_stacked`` methods (:meth:`~xpersson.plugins.Coefficient.tau_stacked`,
        :meth:`~xpersson.plugins.Coefficient.interpret_stacked`,
        :meth:`~xpersson.plugins.Analysis.compute_stacked`; the base classes' versions loop over
        the points). Used when every plugin of the scene declares it, the boundary also declares
        ``shared_walls``, and the points differ only in declared parameters. Check: a sweep
        over the declared parameters through the stacked path equals the point-by-point path
        (1e-12 relative).
    shared_walls : bool
        Boundaries. Promise: :meth:`~xpersson.plugins.Boundary.walls` gives the same walls for
        every load ``p0``. Path: the walls are asked once for every load of a run (and of a
        stacked block). Check: the walls at several loads are at the same positions (1e-12
        relative).
    wall_tables : bool
        Boundaries. Promise: every moving wall :meth:`~xpersson.plugins.Boundary.walls` gives
        carries a table (``Wall.absorbing(position, table=WallTable(...))``, the compiled wall
        protocol of :class:`xpersson.engine.WallTable`: a clipped piecewise polynomial in tau)
        with the positions of its callable. Path: where the compiled code runs, the engine
        evaluates the table (positions, window-edge kinks) in compiled code instead of calling
        the position back. The plugin attaches the tables only while
        :func:`fast_paths_on` (the plain path: the callables alone). Check: the tables' positions
        equal the callables' at times across and beyond each table (1e-12 relative) and a
        solve equals the plain path's (1e-12 relative).
    shared_tau : bool or Mapping
        Coefficients. Promise: :meth:`~xpersson.plugins.Coefficient.effective_tau` equals
        :meth:`~xpersson.plugins.Coefficient.tau` at every load: always (``True``) or on the
        instances whose parameters have the given values (``{"closure": "persson01"}``).
        Path: the pipeline uses ``tau(zeta)`` for every load without asking ``effective_tau``
        (which would only broadcast it). A class that does not override ``effective_tau``
        has this path without declaring it. Check: every ``effective_tau`` row equals
        ``tau(zeta)`` (1e-12 relative).
    reused : bool
        Spectra, coefficients, boundaries, analyses. Promise: what an instance gives depends
        only on its class, its parameters and each call's arguments (no call changes what a
        later call gives, nor the instance: an analysis completes its parameters in
        ``__init__`` or ``check_scene`` only; nothing is read but the parameters and a
        ``kind="path"`` parameter's file). Path: :func:`xpersson.solve` of a flat scene whose
        plugins and analyses (those requested and the providers they pull in) all declare it,
        none with a file parameter, resolves the scene once per content and its later solves
        reuse the instances (:func:`xpersson.pipeline.frontend.resolve`). Check: a scene
        solved a second time (on the reused resolution) equals its solve inside
        :func:`plain_paths` (resolved afresh).
    """

    contact_similarity: bool = False
    stacked_params: frozenset[str] | None = None
    shared_walls: bool = False
    shared_tau: bool | Mapping[str, Any] = False
    wall_tables: bool = False
    reused: bool = False

    def __post_init__(self) -> None:
        sp = self.stacked_params
        if isinstance(sp, set | list | tuple):  # a frozenset whatever collection was given
            object.__setattr__(self, "stacked_params", frozenset(sp))
        if isinstance(self.shared_tau, Mapping):  # read-only
            object.__setattr__(self, "shared_tau", types.MappingProxyType(dict(self.shared_tau)))

    def __repr__(self) -> str:
        given = {
            f.name: dict(v) if isinstance(v, Mapping) else v
            for f in dataclasses.fields(self)
            if (v := getattr(self, f.name)) != f.default
        }
        return f"FastPaths({', '.join(f'{k}={v!r}' for k, v in given.items())})"

    def declared(self) -> tuple[str, ...]:
        """The names of the paths declared (``stacked`` for ``stacked_params``)."""
        return tuple(
            name
            for name, on in (
                ("contact_similarity", self.contact_similarity),
                ("stacked", self.stacked_params is not None),
                ("shared_walls", self.shared_walls),
                ("shared_tau", self.shared_tau is not False),
                ("wall_tables", self.wall_tables),
                ("reused", self.reused),
            )
            if on
        )

    def stacks(self, name: str) -> bool:
        """Whether parameter ``name`` may differ between the points of a stacked block."""
        return self.stacked_params is not None and name in self.stacked_params

    def tau_shared(self, params: Mapping[str, Any]) -> bool:
        """Whether the declaration promises ``effective_tau == tau`` for an instance with
        these parameters (``shared_tau`` True, or each given parameter at its value)."""
        cond = self.shared_tau
        if isinstance(cond, Mapping):
            return all(k in params and params[k] == v for k, v in cond.items())
        return cond is True


NO_FAST_PATHS = FastPaths()
"""No fast path: every load and every sweep point on the plain path."""

_PLAIN = [0]  # plain_paths() blocks open now
_PLAIN_LOCK = threading.Lock()


@contextlib.contextmanager
def plain_paths() -> Iterator[None]:
    """Run everything on the plain path while the block runs: every load asked for its own
    walls and effective tau, every sweep point resolved and solved on its own (no batch of
    loads, no stacked block), whatever the plugins declare.

    The reference the fast paths are checked against (the tests,
    :func:`xpersson.testing.check_plugin`). Process-wide while open, like
    ``xpersson.set_options(fast_paths=False)`` (threads see it; dask worker processes do not:
    start them with ``XPERSSON_FAST_PATHS=off`` for that); blocks nest, also across threads.

    Examples
    --------
    >>> from xpersson.sweep import plain_paths
    >>> with plain_paths():  # doctest: +SKIP
    ...     reference = xpersson.solve(scene)
    """
    with _PLAIN_LOCK:
        _PLAIN[0] += 1
    try:
        yield
    finally:
        with _PLAIN_LOCK:
            _PLAIN[0] -= 1


def fast_paths_on() -> bool:
    """Whether declared fast paths may be taken: no :func:`plain_paths` block is open and the
    ``fast_paths`` option (:func:`xpersson.set_options`, ``XPERSSON_FAST_PATHS``) is on."""
    return _PLAIN[0] == 0 and fast_paths_enabled()


#: Field -> the groups it applies to.
_GROUPS = {
    "contact_similarity": ("coefficients", "boundaries", "analyses"),
    "stacked_params": ("spectra", "coefficients", "boundaries", "analyses"),
    "shared_walls": ("boundaries",),
    "shared_tau": ("coefficients",),
    "wall_tables": ("boundaries",),
    "reused": ("spectra", "coefficients", "boundaries", "analyses"),
}

#: Class attributes of the flags this contract replaced -> the declaration that replaces them.
_REPLACED = {
    "pressure_scaled": "fast_paths = FastPaths(contact_similarity=True)",
    "batched": "fast_paths = FastPaths(stacked_params=frozenset({...}))",
    "walls_per_load": "fast_paths = FastPaths(shared_walls=True)",
    "tau_per_load": "fast_paths = FastPaths(shared_tau=True) (or shared_tau={param: value})",
}
_FIELDS = tuple(f.name for f in dataclasses.fields(FastPaths))
_SPELLINGS = {
    **_REPLACED,
    "fast_paths": "fast_paths = FastPaths(...)",
    **{f: f"fast_paths = FastPaths({f}=...)" for f in _FIELDS},
}


def _suspect(cls: type) -> tuple[str, str] | None:
    """A class attribute that looks like a fast-path declaration made the wrong way (a
    replaced flag, a field set on the class, a near miss of either): ``(name, fix)``."""
    for attr, value in vars(cls).items():
        if attr == "fast_paths" or attr.startswith("__"):
            continue
        if isinstance(value, types.FunctionType | classmethod | staticmethod):
            continue  # methods (e.g. the *_stacked hooks) are not declarations
        hit = difflib.get_close_matches(attr.lower().lstrip("_"), _SPELLINGS, n=1, cutoff=0.8)
        if hit:
            return attr, _SPELLINGS[hit[0]]
    return None


def settle(cls: type, name: str) -> None:
    """Check the fast-path declaration of plugin class ``cls`` (qualified name ``name``) and
    give a class without its own declaration :data:`NO_FAST_PATHS` (the one place where the
    declaration is made not to be inherited).

    Raises
    ------
    SpecError
        A flag or near miss outside ``fast_paths``, a declaration that is not a
        :class:`FastPaths`, a field of the wrong type, a field that does not apply to the
        class's group, or stacked parameters that are not the class's own parameters.
    """
    bad = _suspect(cls)
    if bad is not None:
        raise SpecError(
            f"{name}: class attribute {bad[0]!r} is not a fast-path declaration; declare the "
            f"plugin's fast paths in one place, `{bad[1]}` (xpersson.plugins.FastPaths)"
        )
    if "fast_paths" not in vars(cls):
        cls.fast_paths = NO_FAST_PATHS  # type: ignore[attr-defined]
        return
    fp = vars(cls)["fast_paths"]
    if not isinstance(fp, FastPaths):
        raise SpecError(f"{name}: fast_paths must be a FastPaths(...), got {fp!r}")
    for field in ("contact_similarity", "shared_walls", "wall_tables", "reused"):
        if not isinstance(getattr(fp, field), bool):
            raise SpecError(f"{name}: fast_paths.{field} must be True or False")
    group = getattr(cls, "group", "")
    for field, groups in _GROUPS.items():
        if getattr(fp, field) not in (False, None) and group not in groups:
            raise SpecError(
                f"{name}: fast_paths.{field} applies to {', '.join(groups)} only, not {group}"
            )
    _check_stacked(cls, name, fp.stacked_params)
    _check_shared_tau(cls, name, fp.shared_tau)


def _check_stacked(cls: type, name: str, sp: Any) -> None:
    if sp is None:
        return
    own = getattr(cls, "parameters", {})
    if not isinstance(sp, frozenset) or not all(isinstance(p, str) for p in sp):
        raise SpecError(
            f"{name}: fast_paths.stacked_params must be None or a frozenset of parameter "
            f"names, got {sp!r}"
        )
    unknown = sorted(sp - set(own))
    if unknown:
        raise SpecError(
            f"{name}: fast_paths.stacked_params {unknown} are not parameters of the class "
            f"(its parameters: {sorted(own)})"
        )


def _check_shared_tau(cls: type, name: str, cond: Any) -> None:
    if isinstance(cond, bool):
        return
    own = getattr(cls, "parameters", {})
    if not isinstance(cond, Mapping) or not cond:
        raise SpecError(
            f"{name}: fast_paths.shared_tau must be True, False or a non-empty mapping "
            f"parameter -> value, got {cond!r}"
        )
    for pname, value in cond.items():
        spec = own.get(pname)
        if spec is None:
            raise SpecError(
                f"{name}: fast_paths.shared_tau names {pname!r}, not a parameter of the class "
                f"(its parameters: {sorted(own)})"
            )
        choices = getattr(spec, "choices", None)
        if choices and value not in choices:
            raise SpecError(
                f"{name}: fast_paths.shared_tau[{pname!r}] = {value!r} is not one of the "
                f"parameter's choices {list(choices)}"
            )
