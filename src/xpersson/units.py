"""The pint boundary: parse user quantities, convert to SI floats, map to CF unit strings.

pint is imported lazily (on the first parse) so that importing xpersson and ``xpersson --help``
stay cheap; quantities in simple SI units (``"10 MPa"``, ``"1e3 1/m"``, ``"1 um"``) are
converted without it, to the same float (pint itself imports dask when it is installed).
Inside the engine and the plugins there is no pint: only SI floats.
"""

from __future__ import annotations

import re
import threading
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:  # pragma: no cover
    import numpy as np
    import pint
    import xarray as xr

from .cache import memoize
from .errors import UnitError

__all__ = [
    "ureg",
    "to_si",
    "strings_to_si",
    "udunits_to_pint",
    "quantify",
    "UnitError",
    "check_expression",
]


_UREG: list[pint.UnitRegistry] = []
_UREG_LOCK = threading.Lock()


def ureg() -> pint.UnitRegistry:
    """The package's pint registry (created on first use).

    One registry per process by design, not a cache: quantities of different pint registries
    do not combine, so this stays the same object when the caches are off.
    """
    with _UREG_LOCK:
        if not _UREG:
            import pint

            reg = pint.UnitRegistry(force_ndarray_like=True)
            reg.formatter.default_format = "~P"
            _UREG.append(reg)
        return _UREG[0]


MAX_TEXT = 200
"""Longest quantity text parsed [characters]."""
MAX_EXPONENT = 64.0
"""Largest magnitude of an exponent in a unit expression."""
MAX_NESTING = 8
"""Deepest nesting of parentheses in a unit expression."""
MAX_POWER = 4 * MAX_EXPONENT
"""Largest sum of the magnitudes of all exponents of a unit expression (a unit without one
counts 1): bounds products of large powers such as ``'Tm**60*Tm**60*Tm**60/m**180'``."""
#: a number (as Python's float reads one, taken whole) directly followed by a decimal point
_MALFORMED = re.compile(r"((?>(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?))\.\d*")
_NAME = re.compile(r"(?<![\d.])[A-Za-z_\u00b5\u03bc][A-Za-z0-9_\u00b5\u03bc]*")
_EXPONENT = re.compile(
    r"(?:\*\*|\^)\s*(\(\s*[-+]?\d+(?:\.\d*)?(?:\s*/\s*\d+)?\s*\)"
    r"|[-+]?\d+(?:\.\d*)?(?:[eE][-+]?\d+)?)"
)


def check_expression(text: str, where: str) -> None:
    """Refuse a quantity text that could make the unit parser work without bound, or that
    holds a malformed number.

    Bounds: at most :data:`MAX_TEXT` characters, parentheses nested at most
    :data:`MAX_NESTING` deep, and every exponent (``**`` or ``^``) a plain number (or a plain
    fraction in parentheses) of magnitude at most :data:`MAX_EXPONENT`, never itself raised to
    a power (no towers such as ``m**9**9**9``). A number directly followed by a decimal point
    (``"1.2.3 Pa"``, ``"1e3.5 Pa"``) is refused: pint would read two numbers and multiply
    them (0.36 Pa, 500 Pa); so is any text holding more than one number outside its exponents
    (``"2 Pa 3"``, ``"1.2 .3 Pa"``, ``"2*3 Pa"``; the ``1`` of a unit ``1/m`` is no number).

    Raises
    ------
    UnitError
        Naming ``where`` and the bound.
    """
    if len(text) > MAX_TEXT:
        raise UnitError(f"{where}: quantity text of {len(text)} characters (at most {MAX_TEXT})")
    bad = _MALFORMED.search(text)
    if bad is not None:
        raise UnitError(
            f"{where}: {text[:60]!r}: {bad.group(0)!r} is not a number (a decimal point after "
            f"the number {bad.group(1)!r}); write one number, e.g. '1.23 MPa'"
        )
    depth = deepest = 0
    for c in text:
        depth += (c == "(") - (c == ")")
        deepest = max(deepest, depth)
    if deepest > MAX_NESTING:
        raise UnitError(f"{where}: parentheses nested {deepest} deep (at most {MAX_NESTING})")
    bare = text.replace("**", "^")
    n_ops = bare.count("^")
    found = list(_EXPONENT.finditer(text))
    rest = _EXPONENT.sub(" ", text)
    if len(found) != n_ops or "^" in rest.replace("**", "^"):
        raise UnitError(
            f"{where}: {text[:60]!r}: every exponent must be a plain number (no expressions "
            "or towers of exponents such as 'm**9**9')"
        )
    for m in found:
        value = m.group(1).strip("() ")
        num, _, den = value.partition("/")
        if abs(float(num) / float(den or 1)) > MAX_EXPONENT:
            raise UnitError(
                f"{where}: exponent {value} in {text[:60]!r} is beyond +-{MAX_EXPONENT:g}"
            )
    names = len(_NAME.findall(_EXPONENT.sub(" ", text)))
    power = sum(abs(_exponent(m.group(1))) for m in found) + max(names - len(found), 0)
    if power > MAX_POWER:
        raise UnitError(
            f"{where}: {text[:60]!r}: units raised to {power:g} in all (products of large "
            f"powers; at most {MAX_POWER:g})"
        )
    for k in range(len(found) - 1):  # an exponent directly followed by another: a tower
        if not text[found[k].end() : found[k + 1].start()].strip(" )"):
            raise UnitError(f"{where}: {text[:60]!r}: towers of exponents are not allowed")
    _one_number(text, rest, where)


#: a number as Python's float reads one, not inside a name (``m2``, ``H2O``)
_ANY_NUMBER = re.compile(r"(?<![\w.])(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")
#: what follows the ``1`` of a unit ``1/m``, ``1 / (m*s)``: a slash, then a unit name
_PER_UNIT = re.compile(r"\s*/\s*[(\s]*[^\W\d]")


def _one_number(text: str, rest: str, where: str) -> None:
    """Refuse a quantity text holding more than one number (``rest``: ``text`` without its
    exponents): pint reads ``"2 Pa 3"``, ``"1.2 .3 Pa"``, ``"2*3 Pa"`` or ``"1/2 Pa"`` as a
    product or quotient of its numbers (6 Pa, 0.36 Pa, 6 Pa, 0.5 Pa). The ``1`` of a unit
    ``1/m`` (a slash, then a unit name) is part of the unit, not a number."""
    numbers = [
        m.group(0)
        for m in _ANY_NUMBER.finditer(rest)
        if m.group(0) != "1" or _PER_UNIT.match(rest, m.end()) is None
    ]
    if len(numbers) > 1:
        raise UnitError(
            f"{where}: {text[:60]!r} holds {len(numbers)} numbers "
            f"({', '.join(map(repr, numbers[:3]))}; pint would combine them, e.g. '2 3 Pa' "
            "as 6 Pa); write one number and its unit, e.g. '1.23 MPa'"
        )


def _exponent(text: str) -> float:
    num, _, den = text.strip("() ").partition("/")
    return float(num) / float(den or 1)


def _parse(value: Any, where: str) -> Any:
    reg = ureg()
    import pint

    if isinstance(value, pint.Quantity):
        if value._REGISTRY is not reg:  # noqa: SLF001 - foreign registry: go through text
            return reg.Quantity(value.magnitude, str(value.units))
        return value
    if isinstance(value, str):
        text = value.strip()
        if not text:
            raise UnitError(f"{where}: empty string, expected a quantity such as '3 MPa'")
        check_expression(text, where)
        try:
            q = reg.Quantity(text)
            power = sum(abs(float(v)) for v in q.dimensionality.values())
            if power <= MAX_EXPONENT:  # products of large powers: refused before converting
                q.to_base_units()  # an overflowing conversion factor fails here, named
        except Exception as exc:
            raise UnitError(f"{where}: cannot parse {value!r} as a quantity ({exc})") from None
        if power > MAX_EXPONENT:
            raise UnitError(
                f"{where}: {text[:60]!r} has dimensions raised to {power:g} in all (at most "
                f"{MAX_EXPONENT:g})"
            )
        return q
    return value


_PLAIN_NUMBERS = {int, float}


def to_si(value: Any, unit: str, where: str, *, array: bool = False) -> Any:
    """Convert a scene value to a float (or float array) in ``unit``.

    Parameters
    ----------
    value : str, float, int, pint.Quantity or sequence of those
        ``"3 MPa"``, ``3e6`` (only for dimensionless ``unit``), a pint quantity, or (with
        ``array=True``) a list of such values.
    unit : str
        Target unit (pint syntax), ``"1"`` for dimensionless.
    where : str
        Dotted parameter name used in error messages, e.g. ``"material.E"``.
    array : bool
        Accept and return a 1-D array.

    Returns
    -------
    float or numpy.ndarray
        The magnitude in ``unit``.

    Raises
    ------
    UnitError
        Wrong dimensionality, unparsable text, or a bare number for a dimensional parameter.
    """
    if type(value) in (int, float) and unit in ("1", ""):  # a bare dimensionless number
        if array:
            import numpy as np

            return np.atleast_1d(np.asarray(float(value)))
        return float(value)
    if array and isinstance(value, list | tuple):
        import numpy as np

        if unit in ("1", "") and set(map(type, value)) <= _PLAIN_NUMBERS:
            return np.array(value, float)  # bare numbers (a zeta grid): as float() of each
        fast = strings_to_si(value, unit) if unit not in ("1", "") else None
        if fast is not None:
            return fast
        return np.array([to_si(v, unit, f"{where}[{i}]") for i, v in enumerate(value)], float)
    if isinstance(value, bool):
        raise UnitError(f"{where}: expected a quantity in {unit}, got a boolean")
    if isinstance(value, str) and not array:
        plain = _plain_si(value, unit)  # "<number> <symbol>": within every bound, no pint
        if plain is not None:
            return plain
        check_expression(value.strip(), where)  # the bounds hold for the fast path too
        try:  # sweeps resolve the same strings at every point: parse each once
            return _str_to_si(value, unit)
        except (UnitError, ArithmeticError):
            pass  # redo below, for a message naming ``where`` (overflows too)
    return _to_si(value, unit, where, array)


@memoize("units.str_to_si", scope="process", maxsize=4096)
def _str_to_si(value: str, unit: str) -> float:
    fast = _simple_si(value, unit)
    return _to_si(value, unit, "", False) if fast is None else fast


_PREFIX = {"k": 1e3, "M": 1e6, "G": 1e9, "T": 1e12, "c": 1e-2, "m": 1e-3, "u": 1e-6}
_PREFIX |= {"µ": 1e-6, "μ": 1e-6, "n": 1e-9, "p": 1e-12}
_BASE = ("Pa", "m", "s", "K", "N", "J", "W")
_NUMBER = re.compile(r"^\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*(.*?)\s*$")
_TERM = re.compile(r"([a-zA-Zµμ]+)(?:\^(-?\d+))?")


@memoize("units.simple_unit", scope="process", maxsize=256)
def _simple_unit(text: str) -> tuple[float, tuple[tuple[str, int], ...]] | None:
    """(factor to SI, base powers) of a product/quotient of (prefixed) SI symbols such as
    ``"MPa"``, ``"1/m"``, ``"J/m**2"``, ``"um**4"``; ``None`` for anything else."""
    if text in ("", "1"):
        return 1.0, ()
    factor, dims, sign = 1.0, {}, 1
    for i, tok in enumerate(re.split(r"([*/])", text.replace("**", "^"))):
        tok = tok.strip()
        if tok in ("*", "/"):
            sign = 1 if tok == "*" else -1
            continue
        if tok == "1" and i == 0:
            continue
        m = _TERM.fullmatch(tok)
        if m is None:
            return None
        sym, power = m.group(1), sign * int(m.group(2) or 1)
        if sym in _BASE:
            base, pre = sym, 1.0
        elif sym[1:] in _BASE and sym[0] in _PREFIX:
            base, pre = sym[1:], _PREFIX[sym[0]]
        else:
            return None
        factor *= pre**power
        dims[base] = dims.get(base, 0) + power
    return factor, tuple(sorted((k, v) for k, v in dims.items() if v))


#: one number and one (prefixed) SI symbol, e.g. ``"1.5e3 kPa"``: the texts of loads
_PLAIN = re.compile(r"\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*([A-Za-zµμ]+)\s*")


def _plain_si(value: str, unit: str) -> float | None:
    """:func:`to_si` of a text that is one number and one (prefixed) SI symbol of ``unit``'s
    dimension (``"100.37 kPa"``), without the bound checks' regular expressions: such a text
    meets every bound of :func:`check_expression` (no parentheses, exponents or second
    number; at most :data:`MAX_TEXT` characters checked here). The float
    :func:`_simple_si` gives; ``None`` for any other text (the general path)."""
    if len(value) > MAX_TEXT:
        return None
    return _converted(_PLAIN.fullmatch(value), unit)


def _simple_si(value: str, unit: str) -> float | None:
    """``value`` in ``unit`` without pint where both are simple SI expressions (the same
    float pint gives: the magnitude times the prefix factor); ``None`` otherwise (pint)."""
    return _converted(_NUMBER.match(value), unit)


def _converted(m: re.Match[str] | None, unit: str) -> float | None:
    """The number of match ``m`` (group 1) in its unit (group 2, a simple SI expression of
    ``unit``'s dimension) converted to ``unit`` (an SI base combination); ``None`` otherwise."""
    if m is None:
        return None
    have, want = _simple_unit(m.group(2)), _simple_unit(unit)
    if have is None or want is None or want[0] != 1.0 or have[1] != want[1]:
        return None
    x = float(m.group(1))
    return (x if have[0] == 1.0 else x * have[0]) + 0.0  # + 0.0: a zero is +0.0 (pint: "-0" is 0)


def strings_to_si(values: Any, unit: str) -> np.ndarray | None:
    """Several quantity strings (``["1 MPa", "2 MPa", ...]``) in ``unit`` with one unit parse
    per distinct unit text and one scan of all the numbers (a list of 1000 loads), not one
    parse per value.

    The floats are those :func:`to_si` gives for each string (the magnitude times the unit's
    SI factor, :func:`_simple_si`). ``None`` where a value is not a plain number with a simple
    SI unit of ``unit``'s dimension, or breaks a bound of :func:`check_expression`: the caller
    then converts value by value, which raises the message naming the value's index.

    The list's text (its values joined by line breaks) keys a process cache
    (``units.string_lists``): a scene solved again, or the same list at every point of a
    sweep, reads its numbers once. The array returned is the caller's own (a copy).
    """
    if type(values) not in (list, tuple) or not values:
        return None
    try:
        text = "\n".join(values)
    except TypeError:  # a value that is not a string
        return None
    got = _lines_to_si(text, len(values), unit)
    return None if got is None else got.copy()


@memoize("units.string_lists", scope="process", maxsize=8)
def _lines_to_si(text: str, n: int, unit: str) -> np.ndarray | None:
    """:func:`strings_to_si` of the ``n`` values joined by line breaks in ``text`` (``None``:
    a value holding a line break, or one the caller must convert on its own)."""
    import numpy as np

    want = _simple_unit(unit)
    if want is None or want[0] != 1.0 or text.count("\n") != n - 1:
        return None
    split = _number_and_unit(text, n)
    if split is None:
        return None
    nums, units = split
    factors = {}
    for u in set(units):
        have = _simple_unit(u)
        if have is None or have[1] != want[1] or not _bounded(f"1 {u}"):
            return None
        factors[u] = have[0]
    try:
        x = np.array(list(map(float, nums)), float)
    except ValueError:  # "1.2.3", "e5": not a number
        return None
    if len(factors) == 1:
        f = next(iter(factors.values()))
        return (x if f == 1.0 else x * f) + 0.0  # + 0.0: every zero +0.0, as _simple_si
    return x * np.array([factors[u] for u in units], float) + 0.0


def _number_and_unit(text: str, n: int) -> tuple[list[str], tuple[str, ...]] | None:
    """(number texts, unit texts) of the ``n`` lines ``"<number> <unit>"`` of ``text`` as
    :data:`_NUMBER` reads them (one unit text: the unit of every number), or ``None`` (a line
    that is not one)."""
    same = _one_unit(text, n)
    if same is not None:
        return same
    lines = text.split("\n")
    if max(map(len, lines)) > MAX_TEXT:  # too long for check_expression: value by value
        return None
    pairs = [v.split(None, 1) for v in lines]
    if set(map(len, pairs)) == {2}:  # "1.5 MPa": numbers checked by one scan of all
        nums, units = zip(*pairs, strict=True)
        # over these characters Python's float() reads exactly the numbers _NUMBER reads
        if _NUMBER_CHARS.fullmatch("\n".join(nums)):
            return list(nums), units  # a unit's trailing blanks: _simple_unit strips them
    found = _NUMBERS.findall(text)  # "1.5MPa", "1.5", ...: one scan, slower
    if len(found) != n:
        return None  # a value that is not a plain number and unit
    nums, units = zip(*found, strict=True)
    return list(nums), units


def _one_unit(text: str, n: int) -> tuple[list[str], tuple[str, ...]] | None:
    """(number texts, unit texts) where each of the ``n`` lines of ``text`` is
    ``"<number> <unit>"`` with the first line's unit text and one blank (a list of loads in
    one unit): one split of the whole text on the unit, no split per value; ``None``
    otherwise."""
    head = text.split("\n", 1)[0].split(" ", 1)
    if len(head) != 2 or not head[1] or head[1][0].isspace():
        return None
    nums = (text + "\n").split(f" {head[1]}\n")
    # n + 1 parts, the last empty: every line ends with the unit (no line holds a break)
    if len(nums) != n + 1 or nums.pop() or not _NUMBER_CHARS.fullmatch("\n".join(nums)):
        return None
    if max(map(len, nums)) + 1 + len(head[1]) > MAX_TEXT:  # a line too long: value by value
        return None
    return nums, (head[1],)  # one unit text for every number


_NUMBER_CHARS = re.compile(r"[0-9.eE+\-\n]*")
#: :data:`_NUMBER` of every line of a text at once (line breaks separate the values).
_NUMBERS = re.compile(
    r"^[^\S\n]*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)[^\S\n]*(.*?)[^\S\n]*$", re.M
)


def _bounded(text: str) -> bool:
    """Whether ``text`` passes :func:`check_expression` (its unit part decides: a plain number
    holds no parenthesis or exponent)."""
    try:
        check_expression(text.strip(), "")
    except UnitError:
        return False
    return True


def _to_si(value: Any, unit: str, where: str, array: bool) -> Any:
    dimensionless = unit in ("1", "")
    q = _parse(value, where)
    if isinstance(q, int | float):
        if dimensionless:
            return float(q)
        raise UnitError(
            f"{where}: {value!r} has no unit; give it with a unit, e.g. '{value} {unit}'"
        )
    reg = ureg()
    import pint

    if not isinstance(q, pint.Quantity):
        raise UnitError(f"{where}: expected a quantity in {unit}, got {type(value).__name__}")
    target = reg.Unit("dimensionless") if dimensionless else reg.Unit(unit)
    try:
        mag = q.to(target).magnitude
    except pint.DimensionalityError:
        raise UnitError(
            f"{where}: {value!r} has dimension {q.dimensionality}, expected {unit} "
            f"({target.dimensionality})"
        ) from None
    if array:
        import numpy as np

        return np.atleast_1d(np.asarray(mag, dtype=float)) + 0.0  # a zero is +0.0
    try:
        return float(mag) + 0.0  # + 0.0 changes no number but -0.0 (to +0.0)
    except TypeError:
        raise UnitError(f"{where}: expected a single value, got {value!r}") from None


_POW = re.compile(r"([A-Za-z]+)(-?\d+)")


def udunits_to_pint(units: str) -> str:
    """Translate a UDUNITS string (``"Pa2"``, ``"m-1"``, ``"J m-2"``) to pint syntax."""
    if units in ("1", ""):
        return "dimensionless"
    text = _POW.sub(r"\1**\2", units.strip())
    return "*".join(text.split())


def quantify(ds: xr.Dataset) -> xr.Dataset:
    """Return ``ds`` with pint-backed arrays (requires the optional ``pint-xarray``).

    Units are read from each variable's CF ``units`` attribute.
    """
    try:
        import pint_xarray  # noqa: F401
    except ImportError as exc:  # pragma: no cover - depends on the environment
        raise ImportError(
            "xpersson.units.quantify needs the optional dependency pint-xarray: "
            "pip install 'xpersson[units]'"
        ) from exc
    reg = ureg()
    units = {}
    for name, var in ds.variables.items():
        u = var.attrs.get("units")
        if u is not None and var.dtype.kind in "fiu":
            units[name] = udunits_to_pint(u)
    stripped = ds.copy()
    for name in units:
        stripped[name].attrs.pop("units", None)
    return stripped.pint.quantify(units, unit_registry=reg)
