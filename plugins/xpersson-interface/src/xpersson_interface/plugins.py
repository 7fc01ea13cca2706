"""Thin plugin classes (group ``xpersson.analyses``) over the numerical modules.

Each class reads only the SI data of the :class:`~xpersson.plugins.SceneContext` (spectrum,
``E_star``, loads ``p0``) and returns ``{name: DataArray or (dims, data)}`` with the dims, units
and long names declared in :attr:`outputs`.
"""

from __future__ import annotations

import math
from typing import Any, ClassVar

import numpy as np
import xarray as xr
from xpersson.plugins import Analysis, ParamSpec, VarSpec

from ._closures import CLOSURES, AreaLaw
from ._energy import elastic_energy, full_contact_energy
from ._gap import contact_stiffness, gap_asymptote, mean_gap
from ._gap_diffusion import diffuse_with_injection
from ._gap_pdf import detachment, gap_mean, gap_pdf
from ._leakage import (
    bruggeman_gap,
    critical_junction,
    effective_pressure_drop,
    leak_rate,
)
from ._quad import q_rule

__all__ = ["ElasticEnergy", "MeanGap", "ContactStiffness", "GapPDF", "Leakage"]

_PERSSON2007 = "10.1103/PhysRevLett.99.125502"
_YANG2008 = "10.1088/0953-8984/20/21/215214"
_ALMQVIST2011 = "10.1016/j.jmps.2011.08.004"
_PERSSON_YANG2008 = "10.1088/0953-8984/20/31/315011"
_LORENZ2010 = "10.1140/epje/i2010-10558-6"

_GAMMA = ParamSpec(
    unit="1",
    default=1.0,
    bounds=(0.0, 1.0),
    inclusive=(False, True),
    description="correction factor S = gamma + (1 - gamma) P^2 of the mean separation (1: Persson"
    " 2007, 0.42-0.45: Yang-Persson 2008)",
)


def _p0(ctx: Any) -> np.ndarray:
    return np.atleast_1d(np.asarray(ctx.p0, dtype=float))


class ElasticEnergy(Analysis):
    """Elastic energy per nominal area versus load, with the correction-factor closures."""

    summary = "Elastic energy U_el/A0 stored at the interface versus load (Persson 2007 + closures)"
    references = (_PERSSON2007, _YANG2008, "10.1007/s11249-024-01838-4")
    parameters: ClassVar = {
        "closure": ParamSpec(
            kind="choice",
            choices=CLOSURES,
            default="persson01",
            description="area/S closure: persson01 (S = 1), yp08, wm17, xu24",
        ),
        "gamma": ParamSpec(
            unit="1",
            default=None,
            bounds=(0.0, 1.0),
            inclusive=(False, True),
            description="closure parameter (default: 0.45 yp08/xu24, 5/9 wm17)",
        ),
        "uncorrected_area": ParamSpec(
            kind="bool",
            default=False,
            description="use Persson's area erf(w p/E*) with the closure's S (Yang-Persson form,"
            " consistent with mean_gap)",
        ),
    }
    outputs: ClassVar = {
        "elastic_energy": VarSpec(
            ("p0",), "J m-2", "elastic energy per nominal area at the interface"
        ),
        "elastic_energy_full": VarSpec(
            (), "J m-2", "elastic energy per nominal area at full contact"
        ),
    }
    provides = ("elastic_energy", "elastic_energy_full")

    def compute(self, ctx: Any, ds: xr.Dataset) -> dict[str, Any]:
        law = AreaLaw(self.params["closure"], self.params["gamma"])
        U = elastic_energy(
            ctx.psd,
            ctx.E_star,
            _p0(ctx),
            law,
            uncorrected_area=bool(self.params["uncorrected_area"]),
        )
        return {
            "elastic_energy": (("p0",), U),
            "elastic_energy_full": ((), np.float64(full_contact_energy(ctx.psd, ctx.E_star))),
        }


class MeanGap(Analysis):
    """Mean interfacial separation u(p0) and its low-load asymptote."""

    summary = "Mean interfacial separation u(p0) (Persson 2007 / Yang-Persson 2008)"
    references = (_PERSSON2007, _YANG2008)
    parameters: ClassVar = {"gamma": _GAMMA}
    outputs: ClassVar = {
        "mean_gap": VarSpec(("p0",), "m", "mean interfacial separation"),
        "gap_u0": VarSpec((), "m", "length scale u0 of the low-load law u = -u0 ln(p0/(beta E*))"),
        "gap_beta": VarSpec((), "1", "prefactor beta of the low-load law u = -u0 ln(p0/(beta E*))"),
    }
    provides = ("mean_gap", "gap_u0", "gap_beta")

    def compute(self, ctx: Any, ds: xr.Dataset) -> dict[str, Any]:
        g = float(self.params["gamma"])
        rule = q_rule(ctx.psd)
        u = mean_gap(ctx.psd, ctx.E_star, _p0(ctx), g, rule=rule)
        u0, beta = gap_asymptote(ctx.psd, ctx.E_star, g, rule=rule)
        return {
            "mean_gap": (("p0",), u),
            "gap_u0": ((), np.float64(u0)),
            "gap_beta": ((), np.float64(beta)),
        }


class ContactStiffness(Analysis):
    """Normal contact stiffness K = -dp0/du per nominal area (analytic derivative)."""

    summary = "Normal interfacial stiffness K = -dp0/du per nominal area"
    references = (_PERSSON2007, _YANG2008)
    parameters: ClassVar = {"gamma": _GAMMA}
    outputs: ClassVar = {
        "contact_stiffness": VarSpec(
            ("p0",), "Pa m-1", "normal contact stiffness per nominal area -dp0/du"
        ),
    }
    provides = ("contact_stiffness",)

    def compute(self, ctx: Any, ds: xr.Dataset) -> dict[str, Any]:
        K = contact_stiffness(ctx.psd, ctx.E_star, _p0(ctx), float(self.params["gamma"]))
        return {"contact_stiffness": (("p0",), K)}


class GapPDF(Analysis):
    """Distribution of interfacial separations at the finest magnification."""

    summary = "Gap distribution P(u): closed form (Almqvist 2011) or diffusion in zeta"
    references = (_ALMQVIST2011, _PERSSON2007)
    parameters: ClassVar = {
        "method": ParamSpec(
            kind="choice",
            choices=("closed_form", "diffusion"),
            default="closed_form",
            description="closed_form (Almqvist et al. 2011) or diffusion (engine solve_sourced)",
        ),
        "gamma": _GAMMA,
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
        "n_zeta": ParamSpec(
            kind="int",
            default=300,
            bounds=(20, 100000),
            description="log-spaced magnification bins of the detached area",
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
        ),
        "gap_contact_weight": VarSpec(
            ("p0",), "1", "contact area fraction: weight of delta(u) in the gap distribution"
        ),
        "gap_mean": VarSpec(("p0",), "m", "mean of the gap distribution"),
    }
    provides = ("gap_pdf", "gap_contact_weight", "gap_mean")

    def compute(self, ctx: Any, ds: xr.Dataset) -> dict[str, Any]:
        p = self.params
        det = detachment(ctx.psd, ctx.E_star, _p0(ctx), float(p["gamma"]), n_zeta=int(p["n_zeta"]))
        umax = p["u_max"]
        if umax is None:
            umax = float(np.max(det.mean_gap)) + 6.0 * det.h_rms
        u = np.linspace(0.0, float(umax), int(p["u_points"]))
        if p["method"] == "closed_form":
            rho = gap_pdf(det, u)
            mean = gap_mean(det)
        else:
            rho, mean = _diffusion_pdf(ctx.psd, det, u, int(p["n_grid"]))
        coord = xr.Variable(("u",), u, {"units": "m", "long_name": "interfacial separation"})
        return {
            "gap_pdf": xr.DataArray(rho, dims=("p0", "u"), coords={"u": coord}),
            "gap_contact_weight": (("p0",), det.contact.copy()),
            "gap_mean": (("p0",), mean),
        }


def _diffusion_pdf(psd: Any, det: Any, u: np.ndarray, n_grid: int) -> tuple[np.ndarray, np.ndarray]:
    """Solve §5.5b on ``[0, max(u_max, u(p0) + 10 h_rms)]`` and sample on ``u``."""
    q_L, q_1 = float(psd.q_L), float(psd.q_1)
    h2 = np.array([2.0 * math.pi * float(psd.moment(1.0, z * q_L, q_1)) for z in det.zeta])
    s = 0.5 * (det.h_rms**2 - h2)
    g_max = max(float(u[-1]), float(np.max(det.mean_gap)) + 10.0 * det.h_rms)
    res = diffuse_with_injection(g_max, n_grid, s, det.u1, det.weight)
    rho = np.array([np.interp(u, res.g, r) for r in res.rho])
    vol = np.full(res.g.size, res.g[1] - res.g[0])
    vol[0] *= 0.5
    # bins detaching beyond the far wall (vanishing area at huge u1 near zeta = 1) are not
    # injected; their first moment is added as in the closed form
    far = np.where(det.u1 >= g_max, det.weight * det.u1, 0.0).sum(axis=1)
    mean = res.rho @ (vol * res.g) + far
    return rho, mean


class Leakage(Analysis):
    """Leak rate of a static seal by critical-junction and effective-medium theory."""

    summary = "Seal leak rate: critical junction (percolation) and Bruggeman effective medium"
    references = (_PERSSON_YANG2008, "10.1209/0295-5075/86/44006", _LORENZ2010)
    parameters: ClassVar = {
        "a_c": ParamSpec(
            unit="1",
            default=0.42,
            bounds=(0.0, 1.0),
            inclusive=(False, False),
            description="percolation threshold of the contact area",
        ),
        "gamma": _GAMMA,
        "fluid": ParamSpec(
            kind="choice",
            choices=("liquid", "gas"),
            default="liquid",
            description="incompressible liquid or ideal gas (isothermal)",
        ),
        "viscosity": ParamSpec(
            unit="Pa*s",
            default=1e-3,
            bounds=(0.0, None),
            inclusive=(False, True),
            description="dynamic viscosity of the fluid",
        ),
        "pressure_drop": ParamSpec(
            unit="Pa", default=1e5, bounds=(0.0, None), description="liquid: pressure drop"
        ),
        "p_in": ParamSpec(
            unit="Pa", default=2e5, bounds=(0.0, None), description="gas: inlet pressure"
        ),
        "p_out": ParamSpec(
            unit="Pa",
            default=1e5,
            bounds=(0.0, None),
            inclusive=(False, True),
            description="gas: outlet pressure (reference of the reported volume flow)",
        ),
        "seal_width": ParamSpec(
            unit="m",
            default=1e-3,
            bounds=(0.0, None),
            inclusive=(False, True),
            description="seal width L_x along the flow",
        ),
        "seal_length": ParamSpec(
            unit="m",
            default=1e-2,
            bounds=(0.0, None),
            inclusive=(False, True),
            description="seal length L_y across the flow",
        ),
        "emt_threshold": ParamSpec(
            kind="choice",
            choices=("bruggeman", "a_c"),
            default="bruggeman",
            description="EMT percolation at contact weight 1/2 (plain) or rescaled to a_c",
        ),
        "n_zeta": ParamSpec(
            kind="int",
            default=200,
            bounds=(20, 100000),
            description="magnification bins of the gap distribution (EMT)",
        ),
    }
    outputs: ClassVar = {
        "leak_zeta_c": VarSpec(
            ("p0",), "1", "percolation magnification (NaN when sealed)",
            nan_meaning="sealed: the contact area percolates before zeta_1 (no open channel)",
        ),
        "leak_u1": VarSpec(("p0",), "m", "separation of the critical constriction"),
        "leak_flow_factor": VarSpec(
            ("p0",), "1", "critical-junction pressure flow factor u1^3 / u^3"
        ),
        "leak_rate": VarSpec(("p0",), "m3 s-1", "leak rate, critical-junction theory"),
        "leak_sealed": VarSpec(
            ("p0",),
            "1",
            "sealed flag, critical junction (A(zeta_1)/A0 >= a_c)",
            extra={"flag_values": "0 1", "flag_meanings": "open sealed"},
        ),
        "leak_flow_factor_emt": VarSpec(
            ("p0",), "1", "effective-medium pressure flow factor sigma_eff / sigma(u)"
        ),
        "leak_rate_emt": VarSpec(("p0",), "m3 s-1", "leak rate, Bruggeman effective medium"),
        "leak_sealed_emt": VarSpec(
            ("p0",),
            "1",
            "sealed flag, effective medium (sigma_eff = 0)",
            extra={"flag_values": "0 1", "flag_meanings": "open sealed"},
        ),
    }
    provides = tuple(outputs)

    def compute(self, ctx: Any, ds: xr.Dataset) -> dict[str, Any]:
        p = self.params
        p0 = _p0(ctx)
        g = float(p["gamma"])
        a_c = float(p["a_c"])
        dp = effective_pressure_drop(
            p["fluid"], float(p["pressure_drop"]), float(p["p_in"]), float(p["p_out"])
        )
        cj = critical_junction(ctx.psd, ctx.E_star, p0, a_c, g)
        det = detachment(ctx.psd, ctx.E_star, p0, g, n_zeta=int(p["n_zeta"]))
        ubar = det.mean_gap
        u3 = bruggeman_gap(det, a_c=a_c if p["emt_threshold"] == "a_c" else None)
        args = (float(p["seal_width"]), float(p["seal_length"]), dp, float(p["viscosity"]))
        with np.errstate(divide="ignore", invalid="ignore"):
            ff = np.where(ubar > 0, cj["u1"] ** 3 / ubar**3, 0.0)
            ff_emt = np.where(ubar > 0, u3 / ubar**3, 0.0)
        return {
            "leak_zeta_c": (("p0",), cj["zeta_c"]),
            "leak_u1": (("p0",), cj["u1"]),
            "leak_flow_factor": (("p0",), ff),
            "leak_rate": (("p0",), leak_rate(cj["u1"] ** 3, *args)),
            "leak_sealed": (("p0",), cj["sealed"].astype(np.int8)),
            "leak_flow_factor_emt": (("p0",), ff_emt),
            "leak_rate_emt": (("p0",), leak_rate(u3, *args)),
            "leak_sealed_emt": (("p0",), (u3 <= 0).astype(np.int8)),
        }
