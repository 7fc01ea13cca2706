"""Declarative metadata of parameters (:class:`ParamSpec`) and outputs (:class:`VarSpec`).

Below both :mod:`xpersson.schema` (the core variables are VarSpecs) and :mod:`xpersson.plugins`
(which re-exports these names for plugin authors).

Specs are plain frozen dataclasses: cheap to import (no pint, no numpy) and checked when a plugin
class is defined, so a malformed declaration fails at import time with a message naming the
plugin and the parameter.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from typing import Any

__all__ = ["REQUIRED", "ParamSpec", "VarSpec", "SpecError"]

_NAME = re.compile(r"^[A-Za-z][A-Za-z0-9_]*$")
KINDS = ("quantity", "choice", "string", "bool", "int", "path")


class SpecError(TypeError):
    """A plugin declares malformed metadata (raised when the class is defined)."""


class _Required:
    def __repr__(self) -> str:
        return "REQUIRED"

    def __reduce__(self) -> str:
        return "REQUIRED"

    def cache_key(self) -> str:
        """The sentinel's content key (a :class:`ParamSpec`'s default keys as this)."""
        return "REQUIRED"


REQUIRED: Any = _Required()
"""Sentinel default: the parameter must be given in the scene."""


@dataclass(frozen=True)
class ParamSpec:
    """Declaration of one plugin parameter.

    Parameters
    ----------
    unit : str
        SI unit in pint syntax (``"Pa"``, ``"1/m"``, ``"J/m**2"``); ``"1"`` for dimensionless.
        Scene values are converted to this unit; the engine only sees SI floats.
    default : object
        Default in ``unit`` (a float for quantities) or :data:`REQUIRED`.
    bounds : tuple of (float or None)
        Allowed range ``(low, high)`` in ``unit``; ``None`` for unbounded.
    inclusive : tuple of bool
        Whether ``low``/``high`` themselves are allowed.
    description : str
        One line shown by ``xpersson plugins show``.
    sweepable : bool
        Whether a scene may give a list of values (a sweep dimension).
    kind : str
        ``"quantity"`` (default), ``"choice"``, ``"string"``, ``"bool"``, ``"int"`` or ``"path"``.
    choices : tuple of str
        Allowed values for ``kind="choice"``.
    array : bool
        Whether the parameter is a 1-D array of quantities (e.g. a table column).
    example : object, optional
        A typical value in ``unit`` (SI float for quantities), used by
        :func:`xpersson.testing.check_plugin` and the documentation when ``default`` is
        :data:`REQUIRED`.
    dim : str, optional
        Name of the Dataset dimension this parameter becomes when a scene sweeps it (a list
        or a range of values); only for ``sweepable`` parameters. ``None`` uses the
        documented default naming rule of the sweep mechanism. Plugins declare their own
        dimensions this way (e.g. a sliding speed ``velocity`` swept as dimension ``"v"``).
    """

    unit: str = "1"
    default: Any = REQUIRED
    bounds: tuple[float | None, float | None] = (None, None)
    inclusive: tuple[bool, bool] = (True, True)
    description: str = ""
    sweepable: bool = False
    kind: str = "quantity"
    choices: tuple[str, ...] = ()
    array: bool = False
    example: Any = None
    dim: str | None = None

    def cache_key(self) -> bytes:
        """The declaration's content key (:func:`xpersson.cache.dataclass_key`: a digest of
        its fields, made once per object): a conversion keyed on it is keyed on every field."""
        key = self.__dict__.get("_content_key")  # kept by dataclass_key: no import to run
        if key is not None:
            return key  # type: ignore[no-any-return]
        from .cache import dataclass_key  # noqa: PLC0415 - specs stay cheap to import

        return dataclass_key(self)

    @property
    def required(self) -> bool:
        """Whether the scene must give this parameter (no default)."""
        return self.default is REQUIRED

    @property
    def sample(self) -> Any:
        """A usable value: the default, else the example (``REQUIRED`` if neither)."""
        if not self.required:
            return self.default
        return REQUIRED if self.example is None else self.example

    def range_text(self) -> str:
        """Human-readable allowed range, e.g. ``"0 < H <= 1"``-style ``"(0, 1]"`` with unit."""
        if self.kind == "choice":
            return "one of " + ", ".join(repr(c) for c in self.choices)
        if self.kind in ("string", "path"):
            return "a string"
        if self.kind == "bool":
            return "true or false"
        lo, hi = self.bounds
        left = ("[" if self.inclusive[0] else "(") + ("-inf" if lo is None else f"{lo:g}")
        right = ("inf" if hi is None else f"{hi:g}") + ("]" if self.inclusive[1] else ")")
        unit = "" if self.unit in ("1", "") else f" {self.unit}"
        return f"{left}, {right}{unit}"

    def in_bounds(self, value: float) -> bool:
        """Whether a value (in ``unit``) lies in the declared range (NaN never does)."""
        if isinstance(value, float) and math.isnan(value):
            return False
        lo, hi = self.bounds
        if lo is not None and (value < lo or (value == lo and not self.inclusive[0])):
            return False
        if hi is not None and (value > hi or (value == hi and not self.inclusive[1])):
            return False
        return True

    def check(self, owner: str, name: str) -> None:
        """Raise :class:`SpecError` if this declaration is malformed."""
        where = f"{owner}.parameters[{name!r}]"
        if not _NAME.match(name):
            raise SpecError(f"{where}: parameter names must match {_NAME.pattern}")
        self._check_fields(where)
        self._check_kind_default(where)
        if self.kind == "choice":
            return
        self._check_bounds(where)
        self._check_numbers(where)

    def _check_fields(self, where: str) -> None:
        """kind, unit, description, flags, choices and dim have the right types."""
        if self.kind not in KINDS:
            raise SpecError(f"{where}: kind must be one of {KINDS}, got {self.kind!r}")
        if not isinstance(self.unit, str) or not self.unit.strip():
            raise SpecError(f"{where}: unit must be a non-empty pint unit string ('1' if none)")
        if not isinstance(self.description, str):
            raise SpecError(f"{where}: description must be a string")
        for flag in ("sweepable", "array"):
            if not isinstance(getattr(self, flag), bool):
                raise SpecError(f"{where}: {flag} must be True or False")
        if isinstance(self.choices, str):
            raise SpecError(f"{where}: choices must be a tuple of str, not one string")
        if self.dim is not None:
            if not isinstance(self.dim, str) or not _NAME.match(self.dim.lower()):
                raise SpecError(f"{where}: dim must be a dimension name matching {_NAME.pattern}")
            if not self.sweepable:
                raise SpecError(f"{where}: dim is given but the parameter is not sweepable")

    def _check_kind_default(self, where: str) -> None:
        """The default of a bool, string, path or choice parameter fits its kind."""
        if self.kind == "bool" and not self.required and not isinstance(self.default, bool):
            raise SpecError(f"{where}: kind='bool' needs a bool default, got {self.default!r}")
        if (
            self.kind in ("string", "path")
            and not self.required
            and self.default is not None
            and not isinstance(self.default, str)
        ):
            raise SpecError(f"{where}: kind={self.kind!r} needs a str default")
        if self.kind == "choice":
            if not self.choices or not all(isinstance(c, str) for c in self.choices):
                raise SpecError(f"{where}: kind='choice' needs a non-empty tuple of str choices")
            if not self.required and self.default not in self.choices:
                raise SpecError(f"{where}: default {self.default!r} is not among the choices")

    def _check_bounds(self, where: str) -> None:
        """bounds and inclusive are pairs; the bounds are numbers (or None) in order."""
        if (
            not isinstance(self.bounds, tuple | list)
            or not isinstance(self.inclusive, tuple | list)
            or len(self.bounds) != 2
            or len(self.inclusive) != 2
        ):
            raise SpecError(f"{where}: bounds and inclusive must be pairs")
        lo, hi = self.bounds
        for b in (lo, hi):
            if b is not None and (
                not isinstance(b, int | float) or isinstance(b, bool) or math.isnan(b)
            ):
                raise SpecError(f"{where}: bounds must be numbers or None, got {b!r}")
        if lo is not None and hi is not None and lo > hi:
            raise SpecError(f"{where}: lower bound {lo} exceeds upper bound {hi}")

    def _check_numbers(self, where: str) -> None:
        """A scalar quantity's or int's default and example lie in the declared range."""
        scalar = self.kind in ("quantity", "int") and not self.array
        if scalar and not self.required and self.default is not None:
            if not isinstance(self.default, int | float) or isinstance(self.default, bool):
                raise SpecError(f"{where}: default must be a number in {self.unit!r}")
            if not self.in_bounds(float(self.default)):
                raise SpecError(
                    f"{where}: default {self.default} lies outside the declared range "
                    f"{self.range_text()}"
                )
        if (
            scalar
            and self.example is not None
            and isinstance(self.example, int | float)
            and not self.in_bounds(float(self.example))
        ):
            raise SpecError(
                f"{where}: example {self.example} lies outside the declared range "
                f"{self.range_text()}"
            )


_POWER = re.compile(r"^([A-Za-z_]+)(-?[0-9]+)$")


def caret_units(units: str) -> str:
    """Write a UDUNITS unit string with explicit ``^`` powers (``"Pa2 m-1"`` -> ``"Pa^2 m^-1"``).

    UDUNITS reads both forms; pint (and so pint-xarray's ``ds.pint.quantify()``) reads only the
    explicit one, so every stored ``units`` attribute uses it.
    """
    return (
        " ".join(
            f"{m[1]}^{m[2]}" if (m := _POWER.match(token)) else token for token in units.split()
        )
        or units
    )


@dataclass(frozen=True)
class VarSpec:
    """Declaration of one output variable (CF metadata).

    Parameters
    ----------
    dims : tuple of str
        Dimension names, e.g. ``("p0", "zeta")``. ``"p0"`` is the load dimension.
    units : str
        UDUNITS-parsable unit string; ``"1"`` for dimensionless.
    long_name : str
        CF ``long_name``.
    standard_name : str, optional
        CF ``standard_name`` when one exists.
    description : str
        Longer text stored as the ``comment`` attribute.
    extra : dict of str
        Further CF attributes (``flag_values``, ``flag_meanings``, ...).
    valid_min, valid_max : float, optional
        Declared range of the values (in ``units``); written as the CF attributes
        ``valid_min`` / ``valid_max`` and checked by the pipeline before the variable enters a
        Dataset.
    nan_meaning : str, optional
        What a NaN value means for this variable (e.g. ``"sealed: no percolating channel"``).
        Without it every value must be finite; with it NaN is allowed (never ``inf``) and the
        meaning is written into the ``comment`` attribute. The pipeline enforces both.
    """

    dims: tuple[str, ...]
    units: str
    long_name: str
    standard_name: str | None = None
    description: str = ""
    extra: dict[str, str] = field(default_factory=dict)
    valid_min: float | None = None
    valid_max: float | None = None
    nan_meaning: str | None = None

    def check(self, owner: str, name: str) -> None:
        """Raise :class:`SpecError` if this declaration is malformed."""
        where = f"{owner}.outputs[{name!r}]"
        if not _NAME.match(name):
            raise SpecError(f"{where}: variable names must match {_NAME.pattern}")
        if not isinstance(self.dims, tuple) or not all(isinstance(d, str) for d in self.dims):
            raise SpecError(f"{where}: dims must be a tuple of str")
        if not isinstance(self.units, str) or not self.units:
            raise SpecError(f"{where}: units must be a UDUNITS string ('1' if dimensionless)")
        if not isinstance(self.long_name, str) or not self.long_name:
            raise SpecError(f"{where}: long_name must be a non-empty string")
        for b in (self.valid_min, self.valid_max):
            if b is not None and (
                not isinstance(b, int | float) or isinstance(b, bool) or math.isnan(b)
            ):
                raise SpecError(f"{where}: valid_min/valid_max must be numbers or None")
        if (
            self.valid_min is not None
            and self.valid_max is not None
            and self.valid_min > self.valid_max
        ):
            raise SpecError(
                f"{where}: valid_min {self.valid_min} exceeds valid_max {self.valid_max}"
            )
        if self.nan_meaning is not None and (
            not isinstance(self.nan_meaning, str) or not self.nan_meaning.strip()
        ):
            raise SpecError(f"{where}: nan_meaning must be a non-empty string or None")

    def __post_init__(self) -> None:
        # the CF attributes are static: made once with the declaration (a malformed one, which
        # :meth:`check` reports, makes them at each call instead, raising there as before)
        try:
            made = self.cf_attrs()
        except Exception:  # noqa: BLE001 - reported by check() or by attrs()
            made = None
        object.__setattr__(self, "_attrs", made)
        # the dims of the common contribution's check (xpersson.checks): a tuple of str, NaN
        # not allowed (None otherwise: each value then checked on the general path)
        plain = (
            self.nan_meaning is None
            and type(self.dims) is tuple
            and all(type(d) is str for d in self.dims)
        )
        object.__setattr__(self, "_plain_dims", self.dims if plain else None)

    def attrs(self) -> dict[str, Any]:
        """CF attributes for a variable with this spec (``valid_min``/``valid_max`` as floats):
        a fresh dict each call (its ``flag_values`` array a fresh copy), made once per spec."""
        made = self.__dict__.get("_attrs")
        if made is None:
            return self.cf_attrs()
        out = dict(made)
        if "flag_values" in out and hasattr(out["flag_values"], "copy"):
            out["flag_values"] = out["flag_values"].copy()
        return out

    def cf_attrs(self) -> dict[str, Any]:
        """The CF attributes of :meth:`attrs`, computed from the declaration's fields."""
        out: dict[str, Any] = {"units": caret_units(self.units), "long_name": self.long_name}
        if self.standard_name:
            out["standard_name"] = self.standard_name
        comment = self.description
        if self.nan_meaning:
            comment = f"{comment} NaN means: {self.nan_meaning}".strip()
        if comment:
            out["comment"] = comment
        # ACDD-1.3: every data variable says what it holds ("qualityInformation" for flags)
        out["coverage_content_type"] = (
            "qualityInformation" if "flag_meanings" in self.extra else "modelResult"
        )
        out.update(self.extra)
        if isinstance(out.get("flag_values"), str):  # CF: numbers of the variable's type
            import numpy as np

            out["flag_values"] = np.array(
                [int(v) for v in out["flag_values"].split()], dtype=np.int8
            )
        out.update(self.valid_range())
        return out

    def valid_range(self) -> dict[str, float]:
        """The declared ``valid_min`` / ``valid_max`` as CF attributes (only those given)."""
        out = {}
        if self.valid_min is not None:
            out["valid_min"] = float(self.valid_min)
        if self.valid_max is not None:
            out["valid_max"] = float(self.valid_max)
        return out
