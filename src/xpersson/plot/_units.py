"""Human units and axis labels of the figures: the prefix of a CF unit chosen from the values.

No matplotlib here: these are string and number helpers (public through :mod:`xpersson.plot`:
:func:`human`, :func:`text`).
"""

from __future__ import annotations

from typing import Any

import numpy as np
import xarray as xr

__all__ = ["human", "text", "compact"]

# human prefixes per CF unit: (factor in SI, text), largest first
_PREFIXES: dict[str, list[tuple[float, str]]] = {
    "Pa": [(1e9, "GPa"), (1e6, "MPa"), (1e3, "kPa"), (1.0, "Pa")],
    "m": [(1e-3, "mm"), (1e-6, "µm"), (1e-9, "nm")],
    "m s-1": [(1.0, "m/s"), (1e-2, "cm/s"), (1e-3, "mm/s"), (1e-6, "µm/s"), (1e-9, "nm/s")],
    "m3 s-1": [(1e-6, "cm³/s"), (1e-9, "mm³/s")],
    "J m-2": [(1.0, "J/m²"), (1e-3, "mJ/m²"), (1e-6, "µJ/m²")],
}
# units without prefixes: their text
_PLAIN = {"1": "", "m-1": "1/m", "m2": "m²", "K": "K"}
SYMBOLS = {"p0": "$p_0$", "zeta": r"$\zeta$", "v": "$v$", "T": "$T$", "p": "$p$", "u": "$u$"}


def compact(units: str) -> str:
    """A CF unit string without carets: the stored ``"Pa^-1"`` and the compact ``"Pa-1"`` alike."""
    return str(units).replace("^", "")


def human(units: str, values: Any) -> tuple[float, str]:
    """The SI factor and text of the human unit for ``values`` in CF ``units``.

    Parameters
    ----------
    units : str
        CF/UDUNITS unit string of the values (``"Pa"``, ``"m"``, ``"m3 s-1"``, ...; the stored
        caret form ``"m s^-1"`` too).
    values : array_like
        Values in ``units``; the prefix is the largest one not above their largest magnitude.

    Returns
    -------
    factor, text : float, str
        Divide the values by ``factor`` to express them in ``text`` (``(1e6, "MPa")``).
    """
    units = compact(units)  # stored "m s^-1" and compact "m s-1" alike
    table = _PREFIXES.get(units)
    if not table:
        return 1.0, _PLAIN.get(units, units)
    v = np.abs(np.asarray(values, float))
    v = v[np.isfinite(v) & (v > 0)]
    top = float(v.max()) if v.size else table[-1][0]
    return next(((f, t) for f, t in table if top >= 0.999 * f), table[-1])


def number(value: float) -> str:
    """``1e+05`` as mathtext ``10^5``; other values with three digits."""
    exp = np.log10(value) if value > 0 else 0.5
    return f"$10^{{{int(round(exp))}}}$" if abs(exp - round(exp)) < 1e-9 else f"{value:.3g}"


def text(value: float, units: str) -> str:
    """One value with its human unit: ``10 kPa``, ``0.6``, ``20 °C``."""
    if units == "K":
        return f"{value - 273.15:.3g} °C"
    factor, unit = human(units, [value])
    return f"{value / factor:.3g} {unit}".strip()


def label(var: xr.DataArray, name: str, factor_unit: tuple[float, str]) -> str:
    """Axis label of ``var``: its long name, the symbol of dimension ``name``, the human unit."""
    words = f"{var.attrs.get('long_name', name)} {SYMBOLS.get(name, '')}".strip()
    return words + (f" [{factor_unit[1]}]" if factor_unit[1] else "")
