"""Schema assertions: the CF conventions every xpersson Dataset keeps."""

from __future__ import annotations

from typing import Any

from ..units import udunits_to_pint, ureg

__all__ = ["KNOWN_DIMS", "assert_schema"]

#: Dimensions of the core Dataset (sweep dimensions are accepted when they have a coordinate).
KNOWN_DIMS = ("p0", "zeta", "p", "q_psd")


def _unit_parser() -> Any:
    try:
        return ureg()
    except Exception:  # pint missing: units are not checkable
        return None


def assert_schema(ds: Any, extra_dims: tuple[str, ...] = ()) -> None:
    """Assert the CF conventions of an xpersson Dataset.

    Every variable and coordinate has non-empty ``units`` and ``long_name`` attributes; every
    dimension is one of :data:`KNOWN_DIMS` (plus ``extra_dims``) or a sweep dimension with its
    own coordinate; units parse as UDUNITS strings (checked through pint when available, with
    :func:`xpersson.units.udunits_to_pint`).

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
                reg.Unit(udunits_to_pint(units))
            except Exception as exc:
                problems.append(f"{name}: units {units!r} do not parse ({type(exc).__name__})")
    if problems:
        raise AssertionError("Dataset schema problems:\n  " + "\n  ".join(problems))
