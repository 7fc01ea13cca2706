"""Base classes of the five plugin groups and their class-level contract.

Every concrete plugin class declares ``api_version``, ``summary``, ``references``,
``parameters`` and ``outputs``; they are checked when the class is defined
(:meth:`Plugin.__init_subclass__`), so a malformed plugin fails on import with a message naming
the class. Instances hold their parameters as SI floats (resolved by :mod:`xpersson.scene`),
are deterministic, side-effect free and picklable.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from types import MappingProxyType
from typing import TYPE_CHECKING, Any, ClassVar

from ..specs import ParamSpec, SpecError, VarSpec
from ._bodyquantity import BodyQuantity
from ._classcheck import check_class
from ._fastpaths import NO_FAST_PATHS, FastPaths, settle
from ._groups import GEOMETRY_SYMMETRIES, PLUGIN_GROUPS

if TYPE_CHECKING:  # pragma: no cover
    import numpy as np
    import xarray as xr

    from ..engine import EngineResult, Wall
    from ._context import DiffusionClock, SceneContext

__all__ = [
    "API_VERSION",
    "BOUNDARY_TRAITS",
    "COEFFICIENT_TRAITS",
    "check_plugin_class",
    "Plugin",
    "Spectrum",
    "Coefficient",
    "Boundary",
    "Analysis",
    "Geometry",
    "GEOMETRY_SYMMETRIES",
    "GROUPS",
]

API_VERSION = 1
"""Major version of the plugin API this core implements."""

BOUNDARY_TRAITS: dict[str, str] = {
    "repulsive": "no tensile stress: contact regions carry p >= 0 (hard-wall repulsion, so "
    "virtual work p0 = -dU_el/du holds for the elastic part)",
    "load_similar": "the contact area depends on the nominal pressure only through "
    "G = tau/p0^2 (a fixed wall at p = 0 and no other pressure scale), so one load's area "
    "curve samples the curve of every load",
    "conservative": "no dissipation: the deformation is elastic and reversible",
}
"""Known boundary traits: physical properties a boundary declares and analyses rely on.

Plugins may declare further traits (any ``snake_case`` word); an analysis that requires a trait
runs with every boundary that declares it, installed now or later.
"""

COEFFICIENT_TRAITS: dict[str, str] = {
    "elastic_spectrum": "tau_c(zeta) is the elastic diffusion time (pi/4) E*^2 int q^3 C of "
    "the scene's spectrum (closures act only through effective_diffusion_time)",
}
"""Known coefficient traits (see :data:`BOUNDARY_TRAITS`)."""


class Plugin:
    """Common base of all plugins.

    Attributes
    ----------
    api_version : int
        Major plugin-API version the class was written for; must be <= :data:`API_VERSION`.
    summary : str
        One line describing the physics.
    references : tuple of str
        DOIs (``"10.1063/1.1388626"``), ``"arXiv:..."`` ids or URLs.
    parameters : Mapping[str, ParamSpec]
        Scene parameters with SI units, defaults and bounds.
    outputs : Mapping[str, VarSpec]
        Dataset variables the plugin contributes.
    fast_paths : FastPaths
        The faster paths the pipeline may take (:mod:`xpersson.plugins._fastpaths`).
    """

    group: ClassVar[str] = ""
    api_version: ClassVar[int] = API_VERSION
    summary: ClassVar[str] = ""
    references: ClassVar[tuple[str, ...]] = ()
    parameters: ClassVar[Mapping[str, ParamSpec]] = {}
    outputs: ClassVar[Mapping[str, VarSpec]] = {}
    #: set on abstract intermediate classes to skip the metadata check
    abstract: ClassVar[bool] = True
    #: The fast paths the class declares (:class:`~xpersson.plugins.FastPaths`: contact
    #: similarity, stacked parameters, shared walls, shared tau); checked at class creation,
    #: not inherited (a subclass declares its own; without one, every path is plain).
    fast_paths: ClassVar[FastPaths] = NO_FAST_PATHS

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        settle(cls, f"{cls.__module__}.{cls.__qualname__}")
        if cls.__dict__.get("abstract", False):
            return
        cls.abstract = False
        check_class(cls)

    def __init__(self, **params: Any) -> None:
        unknown = sorted(set(params) - set(self.parameters))
        if unknown:
            raise TypeError(
                f"{type(self).__name__} got unknown parameter(s) {unknown}; "
                f"allowed: {sorted(self.parameters)}"
            )
        values = {}
        for name, spec in self.parameters.items():
            if name in params:
                values[name] = params[name]
            elif spec.required:
                raise TypeError(f"{type(self).__name__} requires parameter {name!r}")
            else:
                values[name] = spec.default
        self._params = values

    @property
    def params(self) -> Mapping[str, Any]:
        """The resolved parameter values (SI floats)."""
        return MappingProxyType(self._params)

    def __getstate__(self) -> dict[str, Any]:
        return dict(self.__dict__)

    def __setstate__(self, state: dict[str, Any]) -> None:
        self.__dict__.update(state)

    def __repr__(self) -> str:
        args = ", ".join(f"{k}={v!r}" for k, v in self._params.items())
        return f"{type(self).__name__}({args})"

    def __eq__(self, other: object) -> bool:
        if type(self) is not type(other):
            return False
        mine, theirs = self._params, other._params  # type: ignore[attr-defined]
        if mine.keys() != theirs.keys():
            return False
        return all(_same(mine[k], theirs[k]) for k in mine)

    def __hash__(self) -> int:
        return hash((type(self), tuple(sorted((k, repr(v)) for k, v in self._params.items()))))


def _same(a: Any, b: Any) -> bool:
    """Parameter equality that also works for numpy arrays."""
    try:
        return bool(a == b)
    except ValueError:  # arrays: elementwise comparison
        import numpy as np

        return bool(np.array_equal(np.asarray(a), np.asarray(b)))


class Spectrum(Plugin):
    """A roughness power spectrum. Group ``xpersson.spectra``.

    Subclasses implement :meth:`build`, returning an object with the interface of
    :class:`xpersson.physics.psd.PowerSpectrum` (``C(q)`` in m^4, Persson's isotropic
    convention; ``q_L``, ``q_1`` in 1/m; ``moment``, ``I3``, ``nodes``).
    """

    group = PLUGIN_GROUPS["spectrum"]
    abstract = True

    def build(self) -> Any:
        """Return the numerical power spectrum (SI units)."""
        raise NotImplementedError


class Coefficient(Plugin):
    """The diffusion coefficient f(zeta) [Pa^2]. Group ``xpersson.coefficients``."""

    group = PLUGIN_GROUPS["coefficient"]
    abstract = True
    #: Physical properties analyses may rely on (see :data:`COEFFICIENT_TRAITS`).
    traits: ClassVar[frozenset[str]] = frozenset()

    def corrects_variance(self) -> bool:
        """Whether :meth:`effective_tau` differs from :meth:`tau` (a correction closure)."""
        return False

    def variance_factor(self, ctx: SceneContext, area: np.ndarray) -> np.ndarray | None:
        """``S = d tau_eff / d tau_c`` [1] at the running contact area ``area`` (n_load, n_zeta).

        ``None`` when unknown; analyses then take it from the Dataset's diffusion times. The
        elastic energy of a closure is ``(pi E*/2) int q^2 C A S dq``.
        """
        return None

    def f(self, ctx: SceneContext, zeta: np.ndarray) -> np.ndarray:
        """Diffusion coefficient f(zeta) in Pa^2 at magnifications ``zeta`` (>= 1).

        ``zeta`` may have any shape (the engine's clocks pass 1-D and 2-D arrays); return an
        array of the same shape.
        """
        raise NotImplementedError

    def tau(self, ctx: SceneContext, zeta: np.ndarray) -> np.ndarray:
        """Diffusion time tau(zeta) = int_1^zeta f dzeta in Pa^2 (exact where possible).

        ``zeta`` may have any shape; return an array of the same shape.
        """
        raise NotImplementedError

    def effective_tau(self, ctx: SceneContext, zeta: np.ndarray) -> np.ndarray:
        """Diffusion time per load, shape ``(n_load, n_zeta)`` in Pa^2.

        Differs from :meth:`tau` only for state-dependent closures (correction factors whose
        variance depends on the running contact area); the default broadcasts :meth:`tau`.
        """
        import numpy as np

        t = np.asarray(self.tau(ctx, zeta), dtype=float)
        return np.broadcast_to(t, (ctx.p0.size, t.size)).copy()

    def clock_key(self, ctx: SceneContext) -> Any:
        """A content key of :meth:`tau` and :meth:`f` on ``ctx`` (numbers, strings, arrays,
        spectra: what :func:`xpersson.cache.content_key` takes) whose equality means equal
        functions, or ``None`` (the default: unknown, e.g. a coefficient reading a file).

        With a key, the run's :class:`~xpersson.plugins.DiffusionClock` shares its inverse's
        tables with later solves, and tables derived from it (an adhesive wall's) are keyed
        on it instead of on its samples.
        """
        del ctx
        return None

    def interpret(self, ctx: SceneContext) -> dict[str, tuple[tuple[str, ...], np.ndarray]]:
        """Variables the coefficient contributes to the Dataset (dims, data).

        E.g. the angular averages of a viscoelastic modulus on the ``zeta`` grid, which
        downstream analyses read instead of re-deriving them. Returned names must be declared
        in :attr:`outputs`; the default contributes nothing.
        """
        return {}

    def tau_stacked(
        self, ctxs: Sequence[SceneContext], points: Sequence[Coefficient], zeta: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        """``(tau, f)`` [Pa^2] of a block of points, each ``(n_point, n_zeta)``.

        ``points`` are the points' coefficients (``self`` is the first; their parameters differ
        only in the declared ``fast_paths.stacked_params``), ``ctxs`` their contexts. Called
        only for classes that declare a stacked path; the default asks each point.
        """
        import numpy as np

        tau = np.stack(
            [np.asarray(c.tau(x, zeta), float) for c, x in zip(points, ctxs, strict=True)]
        )
        f = np.stack([np.asarray(c.f(x, zeta), float) for c, x in zip(points, ctxs, strict=True)])
        return tau, f

    def interpret_stacked(
        self, ctxs: Sequence[SceneContext], points: Sequence[Coefficient]
    ) -> dict[str, tuple[tuple[str, ...], np.ndarray]]:
        """:meth:`interpret` of a block: every value with a leading point axis (its dims
        without it). Called as :meth:`tau_stacked` is; the default asks each point."""
        import numpy as np

        outs = [c.interpret(x) for c, x in zip(points, ctxs, strict=True)]
        return {
            n: (dims, np.stack([np.asarray(o[n][1]) for o in outs]))
            for n, (dims, _) in outs[0].items()
        }


class Boundary(Plugin):
    """The walls of the pressure domain and the meaning of what they absorb.

    Group ``xpersson.boundaries``. Walls are given in diffusion time tau (Pa^2); use
    ``clock.zeta_of_tau`` to express a wall law given in zeta.
    """

    group = PLUGIN_GROUPS["boundary"]
    abstract = True
    #: Physical properties analyses may rely on (see :data:`BOUNDARY_TRAITS`).
    traits: ClassVar[frozenset[str]] = frozenset()
    #: Dataset variables whose sum is the contact area that carries the load.
    contact_area: ClassVar[tuple[str, ...]] = ("area_fraction",)
    #: Dataset variable of the elastically deformed contact area (stores elastic energy).
    elastic_area: ClassVar[str] = "area_fraction"
    #: Dataset variables whose sum is ``1 - elastic_area`` without cancellation.
    elastic_area_complement: ClassVar[tuple[str, ...]] = ("non_contact_fraction",)
    #: Whether the boundary accepts tensile nominal loads ``p0 <= 0`` (adhesion); the scene
    #: then checks only that ``p0`` is finite and :meth:`validate` states the allowed range.
    tensile_loads: ClassVar[bool] = False

    def validate(self, ctx: SceneContext) -> None:  # noqa: B027 - optional hook
        """Check the scene against this boundary (e.g. p0 below the yield stress).

        Raise ``ValueError`` naming the parameter, its unit and the allowed range.
        """

    def walls(
        self, ctx: SceneContext, p0: float, clock: DiffusionClock
    ) -> tuple[Wall, Wall | None]:
        """Lower and upper wall (``None`` for none) for one load ``p0`` [Pa]."""
        raise NotImplementedError

    def interpret(
        self, ctx: SceneContext, results: list[EngineResult]
    ) -> dict[str, tuple[tuple[str, ...], np.ndarray]]:
        """Variables derived from the per-load engine results (dims, data).

        The core already stores ``area_fraction`` (probability in the domain) and the
        diagnostics; this hook gives the absorbed fluxes their meaning (non-contact area,
        plastic area, ...). Returned names must be declared in :attr:`outputs`.
        """
        return {}


class Analysis(Plugin):
    """A downstream analysis of a solved Dataset. Group ``xpersson.analyses``.

    Declares ``requires`` (Dataset variables it reads) and ``provides`` (variables it adds,
    each declared in :attr:`outputs`). Runs only when a scene asks for it or for what it
    provides.
    """

    group = PLUGIN_GROUPS["analysis"]
    abstract = True
    requires: ClassVar[tuple[str, ...]] = ()
    provides: ClassVar[tuple[str, ...]] = ()
    #: Traits the scene's boundary must declare (see :data:`BOUNDARY_TRAITS`).
    boundary_traits: ClassVar[frozenset[str]] = frozenset()
    #: Traits the scene's coefficient must declare (see :data:`COEFFICIENT_TRAITS`).
    coefficient_traits: ClassVar[frozenset[str]] = frozenset()
    #: Local quantities a finite body integrates over its nominal pressure (name ->
    #: :class:`~xpersson.plugins.BodyQuantity`; see :mod:`xpersson.plugins._bodyquantity`).
    body_quantities: ClassVar[Mapping[str, BodyQuantity]] = MappingProxyType({})

    @classmethod
    def supports(cls, boundary: type | None = None, coefficient: type | None = None) -> str | None:
        """Why this analysis cannot run with a boundary/coefficient class (``None``: it can).

        The default compares the declared traits; the message names what is missing.
        """
        for kind, other, need in (
            ("boundary", boundary, cls.boundary_traits),
            ("coefficient", coefficient, cls.coefficient_traits),
        ):
            if other is None:
                continue
            have = frozenset(getattr(other, "traits", ()))
            missing = sorted(need - have)
            if missing:
                known = BOUNDARY_TRAITS if kind == "boundary" else COEFFICIENT_TRAITS
                why = "; ".join(f"{t}: {known.get(t, 'declared by the plugin')}" for t in missing)
                need_s, have_s = ", ".join(missing), ", ".join(sorted(have)) or "none"
                return (
                    f"this analysis needs a {kind} declaring trait(s) {need_s} ({why}); "
                    f"{other.__qualname__} declares {have_s}"
                )
        return None

    def check_scene(self, coefficient: Coefficient, boundary: Boundary) -> None:
        """Refuse a scene before any work (``ValueError`` naming the reason).

        Called when a scene is resolved; the default applies :meth:`supports`. Override to add
        parameter/scene contradictions (call ``super().check_scene`` first).
        """
        why = type(self).supports(type(boundary), type(coefficient))
        if why:
            raise ValueError(why)

    def validate(self, ctx: SceneContext) -> None:  # noqa: B027 - optional hook
        """Check the scene's context (loads, magnifications, material) before any solving.

        Called by the pipeline after the boundary's :meth:`Boundary.validate` and before the
        engine runs. Raise ``ValueError`` naming the parameter, its unit and the allowed range.
        """

    def compute(self, ctx: SceneContext, ds: xr.Dataset) -> dict[str, Any]:
        """Return ``{name: DataArray or (dims, data)}`` for every name in :attr:`provides`."""
        raise NotImplementedError

    def compute_stacked(
        self, ctx_of: Callable[[int], SceneContext], ds: xr.Dataset
    ) -> dict[str, Any]:
        """:meth:`compute` of a block: ``ds`` carries the points on a leading ``point``
        dimension, ``ctx_of(k)`` is point k's context (with ``solve_at``). Return
        ``{name: DataArray}`` (or ``(dims, array)`` pairs) with the ``point`` dimension.
        Called only for classes that declare ``fast_paths.stacked_params``; the default
        computes each point.
        """
        import xarray as xr

        outs = [self.compute(ctx_of(k), ds.isel(point=k)) for k in range(ds.sizes["point"])]
        return {
            n: xr.concat([_as_array(o[n]) for o in outs], dim="point", coords="minimal")
            for n in outs[0]
        }


class Geometry(Plugin):
    """A finite body pressed on the rough flat by a total force. Group ``xpersson.geometries``.

    The body is given by its undeformed gap above the flat's mean plane, :meth:`profile`
    ``h(r)`` [m] with ``h(0) = 0``, over the radius ``r`` of an axisymmetric body or the distance
    ``x`` from the line of a plane (line) contact. The core solves the nominal pressure
    ``p(r)`` from the elastic half-space and the interfacial separation ``u(p)`` of the solved
    rough contact (:mod:`xpersson.physics.body`); a geometry only describes the body. The
    :meth:`reference` smooth contact (Hertz for a sphere) sets the scale of the radial grid.
    Declares no ``outputs``: the per-force variables are the core's.
    """

    group = PLUGIN_GROUPS["geometry"]
    abstract = True
    #: One of :data:`GEOMETRY_SYMMETRIES`.
    symmetry: ClassVar[str] = "axisymmetric"

    def profile(self, r: np.ndarray) -> np.ndarray:
        """Undeformed gap ``h(r)`` [m] at radii (or distances) ``r`` [m] >= 0; ``h(0) = 0``."""
        raise NotImplementedError

    def extent(self) -> float:
        """Largest radius [m] the nominal contact may reach (small slopes, the body's size)."""
        raise NotImplementedError

    def reference(self, load: float, E_star: float) -> tuple[float, float, float]:
        """The smooth contact at ``load`` (see :meth:`solver_load`) and contact modulus
        ``E_star`` [Pa]: ``(radius [m], approach [m], peak pressure [Pa])``."""
        raise NotImplementedError

    def solver_load(self, force: float) -> float:
        """The load the pressure carries: the force [N] (axisymmetric) or, for a plane
        contact, the force per length [N/m]."""
        return float(force)

    def roughness_parameter(self, h_rms: float, load: float, E_star: float) -> float:
        """Johnson's roughness parameter ``sigma R / a0^2`` [1] (NaN when undefined)."""
        return float("nan")

    def check_force(self, force: float, E_star: float) -> None:
        """Refuse a force whose smooth contact outgrows :meth:`extent` (``ValueError`` naming
        the force, its unit and the allowed range)."""
        limit = self.extent()
        radius = self.reference(self.solver_load(force), E_star)[0]
        if radius <= limit:
            return
        lo, hi = 0.0, float(force)  # the reference radius grows with the force: bisect
        for _ in range(200):
            mid = 0.5 * (lo + hi)
            if self.reference(self.solver_load(mid), E_star)[0] <= limit:
                lo = mid
            else:
                hi = mid
        raise ValueError(
            f"force = {force:g} N: its smooth contact radius {radius:.4g} m exceeds "
            f"{limit:.4g} m, the largest this body and the small-slope theory allow; "
            f"allowed force in (0, {lo:.4g}] N"
        )


def _as_array(value: Any) -> Any:
    """A DataArray of a plugin's ``DataArray or (dims, data)`` value."""
    import xarray as xr

    return value if isinstance(value, xr.DataArray) else xr.DataArray(value[1], dims=value[0])


def check_plugin_class(cls: type) -> None:
    """Check a plugin class as at definition time (raises :class:`SpecError`)."""
    if not isinstance(cls, type) or not issubclass(cls, Plugin):
        raise SpecError(f"{cls!r} is not a plugin class (derive from Spectrum, Coefficient, ...)")
    check_class(cls)


GROUPS: dict[str, type[Plugin]] = {
    base.group: base for base in (Spectrum, Coefficient, Boundary, Analysis, Geometry)
}
"""Group -> base class (the groups of :data:`PLUGIN_GROUPS`)."""
