"""PowerSpectrum: a piecewise power-law spectrum with exact moments and slope integral."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.special import gammaln

from ..cache import Cache, digest

__all__ = ["profile_factor", "PowerSpectrum", "stacked_C"]

#: Allowed values of the ``convention`` argument of :class:`Tabulated`.
CONVENTIONS: tuple[str, ...] = ("persson", "surface_topography", "profile_1d")

_TWO_PI_SQ = (2.0 * np.pi) ** 2

_MOMENTS = Cache(
    "physics.spectrum_moments",
    scope="spectrum",
    maxsize=512,
    doc="full moments and cumulative moments at the nodes of a spectrum, per power k",
)
_I3_GRID = Cache(
    "physics.spectrum_I3",
    scope="spectrum",
    maxsize=1024,
    doc="I3(q) of a spectrum on an output grid (the scene check and the coefficient share it)",
)
#: Grids longer than this are not kept (hashing them costs what evaluating them does).
_I3_GRID_MAX = 4096


def profile_factor(H: ArrayLike) -> NDArray[np.float64] | float:
    """Return the 1-D/2-D power-law factor :math:`K(H)` (:cite:p:`persson2005,jacobs2017`).

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

    def cache_key(self) -> bytes:
        """The spectrum's content key for :mod:`xpersson.cache`: a 128-bit digest of its
        breakpoints [1/m], left-end values [m^4] and exponents [1], which define it.

        Computed once when the spectrum is frozen (:meth:`freeze`), else at each call.

        Raises
        ------
        TypeError
            For a subclass that does not define its segments with :meth:`_set_segments`
            (it must define ``cache_key()`` itself).
        """
        key = self.__dict__.get("_content_key")
        if key is not None:
            return key  # type: ignore[no-any-return]
        if "_nodes" not in self.__dict__:
            raise TypeError(
                f"{type(self).__qualname__} does not call _set_segments: define cache_key() "
                "(the numbers that define the spectrum) so that results derived from it can "
                "be cached"
            )
        return digest(self._nodes, self._Ca, self._e)

    def freeze(self) -> PowerSpectrum:
        """Make the spectrum immutable (read-only arrays, no attribute assignment); returns it.

        A frozen spectrum may be shared (e.g. by a spectrum plugin for equal parameters); its
        content key (:meth:`cache_key`) is computed here, once.
        """
        for value in vars(self).values():
            if isinstance(value, np.ndarray):
                value.setflags(write=False)
        if "_nodes" in self.__dict__:
            object.__setattr__(self, "_content_key", self.cache_key())
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
        # the inner breakpoints at or below q: the segment, clipped to the first and the last
        idx = np.searchsorted(self._nodes[1:-1], q, side="right")
        return np.intp(idx) if np.ndim(idx) == 0 else idx

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
        if q_a is None and q_b is None:  # the full moment: computed once per k and spectrum
            key = float(k)
            if "_nodes" not in self.__dict__:  # a subclass that does not use _set_segments
                return self._moment(key, self.q_L, self.q_1)
            return _MOMENTS.get(
                (self, "moment", key), lambda: self._moment(key, self.q_L, self.q_1)
            )
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

        def compute() -> NDArray[np.float64]:
            seg = _segment_integral(self._a, self._b, self._Ca, self._e, key)
            return np.concatenate(([0.0], np.cumsum(seg)))

        return _MOMENTS.get((self, "cumulative", key), compute)

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
        if q_arr.ndim == 0:  # (numpy's scalar pow: not the array loop's bits)
            part = _segment_integral(self._a[idx], q_arr, self._Ca[idx], self._e[idx], float(k))
            return float(cum[idx] + part)
        # _segment_integral's per-segment factors once per segment (elementwise: the same bits)
        lead = self._Ca * self._a ** (float(k) + 1.0)
        s = float(k) + self._e + 1.0
        L = np.log(q_arr / self._a[idx])
        part = lead[idx] * L * _expm1_over_x(s[idx] * L)
        return cum[idx] + part

    def _I3_and_C(
        self, q: NDArray[np.float64], moment: bool = True
    ) -> tuple[NDArray[np.float64] | None, NDArray[np.float64]] | None:
        """``(I3(q), C(q))`` of an array ``q`` [1/m] inside ``[q_L, q_1]``: the numbers of
        :meth:`I3` and :meth:`C`, element by element, from one segment search and one ratio
        ``q / q_i`` (inside the support the clip of :meth:`running_moment` and the ``where``
        of :meth:`C` leave ``q`` as it is); ``moment=False``: ``(None, C(q))``. ``None`` where
        it does not apply (a value outside the support or NaN, an empty array, a subclass that
        overrides ``C``, ``I3`` or the moments): ask :meth:`I3` and :meth:`C`.
        """
        cls = type(self)
        if (
            q.ndim == 0
            or q.size == 0
            or "_nodes" not in self.__dict__
            or cls.C is not PowerSpectrum.C
            or (moment and cls.I3 is not PowerSpectrum.I3)
            or (moment and cls.running_moment is not PowerSpectrum.running_moment)
        ):
            return None
        lo, hi = q.min(), q.max()
        if not (lo >= self.q_L and hi <= self.q_1):
            return None
        ends = self._segment(np.array([lo, hi]))
        # one segment holds every q: its factors as scalars (products and sums: the same
        # bits), its exponent an array as ever (pow's own loop)
        one = ends[0] == ends[1]
        idx = int(ends[0]) if one else self._segment(q)
        r = q / self._a[idx]
        C = self._Ca[idx] * r ** (np.full(q.shape, self._e[idx]) if one else self._e[idx])
        if not moment:
            return None, C
        L = np.log(r)
        s = 3.0 + self._e + 1.0  # running_moment's per-segment factors at k = 3
        part = (self._Ca * self._a**4.0)[idx] * L * _expm1_over_x(s[idx] * L)
        return self._cumulative(3.0)[idx] + part, C

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
            A 1-D array of up to 4096 values (an output grid) is kept in the spectrum-scoped
            cache ``physics.spectrum_I3`` and returned read-only.
        """
        if (
            isinstance(q, np.ndarray)
            and q.ndim == 1
            and q.size <= _I3_GRID_MAX
            and "_nodes" in self.__dict__
            and type(self).running_moment is PowerSpectrum.running_moment
        ):  # an output grid: evaluated once per spectrum (the scene check, then tau)
            return _I3_GRID.get((self, q), lambda: self.running_moment(3.0, q))
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


def stacked_C(psds: list[PowerSpectrum], q: ArrayLike) -> NDArray[np.float64] | None:
    """``C(q)`` [m^4] of each spectrum at its row of ``q`` [1/m] (``(K, n)``, or ``(n,)`` for
    all), as ``(K, n)``: the numbers of :meth:`PowerSpectrum.C` (the same operations element
    by element) made once over a block of spectra.

    Returns ``None`` unless every spectrum keeps the base class's ``C`` and power-law segments
    (``_set_segments``), all with the same number of segments: the caller then asks each.
    """
    if not psds or any(
        "_nodes" not in p.__dict__ or type(p).C is not PowerSpectrum.C for p in psds
    ):
        return None
    m = psds[0]._a.size
    if any(p._a.size != m for p in psds):
        return None
    nodes = np.stack([p._nodes for p in psds])
    q = np.broadcast_to(np.asarray(q, dtype=float), (len(psds), np.shape(q)[-1]))
    idx = np.count_nonzero(nodes[:, :, None] <= q[:, None, :], axis=1) - 1
    np.clip(idx, 0, m - 1, out=idx)
    a = np.take_along_axis(nodes[:, :-1], idx, 1)
    Ca = np.take_along_axis(np.stack([p._Ca for p in psds]), idx, 1)
    e = np.take_along_axis(np.stack([p._e for p in psds]), idx, 1)
    q_L, q_1 = nodes[:, :1], nodes[:, -1:]
    inside = (q >= q_L) & (q <= q_1)
    return np.where(inside, Ca * (np.where(inside, q, a) / a) ** e, 0.0)
