"""Analysis classes (group ``xpersson.analyses``): electrical and thermal contact conductance.

Both compute from the solved Dataset, all loads at once: the incremental normal stiffness
``contact_stiffness`` that ``xpersson-interface`` puts there (Persson's ``K = -dp0/du`` with the
scene's closure) turns into the constriction conductance by Barber's analogy
(:mod:`._physics`); the contact area the boundary declares gives the film term and Holm's spots;
the gap distribution of ``gap_pdf`` (its closed form on the same solved curve, through
``xpersson.plugins.solved.solved_curve`` and ``xpersson.physics.gap_cdf``) gives the heat carried by
the gas in the gaps (:mod:`._gap`).

Boundaries: the analogy holds for an elastic contact's incremental (unloading) stiffness. The
analyses need what ``contact_stiffness`` needs (traits ``repulsive`` and ``load_similar``) and
refuse the rest before any work with a message naming both plugins: elastoplastic boundaries
(the theory here gives no unloading stiffness of the plastically flattened surface) and
adhesive ones (tensile contact edges: no stated basis for the analogy's stiffness).
"""

from __future__ import annotations

import math
from typing import Any, ClassVar

import numpy as np
import xarray as xr

from xpersson.plugins import Analysis, FastPaths, ParamSpec, VarSpec
from xpersson.plugins.stored import contact_modulus, spectrum_of

from . import _physics as ph
from ._body import ELECTRICAL, THERMAL
from ._gap import gap_cdf_grid, gas_from_cdf

__all__ = ["ElectricalContact", "ThermalContact"]

BARBER2003 = "10.1098/rspa.2002.1038"
PERSSON2022 = "10.1007/s11249-022-01630-2"
PLV2010 = "10.1140/epje/i2010-10543-1"
PERSSON2007 = "10.1103/PhysRevLett.99.125502"
GREENWOOD1966 = "10.1088/0508-3443/17/12/310"
HOLM1967 = "10.1007/978-3-662-06688-1"


#: NaN meanings at full contact (``contact_stiffness_status`` 1)
_NAN_CONSTRICTION = (
    "full contact (contact_stiffness_status 1): no constriction, the conductance per area is "
    "unbounded (the constriction resistance is 0)"
)
_NAN_SERIES = (
    "full contact (contact_stiffness_status 1) without a film: no resistance at the interface, "
    "the conductance per area is unbounded (with a film: the film's conductance alone)"
)
_NAN_HOLM = (
    "full contact (contact_stiffness_status 1): Barber's conductance is unbounded, no "
    "magnification's spot sum matches it"
)


def _positive(unit: str, what: str, example: float | None = None, **kw: Any) -> ParamSpec:
    return ParamSpec(
        unit=unit,
        bounds=(0.0, None),
        inclusive=(False, True),
        sweepable=True,
        description=what,
        example=example,
        **kw,
    )


_NOMINAL_AREA = _positive("m**2", "nominal contact area for the reported resistance", default=1e-4)
_FILM_THICKNESS = ParamSpec(
    unit="m",
    default=0.0,
    bounds=(0.0, None),
    sweepable=True,
    description="thickness of a film (oxide, contamination) on the real contact area (0: none)",
)
_SPOT_FACTOR = _positive(
    "1", "Holm spots: radius r = c_r / q at magnification zeta (default pi/2)", default=math.pi / 2
)


def _rows(values: Any, n: int) -> np.ndarray:
    a = np.asarray(values, dtype=float)
    return np.broadcast_to(a, (n, a.shape[-1])).copy() if a.ndim else np.full((n, 1), float(a))


def _per_load(ds: xr.Dataset, name: str) -> np.ndarray:
    return np.atleast_1d(np.asarray(ds[name].values, dtype=float))


def _full_contact(ds: xr.Dataset, n: int) -> np.ndarray:
    """Loads at full contact: ``contact_stiffness_status`` 1 (``contact_stiffness`` NaN by its
    declared meaning: the interface is rigid at the solve's resolution)."""
    status = _per_load(ds, "contact_stiffness_status")
    return np.broadcast_to(status == ph.RIGID_FULL_CONTACT, (n,))


def _status(analysis: str) -> VarSpec:
    return VarSpec(
        ("p0",), "1", f"validity of the {analysis} conductances per load",
        description="0: from the theory; 1: full contact (contact_stiffness_status 1, "
        "contact_stiffness NaN): no constriction, so the constriction resistance is 0 and "
        "every conductance per area without a finite part in series is unbounded (NaN)",
        extra={"flag_values": np.array([0, 1], dtype=np.int8),
               "flag_meanings": "valid full_contact"},
    )  # fmt: skip


def _contact_area(ctx: Any, ds: xr.Dataset, n: int) -> np.ndarray:
    """Load-bearing contact area (p0, zeta): the boundary's declared ``contact_area``."""
    names = getattr(type(ctx.boundary), "contact_area", ("area_fraction",))
    total = 0.0
    for name in names:
        da = ds[name]
        if "p0" in da.dims:
            da = da.transpose("p0", "zeta")
        total = total + _rows(da.values, n)
    return np.clip(total, 0.0, 1.0)


class _Transport(Analysis):
    """Shared: boundary support with a message naming both plugins, the stiffness."""

    abstract = True
    boundary_traits = frozenset({"repulsive", "load_similar"})
    coefficient_traits = frozenset({"elastic_spectrum"})

    @classmethod
    def supports(cls, boundary: type | None = None, coefficient: type | None = None) -> str | None:
        """As :meth:`Analysis.supports`, saying why plastic/adhesive boundaries are refused."""
        why = super().supports(boundary, coefficient)
        if why is None or boundary is None:
            return why
        have = frozenset(getattr(boundary, "traits", ()))
        if "repulsive" not in have:
            return (
                f"{why}. xpersson-transport turns the incremental stiffness of "
                "xpersson-interface's contact_stiffness into a conductance by Barber's analogy, "
                "which needs a non-adhesive elastic contact; an adhesive boundary's tensile "
                "contact edges have no stated basis for it (refused)"
            )
        if "load_similar" not in have:
            return (
                f"{why}. Barber's analogy needs the elastic unloading stiffness; for an "
                "elastoplastic boundary xpersson-interface's contact_stiffness is not defined "
                "and xpersson-transport does not estimate the unloading stiffness of the "
                "plastically flattened surface (refused)"
            )
        return why

    def _stiffness(self, ds: xr.Dataset) -> tuple[np.ndarray, np.ndarray]:
        """``contact_stiffness`` [Pa/m] and the loads at full contact (:func:`_full_contact`)."""
        K = _per_load(ds, "contact_stiffness")
        return K, _full_contact(ds, K.size)


class ElectricalContact(_Transport):
    """Electrical contact conductance and resistance from the solved contact (Barber 2003).

    ``g_c = 2 K / ((rho_1 + rho_2) E*)`` per nominal area with Persson's stiffness ``K``; a film
    ``rho_f d`` on the real contact area ``A_c`` (the boundary's contact area at the Dataset's
    finest magnification) in series: ``1/g = 1/g_c + rho_f d / A_c``. Holm's picture beside it:
    the spots seen at each magnification as non-interacting discs (``holm_conductance``), and
    the magnification at which their sum equals (or comes closest to) Barber's conductance.
    """

    summary = "Electrical contact conductance/resistance: Barber's stiffness analogy, Holm's spots"
    references = (BARBER2003, PERSSON2022, HOLM1967, GREENWOOD1966, PERSSON2007)
    requires = ("contact_stiffness", "contact_stiffness_status", "area_fraction")
    parameters: ClassVar = {
        "resistivity_1": _positive("ohm*m", "electrical resistivity of body 1", 1.7e-8),
        "resistivity_2": _positive("ohm*m", "electrical resistivity of body 2", 1.7e-8),
        "film_resistivity": ParamSpec(
            unit="ohm*m",
            default=None,
            bounds=(0.0, None),
            inclusive=(False, True),
            sweepable=True,
            description="resistivity of the film (needed when film_thickness > 0)",
        ),
        "film_thickness": _FILM_THICKNESS,
        "nominal_area": _NOMINAL_AREA,
        "spot_radius_factor": _SPOT_FACTOR,
    }
    outputs: ClassVar = {
        "electrical_constriction_conductance": VarSpec(
            ("p0",), "S m-2", "constriction conductance per nominal area (Barber)", valid_min=0.0,
            nan_meaning=_NAN_CONSTRICTION,
        ),
        "electrical_contact_conductance": VarSpec(
            ("p0",), "S m-2", "contact conductance per nominal area, constriction + film in series",
            valid_min=0.0, nan_meaning=_NAN_SERIES,
        ),
        "electrical_constriction_resistance": VarSpec(
            ("p0",), "ohm", "constriction resistance of the nominal area", valid_min=0.0
        ),
        "electrical_film_resistance": VarSpec(
            ("p0",), "ohm", "film resistance of the nominal area (0: no film)", valid_min=0.0
        ),
        "electrical_contact_resistance": VarSpec(
            ("p0",), "ohm", "contact resistance of the nominal area, constriction + film",
            valid_min=0.0,
        ),
        "holm_conductance": VarSpec(
            ("p0", "zeta"), "S m-2",
            "Holm: non-interacting spots of radius c_r/q seen at magnification zeta",
            valid_min=0.0,
        ),
        "holm_magnification": VarSpec(
            ("p0",), "1",
            "magnification at which Holm's spot sum equals (else comes closest to) Barber's value",
            valid_min=1.0, nan_meaning=_NAN_HOLM,
        ),
        "holm_ratio": VarSpec(
            ("p0",), "1", "Holm's spot sum over Barber's conductance at holm_magnification",
            valid_min=0.0, nan_meaning=_NAN_HOLM,
        ),
        "holm_spot_radius": VarSpec(
            ("p0",), "m", "Holm spot radius c_r/q at holm_magnification", valid_min=0.0,
            nan_meaning=_NAN_HOLM,
        ),
        "electrical_contact_status": _status("electrical"),
    }  # fmt: skip
    provides = tuple(outputs)
    fast_paths = FastPaths(reused=True)
    body_quantities: ClassVar = ELECTRICAL

    def check_scene(self, coefficient: Any, boundary: Any) -> None:
        """Refuse a film thickness without the film's resistivity (before any work)."""
        super().check_scene(coefficient, boundary)
        p = self.params
        if p["film_thickness"] > 0 and p["film_resistivity"] is None:
            raise ValueError(
                "film_resistivity [ohm*m] is required when film_thickness > 0 (allowed range "
                "(0, inf] ohm*m); give it or set film_thickness = 0"
            )

    def compute(self, ctx: Any, ds: xr.Dataset) -> dict[str, Any]:
        p = self.params
        K, full = self._stiffness(ds)
        n = K.size
        E_star, q_L = contact_modulus(ds), spectrum_of(ds).q_L  # the solve's, from the Dataset
        c = ph.electrical_factor(p["resistivity_1"], p["resistivity_2"], E_star)
        g_c = np.where(full, np.nan, c * K)
        area = _contact_area(ctx, ds, n)
        rho_f = p["film_resistivity"] or 0.0
        g_f = ph.film_conductance(area[:, -1], rho_f, p["film_thickness"])
        g = ph.with_full_contact(ph.in_series(g_c, g_f), g_f, full)
        a0 = p["nominal_area"]
        r_c = ph.resistance(g_c, a0, full)
        zeta = np.asarray(ds["zeta"].values, dtype=float)
        q = zeta * q_L
        c_r = p["spot_radius_factor"]
        g_h = c * ph.holm_stiffness(area, q[None, :], E_star, c_r)
        with np.errstate(divide="ignore", invalid="ignore"):
            ratio = np.clip(g_h / np.where(full, 1.0, g_c)[:, None], 1e-300, 1e300)
        z_h, r_h = (np.where(full, np.nan, v) for v in ph.closest_to_one(zeta, ratio))
        with np.errstate(divide="ignore"):
            r_film = np.where(np.isfinite(g_f), 1.0 / (g_f * a0), 0.0)
        return {
            "electrical_constriction_conductance": (("p0",), g_c),
            "electrical_contact_conductance": (("p0",), g),
            "electrical_constriction_resistance": (("p0",), r_c),
            "electrical_film_resistance": (("p0",), r_film),
            "electrical_contact_resistance": (("p0",), r_c + r_film),
            "holm_conductance": (("p0", "zeta"), g_h),
            "holm_magnification": (("p0",), z_h),
            "holm_ratio": (("p0",), r_h),
            "holm_spot_radius": (("p0",), c_r / (z_h * q_L)),
            "electrical_contact_status": (("p0",), full.astype(np.int8)),
        }


_GAS: dict[str, ParamSpec] = {
    "gap_medium": ParamSpec(
        kind="choice",
        choices=("vacuum", "gas"),
        default="vacuum",
        description="what fills the gaps: vacuum (radiation only) or a gas (needs its data)",
    ),
    "gas_conductivity": ParamSpec(
        unit="W/(m*K)",
        default=None,
        bounds=(0.0, None),
        sweepable=True,
        description="thermal conductivity of the gas (gap_medium = 'gas')",
    ),
    "gas_mean_free_path": ParamSpec(
        unit="m",
        default=None,
        bounds=(0.0, None),
        inclusive=(False, True),
        sweepable=True,
        description="gas mean free path at the interface (gap_medium = 'gas'); > 0: the "
        "continuum form diverges logarithmically at the contact edges",
    ),
    "accommodation_1": ParamSpec(
        unit="1", default=1.0, bounds=(0.0, 1.0), inclusive=(False, True), sweepable=True,
        description="thermal accommodation coefficient of the gas on body 1",
    ),
    "accommodation_2": ParamSpec(
        unit="1", default=1.0, bounds=(0.0, 1.0), inclusive=(False, True), sweepable=True,
        description="thermal accommodation coefficient of the gas on body 2",
    ),
    "heat_capacity_ratio": ParamSpec(
        unit="1", default=1.4, bounds=(1.0, 1.7), inclusive=(False, True), sweepable=True,
        description="c_p/c_v of the gas (1.4: air, N2; 5/3: He, Ar)",
    ),
    "prandtl": _positive("1", "Prandtl number of the gas (0.71: air)", default=0.71),
    "temperature": _positive("K", "interface temperature (radiation)", default=293.15),
    "s_factor": ParamSpec(
        kind="choice",
        choices=("closure", "yang_persson"),
        default="closure",
        description="correction factor of the gap distribution, as gap_pdf's (give the same as "
        "contact_stiffness's)",
    ),
    "gamma": ParamSpec(
        unit="1", default=None, bounds=(0.0, 1.0), inclusive=(False, True),
        description="gamma of s_factor = 'yang_persson' (default 0.42)",
    ),
    "zeta_per_decade": ParamSpec(
        kind="int", default=40, bounds=(0, 10000),
        description="dense sampling of the solve for the gap distribution, as gap_pdf's",
    ),
    "n_bins": ParamSpec(
        kind="int", default=200, bounds=(10, 100000),
        description="magnification bins of the detached area (gap_pdf's default is 80; 200 "
        "brings the gas part within 0.7 % of 1000 bins)",
    ),
    "u_per_decade": ParamSpec(
        kind="int", default=100, bounds=(10, 10000),
        description="points per decade of the geometric separation grid of the gas integral",
    ),
    "separation": ParamSpec(
        kind="choice", choices=("pressure", "almqvist"), default="pressure",
        description="mean separation of the detaching area, as gap_pdf's parameter of that name",
    ),
    "emissivity_1": ParamSpec(
        unit="1", default=0.0, bounds=(0.0, 1.0), sweepable=True,
        description="emissivity of body 1 (0: no radiation)",
    ),
    "emissivity_2": ParamSpec(
        unit="1", default=0.0, bounds=(0.0, 1.0), sweepable=True,
        description="emissivity of body 2 (0: no radiation)",
    ),
}  # fmt: skip


class ThermalContact(_Transport):
    """Thermal contact conductance: solid contact (Barber) + gas and radiation across the gaps.

    Solid: ``2 kappa_s K / E*`` (``1/kappa_s = 1/kappa_1 + 1/kappa_2``) in series with a film
    ``d / (kappa_f A_c)``. Gaps (Persson, Lorenz & Volokitin 2010): ``int P(u) kappa_g /
    (u + Lambda) du`` over the solved gap distribution with the temperature-jump length
    ``Lambda`` of the rarefied gas, plus far-field radiation on the non-contact area. The total
    is the sum of the parallel paths; every part is reported. The gap distribution is
    ``gap_pdf``'s closed form (same bins and correction factor), integrated through its exact
    cumulative mass on a geometric grid (:mod:`._gap`: the linear grid of ``gap_pdf`` does
    not resolve the smallest gaps that dominate the integral).
    """

    summary = "Thermal contact conductance: Barber's analogy + gas (temperature jump) + radiation"
    references = (BARBER2003, PLV2010, PERSSON2022, PERSSON2007)
    requires = ("contact_stiffness", "contact_stiffness_status", "area_fraction")
    parameters: ClassVar = {
        "conductivity_1": _positive("W/(m*K)", "thermal conductivity of body 1", 400.0),
        "conductivity_2": _positive("W/(m*K)", "thermal conductivity of body 2", 400.0),
        "film_conductivity": ParamSpec(
            unit="W/(m*K)",
            default=None,
            bounds=(0.0, None),
            inclusive=(False, True),
            sweepable=True,
            description="thermal conductivity of the film (needed when film_thickness > 0)",
        ),
        "film_thickness": _FILM_THICKNESS,
        "nominal_area": _NOMINAL_AREA,
        **_GAS,
    }
    outputs: ClassVar = {
        "thermal_constriction_conductance": VarSpec(
            ("p0",), "W m-2 K-1", "solid constriction conductance per nominal area (Barber)",
            valid_min=0.0, nan_meaning=_NAN_CONSTRICTION,
        ),
        "thermal_solid_conductance": VarSpec(
            ("p0",), "W m-2 K-1", "solid contact conductance, constriction + film in series",
            valid_min=0.0, nan_meaning=_NAN_SERIES,
        ),
        "thermal_gas_conductance": VarSpec(
            ("p0",), "W m-2 K-1", "conductance of the gas in the gaps per nominal area",
            valid_min=0.0,
        ),
        "thermal_radiation_conductance": VarSpec(
            ("p0",), "W m-2 K-1", "far-field radiative conductance of the non-contact area",
            valid_min=0.0,
        ),
        "thermal_contact_conductance": VarSpec(
            ("p0",), "W m-2 K-1", "total thermal contact conductance (solid + gas + radiation)",
            valid_min=0.0, nan_meaning=_NAN_SERIES,
        ),
        "thermal_contact_resistance": VarSpec(
            ("p0",), "K W-1", "thermal contact resistance of the nominal area", valid_min=0.0
        ),
        "gas_jump_length": VarSpec(
            (), "m", "temperature-jump length Lambda of the gas (0: vacuum)", valid_min=0.0
        ),
        "thermal_contact_status": _status("thermal"),
    }  # fmt: skip
    provides = tuple(outputs)
    fast_paths = FastPaths(reused=True)
    body_quantities: ClassVar = THERMAL

    def check_scene(self, coefficient: Any, boundary: Any) -> None:
        """Refuse a gas without its data and a film without its conductivity (before work)."""
        super().check_scene(coefficient, boundary)
        p = self.params
        if p["gap_medium"] == "gas":
            for name, unit, rng in (
                ("gas_conductivity", "W/(m*K)", "[0, inf] W/(m*K)"),
                ("gas_mean_free_path", "m", "(0, inf] m"),
            ):
                if p[name] is None:
                    raise ValueError(
                        f"{name} [{unit}] is required when gap_medium = 'gas' (allowed range "
                        f"{rng}); give it, or set gap_medium = 'vacuum'"
                    )
        if p["s_factor"] == "yang_persson" and coefficient.corrects_variance():
            raise ValueError(
                "s_factor = 'yang_persson' puts the correction factor on Persson's uncorrected "
                "area, but the scene's coefficient already corrects the area with a closure; use "
                "s_factor = 'closure' or coefficient.closure = 'persson01'"
            )
        if p["s_factor"] == "closure" and p["gamma"] is not None:
            raise ValueError("gamma applies to s_factor = 'yang_persson' only")
        if p["film_thickness"] > 0 and p["film_conductivity"] is None:
            raise ValueError(
                "film_conductivity [W/(m*K)] is required when film_thickness > 0 (allowed range "
                "(0, inf] W/(m*K)); give it or set film_thickness = 0"
            )

    def jump(self) -> float:
        """The gas's temperature-jump length ``Lambda`` [m] (0 for vacuum)."""
        p = self.params
        if p["gap_medium"] != "gas":
            return 0.0
        return ph.jump_length(
            p["gas_mean_free_path"],
            p["accommodation_1"],
            p["accommodation_2"],
            p["heat_capacity_ratio"],
            p["prandtl"],
        )

    def compute(self, ctx: Any, ds: xr.Dataset) -> dict[str, Any]:
        p = self.params
        K, full = self._stiffness(ds)
        E_star = contact_modulus(ds)  # the solve's, from the Dataset
        g_c = ph.thermal_factor(p["conductivity_1"], p["conductivity_2"], E_star) * K
        g_c = np.where(full, np.nan, g_c)
        a_c = _contact_area(ctx, ds, K.size)[:, -1]
        kf = p["film_conductivity"]
        g_f = ph.film_conductance(a_c, 0.0 if kf is None else 1.0 / kf, p["film_thickness"])
        g_solid = ph.with_full_contact(ph.in_series(g_c, g_f), g_f, full)
        lam = self.jump()
        if p["gap_medium"] == "gas" and p["gas_conductivity"] > 0:
            u, F = gap_cdf_grid(
                ctx,
                ds,
                s_factor=p["s_factor"],
                gamma=p["gamma"],
                zeta_per_decade=int(p["zeta_per_decade"]),
                n_bins=int(p["n_bins"]),
                jump=lam,
                u_per_decade=int(p["u_per_decade"]),
                separation=p["separation"],
            )
            g_gas = gas_from_cdf(u, F, p["gas_conductivity"], lam)
        else:
            g_gas = np.zeros_like(g_c)
        rad = ph.radiation_conductance(p["temperature"], p["emissivity_1"], p["emissivity_2"])
        g_rad = rad * (1.0 - a_c)
        total = g_solid + g_gas + g_rad
        return {
            "thermal_contact_status": (("p0",), full.astype(np.int8)),
            "thermal_constriction_conductance": (("p0",), g_c),
            "thermal_solid_conductance": (("p0",), g_solid),
            "thermal_gas_conductance": (("p0",), g_gas),
            "thermal_radiation_conductance": (("p0",), g_rad),
            "thermal_contact_conductance": (("p0",), total),
            "thermal_contact_resistance": (("p0",), ph.resistance(total, p["nominal_area"], full)),
            "gas_jump_length": ((), np.float64(lam)),
        }
