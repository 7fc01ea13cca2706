"""Reading the text tables of the viscoelastic plugin (master curves, Prony modes, a_T(T)).

Format (one table per file): ``#`` starts a comment; blank lines are ignored; the first other
line is the header naming every column *with its unit in brackets*; then one row per line,
numbers separated by commas and/or whitespace::

    # tread compound, T_ref = 293.15 K
    omega [rad/s], E_storage [MPa], E_loss [MPa]
    1e-2, 3.01, 0.02
    ...

Units are parsed with pint (the plugin's only pint use) and converted to SI. A first column
named ``f`` or ``frequency`` holds cyclic frequencies (``Hz``) and is converted to angular
frequency ``omega = 2 pi f``; a column named ``omega`` is an angular frequency (``rad/s``).
Every error is a :class:`TableError` naming the file and the line.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

__all__ = ["TableError", "read_table", "load_master_curve", "load_prony", "load_shift_table"]

_COLUMN = re.compile(r"^\s*([A-Za-z_][A-Za-z0-9_']*)\s*\[([^\]]+)\]\s*$")


class TableError(ValueError):
    """A table file is malformed (the message names the file and line)."""


def _split(text: str) -> list[str]:
    return [t for t in re.split(r"[,\s]+", text.strip()) if t]


def _header(path: Path, lineno: int, text: str, want: list[tuple[tuple[str, ...], str]]):
    parts = [p for p in re.split(r",|\t|\s{2,}|(?<=\])\s+", text.strip()) if p.strip()]
    names = " / ".join(f"{'|'.join(n)} [{u}]" for n, u in want)
    if len(parts) != len(want):
        raise TableError(
            f"{path}, line {lineno}: the header must name {len(want)} columns with units in "
            f"brackets ({names}), got {text.strip()!r}"
        )
    from xpersson.units import ureg

    reg = ureg()
    factors, names_out = [], []
    for k, (part, (allowed, dim_unit)) in enumerate(zip(parts, want, strict=True)):
        m = _COLUMN.match(part)
        if m is None:
            raise TableError(
                f"{path}, line {lineno}: column {k + 1} ({part.strip()!r}) has no unit; write "
                f"it as name [unit], e.g. {allowed[0]} [{dim_unit}]"
            )
        name, unit = m.group(1), m.group(2).strip()
        if name.lower() not in allowed:
            raise TableError(
                f"{path}, line {lineno}: column {k + 1} is named {name!r}; expected one of "
                f"{', '.join(allowed)}"
            )
        try:
            reg.Quantity(1.0, unit).to(dim_unit)
        except Exception:
            raise TableError(
                f"{path}, line {lineno}: column {name!r} has unit [{unit}], which is not "
                f"convertible to {dim_unit}"
            ) from None
        factors.append(unit)
        names_out.append(name.lower())
    return names_out, factors


def read_table(
    path: str | Path, want: list[tuple[tuple[str, ...], str]]
) -> tuple[list[str], NDArray[np.float64], list[int]]:
    """Read a table; return (column names, SI values ``(n_rows, n_cols)``, line numbers).

    Parameters
    ----------
    path : str or pathlib.Path
        The text file.
    want : list of (allowed names, SI unit)
        One entry per column: accepted (lower-case) names and the unit to convert to.
    """
    p = Path(path)
    try:
        lines = p.read_text(encoding="utf-8").splitlines()
    except OSError as exc:
        raise TableError(f"{p}: cannot read the table ({exc.strerror})") from None
    names: list[str] | None = None
    factors = None
    rows, where = [], []
    for i, raw in enumerate(lines, start=1):
        text = raw.split("#", 1)[0]
        if not text.strip():
            continue
        if names is None:
            names, factors = _header(p, i, text, want)
            continue
        toks = _split(text)
        if len(toks) != len(want):
            raise TableError(f"{p}, line {i}: expected {len(want)} numbers, got {len(toks)}")
        try:
            vals = [float(t) for t in toks]
        except ValueError:
            raise TableError(f"{p}, line {i}: not a number in {text.strip()!r}") from None
        if not all(np.isfinite(vals)):
            raise TableError(f"{p}, line {i}: values must be finite, got {text.strip()!r}")
        rows.append(vals)
        where.append(i)
    if names is None:
        raise TableError(f"{p}: empty table (no header line with units)")
    if len(rows) < 2:
        raise TableError(f"{p}: at least two rows are needed, got {len(rows)}")
    from xpersson.units import ureg

    reg = ureg()
    arr = np.asarray(rows, dtype=float)
    for k, (unit, (_, si)) in enumerate(zip(factors, want, strict=True)):  # offsets (degC) too
        arr[:, k] = np.asarray(reg.Quantity(arr[:, k], unit).to(si).magnitude, dtype=float)
    return names, arr, where


def _increasing(p: Path, x: NDArray[np.float64], where: list[int], what: str) -> None:
    for k in range(1, x.size):
        if x[k] == x[k - 1]:
            raise TableError(f"{p}, line {where[k]}: duplicate {what} {x[k]:g}")
        if x[k] < x[k - 1]:
            raise TableError(
                f"{p}, line {where[k]}: {what} {x[k]:g} is smaller than on line {where[k - 1]}; "
                f"{what}s must be strictly increasing"
            )


def load_master_curve(path: str | Path, phi_nodes: int = 6):  # noqa: ANN201
    """Read ``(omega | f, E_storage, E_loss)`` into a :class:`~._modulus.MasterCurve`."""
    from ._modulus import MasterCurve

    p = Path(path)
    names, v, where = read_table(
        p,
        [
            (("omega", "f", "frequency"), "1/s"),
            (("e_storage", "storage", "e'", "e1"), "Pa"),
            (("e_loss", "loss", "e''", "e2"), "Pa"),
        ],
    )
    omega = v[:, 0] * (2.0 * np.pi if names[0] in ("f", "frequency") else 1.0)
    for k in range(omega.size):
        if not omega[k] > 0:
            raise TableError(f"{p}, line {where[k]}: frequency must be > 0, got {omega[k]:g}")
        if not v[k, 1] > 0:
            raise TableError(f"{p}, line {where[k]}: storage modulus E' must be > 0 Pa")
        if v[k, 2] < 0:
            raise TableError(
                f"{p}, line {where[k]}: loss modulus E'' = {v[k, 2]:g} Pa < 0 (a passive "
                "material dissipates: E'' >= 0)"
            )
    _increasing(p, omega, where, "frequency")
    return MasterCurve(omega, v[:, 1], v[:, 2], phi_nodes=phi_nodes)


def load_prony(path: str | Path) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Read Prony modes ``(tau [time], delta_E [pressure])``; return ``(delta_E, tau)`` in SI."""
    p = Path(path)
    _, v, where = read_table(p, [(("tau",), "s"), (("delta_e", "de"), "Pa")])
    for k in range(v.shape[0]):
        if not v[k, 0] > 0:
            raise TableError(f"{p}, line {where[k]}: relaxation time must be > 0 s")
        if v[k, 1] < 0:
            raise TableError(f"{p}, line {where[k]}: mode strength delta_E must be >= 0 Pa")
    _increasing(p, v[:, 0], where, "relaxation time")
    return v[:, 1].copy(), v[:, 0].copy()


def load_shift_table(path: str | Path):  # noqa: ANN201
    """Read ``(T [temperature], a_T [1])`` into a :class:`~._shift.TabulatedShift`."""
    from ._shift import TabulatedShift

    p = Path(path)
    _, v, where = read_table(p, [(("t",), "K"), (("a_t", "at"), "1")])
    for k in range(v.shape[0]):
        if not v[k, 1] > 0:
            raise TableError(f"{p}, line {where[k]}: shift factor a_T must be > 0")
    _increasing(p, v[:, 0], where, "temperature")
    return TabulatedShift(v[:, 0].copy(), v[:, 1].copy(), source=str(p))
