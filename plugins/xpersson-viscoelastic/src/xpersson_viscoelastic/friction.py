"""Analysis plugin ``friction``: rubber friction from the solved viscoelastic contact.

``mu_visc = (1/(2 p0)) int_1^zeta_max P(zeta) S(zeta) dL(zeta)`` (physics.md §4.2), with the
relative contact area ``P = A/A0`` read from the solved Dataset (``area_fraction``) and the
cumulative loss integral ``L`` written by the ``viscoelastic`` coefficient; ``S = 1`` (Persson
2001) or ``S = gamma + (1 - gamma) P^2``. ``mu_contact = tau_f A(zeta_c)/A0 / p0`` (§7) with a
constant shear stress or the velocity law ``tau_f = tau_f0 exp(-c log10(a_T v / v*)^2)``;
``mu = mu_visc + mu_contact``.

On the output grid the Stieltjes integral is evaluated with ``g = P S`` and ``L`` both
interpolated by cubics in ``ln zeta`` (:func:`~xpersson_viscoelastic.kernel.stieltjes_increments`;
fourth order, see the README's convergence table for the accuracy per ``zeta_per_decade``).
Loads whose area the output grid does not resolve (``1 - P > 1e-6`` at the first output point,
or a step of ``P`` above 0.02: no roll-off plateau, fast or cold rubber) are integrated up to
past ``zeta = 100`` as the kernel ``friction_curve`` integrates them: Gauss-Legendre panels
graded towards ``q_L`` with ``tau``, ``dL`` at the nodes from the coefficient
(``graded_stacked``, Prony models) and the area there from the same solve (``ctx.solve_at``,
one engine call for a stacked block; :mod:`~xpersson_viscoelastic._graded`); for other models
on a dense grid in ``ln(zeta - 1)`` with the coefficient's ``loss_integral(ctx, zeta)``
(:mod:`~xpersson_viscoelastic._resolve`; issue 22). The area at a
``zeta_c`` between output points comes from the same solve at ``zeta_c`` (was: linear
interpolation, up to 0.8 % off).

Reads the Dataset's ``area_fraction``, ``G``, ``loss_integral``, ``sliding_speed``,
``shift_factor`` and spectrum; where the output grid misses the area drop it evaluates again,
explicitly, the coefficient's ``tau``/``dL`` at the nodes (``ctx.coefficient``: the Dataset
stores them at the output magnifications only) and the area there (``ctx.solve_at``). An
archive reopened later gives the same friction bit for bit (docs/user_guide/04_analyses.md).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np

from xpersson.physics import closure_S
from xpersson.plugins import Analysis, FastPaths, ParamSpec, VarSpec
from xpersson.plugins.stored import spectrum_of

from . import _graded, _resolve
from ._stencil import stacked_weights
from .coefficient import ViscoelasticCoefficient
from .kernel import friction_integral, stieltjes_increments

if TYPE_CHECKING:  # pragma: no cover
    import xarray as xr

__all__ = ["Friction"]

_ZP = ("p0", "zeta")
#: the dims of each output of one point
_DIMS = {
    "mu_visc": ("p0",),
    "mu_contact": ("p0",),
    "mu": ("p0",),
    "mu_visc_cumulative": _ZP,
    "contact_area_cutoff": ("p0",),
    "frictional_shear_stress": (),
}


def _rows(da: xr.DataArray) -> np.ndarray:
    """Values of a ``(p0, zeta)``, ``(zeta, p0)`` or ``(zeta,)`` variable as (n_load, n_zeta)."""
    vals = np.asarray(da.values, dtype=float)
    if da.dims == ("zeta",):
        return vals[None, :]
    return vals.T if da.dims[0] == "zeta" else vals


class Friction(Analysis):
    """Rubber friction coefficient ``mu = mu_visc + mu_contact`` versus load (and v, T)."""

    summary = "rubber friction: viscoelastic mu_visc (Persson 2001) plus contact shear term"
    references = (
        "10.1063/1.1388626",
        "10.1016/j.surfrep.2006.04.001",
        "10.1140/epje/i2010-10558-6",
    )
    requires: ClassVar = ("area_fraction", "loss_integral", "sliding_speed", "shift_factor")
    provides: ClassVar = (
        "mu_visc",
        "mu_contact",
        "mu",
        "mu_visc_cumulative",
        "contact_area_cutoff",
        "frictional_shear_stress",
    )
    #: a block of (v, T) points is computed at once (:meth:`compute_stacked`)
    fast_paths: ClassVar = FastPaths(stacked_params=frozenset(), reused=True)
    parameters: ClassVar = {
        "correction": ParamSpec(
            "1",
            default="none",
            kind="choice",
            choices=("none", "s_factor"),
            description="S = 1 (none) or S = gamma + (1 - gamma) P^2",
        ),
        "gamma": ParamSpec(
            "1",
            default=0.5,
            bounds=(0, 1),
            inclusive=(False, True),
            description="gamma of the S factor",
        ),
        "tau_f": ParamSpec(
            "Pa",
            default=0.0,
            bounds=(0, None),
            description="frictional shear stress in the real contact area "
            "(tau_f0 of the velocity law)",
        ),
        "shear_law": ParamSpec(
            "1",
            default="constant",
            kind="choice",
            choices=("constant", "velocity"),
            description="tau_f constant or tau_f0 exp(-c log10(a_T v/v*)^2)",
        ),
        "c": ParamSpec("1", default=0.1, bounds=(0, None), description="width c of the law"),
        "v_star": ParamSpec(
            "m/s",
            default=1e-2,
            bounds=(0, None),
            inclusive=(False, True),
            description="reference speed v* of the velocity law",
        ),
        "zeta_c": ParamSpec(
            "1",
            default=None,
            bounds=(1, None),
            description="magnification of the contact area in mu_contact "
            "(default: the largest output magnification)",
        ),
    }
    outputs: ClassVar = {
        "mu_visc": VarSpec(("p0",), "1", "viscoelastic friction coefficient", valid_min=0.0),
        "mu_contact": VarSpec(
            ("p0",),
            "1",
            "contact (shear) friction coefficient",
            description="tau_f A(zeta_c)/A0 / p0",
            valid_min=0.0,
        ),
        "mu": VarSpec(("p0",), "1", "friction coefficient mu_visc + mu_contact", valid_min=0.0),
        "mu_visc_cumulative": VarSpec(
            _ZP, "1", "viscoelastic friction from scales up to zeta", valid_min=0.0
        ),
        "contact_area_cutoff": VarSpec(
            ("p0",), "1", "relative contact area at zeta_c", valid_min=0.0, valid_max=1.0
        ),
        "frictional_shear_stress": VarSpec(
            (), "Pa", "frictional shear stress tau_f", valid_min=0.0
        ),
    }

    def shear_stress(self, v: float, aT: float) -> float:
        """``tau_f`` [Pa] at sliding speed ``v`` [m/s] and shift factor ``aT`` [1]."""
        p = self._params
        if p["shear_law"] == "constant":
            return float(p["tau_f"])
        if v <= 0:
            return 0.0
        x = np.log10(aT * v / p["v_star"])
        return float(p["tau_f"] * np.exp(-p["c"] * x * x))

    def _zeta_c(self, zeta: np.ndarray) -> float:
        """The cut-off magnification [1] on the output grid ``zeta`` (checked against it)."""
        zc = float(zeta[-1]) if self._params["zeta_c"] is None else float(self._params["zeta_c"])
        if zc > zeta[-1] * (1 + 1e-12):
            raise ValueError(
                f"zeta_c: {zc:g} exceeds the largest output magnification {zeta[-1]:g}; "
                f"allowed [1, {zeta[-1]:g}] (dimensionless)"
            )
        return zc

    def validate(self, ctx: Any) -> None:
        """Refuse a ``zeta_c`` beyond the output magnifications before any solving."""
        self._zeta_c(np.asarray(ctx.zeta, float))

    def _resolved(self, ctx: Any, ds: xr.Dataset, mu_cum: xr.DataArray) -> xr.DataArray:
        """``mu_visc_cumulative`` with the loads whose area drop the output grid misses
        evaluated on a dense grid up to the output point ``zeta_k`` and continued on the
        output grid beyond (:mod:`~xpersson_viscoelastic._resolve`)."""
        area = _rows(ds["area_fraction"])
        zeta = np.asarray(ds["zeta"].values, dtype=float)
        need = _resolve.unresolved(area)
        if not need.any() or zeta.size < 2:
            return mu_cum
        loads = np.flatnonzero(need)
        k = _resolve.dense_top(zeta, area[loads])
        p0 = np.atleast_1d(np.asarray(ds["p0"].values, dtype=float))
        G_all = _rows(ds["G"])
        got = None
        if _stacked_integrals(ctx.coefficient):
            got = _graded.graded_runs(
                lambda _: ctx,
                _spectra_of(ds),
                [(0, loads, k)],
                zeta,
                lambda _: G_all,
                p0,
                self._factor,
            )
        if got is not None:
            run = got[0]
        else:  # dense grids (models without graded panels)
            G = G_all[:, : k + 1]
            zk = zeta[: k + 1]
            zd, idx = _resolve.dense_grid(zk, G[loads])
            Ad = _resolve.dense_area(ctx, zk, area[:, : k + 1], G, zd, loads)
            Ld = _resolve.dense_loss(ctx, zk, np.asarray(ds["loss_integral"].values)[: k + 1], zd)
            run = _resolve.running_integral(self._factor(Ad), Ld, zd)[:, idx]
            run /= 2.0 * p0[loads][:, None]
        vals = _rows(mu_cum).copy()
        beyond = vals[loads, k + 1 :] - vals[loads, k : k + 1]  # the output-grid rule
        vals[loads] = np.concatenate([run, run[:, -1:] + beyond], axis=-1)
        if mu_cum.dims[0] != "zeta":  # (p0, zeta)
            return mu_cum.copy(data=vals)
        return mu_cum.copy(data=vals.T.reshape(mu_cum.shape))

    def _factor(self, A: np.ndarray) -> np.ndarray:
        """The integrand ``P S`` [1] from the area ``P``."""
        if self._params["correction"] == "s_factor":
            return A * closure_S("yp08", A, self._params["gamma"])
        return A

    def compute_stacked(self, ctx_of: Any, ds: xr.Dataset) -> dict[str, Any]:
        """The friction variables of a block of (v, T) points (leading ``point`` dimension)
        at once, as :meth:`compute` gives each point (:meth:`_arrays` on the block's
        arrays)."""

        zeta = np.asarray(ds.variables["zeta"].values, dtype=float)
        if self._zeta_c(zeta) != zeta[-1] or "G" not in ds or zeta.size < 2:
            return super().compute_stacked(ctx_of, ds)
        zp = ("point", "p0", "zeta")
        got = self._arrays(
            ctx_of,
            _spectra_of(ds),
            zeta,
            _values(ds, "area_fraction", zp),
            _values(ds, "loss_integral", ("point", "zeta")),
            _values(ds, "G", zp),
            np.atleast_1d(np.asarray(ds.variables["p0"].values, dtype=float)),
            _values(ds, "sliding_speed", ("point",)),
            _values(ds, "shift_factor", ("point",)),
        )
        self._check_arrays(got)
        return {n: (("point", *_DIMS[n]), v) for n, v in got.items()}

    def _simple(self, ctx: Any, ds: xr.Dataset) -> dict[str, Any] | None:
        """:meth:`compute` of one point's Dataset (loads and magnifications only, the cut-off
        at the last output point) by :meth:`_arrays`, else ``None``."""
        import xarray as xr

        A, L = ds["area_fraction"], ds["loss_integral"]
        zeta = np.asarray(ds["zeta"].values, dtype=float)
        simple = set(A.dims) == {"p0", "zeta"} and L.dims == ("zeta",) and "G" in ds
        simple = simple and ds["sliding_speed"].ndim == 0 and ds["shift_factor"].ndim == 0
        if not simple or zeta.size < 2 or self._zeta_c(zeta) != zeta[-1]:
            return None
        got = self._arrays(
            lambda _: ctx,
            _spectra_of(ds),
            zeta,
            _rows(A)[None],
            np.asarray(L.values, dtype=float)[None],
            _rows(ds["G"])[None],
            np.atleast_1d(np.asarray(ds["p0"].values, dtype=float)),
            np.atleast_1d(np.asarray(ds["sliding_speed"].values, dtype=float)),
            np.atleast_1d(np.asarray(ds["shift_factor"].values, dtype=float)),
        )
        out = {n: xr.DataArray(v[0], dims=_DIMS[n]) for n, v in got.items()}
        self._check(out)
        return out

    def _arrays(
        self,
        ctx_of: Any,
        psd_of: Any,
        zeta: np.ndarray,
        area: np.ndarray,
        L: np.ndarray,
        G: np.ndarray,
        p0: np.ndarray,
        v: np.ndarray,
        aT: np.ndarray,
    ) -> dict[str, np.ndarray]:
        """The friction variables of K points (``area``, ``G`` (K, n_load, n_zeta), ``L``
        (K, n_zeta), ``v``, ``aT`` (K,)), each with a leading point axis: the output-grid rule
        for every load, then the loads whose area drop the output grid misses on the graded
        panels of :mod:`~xpersson_viscoelastic._graded` (points with equal panels in one call
        each, one engine call), else on their dense grids (:meth:`_dense_block`)."""
        inc = stieltjes_increments(self._factor(area), L[:, None, :], np.log(zeta))
        mu = friction_integral(inc, p0)
        mu_cum = np.concatenate([np.zeros(mu.shape[:-1] + (1,)), mu], axis=-1)
        need = _resolve.unresolved(area.reshape(-1, zeta.size)).reshape(area.shape[:2])
        tops = _resolve.dense_tops(zeta, area, need)
        items = [(k, np.flatnonzero(need[k]), int(tops[k])) for k in np.flatnonzero(need.any(1))]
        if items:
            runs = None
            if _stacked_integrals(ctx_of(0).coefficient):
                runs = _graded.graded_runs(
                    ctx_of, psd_of, items, zeta, lambda k: G[k], p0, self._factor
                )
            if runs is None:
                runs = self._dense_block(ctx_of, items, zeta, area, G, L, p0)
            for k, loads, top in items:
                vals = mu_cum[k]
                beyond = vals[loads, top + 1 :] - vals[loads, top : top + 1]  # output grid
                vals[loads] = np.concatenate([runs[k], runs[k][:, -1:] + beyond], axis=-1)
        tau_f = np.vectorize(self.shear_stress, otypes=[float])(v, aT)
        A_c = area[..., -1]
        mu_contact = tau_f[:, None] * A_c / p0
        return {
            "mu_visc": mu_cum[..., -1],
            "mu_contact": mu_contact,
            "mu": mu_cum[..., -1] + mu_contact,
            "mu_visc_cumulative": mu_cum,
            "contact_area_cutoff": A_c,
            "frictional_shear_stress": tau_f,
        }

    def _dense_block(
        self,
        ctx_of: Any,
        items: list[Any],
        zeta: np.ndarray,
        area: np.ndarray,
        G: np.ndarray,
        L: np.ndarray,
        p0: np.ndarray,
    ) -> dict[int, np.ndarray]:
        """The running integral (n_sel, top + 1) of every item ``(k, loads, top)`` on its
        dense grid (:mod:`~xpersson_viscoelastic._resolve`; models without graded panels)."""
        plans = []
        for k, loads, top in items:
            zd, idx = _resolve.dense_grid(zeta[: top + 1], G[k][:, : top + 1][loads])
            plans.append((k, loads, top, zd, idx))
        redo = [plan[0] for plan in plans]
        dense = _dense_integrals(ctx_of, redo, [plan[3] for plan in plans])
        weights = stacked_weights([_resolve.dense_x(plan[3]) for plan in plans])  # one call
        rows = _dense_rows(ctx_of, plans, dense)
        runs = {}
        for r, (k, loads, top, zd, idx) in enumerate(plans):
            ctx, zk = ctx_of(k), zeta[: top + 1]
            if dense is None:
                Ad = _resolve.dense_area(
                    ctx, zk, area[k][:, : top + 1], G[k][:, : top + 1], zd, loads
                )
                Ld = _resolve.dense_loss(ctx, zk, L[k][: top + 1], zd)
            else:
                if rows is None:
                    got = ctx.solve_at(zd, loads, tau=dense[0][r, : zd.size])["area_fraction"]
                else:
                    got = rows[1][rows[0] == r, : zd.size]
                Ad = np.asarray(got, dtype=float).reshape(loads.size, -1)
                Ld = dense[1][r, : zd.size]
            run = _resolve.running_integral(self._factor(Ad), Ld, zd, weights[r])[:, idx]
            runs[k] = run / (2.0 * p0[loads][:, None])
        return runs

    def compute(self, ctx: Any, ds: xr.Dataset) -> dict[str, Any]:
        """The friction variables, vectorised over loads (and any sweep dimension)."""
        import xarray as xr

        simple = self._simple(ctx, ds)
        if simple is not None:
            return simple
        p = self._params
        A = ds["area_fraction"]
        L = ds["loss_integral"]
        zeta = ds["zeta"].values
        zc = self._zeta_c(zeta)
        g = A * (closure_S("yp08", A, p["gamma"]) if p["correction"] == "s_factor" else 1.0)
        p0 = ds["p0"]

        x = np.log(zeta)

        def running(gv: np.ndarray, Lv: np.ndarray, p0v: np.ndarray) -> np.ndarray:
            mu = friction_integral(stieltjes_increments(gv, Lv, x), p0v)
            return np.concatenate([np.zeros(mu.shape[:-1] + (1,)), mu], axis=-1)

        mu_cum = xr.apply_ufunc(
            running,
            g,
            L,
            p0,
            input_core_dims=[["zeta"], ["zeta"], []],
            output_core_dims=[["zeta"]],
            dask="parallelized",
            output_dtypes=[float],
        )
        if set(A.dims) <= {"p0", "zeta"} and L.dims == ("zeta",) and "G" in ds:
            mu_cum = self._resolved(ctx, ds, mu_cum)
        mu_visc = mu_cum.isel(zeta=-1, drop=True)
        if zc == zeta[-1]:
            A_c = A.isel(zeta=-1, drop=True)
        elif set(A.dims) <= {"p0", "zeta"} and "G" in ds:  # between output points
            at = _resolve.area_at(ctx, zeta, _rows(A), _rows(ds["G"]), zc)
            last = A.isel(zeta=-1, drop=True)
            A_c = last.copy(data=at.reshape(last.shape))
        else:  # stacked over sweep dims: linear between output points
            A_c = A.interp(zeta=zc, method="linear", kwargs={"fill_value": None}).drop_vars("zeta")
            A_c = A_c.drop_vars([c for c in A_c.coords if c not in A_c.dims])
        v = float(ds["sliding_speed"].values) if ds["sliding_speed"].ndim == 0 else None
        aT = float(ds["shift_factor"].values) if ds["shift_factor"].ndim == 0 else None
        if v is None or aT is None:  # already stacked over sweep dims: elementwise law
            tau_f = xr.apply_ufunc(
                np.vectorize(self.shear_stress), ds["sliding_speed"], ds["shift_factor"]
            )
        else:
            tau_f = xr.DataArray(self.shear_stress(v, aT))
        mu_contact = tau_f * A_c / p0
        out = {
            "mu_visc": mu_visc,
            "mu_contact": mu_contact,
            "mu": mu_visc + mu_contact,
            "mu_visc_cumulative": mu_cum,
            "contact_area_cutoff": A_c,
            "frictional_shear_stress": tau_f,
        }
        self._check(out)
        return out

    def _check(self, out: dict[str, Any]) -> None:
        """Finite values inside each output's declared range."""
        self._check_arrays({name: da.values for name, da in out.items()})

    def _check_arrays(self, out: dict[str, Any]) -> None:
        """:meth:`_check` of plain arrays."""
        for name, values in out.items():
            vals = np.asarray(values, dtype=float)
            spec = self.outputs[name]
            if not np.all(np.isfinite(vals)):
                raise RuntimeError(f"analysis 'friction': {name!r} has non-finite values")
            if spec.valid_min is not None and np.any(vals < spec.valid_min - 1e-15):
                raise RuntimeError(f"analysis 'friction': {name!r} below {spec.valid_min}")
            if spec.valid_max is not None and np.any(vals > spec.valid_max + 1e-15):
                raise RuntimeError(f"analysis 'friction': {name!r} above {spec.valid_max}")


def _spectra_of(ds: xr.Dataset) -> Any:
    """``psd_of(k)``: point ``k``'s spectrum as the Dataset stores it
    (:func:`~xpersson.plugins.stored.spectrum_of`, the solve's bit for bit), built on first use
    and once for all points where the spectrum is not per point."""
    per_point = "point" in ds.variables["psd_C"].dims
    built: dict[int, Any] = {}

    def psd_of(k: int) -> Any:
        key = k if per_point else 0
        if key not in built:
            built[key] = spectrum_of(ds, point=k) if per_point else spectrum_of(ds)
        return built[key]

    return psd_of


def _values(ds: xr.Dataset, name: str, dims: tuple[str, ...]) -> np.ndarray:
    """The float values of variable ``name`` in ``dims`` order (no DataArray built)."""
    return np.asarray(ds.variables[name].transpose(*dims).values, dtype=float)


def _dense_integrals(ctx_of: Any, points: list[int], grids: list[np.ndarray]) -> Any:
    """``(tau, L)`` of the points at their dense grids (rows padded with their last value) from
    the coefficient's ``dense_stacked`` (one call), or ``None`` (each point asks its own)."""
    coefs = [ctx_of(k).coefficient for k in points]
    if not _stacked_integrals(coefs[0]) or any(type(c) is not type(coefs[0]) for c in coefs):
        return None
    m = max(z.size for z in grids)
    Z = np.stack([np.concatenate([z, np.full(m - z.size, z[-1])]) for z in grids])
    return coefs[0].dense_stacked([ctx_of(k) for k in points], coefs, Z)


def _stacked_integrals(coef: Any) -> bool:
    """Whether ``coef`` is this distribution's coefficient, which computes the integrals of
    several points at once (:meth:`~.ViscoelasticCoefficient.dense_stacked`,
    :meth:`~.ViscoelasticCoefficient.graded_stacked`); another coefficient that provides
    ``loss_integral`` is asked point by point."""
    return isinstance(coef, ViscoelasticCoefficient)


def _dense_rows(ctx_of: Any, plans: list[Any], dense: Any) -> Any:
    """``(plan index, A/A0)`` of every (point, load) the dense path solves, from one engine
    call (``ctx_of.solve_rows`` of a stacked run), or ``None`` (each point's ``solve_at``).
    Padded tau rows get a strictly increasing tail (the engine's requirement), not read."""
    solve_rows = getattr(ctx_of, "solve_rows", None)
    if dense is None or solve_rows is None:
        return None
    tau = np.array(dense[0], dtype=float)
    for r, plan in enumerate(plans):
        n = plan[3].size
        tau[r, n:] = tau[r, n - 1] * (1.0 + 1e-12 * np.arange(1, tau.shape[1] - n + 1))
    plan_of = np.concatenate([np.full(plan[1].size, r) for r, plan in enumerate(plans)])
    point = np.array([plans[r][0] for r in plan_of])
    load = np.concatenate([plan[1] for plan in plans])
    got = solve_rows(point, load, tau[plan_of])
    return None if got is None else (plan_of, got)
