"""Leak rate of a static seal (physics.md §6): critical junction and effective medium.

*Critical junction* (Persson & Yang 2008; Lorenz & Persson 2009): the non-contact channels
percolate at the magnification ``zeta_c`` where the solved contact area equals ``a_c`` (default
0.42); the flow is limited by the critical constrictions of height ``u1(zeta_c) = d(A u)/dA``
(:func:`xpersson.physics.critical_magnification`,
:func:`xpersson.physics.separation_of_detaching_area`) and

    Q = (L_y / L_x) u1^3 dP_eff / (12 eta)          [m^3/s]

(``L_x`` seal width along the flow, ``L_y`` length across it). *Effective medium* (Bruggeman,
Lorenz & Persson 2010): the local conductance ``sigma(u) = u^3/(12 eta)`` is averaged over the gap
distribution (contact as a ``delta(u)`` weight with ``sigma = 0``) by the 2-D condition
``int P(u) (sigma - sigma_eff)/(sigma + sigma_eff) du = 0``. Plain 2-D Bruggeman percolates at a
contact weight of 1/2; ``a_c=`` multiplies the contact weight by ``0.5/a_c`` (a documented design
choice, not from the papers) so both theories seal together.

Flow direction: the fluid flows from the high-pressure side (``p_in``, liquid: the side
``pressure_drop`` above the other) to the low-pressure side; the leak rate is >= 0. For an ideal
gas at constant temperature the laminar flow gives the volume flow at the outlet pressure
``p_out`` with ``dP_eff = (p_in^2 - p_out^2) / (2 p_out)`` (no slip correction); ``p_in < p_out``
is refused (name the high-pressure side ``p_in``).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from xpersson.physics import Detachment, gap_cdf
from xpersson.plugins.solved import per_solve
from xpersson.plugins.stored import spectrum_of

from ._by_load import COMPUTED
from ._newton import newton
from ._stencils import Weight

__all__ = [
    "LEAK_KEYS",
    "bruggeman",
    "bruggeman_gap",
    "effective_pressure_drop",
    "junction_piece",
    "leak_rate",
    "next_to_open",
    "sealed_both",
    "sealed_plan",
    "table_weights",
    "with_sealed",
]


#: The leak outputs never interpolated (:func:`._by_load.by_load`'s keys).
LEAK_KEYS = frozenset({"leak_sealed", "leak_sealed_emt", "piece"})


def _bruggeman_rows(
    contact: NDArray[np.float64],
    masses: NDArray[np.float64],
    sigma: NDArray[np.float64],
    infinite: NDArray[np.float64],
    *,
    rtol: float = 1e-12,
    per_row: bool = False,
    ln_sigma: NDArray[np.float64] | None = None,
) -> NDArray[np.float64]:
    """Vectorised root of ``-c + sum m_k (s_k - s)/(s_k + s) + m_inf = 0`` per row.

    ``contact`` (n,), ``masses`` (n, k), ``sigma`` (k,) or (n, k) >= 0 (``inf`` allowed),
    ``infinite`` (n,) the weight of further elements with infinite conductance. Returns 0 where
    the contact weight reaches the percolation value (half of the total weight), ``inf`` where
    the infinite elements percolate. ``per_row``: bracket each row by its own conductances
    (each row's root then equals that of the row solved alone), else by all rows'.
    ``ln_sigma`` (n, k): ``ln sigma`` where known (used for the start and the bracket only, where
    ``sigma`` is finite and > 0 everywhere; an error there only costs iterations).

    Safeguarded Newton in ``x = ln s`` from the mass-weighted mean of ``ln s_k`` (4-6 steps on
    the leakage cells). With ``r_k = s_k/(s_k + s)``, ``f' = -2 sum m r (1 - r)`` and
    ``|f''| <= |f'|``, so a Newton step of length ``d`` leaves an error below
    ``d^2 exp(d)/2``: the iteration stops after a step ``<= sqrt(rtol)`` (error
    ``<= 0.51 rtol``) or once the bracket is narrower than ``rtol``.
    """
    c = np.asarray(contact, dtype=float)
    m = np.asarray(masses, dtype=float)
    s_k = np.broadcast_to(np.atleast_2d(np.asarray(sigma, dtype=float)), m.shape)
    m_inf = np.asarray(infinite, dtype=float)
    big = ~np.isfinite(s_k)
    if big.any():
        m_inf = m_inf + np.sum(np.where(big, m, 0.0), axis=1)
        m = np.where(big, 0.0, m)
        s_k = np.where(big, 1.0, s_k)
    m_sum = m.sum(axis=1)
    total = c + m_sum + m_inf
    out = np.zeros(c.size)
    sealed = c >= 0.5 * total
    flooded = m_inf >= 0.5 * total
    work = ~sealed & ~flooded
    out[flooded & ~sealed] = np.inf
    if not work.any():
        return out
    c, m, m_sum, m_inf = c[work], m[work], m_sum[work], m_inf[work]
    s_k = np.ascontiguousarray(s_k[work])
    pos = s_k > 0
    every = bool(pos.all())  # the usual case: no masking below
    if ln_sigma is None:
        with np.errstate(divide="ignore"):
            ln_s = np.log(s_k)
    else:  # the known logarithms in the rows that are all finite and > 0 (row by row: a
        # row's start and bracket, and so its root's last bits, never depend on the others)
        ln_s = np.array(np.broadcast_to(np.atleast_2d(ln_sigma), big.shape)[work])
        odd = np.flatnonzero(~pos.all(axis=1) | big[work].any(axis=1))
        if odd.size:
            with np.errstate(divide="ignore"):
                ln_s[odd] = np.log(s_k[odd])
    if per_row:  # each row bracketed by its own conductances (as if solved alone)
        low = ln_s if every else np.where(pos, ln_s, np.inf)
        any_pos = pos.any(axis=1)
        lo = np.where(any_pos, np.min(low, axis=1), 0.0) - 60.0
        hi = np.where(any_pos, np.max(ln_s, axis=1), 0.0) + 60.0
    else:
        ln_pos = ln_s if every else ln_s[pos]
        lo = np.full(c.size, float(ln_pos.min() if ln_pos.size else 0.0) - 60.0)
        hi = np.full(c.size, float(ln_pos.max() if ln_pos.size else 0.0) + 60.0)
    # start: the open masses' weighted mean of ln s_k (the exact root of a symmetric mixture)
    mp = m if every else np.where(pos, m, 0.0)
    mp_sum = m_sum if every else mp.sum(axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        x = np.einsum("ij,ij->i", mp, ln_s if every else np.where(pos, ln_s, 0.0)) / mp_sum
    x = np.where((mp_sum > 0) & (x > lo) & (x < hi), x, 0.5 * (lo + hi))
    out[work] = np.exp(newton(x, lo, hi, m, s_k, m_inf - c - m_sum, rtol))
    return out


def bruggeman(contact: float, masses: ArrayLike, sigma: ArrayLike, *, rtol: float = 1e-12) -> float:
    """2-D Bruggeman effective conductance of a mixture with a non-conducting contact weight.

    Solves ``-contact + sum m_k (s_k - s)/(s_k + s) = 0`` for ``s > 0`` (``s_k = inf`` allowed).

    Parameters
    ----------
    contact : float
        Weight of the contact (``sigma = 0``) [1].
    masses : array_like
        Weights of the open elements [1].
    sigma : array_like
        Their conductances (any unit; the result has the same unit), ``> 0``.

    Returns
    -------
    float
        ``sigma_eff``; 0 when the contact weight reaches the percolation value (half the total).
    """
    m = np.asarray(masses, dtype=float).ravel()
    s = np.asarray(sigma, dtype=float).ravel()
    use = m > 0
    m, s = m[use], s[use]
    fin = np.isfinite(s)
    if not fin.any():
        return 0.0 if contact >= 0.5 * (contact + m.sum()) else math.inf
    return float(
        _bruggeman_rows(
            np.array([contact]), m[fin][None, :], s[fin], np.array([m[~fin].sum()]), rtol=rtol
        )[0]
    )


#: Bins of detached weight below this fraction of the load's largest are left out of the cell
#: masses: their share of the Bruggeman sum is round-off (the conductance changes <= 1e-14 rel).
NEGLIGIBLE = 1e-30


def bruggeman_gap(
    det: Detachment,
    *,
    a_c: float | None = None,
    n_u: int = 120,
    u_min: float = 1e-6,
    u_max: float | None = None,
    per_load: bool = False,
) -> NDArray[np.float64]:
    """Effective ``<u^3>_EMT`` [m^3] over the closed-form gap distribution, per load.

    ``sigma_eff = result / (12 eta)``. Cells geometric in ``u`` on ``[u_min h_rms, u_max]``
    carry the exact closed-form mass (analytic CDF, :func:`xpersson.physics.gap_cdf`) at their
    conductance, the mass below is one cell at half the first edge, the mass beyond ``u_max``
    one element of infinite conductance. All loads at once; bins of weight below
    :data:`NEGLIGIBLE` of the load's largest are left out (round-off).

    A cell's conductance is that of its midpoint ``x`` in ``ln u`` moved by ``h^2 g / 8`` (``h``
    the cells' width in ``ln u``, ``g = (sigma - s)/(sigma + s)`` its term of the Bruggeman sum
    at the midpoints' root ``s``; :func:`_moved`): the midpoint rule's error of ``int g dP``,
    ``sum m (g' beta / 12 + g'' / 24) h^2`` (``beta`` the mass density's slope in ``ln u``),
    is ``-sum m g'' h^2 / 24`` as ``sum m beta g' = -sum m g''`` (by parts, ``g'`` vanishing at
    both ends), which the move cancels (``g'' = -3 g g'``). Against 3840 midpoint cells (6
    design and held-out scenes, 40 loads): 120 cells within 3.6e-6 (the midpoint rule at 120
    cells 1.4e-3, at 240 3.6e-4); near the medium's sealing 2.7e-6 (240: 5.7e-4).

    Parameters
    ----------
    det : Detachment
        Gap-distribution bins (:func:`xpersson.physics.detachment`).
    a_c : float, optional
        When given, rescale the contact weight by ``0.5 / a_c`` so that the effective medium
        seals at ``A/A0 = a_c`` (open weights rescaled to keep unit total).
    n_u : int
        Number of cells.
    u_min : float
        First cell edge in units of ``h_rms``.
    u_max : float, optional
        Upper end of the cells [m] (default ``max(u(p0)) + 10 h_rms``).
    per_load : bool
        Give every load its own cells, spanning that load's gaps (``u_max`` default
        ``u(p0) + 10 h_rms`` of the load): each load's result is then that of the load alone,
        never dependent on the others in the batch. Still computed for all loads at once.
    """
    if per_load:
        top = det.mean_gap + 10.0 * det.h_rms if u_max is None else np.full(det.p0.size, u_max)
        edges, ln_sigma, lr = _cells(u_min * det.h_rms, top, n_u)  # (n_load, n_u + 1)
    else:
        umax = float(np.max(det.mean_gap)) + 10.0 * det.h_rms if u_max is None else u_max
        edges, ln_sigma, lr = _cells(u_min * det.h_rms, np.array([umax]), n_u)
        edges = edges[0]
    cdf = gap_cdf(det, edges, negligible=NEGLIGIBLE)
    a = np.asarray(det.contact, dtype=float)
    m = np.diff(cdf, axis=1)
    m[:, 0] += cdf[:, 0]
    far = np.maximum(1.0 - a - cdf[:, -1], 0.0)
    if a_c is not None:
        a_new = np.minimum(1.0, a * 0.5 / a_c)
        scale = np.where(a < 1.0, (1.0 - a_new) / np.where(a < 1.0, 1.0 - a, 1.0), 0.0)
        m, far, a = m * scale[:, None], far * scale, a_new
    mid = np.sqrt(edges[..., :-1] * edges[..., 1:])
    mid[..., 0] = 0.5 * edges[..., 1]
    sigma = mid * mid * mid
    s = _bruggeman_rows(a, m, sigma, far, per_row=per_load, ln_sigma=ln_sigma)
    return _moved(s, m, sigma, lr)


def _moved(
    s: NDArray[np.float64], m: NDArray[np.float64], sigma: NDArray[np.float64], lr: NDArray
) -> NDArray[np.float64]:
    """The root ``s`` (n_load,) of the midpoints' Bruggeman sum (cell masses ``m``, midpoint
    conductances ``sigma``, cells ``lr`` wide in ``ln u``), every cell but the first moved by
    ``mu = 3 lr^2 g / 8`` in ``ln sigma`` (:func:`bruggeman_gap`), by one Newton step in
    ``ln s``: ``+ sum w mu / sum w``, ``w = m sigma / (sigma + s)^2`` (error ``~mu^2``, ~1e-8
    relative); 0 and ``inf`` (sealed, flooded) kept."""
    s = np.asarray(s, dtype=float)
    use = np.isfinite(s) & (s > 0)
    if not use.any():
        return s
    sig = np.broadcast_to(sigma, m.shape)
    sv, sig, m = (s, sig, m) if use.all() else (s[use], sig[use], m[use])
    den = sig + sv[:, None]
    mu = sig - sv[:, None]
    mu /= den
    mu *= (0.375 * np.broadcast_to(lr, s.shape)[use] ** 2)[:, None]
    mu[:, 0] = 0.0  # (the first cell, [0, u_min h_rms], as it was)
    den *= den
    w = m * sig
    w /= den
    out = s.copy()
    out[use] = sv * np.exp(np.einsum("ij,ij->i", w, mu) / np.sum(w, axis=1))
    return out


def _cells(
    u0: float, top: NDArray[np.float64], n_u: int
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Cell edges ``(n, n_u + 1)`` [m]: 0, then ``n_u`` geometric from ``u0`` to ``top`` (n,)
    (both ends exact, as :func:`numpy.geomspace`), ``ln`` of the cells' midpoint
    conductances ``mid^3`` (``mid`` the geometric midpoint, half the first edge for the first
    cell), to round-off, from the exponents themselves, and the cells' width in ``ln u``."""
    ln0 = math.log(u0)
    with np.errstate(divide="ignore", invalid="ignore"):
        lr = (np.log(top) - ln0) / max(n_u - 1, 1)  # ln of each row's ratio
    j = np.arange(n_u, dtype=float)
    edges = np.zeros((top.size, n_u + 1))
    np.exp(np.multiply.outer(lr, j) + ln0, out=edges[:, 1:])
    edges[:, -1], edges[:, 1] = top, u0  # (one cell: [0, u0], as geomspace)
    ln_sigma = np.multiply.outer(3.0 * lr, j - 0.5)
    ln_sigma += 3.0 * ln0
    ln_sigma[:, 0] = 3.0 * (ln0 - math.log(2.0))
    return edges, ln_sigma, lr


def effective_pressure_drop(
    fluid: str,
    pressure_drop: float = 0.0,
    p_in: float = 0.0,
    p_out: float = 0.0,
) -> float:
    """Pressure difference [Pa] driving the laminar flow from the inlet to the outlet.

    ``liquid``: ``pressure_drop`` (>= 0). ``gas`` (ideal, isothermal):
    ``(p_in^2 - p_out^2)/(2 p_out)`` so that the result times the conductance is the volume flow
    at ``p_out``.

    Raises
    ------
    ValueError
        Negative ``pressure_drop``, ``p_out <= 0`` or ``p_in < p_out`` (the flow direction is
        from ``p_in`` to ``p_out``: give the high-pressure side as ``p_in``).
    """
    if fluid == "liquid":
        if not pressure_drop >= 0:
            raise ValueError(
                f"leakage.pressure_drop = {pressure_drop!r} Pa must be >= 0 (the flow runs from "
                "the high- to the low-pressure side)"
            )
        return float(pressure_drop)
    if fluid == "gas":
        if not p_out > 0:
            raise ValueError(f"leakage.p_out = {p_out!r} Pa must be > 0 for gas leakage")
        if not p_in >= p_out:
            raise ValueError(
                f"leakage.p_in = {p_in:g} Pa must be >= leakage.p_out = {p_out:g} Pa: gas flows "
                "from the inlet p_in to the outlet p_out (give the high-pressure side as p_in)"
            )
        return (p_in**2 - p_out**2) / (2.0 * p_out)
    raise ValueError(f"leakage.fluid must be 'liquid' or 'gas', got {fluid!r}")


def leak_rate(
    u3: ArrayLike, seal_width: float, seal_length: float, dp_eff: float, viscosity: float
) -> NDArray[np.float64]:
    """Volume leak rate ``Q = (L_y/L_x) u3 dP_eff / (12 eta)`` [m^3/s] (NaN stays NaN).

    Parameters
    ----------
    u3 : array_like
        ``u1^3`` (critical junction) or ``<u^3>_EMT`` [m^3].
    seal_width : float
        ``L_x`` along the flow [m].
    seal_length : float
        ``L_y`` across the flow [m].
    dp_eff : float
        Effective pressure drop [Pa].
    viscosity : float
        Dynamic viscosity [Pa s].
    """
    return (seal_length / seal_width) * np.asarray(u3, dtype=float) * dp_eff / (12.0 * viscosity)


#: ``zeta_c`` above this fraction of the largest magnification: ``u1`` computed directly.
NEAR_SEALING = 2.0 / 3.0


def junction_piece(
    psd: object, zc: NDArray[np.float64], z_max: float, p0: NDArray[np.float64]
) -> NDArray[np.float64]:
    """Per load, which breakpoints of the spectrum lie below ``zeta_c`` times ``exp(-+w)``
    (``w = min(2e-3, ln(zeta_c)/2)``: at least twice the step of ``separation_at``'s difference
    quotient, 1e-3 and at most 1 % of ``ln zeta_c``, so ``q_L`` is never inside), as one
    number; a number of its own (the load) where ``zeta_c > NEAR_SEALING zeta_max``: near
    sealing ``u1 -> 0`` too fast for the table's estimate (it fell 3-4x short), those loads
    are computed directly."""
    nodes = np.asarray(psd.nodes(), dtype=float)  # type: ignore[attr-defined]
    nodes = np.log(nodes / float(psd.q_L))  # type: ignore[attr-defined]
    with np.errstate(divide="ignore", invalid="ignore"):
        lz = np.log(zc)
        w = np.minimum(2e-3, 0.5 * lz)
    lo, hi = np.searchsorted(nodes, lz - w), np.searchsorted(nodes, lz + w)
    piece = (lo * (nodes.size + 1) + hi).astype(float)
    return np.where(zc > NEAR_SEALING * z_max, -np.atleast_1d(p0), piece)


def table_weights(
    ds: Any, boundary: Any, p0: ArrayLike, a_c: float, threshold: str
) -> tuple[Weight, ...]:
    """The load table's regularised leak outputs (:data:`._stencils.Weight`): the junction's as
    ``ln(zeta_max/zeta_c) ln v`` (near sealing ``ln u1 ~ -f/ln(zeta_max/zeta_c)``), the
    effective medium's as ``ln v - 3 ln r`` with ``r = 1 - A(zeta_max)/A_seal`` from the solved
    Dataset ``ds`` (``A_seal`` the contact weight at which the medium percolates: ``a_c`` for
    ``threshold = "a_c"``, else 1/2): its conductance falls to 0 there as ``r^3``
    (``d ln v/d ln r`` 2.99 at ``r = 1e-3`` on the speed design's scenes). ``r`` is read
    once, when the table first asks for it."""
    z_max = float(ds.variables["zeta"].values[-1])
    x_all = np.sort(np.log(np.atleast_1d(np.asarray(p0, dtype=float))))
    ln_r: list[NDArray[np.float64]] = []

    def junction(o: dict[str, NDArray], x: NDArray) -> tuple[NDArray, NDArray]:
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.log(z_max / o["leak_zeta_c"]), np.zeros(x.size)

    def emt(o: dict[str, NDArray], x: NDArray) -> tuple[NDArray, NDArray]:
        if not ln_r:
            area = _contact_area(ds, boundary)[:, -1]
            order = np.argsort(np.log(np.atleast_1d(np.asarray(p0, dtype=float))), kind="stable")
            seal = a_c if threshold == "a_c" else 0.5
            with np.errstate(divide="ignore", invalid="ignore"):
                ln_r.append(3.0 * np.log(1.0 - np.atleast_1d(area)[order] / seal))
        at = np.clip(np.searchsorted(x_all, x), 0, x_all.size - 1)  # each load's own
        return np.ones(x.size), ln_r[0][at]

    return (
        (frozenset({"leak_u1", "leak_flow_factor", "leak_rate"}), junction),
        (frozenset({"leak_flow_factor_emt", "leak_rate_emt"}), emt),
    )


#: Relative margin above the sealing contact of :func:`sealed_both` (the effective medium's
#: total weight exceeds 1 by round-off only, ~1e-13).
SEAL_MARGIN = 1e-6


def _contact_area(ds: Any, boundary: Any) -> NDArray[np.float64]:
    """The stored load-bearing contact area ``(n_load, n_zeta)`` [1] (the boundary's
    ``contact_area`` variables summed)."""
    names = getattr(type(boundary), "contact_area", ("area_fraction",))
    return np.atleast_2d(sum(_by_zeta(ds, c) for c in names))


def _by_zeta(ds: Any, name: str) -> NDArray[np.float64]:
    """The stored variable ``name`` with ``zeta`` as its last axis (a view where it is already:
    ``ds[name].transpose(..., "zeta").values`` without xarray's DataArray, ~0.1 ms each)."""
    v = ds.variables[name]
    return np.moveaxis(np.asarray(v.values, dtype=float), v.dims.index("zeta"), -1)


def sealed_both(ds: Any, boundary: Any, a_c: float, threshold: str) -> NDArray[np.bool_]:
    """Per load (the Dataset's order): sealed by both theories, from the stored curve alone.

    The critical junction seals where the contact area stays above ``a_c`` at every
    magnification (no crossing), the effective medium where the contact weight at the last
    one reaches its percolation value (1/2, or ``a_c`` for ``threshold = "a_c"``). A load whose
    stored contact area (and elastic area, and one minus its complement) stays above both,
    by :data:`SEAL_MARGIN`, at every stored magnification has the sealed outputs whatever its
    dense re-solve (which keeps the stored nodes' values): the leak analysis gives them
    without computing (flags 1, ``zeta_c`` and ``u1`` NaN, flow factors and rates 0).
    """
    seal = max(a_c, a_c if threshold == "a_c" else 0.5) * (1.0 + SEAL_MARGIN)
    bnd = type(boundary) if boundary is not None else None
    el = getattr(bnd, "elastic_area", "area_fraction")
    comp = tuple(getattr(bnd, "elastic_area_complement", ("non_contact_fraction",)))
    low = np.min(_contact_area(ds, boundary), axis=1)
    low = np.minimum(low, np.min(np.atleast_2d(_by_zeta(ds, el)), axis=1))
    if all(c in ds.variables for c in comp):  # min(1 - n) = 1 - max(n): rounding is monotone
        n = sum(_by_zeta(ds, c) for c in comp)
        low = np.minimum(low, 1.0 - np.max(np.atleast_2d(n), axis=1))
    return np.asarray(low > seal)


def with_sealed(
    direct: Callable[..., dict[str, NDArray[np.float64]]],
    ctx: Any,
    ds: Any,
    rows: NDArray[np.intp],
    sealed: NDArray[np.bool_],
    which: NDArray[np.bool_] | None = None,
) -> dict[str, NDArray[np.float64]]:
    """The leak outputs of the loads ``rows``: ``direct(ctx, ds, open, which)`` of those not
    sealed (``sealed``: every load's, :func:`sealed_both`; ``which``: the groups asked for
    per load, :mod:`._by_group`); the others take the outputs ``direct`` gives a sealed load
    (flags 1, ``zeta_c`` and ``u1`` NaN, flow factors and rates 0, the junction piece of a
    NaN ``zeta_c``) without computing: 0-90 % of the loads of 1 kPa - 1 MPa on the speed
    design's scenes. With ``which``, also the groups computed per load
    (:data:`._by_load.COMPUTED`: every group of a sealed load)."""
    shut = sealed[rows]
    if not shut.any():
        return direct(ctx, ds, rows) if which is None else direct(ctx, ds, rows, which)
    n = rows.size
    out = {k: np.zeros(n) for k in ("leak_flow_factor", "leak_rate")}
    out |= {k: np.zeros(n) for k in ("leak_flow_factor_emt", "leak_rate_emt")}
    out |= {k: np.full(n, np.nan) for k in ("leak_zeta_c", "leak_u1")}
    out |= {k: np.ones(n) for k in ("leak_sealed", "leak_sealed_emt")}
    psd = per_solve(ctx, ("stored_spectrum",), lambda: spectrum_of(ds))  # the direct path's
    out["piece"] = np.full(n, junction_piece(psd, np.full(1, np.nan), 1.0, np.ones(1))[0])
    if which is not None:  # (a sealed load's outputs: every group's, exact)
        out[COMPUTED] = np.ones((n, np.shape(which)[0]), dtype=bool)
    if not shut.all():
        sub = () if which is None else (np.asarray(which)[:, ~shut],)
        for k, v in direct(ctx, ds, rows[~shut], *sub).items():
            out[k][~shut] = v
    return out


def next_to_open(p0: ArrayLike, sealed: NDArray[np.bool_]) -> NDArray[np.bool_]:
    """The lowest ``sealed`` load (:func:`sealed_both`) above the highest open one (its
    repeats too): a node of the load table's first level at no cost (:func:`with_sealed`),
    so that the sealed stretch above it is flat from there on, not refined."""
    x = np.log(np.atleast_1d(np.asarray(p0, dtype=float)))
    out = np.zeros(x.size, dtype=bool)
    if sealed.all() or not sealed.any():
        return out
    above = sealed & (x > float(np.max(x[~sealed])))
    if above.any():
        out[above & (x == np.min(x[above]))] = True
    return out


def sealed_plan(
    ds: Any, boundary: Any, p0: ArrayLike, a_c: float, threshold: str
) -> tuple[NDArray[np.bool_], NDArray[np.bool_]]:
    """:func:`sealed_both` and :func:`next_to_open` of the loads ``p0`` (the Dataset's)."""
    sealed = sealed_both(ds, boundary, a_c, threshold)
    return sealed, next_to_open(p0, sealed)
