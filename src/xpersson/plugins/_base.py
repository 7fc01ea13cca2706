"""Base classes of the four plugin groups and their class-level contract.

Every concrete plugin class declares ``api_version``, ``summary``, ``references``,
``parameters`` and ``outputs``; they are checked when the class is defined
(:meth:`Plugin.__init_subclass__`), so a malformed plugin fails on import with a message naming
the class. Instances hold their parameters as SI floats (resolved by :mod:`xpersson.scene`),
are deterministic, side-effect free and picklable.
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from types import MappingProxyType
from typing import TYPE_CHECKING, Any, ClassVar

from ._specs import ParamSpec, SpecError, VarSpec

if TYPE_CHECKING:  # pragma: no cover
    import numpy as np
    import xarray as xr

    from ..engine import EngineResult, Wall
    from ._context import DiffusionClock, SceneContext

__all__ = [
    "API_VERSION",
    "Plugin",
    "Spectrum",
    "Coefficient",
    "Boundary",
    "Analysis",
    "GROUPS",
]

API_VERSION = 1
"""Major version of the plugin API this core implements."""

_DOI = re.compile(r"^(doi:)?10\.\d{4,9}/\S+$|^arXiv:\S+$|^https?://\S+$", re.IGNORECASE)


class Plugin:
    """Common base of all plugins.

    Class attributes
    ----------------
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
    """

    group: ClassVar[str] = ""
    api_version: ClassVar[int] = API_VERSION
    summary: ClassVar[str] = ""
    references: ClassVar[tuple[str, ...]] = ()
    parameters: ClassVar[Mapping[str, ParamSpec]] = {}
    outputs: ClassVar[Mapping[str, VarSpec]] = {}
    #: set on abstract intermediate classes to skip the metadata check
    abstract: ClassVar[bool] = True

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        if cls.__dict__.get("abstract", False):
            return
        cls.abstract = False
        _check_class(cls)

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


def _check_class(cls: type[Plugin]) -> None:
    name = f"{cls.__module__}.{cls.__qualname__}"
    if cls.group not in GROUPS:
        raise SpecError(f"{name}: derive from Spectrum, Coefficient, Boundary or Analysis")
    if (
        not isinstance(cls.api_version, int)
        or isinstance(cls.api_version, bool)
        or cls.api_version < 1
    ):
        raise SpecError(f"{name}: api_version must be a positive int, got {cls.api_version!r}")
    if not isinstance(cls.summary, str) or not cls.summary.strip():
        raise SpecError(f"{name}: summary must be a non-empty one-line string")
    if isinstance(cls.references, str) or not isinstance(cls.references, tuple | list):
        raise SpecError(
            f"{name}: references must be a tuple of DOIs ('10.xxxx/...'), 'arXiv:...' ids or URLs"
        )
    bad = [r for r in cls.references if not (isinstance(r, str) and _DOI.match(r))]
    if bad:
        raise SpecError(
            f"{name}: references {bad} are not DOIs ('10.xxxx/...'), 'arXiv:...' ids or URLs"
        )
    if not isinstance(cls.parameters, Mapping):
        raise SpecError(f"{name}: parameters must be a mapping name -> ParamSpec")
    for pname, spec in cls.parameters.items():
        if not isinstance(spec, ParamSpec):
            raise SpecError(f"{name}.parameters[{pname!r}] must be a ParamSpec, got {spec!r}")
        spec.check(name, pname)
    if not isinstance(cls.outputs, Mapping):
        raise SpecError(f"{name}: outputs must be a mapping name -> VarSpec")
    for vname, vspec in cls.outputs.items():
        if not isinstance(vspec, VarSpec):
            raise SpecError(f"{name}.outputs[{vname!r}] must be a VarSpec, got {vspec!r}")
        vspec.check(name, vname)
    extra = GROUP_CHECKS.get(cls.group)
    if extra is not None:
        extra(cls, name)


class Spectrum(Plugin):
    """A roughness power spectrum. Group ``xpersson.spectra``.

    Subclasses implement :meth:`build`, returning an object with the interface of
    :class:`xpersson.physics.psd.PowerSpectrum` (``C(q)`` in m^4, Persson's isotropic
    convention; ``q_L``, ``q_1`` in 1/m; ``moment``, ``I3``, ``nodes``).
    """

    group = "spectra"
    abstract = True

    def build(self) -> Any:
        """Return the numerical power spectrum (SI units)."""
        raise NotImplementedError


class Coefficient(Plugin):
    """The diffusion coefficient f(zeta) [Pa^2]. Group ``xpersson.coefficients``."""

    group = "coefficients"
    abstract = True

    def f(self, ctx: SceneContext, zeta: np.ndarray) -> np.ndarray:
        """Diffusion coefficient f(zeta) in Pa^2 at magnifications ``zeta`` (>= 1)."""
        raise NotImplementedError

    def tau(self, ctx: SceneContext, zeta: np.ndarray) -> np.ndarray:
        """Diffusion time tau(zeta) = int_1^zeta f dzeta in Pa^2 (exact where possible)."""
        raise NotImplementedError

    def effective_tau(self, ctx: SceneContext, zeta: np.ndarray) -> np.ndarray:
        """Diffusion time per load, shape ``(n_load, n_zeta)`` in Pa^2.

        Differs from :meth:`tau` only for state-dependent closures (correction factors whose
        variance depends on the running contact area); the default broadcasts :meth:`tau`.
        """
        import numpy as np

        t = np.asarray(self.tau(ctx, zeta), dtype=float)
        return np.broadcast_to(t, (ctx.p0.size, t.size)).copy()

    def interpret(self, ctx: SceneContext) -> dict[str, tuple[tuple[str, ...], np.ndarray]]:
        """Variables the coefficient contributes to the Dataset (dims, data).

        E.g. the angular averages of a viscoelastic modulus on the ``zeta`` grid, which
        downstream analyses read instead of re-deriving them. Returned names must be declared
        in :attr:`outputs`; the default contributes nothing.
        """
        return {}


class Boundary(Plugin):
    """The walls of the pressure domain and the meaning of what they absorb.

    Group ``xpersson.boundaries``. Walls are given in diffusion time tau (Pa^2); use
    ``clock.zeta_of_tau`` to express a wall law given in zeta.
    """

    group = "boundaries"
    abstract = True

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

    group = "analyses"
    abstract = True
    requires: ClassVar[tuple[str, ...]] = ()
    provides: ClassVar[tuple[str, ...]] = ()

    def compute(self, ctx: SceneContext, ds: xr.Dataset) -> dict[str, Any]:
        """Return ``{name: DataArray or (dims, data)}`` for every name in :attr:`provides`."""
        raise NotImplementedError


def _check_analysis(cls: type[Plugin], name: str) -> None:
    for attr in ("requires", "provides"):
        val = getattr(cls, attr)
        if isinstance(val, str) or not all(isinstance(v, str) for v in val):
            raise SpecError(f"{name}: {attr} must be a tuple of variable names")
    missing = [v for v in cls.provides if v not in cls.outputs]  # type: ignore[attr-defined]
    if missing:
        raise SpecError(f"{name}: provides {missing} without declaring them in outputs")
    both = sorted(set(cls.requires) & set(cls.provides))  # type: ignore[attr-defined]
    if both:
        raise SpecError(f"{name}: {both} both required and provided (a cycle of one)")


GROUPS: dict[str, type[Plugin]] = {
    "spectra": Spectrum,
    "coefficients": Coefficient,
    "boundaries": Boundary,
    "analyses": Analysis,
}
GROUP_CHECKS = {"analyses": _check_analysis}
