"""Scale-dependent penetration hardness laws Y(zeta) [Pa] for ``plastic_scale_dependent``."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from scipy.interpolate import PchipInterpolator

__all__ = ["HardnessLaw", "PowerLaw", "TabulatedLaw", "load_table", "table_law"]


class HardnessLaw:
    """Increasing hardness Y(zeta) [Pa] and its derivative dY/dzeta [Pa]."""

    def Y(self, zeta: np.ndarray) -> np.ndarray:
        """Hardness [Pa] at magnification ``zeta`` [1]."""
        raise NotImplementedError

    def dY(self, zeta: np.ndarray) -> np.ndarray:
        """Derivative dY/dzeta [Pa] at ``zeta``."""
        raise NotImplementedError

    @property
    def is_constant(self) -> bool:
        """Whether Y does not depend on zeta (then the yield wall is a fixed absorbing wall)."""
        raise NotImplementedError

    @property
    def kinks(self) -> tuple[float, ...]:
        """Magnifications [1] where ``dY/dzeta`` has a kink (none for a smooth law)."""
        return ()

    def check_range(self, zeta_max: float) -> None:  # noqa: B027 - optional hook
        """Raise ``ValueError`` if the law is not defined on ``[1, zeta_max]``."""


class PowerLaw(HardnessLaw):
    """``Y(zeta) = Y1 zeta**n`` with ``Y1 > 0`` [Pa] and ``n >= 0`` [1]."""

    def __init__(self, Y1: float, n: float) -> None:
        self.Y1 = float(Y1)
        self.n = float(n)

    def Y(self, zeta: np.ndarray) -> np.ndarray:
        return self.Y1 * np.asarray(zeta, dtype=float) ** self.n

    def dY(self, zeta: np.ndarray) -> np.ndarray:
        z = np.asarray(zeta, dtype=float)
        if self.n == 0.0:
            return np.zeros_like(z)
        return self.n * self.Y1 * z ** (self.n - 1.0)

    @property
    def is_constant(self) -> bool:
        return self.n == 0.0


class TabulatedLaw(HardnessLaw):
    """Monotone (PCHIP in log zeta, log Y) interpolation of a table ``(zeta, Y)``.

    Parameters
    ----------
    zeta : numpy.ndarray
        Strictly increasing magnifications [1], > 0.
    Y : numpy.ndarray
        Non-decreasing hardness values [Pa], > 0.
    """

    def __init__(self, zeta: np.ndarray, Y: np.ndarray) -> None:
        self.zeta = np.asarray(zeta, dtype=float)
        self.values = np.asarray(Y, dtype=float)
        self._s = PchipInterpolator(np.log(self.zeta), np.log(self.values), extrapolate=False)
        self._ds = self._s.derivative()

    def _logz(self, zeta: np.ndarray) -> np.ndarray:
        z = np.asarray(zeta, dtype=float)
        lz = np.log(z)
        lo, hi = np.log(self.zeta[0]), np.log(self.zeta[-1])
        return np.clip(lz, lo, hi)  # rounding at the ends; range is checked in check_range

    def Y(self, zeta: np.ndarray) -> np.ndarray:
        return np.exp(self._s(self._logz(zeta)))

    def dY(self, zeta: np.ndarray) -> np.ndarray:
        z = np.asarray(zeta, dtype=float)
        return np.maximum(self.Y(z) * self._ds(self._logz(z)) / z, 0.0)

    @property
    def is_constant(self) -> bool:
        return bool(np.all(self.values == self.values[0]))

    @property
    def kinks(self) -> tuple[float, ...]:
        """The table's magnifications [1]: PCHIP is C^1, its second derivative jumps there."""
        return tuple(float(z) for z in self.zeta)

    def check_range(self, zeta_max: float) -> None:
        lo, hi = self.zeta[0], self.zeta[-1]
        if lo > 1.0 * (1 + 1e-12) or hi < zeta_max * (1 - 1e-12):
            raise ValueError(
                f"boundary.table covers zeta in [{lo:g}, {hi:g}] but the scene needs "
                f"[1, {zeta_max:g}]: the table must span every output magnification"
            )


def load_table(path: str | Path, unit: str = "Pa") -> TabulatedLaw:
    """Read a two-column text file ``zeta  Y`` (``#`` comments, whitespace or commas).

    Parameters
    ----------
    path : str or Path
        The file.
    unit : str
        Unit of the Y column (pint syntax, a pressure: ``"Pa"``, ``"GPa"``, ``"MPa"``).

    Raises
    ------
    ValueError
        Naming ``boundary.table`` / ``boundary.table_unit`` if the file is unreadable, has the
        wrong shape, non-positive or non-finite values, non-increasing zeta, or decreasing Y.
    """
    factor = _pascal_factor(unit)
    p = Path(path)
    try:
        text = p.read_text()
    except OSError as exc:
        raise ValueError(f"boundary.table: cannot read {str(p)!r}: {exc}") from exc
    rows = []
    for k, line in enumerate(text.splitlines(), start=1):
        line = line.split("#", 1)[0].replace(",", " ").strip()
        if not line:
            continue
        parts = line.split()
        try:
            vals = [float(v) for v in parts]
        except ValueError:
            raise ValueError(
                f"boundary.table {str(p)!r} line {k}: expected two numbers 'zeta Y', got {line!r}"
            ) from None
        if len(vals) != 2:
            raise ValueError(
                f"boundary.table {str(p)!r} line {k}: expected two columns 'zeta Y', "
                f"got {len(vals)}"
            )
        rows.append(vals)
    if len(rows) < 2:
        raise ValueError(f"boundary.table {str(p)!r}: needs at least two rows 'zeta Y'")
    arr = np.asarray(rows)
    return table_law(arr[:, 0], arr[:, 1] * factor, f"boundary.table {str(p)!r}", unit)


def table_law(zeta: np.ndarray, Y: np.ndarray, where: str, unit: str = "Pa") -> TabulatedLaw:
    """The hardness law of the table ``zeta`` [1], ``Y`` [Pa], checked (``where`` names it in
    the messages; ``unit``: the unit its ``Y`` was given in)."""
    zeta, Y = np.atleast_1d(np.asarray(zeta, float)), np.atleast_1d(np.asarray(Y, float))
    if not (zeta.ndim == 1 and zeta.shape == Y.shape and zeta.size >= 2):
        raise ValueError(f"{where}: needs at least two rows 'zeta Y' of the same length")
    if not (np.all(np.isfinite(zeta + Y)) and np.all(zeta > 0) and np.all(Y > 0)):
        raise ValueError(f"{where}: zeta [1] and Y [{unit}] must be finite and > 0")
    if np.any(np.diff(zeta) <= 0):
        raise ValueError(f"{where}: zeta must be strictly increasing")
    if np.any(np.diff(Y) < 0):
        i = int(np.argmax(np.diff(Y) < 0))
        raise ValueError(
            f"{where}: the hardness Y [{unit}] must be non-decreasing in zeta "
            f"(force conservation needs dY/dzeta >= 0); it decreases between zeta = "
            f"{zeta[i]:g} and {zeta[i + 1]:g}"
        )
    return TabulatedLaw(zeta, Y)


def _pascal_factor(unit: str) -> float:
    import pint

    ureg = pint.UnitRegistry()
    try:
        q = ureg.Quantity(1.0, unit).to("Pa")
    except (pint.errors.PintError, AttributeError, TypeError, ValueError) as exc:
        raise ValueError(
            f"boundary.table_unit = {unit!r} must be a pressure unit such as 'Pa', 'MPa', "
            f"'GPa' ({exc})"
        ) from exc
    return float(q.magnitude)
