"""Tabulated spectra: measured (q, C) tables in one of the CONVENTIONS, interpolated log-log."""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from os import PathLike
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._spectrum import _TWO_PI_SQ, CONVENTIONS, PowerSpectrum, profile_factor

__all__ = ["Convention", "Tabulated"]

Convention = Literal["persson", "surface_topography", "profile_1d"]
"""The spectrum conventions a table may be given in (see :data:`CONVENTIONS`)."""


class Tabulated(PowerSpectrum):
    """Tabulated isotropic PSD with log-log linear interpolation.

    Between consecutive points the PSD is the power law through both points, so moments and
    :meth:`I3` are exact sums of analytic segment integrals.

    Parameters
    ----------
    q : array_like
        Wavevectors [1/m], strictly increasing, > 0, finite, at least 2 points.
    C : array_like
        PSD values in the units of ``convention`` (> 0, finite).
    convention : {"persson", "surface_topography", "profile_1d"}
        * ``"persson"``: isotropic Persson convention [m^4], used as is.
        * ``"surface_topography"``: isotropic Jacobs-Junge-Pastewka / SurfaceTopography
          convention [m^4]; converted with ``C_P = C_JJP / (2 pi)^2``
          (:cite:p:`persson2005,jacobs2017`).
        * ``"profile_1d"``: line-scan PSD in the JJP convention [m^3]
          (``h_rms^2 = (1/pi) int_0^inf C1D dq``). Converted with the **local power-law
          approximation** ``C_P(q) = C1D(q) / (K(H_loc) q (2 pi)^2)``, where
          ``H_loc = -(1 + s)/2`` and ``s = d ln C1D / d ln q`` is the local log-log slope at
          each point (second-order finite differences, one-sided at the ends) and
          ``K(H)`` is :func:`profile_factor`. This is *exact for a pure power law*; near
          cut-offs/roll-offs (where the true relation is the non-local Abel-type integral
          ``C1D(q_x) = (1/2 pi) int dq_y C_iso(sqrt(q_x^2+q_y^2))``) it is an approximation.
          ``H_loc`` is clipped to ``[h_clip[0], h_clip[1]]`` (default ``[0, 1]``) to keep
          ``K`` finite on plateaus.
    q_L, q_1 : float, optional
        Truncate the support to ``[q_L, q_1]`` (must lie within the table; defaults: table
        ends). The truncation points are interpolated log-log.
    h_clip : tuple of float, optional
        Clipping interval for ``H_loc`` (``profile_1d`` only).

    Attributes
    ----------
    q_table, C_table : ndarray
        The table after conversion to the Persson convention and truncation.
    H_local : ndarray or None
        The local Hurst exponents used for ``profile_1d`` (before truncation), else ``None``.
    """

    def __init__(
        self,
        q: ArrayLike,
        C: ArrayLike,
        convention: Convention = "persson",
        *,
        q_L: float | None = None,
        q_1: float | None = None,
        h_clip: tuple[float, float] = (0.0, 1.0),
    ) -> None:
        q_arr, C_arr = _validate_table(q, C)
        if convention not in CONVENTIONS:
            raise ValueError(
                f"unknown PSD convention {convention!r}; allowed: {', '.join(CONVENTIONS)}"
            )
        self.convention = convention
        self.H_local: NDArray[np.float64] | None = None
        if convention == "surface_topography":
            C_arr = C_arr / _TWO_PI_SQ
        elif convention == "profile_1d":
            lo, hi = h_clip
            if not -0.5 < lo <= hi:
                raise ValueError("h_clip must satisfy -1/2 < h_clip[0] <= h_clip[1]")
            lq, lC = np.log(q_arr), np.log(C_arr)
            if q_arr.size == 2:
                slope = np.full(2, (lC[1] - lC[0]) / (lq[1] - lq[0]))
            else:
                slope = np.gradient(lC, lq, edge_order=2)
            H_loc = np.clip(-(1.0 + slope) / 2.0, lo, hi)
            self.H_local = H_loc
            C_arr = C_arr / (profile_factor(H_loc) * q_arr) / _TWO_PI_SQ
        # exponents of the log-log interpolant
        e = np.diff(np.log(C_arr)) / np.diff(np.log(q_arr))
        qL = float(q_arr[0]) if q_L is None else float(q_L)
        q1 = float(q_arr[-1]) if q_1 is None else float(q_1)
        if not (q_arr[0] <= qL < q1 <= q_arr[-1]):
            raise ValueError(
                "Tabulated: need q[0] <= q_L < q_1 <= q[-1] "
                f"(got q_L={qL:g}, q_1={q1:g}, table [{q_arr[0]:g}, {q_arr[-1]:g}])"
            )
        inner = (q_arr > qL) & (q_arr < q1)
        nodes = np.concatenate(([qL], q_arr[inner], [q1]))
        # PSD at each node via the full-table interpolant
        self._set_segments(q_arr, C_arr[:-1], e)
        C_nodes = np.asarray(self.C(nodes), dtype=float)
        e_nodes = np.diff(np.log(C_nodes)) / np.diff(np.log(nodes))
        self._set_segments(nodes, C_nodes[:-1], e_nodes)
        self.q_table = nodes
        self.C_table = C_nodes

    @classmethod
    def from_file(
        cls,
        path: str | PathLike[str],
        q_unit_factor: float = 1.0,
        C_unit_factor: float = 1.0,
        convention: Convention = "persson",
        *,
        columns: Sequence[int] = (0, 1),
        q_L: float | None = None,
        q_1: float | None = None,
        h_clip: tuple[float, float] = (0.0, 1.0),
    ) -> Tabulated:
        """Read a two-column text/CSV table ``q, C``.

        Lines are split on commas, semicolons or whitespace; everything after ``#`` is a
        comment; blank lines are ignored; the first non-comment line may be a non-numeric
        header (skipped).

        Parameters
        ----------
        path : path-like
            File to read.
        q_unit_factor : float
            Multiplier converting the file's q column to 1/m (e.g. ``1e6`` for 1/um).
        C_unit_factor : float
            Multiplier converting the file's C column to SI (m^4, or m^3 for ``profile_1d``).
        convention : {"persson", "surface_topography", "profile_1d"}
            See :class:`Tabulated`.
        columns : sequence of 2 int
            Zero-based column indices of q and C.
        q_L, q_1, h_clip
            Passed to :class:`Tabulated`.

        Raises
        ------
        ValueError
            On unparsable rows or invalid data (see :class:`Tabulated`).
        """
        iq, iC = (int(c) for c in columns)
        if not q_unit_factor > 0 or not C_unit_factor > 0:
            raise ValueError("unit factors must be > 0")
        qs: list[float] = []
        Cs: list[float] = []
        lines: list[int] = []
        header_seen = False
        lineno = 0
        with open(path, encoding="utf-8") as fh:
            for lineno, raw in enumerate(fh, start=1):
                line = raw.split("#", 1)[0].strip()
                if not line:
                    continue
                fields = [f for f in re.split(r"[,;\s]+", line) if f]
                try:
                    qv, Cv = float(fields[iq]), float(fields[iC])
                except (ValueError, IndexError):
                    if not qs and not header_seen:
                        header_seen = True
                        continue
                    raise ValueError(
                        f"{path}: line {lineno}: cannot read columns {iq}, {iC} as numbers: "
                        f"{raw.rstrip()!r}"
                    ) from None
                _check_row(
                    path, lineno, qv, Cv, qs[-1] if qs else None, lines[-1] if lines else None
                )
                qs.append(qv)
                Cs.append(Cv)
                lines.append(lineno)
        if len(qs) < 2:
            what = "has no data rows" if not qs else f"has only one data row (line {lines[0]})"
            raise ValueError(
                f"{path}: line {lineno}: end of file; the table "
                f"{what}; a PSD table needs at least 2 rows 'q, C'"
            )
        return cls(
            np.asarray(qs) * q_unit_factor,
            np.asarray(Cs) * C_unit_factor,
            convention,
            q_L=q_L,
            q_1=q_1,
            h_clip=h_clip,
        )

    def __repr__(self) -> str:
        return (
            f"Tabulated(n={self.q_table.size}, q_L={self.q_L:.6g}, q_1={self.q_1:.6g}, "
            f"convention={self.convention!r})"
        )


def _check_row(
    path: Any, lineno: int, q: float, C: float, q_prev: float | None, line_prev: int | None
) -> None:
    """One table row: finite, q > 0, C > 0, q above the previous row's (file and line named)."""
    where = f"{path}: line {lineno}"
    if not math.isfinite(q):
        raise ValueError(f"{where}: q = {q!r} is not finite")
    if not math.isfinite(C):
        raise ValueError(f"{where}: C = {C!r} is not finite")
    if not q > 0:
        raise ValueError(f"{where}: q = {q:g} must be > 0")
    if not C > 0:
        raise ValueError(f"{where}: C = {C:g} must be > 0 (log-log interpolation)")
    if q_prev is not None and not q > q_prev:
        what = "duplicates" if q == q_prev else "is below"
        raise ValueError(
            f"{where}: q = {q:g} {what} q = {q_prev:g} of line {line_prev}; q must be strictly "
            "increasing"
        )


def _validate_table(q: ArrayLike, C: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    q_arr = np.asarray(q, dtype=float)
    C_arr = np.asarray(C, dtype=float)
    if q_arr.ndim != 1 or C_arr.ndim != 1:
        raise ValueError("Tabulated: q and C must be one-dimensional")
    if q_arr.shape != C_arr.shape:
        raise ValueError(f"Tabulated: q and C differ in length ({q_arr.size} vs {C_arr.size})")
    if q_arr.size < 2:
        raise ValueError(f"Tabulated: need at least 2 points, got {q_arr.size}")
    if not np.all(np.isfinite(q_arr)):
        raise ValueError("Tabulated: q contains non-finite values")
    if not np.all(np.isfinite(C_arr)):
        raise ValueError("Tabulated: C contains non-finite values")
    if np.any(q_arr <= 0):
        raise ValueError("Tabulated: q must be > 0")
    if np.any(C_arr <= 0):
        raise ValueError("Tabulated: C must be > 0 (log-log interpolation)")
    if np.any(np.diff(q_arr) <= 0):
        i = int(np.argmax(np.diff(q_arr) <= 0))
        raise ValueError(
            f"Tabulated: q must be strictly increasing (q[{i}]={q_arr[i]:g} >= "
            f"q[{i + 1}]={q_arr[i + 1]:g})"
        )
    return q_arr, C_arr
