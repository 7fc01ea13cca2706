"""Thin analysis classes (group ``xpersson.analyses``) over :mod:`xpersson.physics.interface`.

Every analysis computes from the solved contact (:mod:`xpersson.plugins.solved`, in the core):
the boundary's declared area variables, the coefficient's correction factor, all loads at once.
Which boundaries an analysis supports is declared as the boundary traits it needs
(``boundary_traits``), so boundaries installed later are accepted or refused by what they
declare, never by name.

The correction factor of energy and gap (``s_factor``):

* ``"auto"`` (the default of ``mean_gap`` and ``contact_stiffness``, chosen by accuracy): the
  Yang-Persson form below where the scene's coefficient leaves the area uncorrected (closure
  ``persson01``, the default), else the closure's; resolved when the scene is (the archive
  records the form used). Over the validation campaign (docs/verification.md, part II) the
  Yang-Persson stiffness and mean gap are several times closer to the boundary-element
  solutions than Persson 2007's (stiffness: median exact/theory about 1 instead of 1.5-4 below
  5 % contact).
* ``"closure"`` (the default of the other analyses: no campaign evidence yet): the scene's
  ``[coefficient]`` closure decides area and ``S`` (``S = d tau_eff/d tau_c``: 1 for
  persson01, ``S(A)`` for yp08/wm17, Xu24's hybrid factor); Persson 2007 without a closure.
* ``"yang_persson"``: Yang & Persson 2008, ``S = gamma + (1 - gamma) A^2`` in the energy and
  the mean gap with Persson's *uncorrected* area (the form whose mean gap matches GFMD within
  1-8 %); only with ``closure = "persson01"`` (else refused: the area would be corrected twice).
  ``gamma`` defaults to :data:`xpersson.physics.closures.GAMMA_DEFAULT` (0.42).
"""

from __future__ import annotations

from typing import Any, ClassVar

import numpy as np
import xarray as xr

from xpersson import physics
from xpersson.physics.closures import GAMMA_DEFAULT
from xpersson.plugins import Analysis, FastPaths, ParamSpec, VarSpec
from xpersson.plugins.solved import Solved, per_solve, solved_curve

from ._body import ENERGY, LEAKAGE
from ._by_group import by_group
from ._by_load import (
    LEAK_MIN,
    LEAK_NOISE,
    LEAK_ORDERS,
    LEAK_SAFETY,
    LEAK_TOL,
    TABLE_MIN,
    TOL,
    by_load,
)
from ._chunks import CHUNK, Part, bin_edges, contact_of, contacts, joined, on_gap_grid, subset
from ._first_level import at_kinks, first_level, table_min
from ._gap_diffusion import gap_pdf_by_diffusion
from ._leak_direct import outputs
from ._leakage import (
    LEAK_KEYS,
    effective_pressure_drop,
    sealed_plan,
    table_weights,
    with_sealed,
)
from ._params import _DENSE, _FORM, _FORM_AUTO, _GAMMA, _NEVER, LEAKAGE_PARAMS, UNTABLED, load_error

__all__ = ["ElasticEnergy", "MeanGap", "ContactStiffness", "GapPDF", "Leakage"]

_PERSSON2001 = "10.1063/1.1388626"
_PERSSON2007 = "10.1103/PhysRevLett.99.125502"
_YANG2008 = "10.1088/0953-8984/20/21/215214"
_ALMQVIST2011 = "10.1016/j.jmps.2011.08.004"
_PERSSON_YANG2008 = "10.1088/0953-8984/20/31/315011"
_LORENZ2010 = "10.1140/epje/i2010-10558-6"
_XU2024 = "10.1007/s11249-024-01838-4"

#: CF flags: numeric flag_values of the variable's type
_FLAG = {"flag_values": np.array([0, 1], dtype=np.int8), "flag_meanings": "open sealed"}
_GAP_TRAITS = frozenset({"repulsive", "load_similar"})
#: the instances complete their parameters in __init__ and check_scene only (s_factor "auto",
#: gamma's default); compute reads them: a scene's later solves may reuse its instances
_REUSED = FastPaths(reused=True)


class _Interface(Analysis):
    """Shared: S-factor form, refusal rules, reading the solved curve."""

    abstract = True
    coefficient_traits = frozenset({"elastic_spectrum"})
    requires = ("area_fraction", "non_contact_fraction", "diffusion_time")

    def __init__(self, **params: Any) -> None:
        super().__init__(**params)
        if self._params.get("s_factor") == "yang_persson" and self._params.get("gamma") is None:
            self._params["gamma"] = GAMMA_DEFAULT  # recorded in the archive's resolved scene

    def check_scene(self, coefficient: Any, boundary: Any) -> None:
        """Refuse unsupported boundaries and a Yang-Persson form on a corrected area; resolve
        ``s_factor = "auto"`` for the scene's coefficient."""
        super().check_scene(coefficient, boundary)
        self._resolve_form(coefficient)
        form, gamma = self.params.get("s_factor", "closure"), self.params.get("gamma")
        if form == "yang_persson" and coefficient.corrects_variance():
            raise ValueError(
                "s_factor = 'yang_persson' puts the correction factor into energy and gap on "
                "Persson's uncorrected area, but the scene's coefficient already corrects the "
                "area with a closure; use s_factor = 'closure' or coefficient.closure = "
                "'persson01'"
            )
        if form == "closure" and gamma is not None:
            raise ValueError(
                "gamma applies to s_factor = 'yang_persson'; with s_factor = 'closure' the "
                "scene's closure and its coefficient.gamma decide S"
            )

    def _resolve_form(self, coefficient: Any) -> None:
        """``"auto"`` -> ``"yang_persson"`` (area uncorrected) or ``"closure"``; gamma's default."""
        if self._params.get("s_factor") != "auto":
            return
        corrected = coefficient is not None and coefficient.corrects_variance()
        self._params["s_factor"] = "closure" if corrected else "yang_persson"
        if not corrected and self._params.get("gamma") is None:
            self._params["gamma"] = GAMMA_DEFAULT  # recorded in the archive's resolved scene

    def _key(self) -> tuple[Any, ...]:
        per = int(self.params.get("zeta_per_decade", 0))
        return self.params.get("s_factor", "closure"), self.params.get("gamma"), per

    def _solved(self, ctx: Any, ds: Any) -> Solved:
        self._resolve_form(ctx.coefficient)  # an instance used without check_scene
        return per_solve(
            ctx,
            ("solved", *self._key()),
            lambda: solved_curve(ctx, ds, *self._key()),
        )

    def _contact(self, ctx: Any, ds: Any, s: Any = None) -> tuple[Solved, physics.SolvedContact]:
        s = self._solved(ctx, ds) if s is None else s  # s: the solved curve of ctx, ds if known
        sc = per_solve(
            ctx,
            ("contact", *self._key()),
            lambda: contact_of(ctx, s),
        )
        return s, sc

    def _parts(self, ctx: Any, ds: Any) -> tuple[Solved, list[Part]]:
        """The solved curve and its loads in chunks (:mod:`._chunks`; one up to CHUNK)."""
        s = self._solved(ctx, ds)
        if s.p0.size <= CHUNK:
            return s, [(slice(None), s, self._contact(ctx, ds, s)[1])]
        return s, contacts(ctx, s, self._key(), CHUNK)


class ElasticEnergy(_Interface):
    """Elastic energy per nominal area versus load from the solved area (physics.md §5.1).

    ``U_el/A0 = (pi E*/2) int q^2 C A S dq`` with the solved *elastic* contact area ``A`` (the
    boundary's ``elastic_area``) and the scene's ``S``. For an elastoplastic boundary this is
    Persson's elastic-energy expression with ``P(q)`` the elastic contact area ``P_el(q)`` (the
    plastically flattened area stores no elastic energy of the finer scales), as in Persson's
    elastoplastic treatment (J. Chem. Phys. 115, 3840 (2001); attribution from memory: physics.md
    gives no verified source for this form). It tends to the elastic energy as
    ``sigma_Y -> inf`` and lies below it at finite ``sigma_Y``.
    """

    summary = "Elastic energy U_el/A0 stored at the interface, from the solved contact area"
    references = (_PERSSON2001, _PERSSON2007, _YANG2008, _XU2024)
    boundary_traits = frozenset({"repulsive"})
    parameters: ClassVar = {"s_factor": _FORM, "gamma": _GAMMA, "zeta_per_decade": _DENSE}
    outputs: ClassVar = {
        "elastic_energy": VarSpec(
            ("p0",), "J m-2", "elastic energy per nominal area at the interface", valid_min=0.0
        ),
        "elastic_energy_full": VarSpec(
            (), "J m-2", "elastic energy per nominal area at full contact", valid_min=0.0
        ),
    }
    provides = ("elastic_energy", "elastic_energy_full")
    fast_paths = _REUSED
    body_quantities: ClassVar = ENERGY

    def compute(self, ctx: Any, ds: xr.Dataset) -> dict[str, Any]:
        s, parts = self._parts(ctx, ds)
        U = joined(parts, lambda part: part[2].elastic_energy())
        psd = s.psd  # the Dataset's spectrum (xpersson.plugins.stored), as the solve's
        q_hi = min(float(psd.q_1), float(s.zeta[-1]) * psd.q_L)
        full = physics.full_contact_energy(psd, s.E_star, psd.q_L, q_hi)
        return {
            "elastic_energy": (("p0",), np.clip(U, 0.0, full)),
            "elastic_energy_full": ((), np.float64(full)),
        }


class MeanGap(_Interface):
    """Mean interfacial separation u(p0) by virtual work from the solved area (§5.2)."""

    summary = "Mean interfacial separation u(p0) from the solved area (Persson 2007 virtual work)"
    references = (_PERSSON2007, _YANG2008)
    boundary_traits = _GAP_TRAITS
    parameters: ClassVar = {"s_factor": _FORM_AUTO, "gamma": _GAMMA, "zeta_per_decade": _DENSE}
    outputs: ClassVar = {
        "mean_gap": VarSpec(
            ("p0",),
            "m",
            "mean interfacial separation (virtual work, Persson 2007)",
            valid_min=0.0,
            description="u(p0) = int_p0^inf dp/p dU_el/dp: the separation consistent with the "
            "elastic energy and the load (p = -dU_el/du; contact_stiffness is its slope). Not "
            "the mean of gap_pdf: gap_mean (analysis gap_pdf) adds the mirror term of the "
            "detached area's Gaussian spread at the wall and leaves out the gap content of "
            "removed scales, so the two differ by 1.2-5x at high load. Against GFMD "
            "(xu2024-gfmd, E* = 1 Pa scene) u(p0) is -13 to -70 % for p0/E* = 0.025-0.19 "
            "and +14 to +110 % for p0/E* <= 0.01 (gap_mean: +1 to +26 % for 0.015-0.19)",
        ),
    }
    provides = ("mean_gap",)
    fast_paths = _REUSED

    def compute(self, ctx: Any, ds: xr.Dataset) -> dict[str, Any]:
        _, parts = self._parts(ctx, ds)
        return {"mean_gap": (("p0",), joined(parts, lambda part: part[2].mean_gap()))}


class ContactStiffness(_Interface):
    """Normal contact stiffness K = -dp0/du per nominal area (analytic, §5.4)."""

    summary = "Normal interfacial stiffness K = -dp0/du per nominal area from the solved area"
    references = (_PERSSON2007, _YANG2008)
    boundary_traits = _GAP_TRAITS
    parameters: ClassVar = {"s_factor": _FORM_AUTO, "gamma": _GAMMA, "zeta_per_decade": _DENSE}
    outputs: ClassVar = {
        "contact_stiffness": VarSpec(
            ("p0",), "Pa m-1", "normal contact stiffness per nominal area -dp0/du",
            valid_min=0.0,
            description="-1/(du/dp0) with du/dp0 = -(4/(E* p0^2)) int (tau_c/q) (-dF), F = A S; "
            "taken from ln(1 - F), so finite up to 1 - A ~ 1e-300",
            nan_meaning="full contact: du/dp0 underflows (K exceeds the largest float, the "
            "interface is rigid at the solve's resolution; contact_compliance holds 0 and "
            "contact_stiffness_status 1)",
        ),
        "contact_compliance": VarSpec(
            ("p0",), "m Pa-1", "normal contact compliance per nominal area -du/dp0",
            valid_min=0.0,
            description="1/contact_stiffness; finite at every load (0 at full contact)",
        ),
        "contact_stiffness_status": VarSpec(
            ("p0",), "1", "validity of the stiffness per load",
            description="0: K from the theory; 1: full contact, K not representable (NaN); "
            "2: p0 above E*, outside the small-slope linear elasticity the theory assumes "
            "(K is the theory's value, not the solid's)",
            extra={"flag_values": np.array([0, 1, 2], dtype=np.int8),
                   "flag_meanings": "valid rigid_full_contact above_contact_modulus"},
        ),
    }  # fmt: skip
    provides = ("contact_stiffness", "contact_compliance", "contact_stiffness_status")
    fast_paths = _REUSED

    def compute(self, ctx: Any, ds: xr.Dataset) -> dict[str, Any]:
        s, parts = self._parts(ctx, ds)
        slope = joined(parts, lambda part: part[2].mean_gap_slope())
        compliance = np.maximum(-slope, 0.0)
        with np.errstate(divide="ignore", over="ignore"):
            K = np.where(compliance > 0.0, 1.0 / np.where(compliance > 0, compliance, 1.0), np.nan)
        rigid = ~np.isfinite(K)
        K[rigid] = np.nan
        status = np.where(rigid, 1, np.where(s.p0 > float(s.E_star), 2, 0)).astype(np.int8)
        return {
            "contact_stiffness": (("p0",), K),
            "contact_compliance": (("p0",), compliance),
            "contact_stiffness_status": (("p0",), status),
        }


#: The smallest positive float as ``detachment``'s ``negligible``: every bin of non-zero weight
#: counts (weights are area fractions <= 1, so ``negligible`` times the largest is 0 or this
#: float), and the sub-problem mean gaps are computed only at the edges of such bins (45-78 % of
#: the bins have zero weight on the speed design's scenes). The weights, ``u1`` and the mean gap
#: (``ubar[:, 0]``), all that gap_pdf and gap_mean read, are the same bits as with 0.
_NONZERO = 5e-324


class GapPDF(_Interface):
    """Distribution of interfacial separations at the finest magnification (§5.5)."""

    summary = "Gap distribution P(u) from the solved area: closed form (Almqvist 2011) or diffusion"
    references = (_ALMQVIST2011, _PERSSON2007)
    boundary_traits = _GAP_TRAITS
    parameters: ClassVar = {
        "method": ParamSpec(
            kind="choice",
            choices=("closed_form", "diffusion"),
            default="closed_form",
            description="closed_form (Almqvist et al. 2011) or diffusion (engine solve_sourced)",
        ),
        "separation": ParamSpec(
            kind="choice",
            choices=("pressure", "almqvist"),
            default="pressure",
            description="mean separation u1 of the detaching area: the part of d(A u)/dA due to"
            " the rising pressure p0/A (default), or Almqvist's full d(A u)/dA, whose"
            " removed-scale part puts a far tail at many h_rms at high load"
            " (docs/verification.md; not smooth in the load: every load computed directly)",
        ),
        "s_factor": _FORM,
        "gamma": _GAMMA,
        "zeta_per_decade": _DENSE,
        "u_max": ParamSpec(
            unit="m",
            default=None,
            bounds=(0.0, None),
            inclusive=(False, True),
            description="largest separation of the output grid (default max u(p0) + 6 h_rms)",
        ),
        "u_points": ParamSpec(
            kind="int", default=256, bounds=(8, 100000), description="points of the gap grid"
        ),
        "n_bins": ParamSpec(
            kind="int",
            default=80,
            bounds=(10, 100000),
            description="magnification bins of the detached area (geometric in zeta - 1)",
        ),
        "n_grid": ParamSpec(
            kind="int",
            default=3000,
            bounds=(50, 1000000),
            description="grid intervals of the diffusion solver",
        ),
    }
    outputs: ClassVar = {
        "gap_pdf": VarSpec(
            ("p0", "u"),
            "m-1",
            "probability density of the interfacial separation (continuous part)",
            description="the contact fraction is the delta weight gap_contact_weight at u = 0",
            valid_min=0.0,
        ),
        "gap_contact_weight": VarSpec(
            ("p0",), "1", "contact area fraction: weight of delta(u) in the gap distribution",
            valid_min=0.0, valid_max=1.0,
        ),
        "gap_mean": VarSpec(
            ("p0",), "m", "mean of the gap distribution gap_pdf (contact counted at u = 0)",
            valid_min=0.0,
            description="int u gap_pdf du over the detached area's Gaussians with their mirror "
            "term at the wall (Almqvist et al. 2011). Differs from mean_gap (Persson's "
            "virtual-work u(p0), the separation consistent with energy and load): the mirror "
            "term adds mean (+0.3 % at low load, several times near full contact) and "
            "separation = 'pressure' leaves out the removed-scale content (with 'almqvist' "
            "the no-mirror mean equals u(p0) exactly). Use mean_gap for energy/stiffness, "
            "gap_mean for the distribution; against GFMD (xu2024-gfmd) gap_mean is closer for "
            "p0/E* >= 0.015 (+1 to +26 % vs -13 to -70 %)",
        ),
        "gap_pdf_load_error": load_error(TOL, TABLE_MIN, never=_NEVER),
    }  # fmt: skip
    provides = ("gap_pdf", "gap_contact_weight", "gap_mean", "gap_pdf_load_error")
    fast_paths = _REUSED

    def compute(self, ctx: Any, ds: xr.Dataset) -> dict[str, Any]:
        grid: list[np.ndarray] = []  # the gap grid, fixed by the first loads computed
        untabled = any(self.params[k] == v for k, v in UNTABLED)  # (not smooth in the load)
        least = np.size(ctx.p0) + 1 if untabled else 0
        out, err = by_load(ctx.p0, lambda rows: self._direct(ctx, ds, rows, grid), least=least)
        return {
            "gap_pdf": on_gap_grid(out["gap_pdf"], grid[0]),
            "gap_contact_weight": (("p0",), np.minimum(out["gap_contact_weight"], 1.0)),
            "gap_mean": (("p0",), out["gap_mean"]),
            "gap_pdf_load_error": (("p0",), err),
        }

    def _direct(
        self, ctx: Any, ds: xr.Dataset, rows: np.ndarray, grid: list[np.ndarray]
    ) -> dict[str, np.ndarray]:
        """The outputs of the loads ``rows``, computed directly (the gap grid: ``grid[0]``,
        set here on the first call from these loads' largest mean gap)."""
        p = self.params
        ctx, ds = subset(ctx, ds, rows)
        s, parts = self._parts(ctx, ds)
        edges = bin_edges(s, int(p["n_bins"]))
        dets = [sc.detachment(edges, p["separation"], negligible=_NONZERO) for _, _, sc in parts]
        if not grid:
            umax = p["u_max"]
            if umax is None:  # over every load (the lowest load, always computed first)
                umax = max(float(np.max(d.mean_gap)) for d in dets) + 6.0 * dets[0].h_rms
            grid.append(np.linspace(0.0, float(umax), int(p["u_points"])))
        u = grid[0]

        def one(det: physics.Detachment) -> tuple[np.ndarray, ...]:
            if p["method"] == "closed_form":
                return physics.gap_pdf(det, u), physics.gap_mean(det), det.contact.copy()
            rho, mean = gap_pdf_by_diffusion(s.psd, det, u, int(p["n_grid"]))
            return rho, mean, det.contact.copy()

        rho, mean, contact = joined(dets, one)
        return {
            "gap_pdf": np.maximum(rho, 0.0),
            "gap_contact_weight": contact,
            "gap_mean": mean,
        }


#: The medium's measured discretisation error (benchmarks/results/leakage_emt_error.md)
_EMT_ERROR = (
    "discretisation error (n_bins 60 against 480 bins; 60 scenes, 40 loads 1 kPa - 1 MPa, "
    "default threshold): <= 0.015 relative where A/A0 < 0.2, <= 0.07 at 0.2 - 0.3, <= 0.25 at "
    "0.3 - 0.4, up to 0.46 toward the medium's sealing (A/A0 -> 1/2, sigma_eff -> 0); not "
    "included in leak_load_error. The theory's spread is larger there: Bruggeman against a "
    "resistor network 1.7x at A/A0 0.45, and the critical junction seals at A/A0 = a_c"
)


class Leakage(_Interface):
    """Leak rate of a static seal by critical-junction and effective-medium theory (§6)."""

    summary = "Seal leak rate: critical junction (percolation) and Bruggeman effective medium"
    references = (_PERSSON_YANG2008, "10.1209/0295-5075/86/44006", _LORENZ2010)
    boundary_traits = _GAP_TRAITS
    parameters: ClassVar = {
        "a_c": LEAKAGE_PARAMS["a_c"],
        "s_factor": _FORM,
        "gamma": _GAMMA,
        "zeta_per_decade": _DENSE,
        **{k: v for k, v in LEAKAGE_PARAMS.items() if k != "a_c"},
    }
    outputs: ClassVar = {
        "leak_zeta_c": VarSpec(
            ("p0",), "1", "percolation magnification (NaN when sealed)", valid_min=1.0,
            nan_meaning="sealed: the contact area percolates before zeta_1 (no open channel)",
        ),
        "leak_u1": VarSpec(
            ("p0",), "m", "separation of the critical constriction (NaN when sealed)",
            valid_min=0.0, nan_meaning="sealed: no critical constriction",
        ),
        "leak_flow_factor": VarSpec(
            ("p0",), "1", "critical-junction pressure flow factor u1^3 / u^3 (0 when sealed)",
            valid_min=0.0,
        ),
        "leak_rate": VarSpec(
            ("p0",), "m3 s-1", "leak rate, critical-junction theory (0 when sealed)",
            valid_min=0.0,
            description="volume flow from the inlet to the outlet (gas: at p_out)",
        ),
        "leak_sealed": VarSpec(
            ("p0",), "1", "sealed flag, critical junction (A(zeta_max)/A0 > a_c)",
            extra=_FLAG,
        ),
        "leak_flow_factor_emt": VarSpec(
            ("p0",), "1", "effective-medium pressure flow factor sigma_eff / sigma(u)",
            valid_min=0.0, description="discretisation error: as leak_rate_emt's",
        ),
        "leak_rate_emt": VarSpec(
            ("p0",), "m3 s-1", "leak rate, Bruggeman effective medium", valid_min=0.0,
            description=_EMT_ERROR,
        ),
        "leak_sealed_emt": VarSpec(
            ("p0",), "1", "sealed flag, effective medium (sigma_eff = 0)", extra=_FLAG,
        ),
        "leak_load_error": load_error(LEAK_TOL, LEAK_MIN, "4 times", " not sealed by both"),
    }  # fmt: skip
    provides = tuple(outputs)
    fast_paths = _REUSED
    body_quantities: ClassVar = LEAKAGE

    def _pressure_drop(self) -> float:
        p = self.params
        return effective_pressure_drop(
            p["fluid"], float(p["pressure_drop"]), float(p["p_in"]), float(p["p_out"])
        )

    def check_scene(self, coefficient: Any, boundary: Any) -> None:
        """Also refuse a gas scene with ``p_in < p_out`` (names both parameters)."""
        super().check_scene(coefficient, boundary)
        self._pressure_drop()

    def compute(self, ctx: Any, ds: xr.Dataset) -> dict[str, Any]:
        p = self.params
        sealed, free = sealed_plan(ds, ctx.boundary, ctx.p0, float(p["a_c"]), p["emt_threshold"])
        least = table_min(ctx.p0, sealed)
        per_decade, near, shut = first_level(ctx, ds, float(p["a_c"]), sealed, least)
        direct, groups = at_kinks(
            ctx, ds, lambda r, w=None: with_sealed(self._direct, ctx, ds, r, sealed, w), least
        )
        weights = table_weights(ds, ctx.boundary, ctx.p0, float(p["a_c"]), p["emt_threshold"])
        settings = (LEAK_NOISE, least, LEAK_ORDERS, LEAK_SAFETY, per_decade, weights)
        first = np.stack([free | near | shut, free | shut]) if groups else free | near | shut
        args = (ctx.p0, direct, LEAK_TOL, LEAK_KEYS, *settings, first)
        out, err = by_group(*args, groups) if groups else by_load(*args)
        res: dict[str, Any] = {k: (("p0",), v) for k, v in out.items() if k in self.outputs}
        for k in ("leak_sealed", "leak_sealed_emt"):
            res[k] = (("p0",), out[k].astype(np.int8))
        res["leak_load_error"] = (("p0",), err)
        return res

    def _direct(
        self, ctx: Any, ds: xr.Dataset, rows: np.ndarray, which: np.ndarray | None = None
    ) -> dict[str, np.ndarray]:
        """The outputs of the loads ``rows``, computed directly (:func:`._leak_direct.outputs`;
        ``which`` (2, n_rows): the groups (``LEAK_GROUPS``) each load is computed for: the
        junction always, the effective medium where ``which[1]``; None: both)."""
        ctx, ds = subset(ctx, ds, rows)
        s, parts = self._parts(ctx, ds)
        medium = None if which is None else np.asarray(which[1], dtype=bool)
        return outputs(self.params, self._pressure_drop(), s, parts, ctx.p0, medium)
