"""Schema assertions: the CF conventions every xpersson Dataset keeps."""

from __future__ import annotations

from typing import Any

from ..units import udunits_to_pint, ureg

__all__ = ["KNOWN_DIMS", "assert_schema"]

#: Dimensions of the core Dataset (sweep dimensions are accepted when they have a coordinate).
KNOWN_DIMS = ("p0", "zeta", "p", "q_psd")


def assert_schema(ds: Any, extra_dims: tuple[str, ...] = ()) -> None:
    """Assert the CF conventions of an xpersson Dataset.

    Every variable and coordinate has non-empty ``units`` and ``long_name`` attributes; every
    dimension is one of :data:`KNOWN_DIMS` (plus ``extra_dims``) or a sweep dimension with its
    own coordinate; units parse as UDUNITS strings (checked through pint, a dependency of
    xpersson, with :func:`xpersson.units.udunits_to_pint`; a unit registry that cannot be
    built raises instead of skipping the unit checks).

    Raises
    ------
    AssertionError
        Listing every problem found.
    """
    problems: list[str] = []
    reg = ureg()
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
        if isinstance(units, str) and units.strip():
            try:
                reg.Unit(udunits_to_pint(units))
            except Exception as exc:
                problems.append(f"{name}: units {units!r} do not parse ({type(exc).__name__})")
    if problems:
        raise AssertionError("Dataset schema problems:\n  " + "\n  ".join(problems))
