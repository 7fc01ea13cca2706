"""Isotropic surface-roughness power spectra (pure numpy, SI units).

All spectra are stored internally in **Persson's isotropic convention** (physics.md §0, §8.1):

.. math::

    C(q) = (2\\pi)^{-2} \\int d^2x \\, \\langle h(x) h(0) \\rangle e^{-i q\\cdot x}
    \\quad [\\mathrm{m^4}], \\qquad
    \\langle h^2 \\rangle = 2\\pi \\int q C(q)\\, dq .

Every spectrum in this module is *piecewise power law* between its breakpoints
(:meth:`PowerSpectrum.nodes`), so all moments
:math:`m_k = \\int q^k C(q)\\, dq` and the running slope integral
:math:`I_3(q) = \\int_{q_L}^{q} q'^3 C(q')\\, dq'` are evaluated **exactly** as sums of analytic
segment integrals (the logarithmic case, segment exponent :math:`k + e = -1`, is handled
continuously through :math:`\\mathrm{expm1}(x)/x`).

Wavevectors ``q`` are in rad/m (written 1/m).
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from os import PathLike
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.special import gammaln

__all__ = [
    "CONVENTIONS",
    "PowerSpectrum",
    "SelfAffineRollOff",
    "Tabulated",
    "profile_factor",
]

Convention = Literal["persson", "surface_topography", "profile_1d"]

#: Allowed values of the ``convention`` argument of :class:`Tabulated`.
CONVENTIONS: tuple[str, ...] = ("persson", "surface_topography", "profile_1d")

_TWO_PI_SQ = (2.0 * np.pi) ** 2


def profile_factor(H: ArrayLike) -> NDArray[np.float64] | float:
    """Return the 1-D/2-D power-law factor :math:`K(H)` (physics.md §8.2).

    For an isotropic power law :math:`C^{iso}(q) = C_0 q^{-2-2H}` (JJP convention) the line-scan
    PSD is :math:`C^{1D}(q) = K(H)\\, C_0\\, q^{-1-2H}` with

    .. math:: K(H) = \\frac{\\Gamma(H + 1/2)}{2\\sqrt{\\pi}\\,\\Gamma(H + 1)} .

    Parameters
    ----------
    H : array_like
        Hurst exponent(s), dimensionless, ``H > -1/2``.

    Returns
    -------
    float or ndarray
        :math:`K(H)`, dimensionless (``1/K = pi`` at ``H = 1/2``, ``4`` at ``H = 1``).
    """
    H_arr = np.asarray(H, dtype=float)
    if np.any(~(H_arr > -0.5)):
        raise ValueError("profile_factor: H must be > -1/2")
    out = np.exp(gammaln(H_arr + 0.5) - gammaln(H_arr + 1.0)) / (2.0 * np.sqrt(np.pi))
    return float(out) if out.ndim == 0 else out


def _expm1_over_x(x: NDArray[np.float64]) -> NDArray[np.float64]:
    """Return ``expm1(x)/x`` with the removable singularity (value 1) at ``x = 0``."""
    x = np.asarray(x, dtype=float)
    zero = x == 0.0
    if not zero.any():
        return np.expm1(x) / x
    xs = np.where(zero, 1.0, x)
    return np.where(zero, 1.0, np.expm1(xs) / xs)


def _segment_integral(
    a: NDArray[np.float64],
    b: NDArray[np.float64],
    Ca: NDArray[np.float64],
    e: NDArray[np.float64],
    k: float,
) -> NDArray[np.float64]:
    """Exact :math:`\\int_a^b q^k C(q) dq` for ``C(q) = Ca (q/a)^e`` (element-wise, ``b >= a > 0``).

    Written as ``Ca a^{k+1} L expm1(s L)/(s L)`` with ``L = ln(b/a)``, ``s = k + e + 1``; the
    logarithmic case ``s = 0`` is the continuous limit ``Ca a^{k+1} L``.
    """
    L = np.log(b / a)
    s = k + e + 1.0
    return Ca * a ** (k + 1.0) * L * _expm1_over_x(s * L)


class PowerSpectrum:
    """Abstract isotropic PSD made of power-law segments (Persson convention, m^4).

    Subclasses call :meth:`_set_segments` with the breakpoints ``nodes`` (strictly increasing,
    1/m), the PSD values at the *left* end of each segment ``C_left`` (m^4) and the log-log
    exponents ``exponents`` of each segment (``C(q) = C_left (q/q_i)^e_i`` on
    ``[q_i, q_{i+1}]``). ``C(q) = 0`` outside ``[q_L, q_1]``.

    Attributes
    ----------
    q_L : float
        Lower cut-off wavevector of the support [1/m] (defines the magnification
        ``zeta = q / q_L``).
    q_1 : float
        Upper cut-off wavevector of the support [1/m].
    """

    q_L: float
    q_1: float

    # ------------------------------------------------------------------ set-up
    def _set_segments(self, nodes: ArrayLike, C_left: ArrayLike, exponents: ArrayLike) -> None:
        nodes = np.asarray(nodes, dtype=float)
        C_left = np.asarray(C_left, dtype=float)
        exponents = np.asarray(exponents, dtype=float)
        if nodes.ndim != 1 or nodes.size < 2:
            raise ValueError("a spectrum needs at least two breakpoints")
        if not (C_left.shape == exponents.shape == (nodes.size - 1,)):
            raise ValueError("C_left and exponents must have one entry per segment")
        if np.any(np.diff(nodes) <= 0):
            raise ValueError("breakpoints must be strictly increasing")
        self._nodes = nodes
        self._a = nodes[:-1]
        self._b = nodes[1:]
        self._Ca = C_left
        self._e = exponents
        self.q_L = float(nodes[0])
        self.q_1 = float(nodes[-1])
        self._cum_cache: dict[float, NDArray[np.float64]] = {}
        self._moment_cache: dict[float, float] = {}

    def freeze(self) -> PowerSpectrum:
        """Make the spectrum immutable (read-only arrays, no attribute assignment); returns it.

        A frozen spectrum may be shared (e.g. cached by a spectrum plugin for equal
        parameters): its moments are computed once. Memo tables stay private.
        """
        for value in vars(self).values():
            if isinstance(value, np.ndarray):
                value.setflags(write=False)
        object.__setattr__(self, "_frozen", True)
        return self

    @property
    def frozen(self) -> bool:
        """Whether :meth:`freeze` was called."""
        return bool(getattr(self, "_frozen", False))

    def __setattr__(self, name: str, value: object) -> None:
        if getattr(self, "_frozen", False):
            raise AttributeError(
                f"{type(self).__name__} is frozen (shared); build a new one "
                f"instead of setting {name!r}"
            )
        object.__setattr__(self, name, value)

    # ----------------------------------------------------------------- basics
    def nodes(self) -> NDArray[np.float64]:
        """Return the breakpoints of the piecewise power-law PSD [1/m] (a copy).

        Storing ``nodes()`` together with ``C(nodes())`` reproduces the spectrum exactly
        (log-log interpolation, see :class:`Tabulated`).
        """
        return self._nodes.copy()

    def C(self, q: ArrayLike) -> NDArray[np.float64] | float:
        """Evaluate the PSD :math:`C(q)` [m^4] (Persson convention).

        Parameters
        ----------
        q : array_like
            Wavevector(s) [1/m].

        Returns
        -------
        float or ndarray
            ``C(q)``, zero outside ``[q_L, q_1]``. Same shape as ``q``.
        """
        q_arr = np.asarray(q, dtype=float)
        idx = self._segment(q_arr)
        inside = (q_arr >= self.q_L) & (q_arr <= self.q_1)
        a = self._a[idx]
        val = self._Ca[idx] * (np.where(inside, q_arr, a) / a) ** self._e[idx]
        out = np.where(inside, val, 0.0)
        return float(out) if out.ndim == 0 else out

    def _segment(self, q: NDArray[np.float64]) -> NDArray[np.intp]:
        """Index of the segment holding each ``q`` (clipped to the first / last segment)."""
        idx = np.asarray(np.searchsorted(self._nodes, q, side="right"))
        if idx.ndim == 0:  # scalar q
            return np.intp(min(max(int(idx) - 1, 0), self._a.size - 1))
        idx -= 1
        np.maximum(idx, 0, out=idx)
        np.minimum(idx, self._a.size - 1, out=idx)
        return idx

    # ---------------------------------------------------------------- moments
    def moment(self, k: float, q_a: float | None = None, q_b: float | None = None) -> float:
        """Exact moment :math:`\\int_{q_a}^{q_b} q^k C(q)\\, dq`.

        Parameters
        ----------
        k : float
            Power of ``q`` (any real; ``k = 1, 3, 5`` give height, slope, curvature moments).
        q_a, q_b : float, optional
            Integration limits [1/m]; default to the support ``q_L``, ``q_1``. Limits are
            clipped to the support (``C = 0`` outside). ``q_b < q_a`` returns the negative.

        Returns
        -------
        float
            The moment in m^(4+k+1) (e.g. m^2 for ``k = 1``, dimensionless for ``k = 3``).
        """
        if q_a is None and q_b is None:  # the full moment: computed once per k
            cache = getattr(self, "_moment_cache", None)
            if cache is None:  # a subclass that does not use _set_segments
                return self._moment(float(k), self.q_L, self.q_1)
            key = float(k)
            if key not in cache:
                cache[key] = self._moment(key, self.q_L, self.q_1)
            return cache[key]
        qa = self.q_L if q_a is None else float(q_a)
        qb = self.q_1 if q_b is None else float(q_b)
        return self._moment(float(k), qa, qb)

    def _moment(self, k: float, qa: float, qb: float) -> float:
        if qb < qa:
            return -self._moment(k, qb, qa)
        lo = np.clip(np.maximum(self._a, qa), self._a, self._b)
        hi = np.clip(np.minimum(self._b, qb), self._a, self._b)
        use = hi > lo
        if not np.any(use):
            return 0.0
        lo, hi = lo[use], hi[use]
        a, Ca, e = self._a[use], self._Ca[use], self._e[use]
        C_lo = Ca * (lo / a) ** e
        return float(np.sum(_segment_integral(lo, hi, C_lo, e, float(k))))

    def _cumulative(self, k: float) -> NDArray[np.float64]:
        """Cumulative moment at the nodes, ``M_k(nodes[i]) = int_{q_L}^{nodes[i]} q^k C``."""
        key = float(k)
        cum = self._cum_cache.get(key)
        if cum is None:
            seg = _segment_integral(self._a, self._b, self._Ca, self._e, key)
            cum = np.concatenate(([0.0], np.cumsum(seg)))
            self._cum_cache[key] = cum
        return cum

    def running_moment(self, k: float, q: ArrayLike) -> NDArray[np.float64] | float:
        """Exact :math:`\\int_{q_L}^{q} q'^k C(q')\\, dq'`, vectorised over ``q``.

        Parameters
        ----------
        k : float
            Power of ``q``.
        q : array_like
            Upper limit(s) [1/m]; values below ``q_L`` give 0, above ``q_1`` the full moment.

        Returns
        -------
        float or ndarray
            Same shape as ``q``.
        """
        q_arr = np.minimum(np.maximum(np.asarray(q, dtype=float), self.q_L), self.q_1)
        cum = self._cumulative(k)
        idx = self._segment(q_arr)
        a = self._a[idx]
        part = _segment_integral(a, q_arr, self._Ca[idx], self._e[idx], float(k))
        out = cum[idx] + part
        return float(out) if out.ndim == 0 else out

    def I3(self, q: ArrayLike) -> NDArray[np.float64] | float:
        """Exact slope integral :math:`I_3(q) = \\int_{q_L}^{q} q'^3 C(q')\\, dq'` (§1.2).

        Parameters
        ----------
        q : array_like
            Upper limit(s) [1/m], vectorised; clipped to ``[q_L, q_1]``.

        Returns
        -------
        float or ndarray
            ``I3(q)`` (dimensionless: m^-3 * m^4 * m^-1); ``<|grad h|^2>_q = 2 pi I3(q)``.
        """
        return self.running_moment(3.0, q)

    def h_rms(self) -> float:
        """Root-mean-square height [m]: ``sqrt(2 pi m_1)``."""
        return math.sqrt(2.0 * np.pi * self.moment(1.0))

    def rms_slope(self) -> float:
        """Root-mean-square 2-D gradient ``sqrt(<|grad h|^2>) = sqrt(2 pi m_3)``.

        Dimensionless. The profile (1-D) slope is this value divided by ``sqrt(2)``.
        """
        return math.sqrt(2.0 * np.pi * self.moment(3.0))

    def rms_curvature(self) -> float:
        """Root-mean-square Laplacian :math:`\\sqrt{\\langle(\\nabla^2 h)^2\\rangle}` [1/m]."""
        return math.sqrt(2.0 * np.pi * self.moment(5.0))

    def __repr__(self) -> str:
        return f"{type(self).__name__}(q_L={self.q_L:.6g}, q_1={self.q_1:.6g})"


class SelfAffineRollOff(PowerSpectrum):
    """Self-affine PSD with roll-off (physics.md §8.2, Persson convention).

    .. math::

        C(q) = \\begin{cases} C_r & q_L \\le q < q_r \\\\
                              C_r (q/q_r)^{-2(1+H)} & q_r \\le q \\le q_1 \\\\
                              0 & \\text{otherwise} \\end{cases}

    Parameters
    ----------
    C_r : float
        Plateau value [m^4] (power-law prefactor ``C0 = C_r q_r^(2+2H)``).
    H : float
        Hurst exponent, ``0 < H <= 1`` (``H = 1`` uses the logarithmic forms).
    q_L : float
        Lower cut-off [1/m].
    q_r : float
        Roll-off wavevector [1/m], ``q_L <= q_r <= q_1`` (``q_r = q_L``: no plateau).
    q_1 : float
        Upper cut-off [1/m], ``q_1 > q_L``.
    """

    def __init__(self, C_r: float, H: float, q_L: float, q_r: float, q_1: float) -> None:
        C_r, H, q_L, q_r, q_1 = (float(v) for v in (C_r, H, q_L, q_r, q_1))
        if not all(np.isfinite(v) for v in (C_r, H, q_L, q_r, q_1)):
            raise ValueError("SelfAffineRollOff: all parameters must be finite")
        if not 0.0 < H <= 1.0:
            raise ValueError(f"SelfAffineRollOff: Hurst exponent H={H} must satisfy 0 < H <= 1")
        if not q_L > 0.0:
            raise ValueError("SelfAffineRollOff: q_L must be > 0")
        if not q_1 > q_L:
            raise ValueError("SelfAffineRollOff: q_1 must be > q_L")
        if not q_L <= q_r <= q_1:
            raise ValueError("SelfAffineRollOff: q_r must satisfy q_L <= q_r <= q_1")
        if not C_r > 0.0:
            raise ValueError("SelfAffineRollOff: C_r must be > 0")
        self.C_r = C_r
        self.H = H
        self.q_r = q_r
        e_tail = -2.0 * (1.0 + H)
        nodes: list[float] = [q_L]
        C_left: list[float] = []
        expo: list[float] = []
        if q_r > q_L:
            nodes.append(q_r)
            C_left.append(C_r)
            expo.append(0.0)
        if q_1 > q_r:
            nodes.append(q_1)
            C_left.append(C_r)
            expo.append(e_tail)
        self._set_segments(nodes, C_left, expo)

    @property
    def C0(self) -> float:
        """Power-law prefactor ``C0 = C_r q_r^(2+2H)`` [m^(2-2H)] so that ``C = C0 q^(-2-2H)``."""
        return self.C_r * self.q_r ** (2.0 + 2.0 * self.H)

    @classmethod
    def _unit(cls, H: float, q_L: float, q_r: float, q_1: float) -> SelfAffineRollOff:
        return cls(1.0, H, q_L, q_r, q_1)

    @classmethod
    def from_h_rms(
        cls, h_rms: float, H: float, q_L: float, q_r: float, q_1: float
    ) -> SelfAffineRollOff:
        """Build from the rms height [m]: ``C_r = h_rms^2 / (2 pi m_1[C_r = 1])``."""
        if not h_rms > 0:
            raise ValueError("from_h_rms: h_rms must be > 0")
        unit = cls._unit(H, q_L, q_r, q_1)
        return cls(h_rms**2 / (2.0 * np.pi * unit.moment(1.0)), H, q_L, q_r, q_1)

    @classmethod
    def from_rms_slope(
        cls, slope: float, H: float, q_L: float, q_r: float, q_1: float
    ) -> SelfAffineRollOff:
        """Build from the rms 2-D gradient (dimensionless): ``C_r = slope^2/(2 pi m_3[C_r=1])``."""
        if not slope > 0:
            raise ValueError("from_rms_slope: slope must be > 0")
        unit = cls._unit(H, q_L, q_r, q_1)
        return cls(slope**2 / (2.0 * np.pi * unit.moment(3.0)), H, q_L, q_r, q_1)

    def __repr__(self) -> str:
        return (
            f"SelfAffineRollOff(C_r={self.C_r:.6g}, H={self.H:g}, q_L={self.q_L:.6g}, "
            f"q_r={self.q_r:.6g}, q_1={self.q_1:.6g})"
        )


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
          convention [m^4]; converted with ``C_P = C_JJP / (2 pi)^2`` (physics.md §8.1).
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
