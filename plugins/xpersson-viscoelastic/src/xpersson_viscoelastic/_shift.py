"""Time-temperature superposition: shift factors a_T(T) [1] (physics.md §4.3).

``E(omega, T) = E_ref(a_T(T) omega)`` (vertical factor ``b_T = 1``); ``a_T > 1`` below the
reference temperature (the rubber is stiffer). All functions are vectorised over ``T`` [K].
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from xpersson.cache import dataclass_key

__all__ = [
    "GAS_CONSTANT",
    "WLF_UNIVERSAL",
    "ShiftLaw",
    "NoShift",
    "WLF",
    "Arrhenius",
    "TabulatedShift",
]

#: Molar gas constant [J/(mol K)] (CODATA 2018, exact).
GAS_CONSTANT = 8.314462618
#: "Universal" WLF constants (C1 [1], C2 [K]) for ``T_ref = T_g`` (Williams, Landel, Ferry 1955).
WLF_UNIVERSAL = (17.44, 51.6)

Array = NDArray[np.float64]


class ShiftLaw:
    """A shift law: :meth:`log10_aT` [1] at temperatures ``T`` [K]; :meth:`check` the range."""

    def log10_aT(self, T: ArrayLike) -> Array:
        """Decimal logarithm of the shift factor at ``T`` [K]."""
        raise NotImplementedError

    def aT(self, T: ArrayLike) -> Array:
        """Shift factor ``a_T`` [1] at ``T`` [K]."""
        return 10.0 ** self.log10_aT(T)

    def cache_key(self) -> bytes:
        """The law's content for :mod:`xpersson.cache`: a digest of its defining (init)
        fields, computed once (:func:`xpersson.cache.dataclass_key`)."""
        return dataclass_key(self)

    def check(self, T: ArrayLike) -> None:  # noqa: B027 - optional hook
        """Raise ``ValueError`` naming ``temperature`` [K] and the allowed range if outside."""


@dataclass(frozen=True)
class NoShift(ShiftLaw):
    """``a_T = 1`` at every temperature."""

    def log10_aT(self, T: ArrayLike) -> Array:
        return np.zeros_like(np.asarray(T, dtype=float))


@dataclass(frozen=True)
class WLF(ShiftLaw):
    """Williams-Landel-Ferry: ``log10 a_T = -C1 (T - T_ref) / (C2 + T - T_ref)``.

    Parameters
    ----------
    C1 : float
        [1], > 0 (universal 17.44 with ``T_ref = T_g``).
    C2 : float
        [K], > 0 (universal 51.6 K).
    T_ref : float
        Reference temperature of the master curve [K].
    """

    C1: float
    C2: float
    T_ref: float

    def log10_aT(self, T: ArrayLike) -> Array:
        dT = np.asarray(T, dtype=float) - self.T_ref
        return -self.C1 * dT / (self.C2 + dT)

    def check(self, T: ArrayLike) -> None:
        T = np.asarray(T, dtype=float)
        low = self.T_ref - self.C2
        if np.any(T <= low):
            raise ValueError(
                f"temperature: {float(np.min(T)):g} K is outside the range of the WLF law; "
                f"allowed (T_ref - C2, inf) = ({low:g}, inf) K"
            )


@dataclass(frozen=True)
class Arrhenius(ShiftLaw):
    """Arrhenius: ``ln a_T = (E_a / R) (1/T - 1/T_ref)``.

    Parameters
    ----------
    activation_energy : float
        ``E_a`` [J/mol], >= 0.
    T_ref : float
        Reference temperature [K], > 0.
    """

    activation_energy: float
    T_ref: float

    def log10_aT(self, T: ArrayLike) -> Array:
        T = np.asarray(T, dtype=float)
        return (self.activation_energy / GAS_CONSTANT) * (1.0 / T - 1.0 / self.T_ref) / np.log(10)


@dataclass(frozen=True)
class TabulatedShift(ShiftLaw):
    """Tabulated ``a_T(T)``: ``log10 a_T`` interpolated linearly in ``T``, no extrapolation.

    Parameters
    ----------
    T : array_like
        Strictly increasing temperatures [K].
    aT : array_like
        Shift factors [1], > 0.
    source : str
        Where the table came from (named in range errors).
    """

    T: Array
    aT_values: Array
    source: str = "shift table"

    def log10_aT(self, T: ArrayLike) -> Array:
        return np.interp(np.asarray(T, dtype=float), self.T, np.log10(self.aT_values))

    def check(self, T: ArrayLike) -> None:
        T = np.asarray(T, dtype=float)
        lo, hi = float(self.T[0]), float(self.T[-1])
        if np.any((T < lo) | (T > hi)):
            bad = float(T[(T < lo) | (T > hi)].flat[0])
            raise ValueError(
                f"temperature: {bad:g} K is outside the range of {self.source}; "
                f"allowed [{lo:g}, {hi:g}] K"
            )
