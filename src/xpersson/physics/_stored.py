"""A spectrum rebuilt from its stored segments: what a solved Dataset keeps of its spectrum.

Every spectrum of xpersson is a piecewise power law (:class:`PowerSpectrum`): its breakpoints
``q_i`` [1/m], the value ``C(q_i)`` at the left end of each segment [m^4] and each segment's
log-log exponent ``e_i`` [1] define it. A solved Dataset stores the three as ``q_psd``,
``psd_C`` and ``psd_exponent`` (:func:`segment_exponents`), and :class:`StoredSpectrum` rebuilds
from them a spectrum whose every number (``C``, the moments, ``I3``) is the original's, bit for
bit: the same segments go through the same :class:`PowerSpectrum` code.

Without the exponents (an archive written before they were stored) each segment's exponent is
the log-log slope between its two stored values, as :class:`Tabulated` interpolates a table:
the same spectrum up to round-off in the exponents (a few 1e-16 relative, amplified to
``|ln(q/q_i)| * 1e-16`` in ``C``).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._spectrum import PowerSpectrum

__all__ = ["StoredSpectrum", "segment_exponents"]


def segment_exponents(psd: PowerSpectrum) -> NDArray[np.float64]:
    """Each breakpoint's segment exponent, as a solved Dataset stores it (``psd_exponent``).

    Parameters
    ----------
    psd : PowerSpectrum
        A spectrum defined by its segments (``_set_segments``: every spectrum of xpersson).

    Returns
    -------
    ndarray, shape (n_nodes,)
        ``e_i`` [1] of the segment ``[q_i, q_{i+1}]`` at node ``i``
        (``C(q) = C(q_i) (q / q_i)^e_i`` there); NaN at the last node, where no segment starts.
    """
    e = np.asarray(psd._e, dtype=float)  # noqa: SLF001 - the segments of the same package
    return np.concatenate((e, [np.nan]))


class StoredSpectrum(PowerSpectrum):
    """The piecewise power-law spectrum of stored breakpoints, values and exponents.

    Parameters
    ----------
    q : array_like, shape (n,)
        Breakpoints [1/m]: finite, > 0, strictly increasing, at least two.
    C : array_like, shape (n,)
        ``C(q)`` at the breakpoints [m^4] (Persson's convention), finite and > 0.
    exponents : array_like, shape (n,) or (n - 1,), optional
        Log-log exponent of the segment starting at each breakpoint [1] (the last entry of an
        ``(n,)`` array, NaN in a Dataset, is not read). ``None``: the slope between the two
        stored values of each segment (round-off in the exponents, see the module docstring).

    Raises
    ------
    ValueError
        Naming the array that is malformed (length, sign, finiteness, order).
    """

    def __init__(self, q: ArrayLike, C: ArrayLike, exponents: ArrayLike | None = None) -> None:
        q_arr = np.asarray(q, dtype=float).ravel()
        C_arr = np.asarray(C, dtype=float).ravel()
        if q_arr.size < 2 or C_arr.shape != q_arr.shape:
            raise ValueError(
                f"a stored spectrum needs at least two breakpoints q [1/m] with one C [m^4] "
                f"each; got {q_arr.size} q and {C_arr.size} C"
            )
        if not (np.all(np.isfinite(q_arr)) and q_arr[0] > 0 and np.all(np.diff(q_arr) > 0)):
            raise ValueError("the breakpoints q [1/m] must be finite, > 0 and strictly increasing")
        if not (np.all(np.isfinite(C_arr)) and np.all(C_arr > 0)):
            raise ValueError("the stored C(q) [m^4] must be finite and > 0 at every breakpoint")
        if exponents is None:
            e = np.diff(np.log(C_arr)) / np.diff(np.log(q_arr))
        else:
            e = np.asarray(exponents, dtype=float).ravel()
            if e.size not in (q_arr.size, q_arr.size - 1):
                raise ValueError(
                    f"one exponent [1] per segment ({q_arr.size - 1}) or per breakpoint "
                    f"({q_arr.size}) expected, got {e.size}"
                )
            e = e[: q_arr.size - 1]
            if not np.all(np.isfinite(e)):
                raise ValueError("the stored segment exponents [1] must be finite")
        self._set_segments(q_arr, C_arr[:-1], e)

    def __repr__(self) -> str:
        return f"StoredSpectrum(q_L={self.q_L:.6g}, q_1={self.q_1:.6g}, segments={self._e.size})"
