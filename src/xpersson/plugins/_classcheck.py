"""The class-level contract of a plugin, checked when the class is defined.

:func:`check_class` (called from :meth:`Plugin.__init_subclass__ <._base.Plugin>` and
:func:`~._base.check_plugin_class`) checks what every plugin declares (``api_version``,
``summary``, ``references``, ``parameters``, ``outputs``), then its group's declarations
(traits; a boundary's area variables; an analysis's ``requires``, ``provides`` and
``body_quantities``) and its fast
paths (:func:`._fastpaths.settle`).
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from typing import Any

from ..specs import ParamSpec, SpecError, VarSpec
from ._bodyquantity import check_body_quantities
from ._fastpaths import settle
from ._groups import GEOMETRY_SYMMETRIES, GROUP_NAMES

__all__ = ["check_class"]

_TRAIT = re.compile(r"^[a-z][a-z0-9_]*$")

_DOI = re.compile(r"^(doi:)?10\.\d{4,9}/\S+$|^arXiv:\S+$|^https?://\S+$", re.IGNORECASE)


def check_class(cls: type[Any]) -> None:
    """Check a plugin class's declarations (raises :class:`SpecError` naming the class)."""
    name = f"{cls.__module__}.{cls.__qualname__}"
    if cls.group not in GROUP_NAMES:
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
    extra = _GROUP_CHECKS.get(cls.group)
    if extra is not None:
        extra(cls, name)
    settle(cls, name)


def _check_analysis(cls: type[Any], name: str) -> None:
    _check_traits(cls, name)
    for attr in ("requires", "provides"):
        val = getattr(cls, attr)
        if isinstance(val, str) or not all(isinstance(v, str) for v in val):
            raise SpecError(f"{name}: {attr} must be a tuple of variable names")
    missing = [v for v in cls.provides if v not in cls.outputs]
    if missing:
        raise SpecError(f"{name}: provides {missing} without declaring them in outputs")
    both = sorted(set(cls.requires) & set(cls.provides))
    if both:
        raise SpecError(f"{name}: {both} both required and provided (a cycle of one)")
    check_body_quantities(cls, name)


def _check_traits(cls: type[Any], name: str) -> None:
    attrs = ("traits",)
    if cls.group == "analyses":
        attrs = ("boundary_traits", "coefficient_traits")
    for attr in attrs:
        val = getattr(cls, attr)
        if not isinstance(val, frozenset) or not all(
            isinstance(t, str) and _TRAIT.match(t) for t in val
        ):
            raise SpecError(f"{name}: {attr} must be a frozenset of snake_case trait names")


def _check_boundary(cls: type[Any], name: str) -> None:
    _check_traits(cls, name)
    core = ("area_fraction", "non_contact_fraction")
    ca = cls.contact_area
    ea = cls.elastic_area
    comp = cls.elastic_area_complement
    if isinstance(ca, str) or isinstance(comp, str) or not isinstance(ea, str):
        raise SpecError(
            f"{name}: contact_area and elastic_area_complement must be tuples of variable "
            "names, elastic_area one name"
        )
    for var in (*ca, ea, *comp):
        if var not in core and var not in cls.outputs:
            raise SpecError(
                f"{name}: area variable {var!r} is neither a core variable ({', '.join(core)}) "
                "nor declared in outputs"
            )


def _check_geometry(cls: type[Any], name: str) -> None:
    if cls.symmetry not in GEOMETRY_SYMMETRIES:
        raise SpecError(f"{name}: symmetry must be one of {GEOMETRY_SYMMETRIES}")
    if cls.outputs:
        raise SpecError(f"{name}: a geometry declares no outputs (the per-force ones are core)")


_GROUP_CHECKS = {
    "analyses": _check_analysis,
    "geometries": _check_geometry,
    "boundaries": _check_boundary,
    "coefficients": _check_traits,
}
