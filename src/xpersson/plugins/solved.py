"""The solved contact as the analyses see it: the area curve per load, and its S factor.

A public module of the plugin-author layer: every analysis that integrates over the solved
curve (``xpersson-interface``'s energy, gap and leakage, ``xpersson-transport``'s gas gap) reads
it here, so that no plugin imports another (docs/architecture.md, "Where each formula lives").

Everything comes from the solve: the boundary declares which variables hold the elastic contact
area, its complement and the load-bearing contact area (:class:`xpersson.plugins.Boundary`); the
coefficient gives the correction factor ``S = d tau_eff/d tau_c`` of its closure. Nothing is
re-derived from the spectrum. The curve is read from the Dataset on its own magnifications and,
where the pipeline offers ``ctx.solve_at``, from the same solve sampled on a denser grid (the
integrals over zeta need the fast drop of ``A`` near ``zeta = 1`` at small loads resolved).
"""

from __future__ import annotations

import contextlib
import math
import warnings
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from xpersson.cache import Cache, memoize
from xpersson.errors import XperssonWarning
from xpersson.physics.closures import GAMMA_DEFAULT

from .stored import SPECTRUM_VARIABLES, contact_modulus, spectrum_of

__all__ = [
    "Solved",
    "UnresolvedDrop",
    "unresolved_quiet",
    "solved_curve",
    "curve_variables",
    "dense_zeta",
    "LOWEST",
    "per_solve",
    "solve_key",
    "FORMS",
]

#: Forms of the correction factor in energy and gap.
FORMS = ("closure", "yang_persson")


@dataclass(frozen=True)
class Solved:
    """Per-load curves on ``zeta`` (arrays ``(n_load, n_zeta)``, SI units).

    Attributes
    ----------
    p0 : ndarray
        Nominal pressures [Pa].
    zeta : ndarray
        Magnifications [1] (the Dataset's, merged with the dense grid when sampled).
    area, non_area : ndarray
        Elastic contact area fraction and its complement [1].
    contact : ndarray
        Load-bearing contact area fraction [1] (elastic + plastic, ...).
    s_factor : ndarray or None
        Correction factor ``S`` [1] (None: 1).
    form : str
        ``"closure"`` (the scene's closure) or ``"yang_persson"``.
    gamma : float or None
        The ``gamma`` of the Yang-Persson form (None for the closure form).
    psd : PowerSpectrum or None
        The spectrum the solve used, rebuilt from the Dataset
        (:func:`xpersson.plugins.stored.spectrum_of`).
    E_star : float or None
        The contact modulus of the solve [Pa], the Dataset's ``E_star``.
    """

    p0: NDArray[np.float64]
    zeta: NDArray[np.float64]
    area: NDArray[np.float64]
    non_area: NDArray[np.float64]
    contact: NDArray[np.float64]
    s_factor: NDArray[np.float64] | None
    form: str
    gamma: float | None
    psd: Any = None
    E_star: float | None = None

    @property
    def curve(self) -> tuple[Any, ...]:
        """``(zeta, area, s_factor, non_area)``: the arguments of :mod:`xpersson.physics`."""
        return self.zeta, self.area, self.s_factor, self.non_area


#: ``zeta - 1`` of the dense sampling's first magnification above 1 (:func:`dense_zeta`).
LOWEST = 1e-9


def dense_zeta(zeta: NDArray[np.float64], per_decade: int) -> NDArray[np.float64]:
    """The Dataset's magnifications merged with ``1 + geomspace(LOWEST, zeta_max - 1)``.

    The same grid for every solve of a scene: merged once (cached on the magnifications and
    ``per_decade``), a fresh copy returned.
    """
    z = np.asarray(zeta, dtype=float)
    if z.ndim != 1:
        return _merged(z, per_decade)
    return _dense_zeta(z, int(per_decade)).copy()


@memoize("plugins.dense_zeta", scope="process", maxsize=8)
def _dense_zeta(zeta: NDArray[np.float64], per_decade: int) -> NDArray[np.float64]:
    """:func:`_merged` (cached)."""
    return _merged(zeta, per_decade)


def _merged(zeta: NDArray[np.float64], per_decade: int) -> NDArray[np.float64]:
    z_max = float(zeta[-1])
    decades = -math.log10(LOWEST) + np.log10(max(z_max - 1.0, LOWEST))  # (9.0 exactly + ...)
    n = max(2, int(per_decade * decades))
    extra = 1.0 + np.geomspace(LOWEST, z_max - 1.0, n) if z_max > 1.0 else np.zeros(0)
    z = np.unique(np.concatenate((zeta, extra[extra < z_max])))
    return z[z >= 1.0]


#: Largest change of the area between two output magnifications that the analyses integrate
#: without sampling the solve more densely (and of ``1 - A`` over the first interval).
MAX_STEP = 0.02
MAX_FIRST = 1e-7
#: Largest change of ln(1 - A) between output magnifications integrated without dense sampling.
MAX_LOG_STEP = 5.0
#: ``1 - A`` at the dense grid's first magnification above 1 (``zeta - 1 =`` :data:`LOWEST`)
#: above which a load's drop from full contact is unresolved and :func:`solved_curve` warns:
#: against a grid from ``zeta - 1 = 1e-15`` (60 loads from a contact area of 1e-8 on four
#: spectra of 7-9 decades, ``benchmarks/results/speed_notes.md``, "light loads") the mean gap
#: and the gap distribution's mean were off by 2.9e-4 at 5.4e-3, 1.6e-3 at 2.9e-2, 0.18-7.4
#: times at 0.7-0.99 (contact areas 1e-8 - 2e-7); below 1e-9, by less than 6e-6 (as every
#: other load).
UNRESOLVED = 1e-3


def _coarse(area: NDArray[np.float64], non: NDArray[np.float64]) -> NDArray[np.bool_]:
    """Loads whose output curve is too coarse for the zeta integrals."""
    if area.shape[1] < 3:
        return np.ones(area.shape[0], dtype=bool)
    step = np.max(np.abs(np.diff(area, axis=1)), axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):  # near full contact: 1 - A spans
        ln = np.log(np.maximum(non[:, 1:], 1e-300))  # decades between nodes
    jump = np.max(np.abs(np.diff(ln, axis=1)), axis=1) if ln.shape[1] > 1 else np.zeros(len(ln))
    return (step > MAX_STEP) | (non[:, 1] > MAX_FIRST) | (jump > MAX_LOG_STEP)


def _coarse_first(ds: Any, el: str, comp: tuple[str, ...]) -> bool:
    """Whether the first load's output curve is too coarse (:func:`_coarse` of its row alone:
    the same test, row by row); with ``ctx.solve_at`` one such load re-solves every load, and
    the other loads' rows need not be read."""

    def first(name: str) -> NDArray[np.float64]:
        a = _from_ds(ds, name)
        return _rows(a[:1] if a.ndim > 1 else a, 1)

    return bool(_coarse(first(el), sum(first(c) for c in comp))[0])


def _interp(z: NDArray, y: NDArray[np.float64], z_new: NDArray) -> NDArray[np.float64]:
    """Monotone (PCHIP) interpolation of smooth output curves in ``ln zeta``.

    Positive curves are interpolated in ``ln y``: near full contact ``1 - A`` spans hundreds of
    decades between output magnifications, and a linear interpolant gives the detached area
    there (and so the gap distribution's far bins) no relative accuracy at all.
    """
    from scipy.interpolate import PchipInterpolator

    if y.shape[1] == z_new.size and np.array_equal(z, z_new):
        return y.copy()
    x, x_new = np.log(z), np.log(z_new)
    with np.errstate(over="ignore", divide="ignore", invalid="ignore", under="ignore"):
        if np.all(y > 0):
            return np.exp(PchipInterpolator(x, np.log(y), axis=1)(x_new))
        return PchipInterpolator(x, y, axis=1)(x_new)


class UnresolvedDrop(XperssonWarning):
    """Loads whose drop from full contact the dense sampling does not resolve
    (:data:`UNRESOLVED`): the analyses' zeta integrals are inaccurate there. A finite body's
    pipeline silences it: its lightest rings weigh ~nothing in its integrals (the three bundled
    body examples moved by <= 2e-5, below their grid errors, with the drop resolved)."""


@contextlib.contextmanager
def unresolved_quiet() -> Iterator[None]:
    """:class:`UnresolvedDrop` silenced (a finite body's solve and re-analysis)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UnresolvedDrop)
        yield


def _warn_unresolved(
    v: Any, zeta: NDArray[np.float64], comp: tuple[str, ...], p0: NDArray[np.float64]
) -> None:
    """Warn where the dense solve ``v`` (on ``zeta``) of the loads ``p0`` [Pa] leaves a load's
    drop from full contact unresolved (:data:`UNRESOLVED`, at the first magnification above 1;
    ``comp``: the complement's variables)."""
    j = min(int(np.searchsorted(zeta, 1.0, side="right")), zeta.size - 1)
    first = sum(np.asarray(v[c], dtype=float)[..., j] for c in comp)
    late = np.broadcast_to(np.asarray(first) > UNRESOLVED, p0.shape)
    if late.any():
        warnings.warn(
            f"{int(late.sum())} load(s) (p0 <= {float(np.max(p0[late])):.3g} Pa) leave full "
            f"contact before zeta - 1 = {LOWEST:g}, the dense sampling's first magnification "
            "above 1 "
            f"(1 - A there > {UNRESOLVED:g}): the analyses' zeta integrals (mean gap, gap "
            "distribution, leakage) are inaccurate at those loads, up to several times off at "
            "contact areas ~1e-8 on spectra of 7-9 decades",
            UnresolvedDrop,
            stacklevel=4,
        )


def _rows(arr: Any, n_load: int) -> NDArray[np.float64]:
    a = np.asarray(arr, dtype=float)
    return np.broadcast_to(a, (n_load, a.shape[-1])).copy()


def _from_ds(ds: Any, name: str) -> NDArray[np.float64]:
    var = ds.variables[name]  # the bare Variable: no DataArray built, no xarray transpose
    vals = np.asarray(var.values, dtype=float)
    if "p0" in var.dims:
        vals = np.transpose(vals, (var.dims.index("p0"), var.dims.index("zeta")))
    return vals


def curve_variables(ctx: Any) -> tuple[str, ...]:
    """The names of every Dataset variable :func:`solved_curve` may read for the scene of
    ``ctx`` (its boundary's area variables, the diffusion times of a closure without ``S``,
    the spectrum, ``E_star`` and ``zeta``): a Dataset of these alone gives the same curve
    (e.g. a cheap selection of some loads, ``ds[names].isel(p0=rows)``)."""
    el, comp, cont = _area_names(ctx)
    times = ("effective_diffusion_time", "diffusion_time")
    return tuple(dict.fromkeys((el, *comp, *cont, *times, *SPECTRUM_VARIABLES, "E_star", "zeta")))


def _area_names(ctx: Any) -> tuple[str, tuple[str, ...], tuple[str, ...]]:
    """The boundary's elastic area, its complement and the load-bearing contact area (the
    Dataset variables' names; the elastic boundary's without a boundary)."""
    bnd = type(ctx.boundary) if ctx.boundary is not None else None
    el = getattr(bnd, "elastic_area", "area_fraction")
    comp = tuple(getattr(bnd, "elastic_area_complement", ("non_contact_fraction",)))
    cont = tuple(getattr(bnd, "contact_area", ("area_fraction",)))
    return el, comp, cont


def solved_curve(
    ctx: Any, ds: Any, form: str = "closure", gamma: float | None = None, per_decade: int = 0
) -> Solved:
    """Read the solved curve of every load (see the module docstring).

    Parameters
    ----------
    ctx : SceneContext
        With ``boundary``/``coefficient`` (and ``solve_at``) set by the pipeline.
    ds : xarray.Dataset
        The solved Dataset.
    form : {"closure", "yang_persson"}
        ``S`` of the scene's closure, or ``S = gamma + (1 - gamma) A^2`` on the scene's area.
    gamma : float, optional
        Yang-Persson ``gamma`` (default :data:`xpersson.physics.closures.GAMMA_DEFAULT`).
    per_decade : int
        Dense sampling (points per decade of ``zeta - 1``) through ``ctx.solve_at``; 0 reads the
        Dataset only.
    """
    if form not in FORMS:
        raise ValueError(f"s_factor must be one of {FORMS}, got {form!r}")
    p0 = np.atleast_1d(np.asarray(ctx.p0, dtype=float))
    n = p0.size
    el, comp, cont = _area_names(ctx)
    zeta = np.asarray(ds.variables["zeta"].values, dtype=float)  # (no DataArray built)
    solve_at = getattr(ctx, "solve_at", None)

    memo: dict[str, NDArray[np.float64]] = {}

    def get(name: str) -> NDArray[np.float64]:  # each variable read (and copied) once
        if name not in memo:
            memo[name] = _rows(_from_ds(ds, name), n)
        return memo[name]

    if n and per_decade and solve_at is not None and _coarse_first(ds, el, comp):
        need = np.ones(n, dtype=bool)  # (the first load decides for all: no other test)
    else:
        need = _coarse(get(el), sum(get(c) for c in comp)) if per_decade else np.zeros(n, bool)
    if need.any() and solve_at is not None:
        need[:] = True  # one grid for every load: a load's result never depends on the others
    if need.any() and solve_at is None:
        warnings.warn(
            f"{int(need.sum())} load(s) have an area curve too coarse for the zeta integrals "
            "(area steps > 0.02 between output magnifications, or the drop above zeta = 1 "
            "unresolved) and no ctx.solve_at to sample the solve densely: results lose "
            "accuracy; give output.zeta_per_decade or output.zeta densely near 1",
            UserWarning,
            stacklevel=3,
        )
    if need.any() and solve_at is not None:
        z_ds, zeta = zeta, dense_zeta(zeta, per_decade)
        v = solve_at(zeta, np.flatnonzero(need))
        _warn_unresolved(v, zeta, comp, p0[need])
        coarse_get, memo_dense = get, {}

        def get(name: str) -> NDArray[np.float64]:  # solved where coarse, else interpolated
            if name not in memo_dense:
                if need.all():  # every load re-solved: nothing to interpolate, and the
                    # solve's read-only values only read (the kept columns are copied below)
                    rows = np.broadcast_to(np.asarray(v[name], dtype=float), (n, zeta.size))
                else:
                    rows = _interp(z_ds, coarse_get(name), zeta)
                    rows[need] = _rows(v[name], int(need.sum()))
                memo_dense[name] = rows
            return memo_dense[name]

    area = get(el)
    S = None
    g = None
    if form == "yang_persson":
        g = GAMMA_DEFAULT if gamma is None else float(gamma)
        S = g + (1.0 - g) * area**2
    else:
        coef = ctx.coefficient
        if coef is not None and coef.corrects_variance():
            S = coef.variance_factor(ctx, area)
            if S is None:  # a closure that does not give S: d tau_eff / d tau_c of the solve
                te = get("effective_diffusion_time")
                tc = np.asarray(get("diffusion_time"), dtype=float)
                S = np.gradient(te, axis=1) / np.maximum(np.gradient(tc, axis=1), 1e-300)
            S = np.clip(np.asarray(S, dtype=float), 1e-12, 1.0)
    keep, nf = None, None
    if need.any() and solve_at is not None:  # (one complement: nf != 0 where 0 + nf != 0)
        nf = _total([get(c) for c in comp]) if len(comp) != 1 else get(comp[0])
        keep = _past_full_contact(area, nf, S)
        S = None if S is None else _columns(np.broadcast_to(S, area.shape), keep)
        zeta, area = zeta[keep], _columns(area, keep)
    # the sums of the kept columns alone (new arrays: clipped in place); the complement's of
    # nf where it was summed (0 + nf: the same numbers, never -0)
    non = _total([get(c) for c in comp] if nf is None else [nf], keep)
    contact = _total([get(c) for c in cont], keep)
    non, contact = np.clip(non, 0.0, 1.0, out=non), np.clip(contact, 0.0, 1.0, out=contact)
    return Solved(p0, zeta, area, non, contact, S, form, g, _spectrum(ds), contact_modulus(ds))


#: The spectrum rebuilt from a Dataset, one per content: the load table's direct calls read the
#: same spectrum from each selection of loads (its rebuild cost ~0.1 ms, its key ~0.01 ms).
_SPECTRA = Cache(
    "plugins.stored_spectrum",
    scope="spectrum",
    maxsize=16,
    doc="the spectrum a Dataset was solved with (spectrum_of), per q_psd, psd_C, psd_exponent",
)


def _spectrum(ds: Any) -> Any:
    """:func:`~xpersson.plugins.stored.spectrum_of` ``(ds)``, built once per content."""
    v = ds.variables
    key = tuple(np.asarray(v[n].values) if n in v else None for n in SPECTRUM_VARIABLES)
    return _SPECTRA.get(key, lambda: spectrum_of(ds))


#: Dense magnifications kept in full contact before the first one out of it (see
#: :func:`_past_full_contact`): the splines of ``ln(1 - F)`` are global, and a boundary this many
#: nodes away changes their values by ~0.27**PLATEAU_MARGIN (round-off).
PLATEAU_MARGIN = 24


def _past_full_contact(
    area: NDArray[np.float64], non: NDArray[np.float64], S: NDArray[np.float64] | None
) -> NDArray[np.intp]:
    """Indices of the dense magnifications to keep: ``zeta = 1`` and the first above it, then
    from :data:`PLATEAU_MARGIN` nodes before the first where any load leaves exact full contact.

    Near ``zeta = 1`` every load is in full contact (``1 - F = 0`` exactly, 40 % of the dense
    grid on the README spectrum): those nodes add nothing to any zeta integral but cost every
    spline, node sum and table. The first node above 1 is kept: it fixes the curve's linear
    first interval and the range of ``Phi``'s look-up table, which stay as before.
    """
    nf = non if S is None else non + area * (1.0 - S)
    open_ = np.flatnonzero(np.any(nf != 0.0, axis=0)[1:]) + 1  # NaN counts as open
    first = int(open_[0]) if open_.size else nf.shape[1] - 1
    start = max(2, first - PLATEAU_MARGIN)
    return np.concatenate((np.arange(min(2, nf.shape[1])), np.arange(start, nf.shape[1])))


def _total(arrays: list[Any], keep: NDArray[np.intp] | None = None) -> NDArray[np.float64]:
    """``sum(arrays)`` (``0 + a_0 + a_1 ...``: a new array; none: 0), of the columns ``keep``
    where given (:func:`_columns`): the same numbers as the columns of the sum."""
    if not arrays:
        return np.zeros(())
    out = np.asarray(arrays[0], dtype=float) if keep is None else _columns(arrays[0], keep)
    out = np.add(0, out) if keep is None else np.add(0, out, out=out)
    for a in arrays[1:]:
        out += a if keep is None else _columns(a, keep)
    return out


def _columns(a: NDArray[np.float64], keep: NDArray[np.intp]) -> NDArray[np.float64]:
    """``a[:, keep]`` (a new array) for :func:`_past_full_contact`'s increasing ``keep``: its
    first two columns and the run to the last joined from two slices (half the time of the
    fancy index on (1000, 500) curves), any other ``keep`` fancy-indexed."""
    n, k = a.shape[1], keep.size
    if k > 2 and keep[0] == 0 and keep[1] == 1 and keep[2] == n - (k - 2) and keep[-1] == n - 1:
        return np.concatenate((a[:, :2], a[:, int(keep[2]) :]), axis=1)
    return a[:, keep]


#: The solved curve and its SolvedContact (splines, Phi, tables), built once per solve and shared
#: by every analysis of that solve with the same curve parameters: nothing outlives the solve.
_SOLVES = Cache(
    "plugins.solved",
    scope="solve",
    maxsize=16,
    doc="the solved area curve of every load and its SolvedContact, per curve parameters",
)
#: The scene's numbers a solve is made of (with its coefficient and boundary).
_CTX_FIELDS = ("psd", "E", "nu", "E_star", "p0", "zeta", "p", "rtol", "atol", "method")


def _plugin_key(plugin: Any) -> Any:
    """A plugin instance's content: its class's qualified name (local classes too: within one
    solve the classes are the scene's) and parameters (``None`` for none)."""
    if plugin is None:
        return None
    cls = type(plugin)
    return f"{cls.__module__}.{cls.__qualname__}", dict(getattr(plugin, "params", {}))


def solve_key(ctx: Any) -> tuple[Any, ...]:
    """The content key of one solve: the scene's numbers, solver options, coefficient and
    boundary (class and parameters), which determine the Dataset the analyses read and what
    ``ctx.solve_at`` returns (the points of a stacked block differ in them)."""
    scene = tuple(getattr(ctx, f, None) for f in _CTX_FIELDS)
    options = dict(getattr(ctx, "options", None) or {})
    return (*scene, options, _plugin_key(ctx.coefficient), _plugin_key(ctx.boundary))


def per_solve(ctx: Any, key: tuple[Any, ...], build: Callable[[], Any]) -> Any:
    """``build()`` once per solve (its content, :func:`solve_key`) and ``key`` (the curve
    parameters); computed afresh outside a solve (direct calls) or with the caches off."""
    return _SOLVES.get((key, solve_key(ctx)), build)
