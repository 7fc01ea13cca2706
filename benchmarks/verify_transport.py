"""Verification rows of ``xpersson-transport`` (issue 27) for ``benchmarks/verify.py``.

``rows(fast)`` follows the matrix's contract (keys output, regime, reference, worst, measure,
note):

- the gas part against an independent quadrature of the same model: the ``gap_pdf``
  analysis's density on a fine *linear* grid (trapezoid, plus its contact weight), integrated
  with ``kappa_g / (u + Lambda)`` -- the plugin integrates the closed-form cumulative mass on a
  geometric grid instead;
- the constriction conductances against Barber's ``2 K/((rho_1 + rho_2) E*)`` and
  ``2 kappa_s K/E*`` with ``K = -dp0/du`` from the quadrature mean gap (``verify_interface.
  stiffness``) on the README spectrum (``constriction_rows``);
- films in series, radiation, totals and resistances against formulas fed with *independent*
  inputs: that quadrature stiffness, Persson's closed-form area, no gas (``series_rows``);
- Holm's spots against Holm's constriction formula written from scratch (``holm_rows``).

Part II (theory against exact contact, not the code): Barber's analogy checked on the BEM
contact sets themselves (``bem_rows``, ``results/transport_bem.md``) and Holm's spots against
the conduction on BEM contact sets (``holm_bem_rows``, ``results/holm_bem.md``); the rows carry
``part = "theory"``.
"""

from __future__ import annotations

import math
import re
import tomllib
import warnings
from pathlib import Path

import numpy as np
from verify_core import _row

HERE = Path(__file__).resolve().parent
EXAMPLE = HERE.parent / "plugins" / "xpersson-transport" / "examples" / "heat_sink.toml"


def _solve(fast: bool):
    import xpersson

    with open(EXAMPLE, "rb") as fh:
        scene = tomllib.load(fh)
    scene["load"]["p0"] = {"start": "10 kPa", "stop": "10 MPa", "num": 4 if fast else 13}
    scene["analyses"]["gap_pdf"] = {"u_points": 8001 if fast else 40001, "u_max": "15 um"}
    scene["analyses"]["thermal_contact"]["emissivity_1"] = 0.0  # the gas part alone below
    scene["analyses"]["thermal_contact"]["emissivity_2"] = 0.0
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return xpersson.solve(scene)


def gas_rows(fast: bool) -> list[dict]:
    """thermal_gas_conductance against the trapezoid of gap_pdf's density on a linear grid."""
    ds = _solve(fast)
    kappa = 0.026
    lam = np.asarray(ds["gas_jump_length"].values, float).reshape(-1)
    u = np.asarray(ds["u"].values, float)
    pdf = np.asarray(ds["gap_pdf"].transpose("p0", "u").values, float)
    lam = np.broadcast_to(lam, (pdf.shape[0],))
    ref = np.array([np.trapezoid(pdf[i] * kappa / (u + lam[i]), u) for i in range(pdf.shape[0])])
    got = np.asarray(ds["thermal_gas_conductance"].values, float).reshape(-1)
    err = float(np.max(np.abs(got / ref - 1.0)))
    return [
        _row(
            "thermal_gas_conductance",
            "heat-sink scene (Al on Al in air), p0 10 kPa-10 MPa (A/A0 1e-4-0.1)",
            f"trapezoid of gap_pdf on {u.size} linear points x kappa_g/(u + Lambda)",
            err,
            "rel",
            "the plugin's quadrature against the same gap distribution (gap_pdf's: not an "
            "independent distribution, see the next row); converges with the linear grid "
            "(5.5e-2 at 8001, 1.5e-2 at 40001 points)",
        )
    ]


def gas_mixture_rows(fast: bool) -> list[dict]:
    """thermal_gas_conductance (``separation = "almqvist"``) against ``kappa_g/(u + Lambda)``
    over the independent continuous gap mixture (``verify_leakage.mixture``; no gap code of
    the library), Lambda from Kennard's formula written here."""
    import sys

    sys.path.insert(0, str(HERE))
    from scipy.special import erfinv
    from verify_core import E_STAR
    from verify_interface import I3, README, _solve
    from verify_leakage import _expect, mixture

    ref = README
    targets = (1e-3, 0.05, 0.5) if fast else (1e-4, 1e-3, 0.01, 0.05, 0.2, 0.5)
    tau1 = 0.25 * math.pi * E_STAR**2 * float(I3(ref, ref.q_1))
    loads = [2 * math.sqrt(tau1) * float(erfinv(a)) for a in targets]
    gas = {
        "gap_medium": "gas",
        "gas_conductivity": "0.026 W/(m*K)",
        "gas_mean_free_path": "68 nm",
        "separation": "almqvist",
    }
    th = {**_TRANSPORT["thermal_contact"], **gas}
    ds = _solve(ref, loads, {"thermal_contact": th, "contact_stiffness": {"s_factor": "closure"}})
    lam = 2 * (2 - 1.0) / 1.0 * (2 * 1.4 / 2.4) * 68e-9 / 0.71  # accommodation 1 (default)
    panels, order = (6, 6) if fast else (24, 8)
    want = []
    for p in loads:
        mix = mixture(ref, p, panels=panels, order=order)
        g = _expect(mix["u1"], mix["h"], lam**3, lambda u: 0.026 / (u + lam))
        want.append(float(np.sum(mix["weight"] * g)))
    got = np.asarray(ds["thermal_gas_conductance"].values, float)
    return [
        _row(
            "thermal_gas_conductance (almqvist)",
            f"README spectrum, air (68 nm), A/A0(zeta_1) {targets[0]:g} .. {targets[-1]:g}",
            "kappa_g/(u + Lambda) over the continuous gap mixture (verify_leakage.mixture)",
            float(np.max(np.abs(got / np.array(want) - 1))),
            "rel",
            "the default separation 'pressure' is checked only against gap_pdf's density "
            "(the row above: the plugin's quadrature, not its gap distribution)",
        )
    ]


def bem_rows(fast: bool) -> list[dict]:
    """Barber's analogy against conduction solved on BEM contact sets (stored results)."""
    del fast
    path = HERE / "results" / "transport_bem.md"
    text = path.read_text() if path.is_file() else ""
    ratios = [
        float(m) for m in re.findall(r"^\| [0-9.e-]+ \|(?:[^|]*\|){4} ([0-9.]+) \|", text, re.M)
    ]
    worst = max((abs(r - 1.0) for r in ratios), default=math.nan)
    note = (
        "the analogy itself, on exact contact (it never reads the plugin): the theory's "
        "conductance against the BEM is the campaign's contact_stiffness ratio (Barber)"
    )
    row = _row(
        "Barber's analogy on BEM contact sets",
        "self-affine H 0.8, A/A0 0.5-5 %, 512^2, 3 surfaces",
        "conduction solved on the BEM contact sets vs the same BEM's stiffness (transport_bem.py)",
        worst,
        "rel",
        note,
    )
    return [{**row, "part": "theory"}]


def constriction_rows(fast: bool) -> list[dict]:
    """Constriction conductances against Barber's analogy with the quadrature stiffness."""
    import sys

    sys.path.insert(0, str(HERE))
    from scipy.special import erfinv
    from verify_core import E_STAR
    from verify_interface import I3, README, _solve, stiffness

    ref = README
    targets = (1e-3, 0.05, 0.5) if fast else (1e-5, 1e-3, 0.01, 0.05, 0.2, 0.5, 0.9)
    tau1 = 0.25 * math.pi * E_STAR**2 * float(I3(ref, ref.q_1))
    loads = [2 * math.sqrt(tau1) * float(erfinv(a)) for a in targets]
    ds = _solve(ref, loads, {**_TRANSPORT, "contact_stiffness": {"s_factor": "closure"}})
    K = np.array([stiffness(ref, p) for p in loads])
    kappa_s = 1 / (1 / 167.0 + 1 / 167.0)
    want = {
        "electrical_constriction_conductance": 2 * K / (_RHO_SUM * E_STAR),
        "thermal_constriction_conductance": 2 * kappa_s * K / E_STAR,
    }
    regime = f"README spectrum, A/A0(zeta_1) {targets[0]:g} .. {targets[-1]:g}"
    reference = {
        "electrical_constriction_conductance": "2 K/((rho_1 + rho_2) E*), K = -dp0/du by quad",
        "thermal_constriction_conductance": "2 kappa_s K/E*, K = -dp0/du by quad",
    }
    return [
        _row(n, regime, reference[n], float(np.max(np.abs(ds[n].values / w - 1))), "rel",
             "s_factor closure: the quadrature is Persson 2007's u(p) (closure persson01)")
        for n, w in want.items()
    ]  # fmt: skip


#: copper on copper (electrical), aluminium on aluminium in vacuum (thermal): the README scene's
_TRANSPORT = {
    "electrical_contact": {"resistivity_1": "1.7e-8 ohm*m", "resistivity_2": "1.7e-8 ohm*m"},
    "thermal_contact": {
        "conductivity_1": "167 W/(m*K)",
        "conductivity_2": "167 W/(m*K)",
        "gap_medium": "vacuum",
    },
}


#: electrical_contact defaults (copper on copper) and the spot radius factor
_RHO_SUM, _C_R = 2 * 1.7e-8, math.pi / 2


def holm_rows(fast: bool) -> list[dict]:
    """Holm's spots against the formula written from Holm's constriction resistance.

    ``R = rho_1/(4a) + rho_2/(4a)`` per disc of radius ``a = c_r/q``, ``A(zeta)/(pi a^2)`` discs
    per nominal area, ``A`` = Persson's ``erf(p0/2sqrt(tau))`` with tau's moment in closed form;
    Barber's ``g = 2K/((rho_1 + rho_2) E*)`` with ``K`` by adaptive quadrature
    (``verify_interface.stiffness``); ``holm_magnification`` the root of ``g_H(zeta) = g_B`` in
    the continuous ``ln zeta`` (``brentq``), else the end closest to 1.
    """
    import sys

    sys.path.insert(0, str(HERE))
    from scipy.optimize import brentq, minimize_scalar
    from scipy.special import erf, erfinv
    from verify_core import E_STAR
    from verify_interface import I3, README, _solve, stiffness

    ref = README
    targets = (1e-4, 0.01, 0.3, 0.9) if fast else (1e-6, 1e-4, 1e-2, 0.1, 0.3, 0.6, 0.9, 0.999)
    tau = lambda z: 0.25 * math.pi * E_STAR**2 * float(I3(ref, z * ref.q_L))  # noqa: E731
    z1 = ref.q_1 / ref.q_L
    loads = [2 * math.sqrt(tau(z1)) * erfinv(a) for a in targets]
    ec = {"resistivity_1": "1.7e-8 ohm*m", "resistivity_2": "1.7e-8 ohm*m"}
    ds = _solve(
        ref, loads, {"electrical_contact": ec, "contact_stiffness": {"s_factor": "closure"}}
    )
    zeta = ds["zeta"].values

    def g_holm(p0: float, z: float) -> float:
        t = tau(z)
        A = 1.0 if t <= 0 else float(erf(p0 / (2 * math.sqrt(t))))
        a = _C_R / (z * ref.q_L)
        return A / (math.pi * a * a) * 4 * a / _RHO_SUM

    got = ds["holm_conductance"].transpose("p0", "zeta").values
    err_g, err_z, err_r, err_a, where = 0.0, 0.0, 0.0, 0.0, ""
    for i, p in enumerate(loads):
        want = np.array([g_holm(p, z) for z in zeta])
        err_g = max(err_g, float(np.max(np.abs(got[i] / want - 1))))
        K = stiffness(ref, p)
        if not math.isfinite(K):
            continue
        gb = 2 * K / (_RHO_SUM * E_STAR)
        f = lambda x, p=p, gb=gb: math.log(g_holm(p, math.exp(x)) / gb)  # noqa: E731
        xs = np.linspace(0.0, math.log(z1), 4001)
        fs = np.array([f(x) for x in xs])
        cross = np.flatnonzero(np.signbit(fs[:-1]) != np.signbit(fs[1:]))
        if cross.size:  # the first crossing, as documented
            k = int(cross[0])
            zh, rh = math.exp(brentq(f, xs[k], xs[k + 1], xtol=1e-14, rtol=1e-14)), 1.0
        else:  # closest to 1: minimise |ln ratio| around the scan's best point
            k = int(np.argmin(np.abs(fs)))
            a, b = xs[max(k - 1, 0)], xs[min(k + 1, xs.size - 1)]
            res = minimize_scalar(lambda x, f=f: abs(f(x)), bounds=(a, b), method="bounded",
                                  options={"xatol": 1e-12})  # fmt: skip
            x = res.x if abs(f(res.x)) < abs(fs[k]) else xs[k]
            zh, rh = math.exp(x), math.exp(f(x))
        ez = abs(float(ds["holm_magnification"].values[i]) / zh - 1)
        if ez > err_z:
            err_z, where = ez, f"worst at A/A0 {targets[i]:g}"
        err_r = max(err_r, abs(float(ds["holm_ratio"].values[i]) / rh - 1))
        err_a = max(
            err_a, abs(float(ds["holm_spot_radius"].values[i]) / (_C_R / (zh * ref.q_L)) - 1)
        )
    regime = f"A/A0(zeta_1) {targets[0]:g} .. {targets[-1]:g}, README spectrum, copper"
    interp = (
        "the grid's: a root is interpolated log-log between the Dataset's magnifications;"
        " without a root (light load: the ratio has a minimum above 1) the nearest grid point"
        " is taken (up to half a grid step off)"
    )
    return [
        _row("holm_conductance", regime + ", every zeta", "Holm's 4a/(rho_1+rho_2) per disc"
             " a = c_r/q, A(zeta)/(pi a^2) discs, A closed form", err_g, "rel"),
        _row("holm_magnification", regime, "first root of g_Holm(zeta) = 2K/((rho_1+rho_2)E*)"
             " (scan + brentq), else the continuous minimum of |ln ratio|; K by quad", err_z,
             "rel", "; ".join(x for x in (where, interp) if x)),
        _row("holm_ratio", regime, "1 at the root, else the continuous minimum's ratio", err_r,
             "rel", "no root: the Dataset's grid point nearest the minimum (the grid's)"),
        _row("holm_spot_radius", regime, "c_r / (zeta_root q_L)", err_a, "rel", interp),
    ]  # fmt: skip


def holm_bem_rows(fast: bool) -> list[dict]:
    """Holm's spot picture against the BEM contact sets (stored: results/holm_bem.md)."""
    del fast
    path = HERE / "results" / "holm_bem.md"
    text = path.read_text() if path.is_file() else ""
    rows = re.findall(
        r"^\| [0-9.e-]+ \| [0-9.]+ \| [0-9]+ \| ([0-9.]+) \| ([0-9.]+) \|", text, re.M
    )
    if not rows:
        return [_row("holm_conductance (BEM)", "-", "holm_bem.py results absent", math.nan, "-",
                     "missing: run benchmarks/holm_bem.py")]  # fmt: skip
    cl = [float(a) for a, _ in rows]
    pl = [float(b) for _, b in rows]
    fac = lambda v: max(max(v), 1 / min(v))  # noqa: E731
    regime = "transport_bem spectrum (H 0.8 only), A/A0 0.5-5 %, BEM contact sets"
    return [{**r, "part": "theory"} for r in [
        _row("holm_conductance at zeta_1 (BEM)", regime, "conduction solved on the BEM contact"
             " sets (holm_bem.py, tamaas)", fac(pl), "factor", f"plugin/BEM {min(pl):.2f}-"
             f"{max(pl):.2f}: the theory's (spots of radius c_r/q_1 on Persson's area, no"
             " interaction)"),
        _row("Holm's picture on the BEM clusters", regime, "same", fac(cl), "factor",
             f"non-interacting cluster discs / BEM {min(cl):.2f}-{max(cl):.2f}: the picture's"
             " (interaction neglected), not the code's"),
    ]]  # fmt: skip


#: Stefan-Boltzmann constant [W m-2 K-4] (CODATA 2018, exact)
_SIGMA_SB = 2 * math.pi**5 * 1.380649e-23**4 / (15 * 6.62607015e-34**3 * 299792458.0**2)


def series_rows(fast: bool) -> list[dict]:
    """Films in series, radiation, totals, resistances and the jump length, written here from
    independent inputs: Barber's conductance of the quadrature stiffness, Persson's closed-form
    area, no gas (the gas part has its own row); Kennard's jump length from a gas scene."""
    import sys

    sys.path.insert(0, str(HERE))
    from scipy.special import erf, erfinv
    from verify_core import E_STAR
    from verify_interface import I3, README, _solve, stiffness

    ref = README
    targets = (1e-3, 0.05, 0.5) if fast else (1e-5, 1e-3, 0.01, 0.05, 0.2, 0.5, 0.9)
    tau1 = 0.25 * math.pi * E_STAR**2 * float(I3(ref, ref.q_1))
    loads = [2 * math.sqrt(tau1) * float(erfinv(a)) for a in targets]
    el = {**_TRANSPORT["electrical_contact"], "film_resistivity": "1 ohm*m"}
    el |= {"film_thickness": "2 nm", "nominal_area": "16 cm^2"}
    th = {**_TRANSPORT["thermal_contact"], "film_conductivity": "1 W/(m*K)"}
    th |= {"film_thickness": "100 nm", "nominal_area": "16 cm^2", "temperature": "300 K"}
    th |= {"emissivity_1": 0.1, "emissivity_2": 0.1}
    ana = {
        "electrical_contact": el,
        "thermal_contact": th,
        "contact_stiffness": {"s_factor": "closure"},
    }
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ds = _solve(ref, loads, ana)
    v = {n: np.asarray(ds[n].values, float).reshape(-1) for n in _SERIES if n in ds}
    K = np.array([stiffness(ref, p) for p in loads])
    area = erf(np.asarray(loads) / (2 * math.sqrt(tau1)))
    a0 = 16e-4
    g_c = 2 * K / (_RHO_SUM * E_STAR)
    t_c = 2 * (1 / (1 / 167.0 + 1 / 167.0)) * K / E_STAR
    g_f, t_f = area / (1.0 * 2e-9), area / (100e-9 / 1.0)
    eps = 1 / (1 / 0.1 + 1 / 0.1 - 1)
    t_rad = 4 * _SIGMA_SB * 300.0**3 * eps * (1 - area)
    t_solid = 1 / (1 / t_c + 1 / t_f)
    t_tot = t_solid + t_rad
    want = {
        "electrical_contact_conductance": 1 / (1 / g_c + 1 / g_f),
        "electrical_constriction_resistance": 1 / (g_c * a0),
        "electrical_film_resistance": 1 / (g_f * a0),
        "electrical_contact_resistance": 1 / (g_c * a0) + 1 / (g_f * a0),
        "thermal_solid_conductance": t_solid,
        "thermal_radiation_conductance": t_rad,
        "thermal_contact_conductance": t_tot,
        "thermal_contact_resistance": 1 / (t_tot * a0),
    }
    refs = {
        "electrical_contact_conductance": "(1/g_B + rho_f d/A)^-1, g_B Barber's of K by quad, "
        "A closed form",
        "electrical_constriction_resistance": "1/(g_B A0)",
        "electrical_film_resistance": "rho_f d/(A A0), A closed form",
        "electrical_contact_resistance": "1/(g_B A0) + rho_f d/(A A0)",
        "thermal_solid_conductance": "(1/g_B + d/(kappa_f A))^-1",
        "thermal_radiation_conductance": "4 sigma_SB T^3 / (1/eps_1 + 1/eps_2 - 1) x (1 - A)",
        "thermal_contact_conductance": "solid + radiation (vacuum), each written here",
        "thermal_contact_resistance": "1/(G_total A0)",
    }
    regime = (
        f"README spectrum, A/A0(zeta_1) {targets[0]:g} .. {targets[-1]:g}, vacuum, 300 K, films "
        "2 nm (1 ohm m) and 100 nm (1 W/(m K)), emissivities 0.1"
    )
    notes = {
        "thermal_radiation_conductance": "far field only (no near-field enhancement): the "
        "plugin's stated model",
    }
    out = [
        _row(n, regime, refs[n], float(np.max(np.abs(v[n] / want[n] - 1))), "rel",
             notes.get(n, ""))
        for n in want
    ]  # fmt: skip
    return [*out, _jump_row()]


def _jump_row() -> dict:
    """Kennard's temperature-jump length of the heat-sink gas (air, 68 nm)."""
    ds = _solve(True)
    lam = 2 * (2 - 0.9) / 0.9 * (2 * 1.4 / 2.4) * 68e-9 / 0.71
    got = float(np.asarray(ds["gas_jump_length"].values, float).reshape(-1)[0])
    # hard-sphere kinetic theory for air at 300 K, 1 atm (d = 3.7e-10 m): the scene's 68 nm
    mfp = 1.380649e-23 * 300 / (math.sqrt(2) * math.pi * 3.7e-10**2 * 101325)
    return _row(
        "gas_jump_length",
        "heat-sink scene (air, accommodation 0.9)",
        "Kennard: sum_walls (2 - a)/a 2 gamma/(gamma + 1) lambda/Pr",
        abs(got / lam - 1),
        "rel",
        f"lambda = 68 nm given; hard-sphere kinetic theory k T/(sqrt2 pi d^2 p) with "
        f"d = 3.7e-10 m gives {mfp * 1e9:.1f} nm",
    )


_SERIES = (
    "electrical_contact_conductance",
    "electrical_constriction_resistance",
    "electrical_film_resistance",
    "electrical_contact_resistance",
    "thermal_solid_conductance",
    "thermal_radiation_conductance",
    "thermal_contact_conductance",
    "thermal_contact_resistance",
)


def full_contact_rows(fast: bool) -> list[dict]:
    """The status flags against contact_stiffness_status (1: full contact), and the
    constriction resistance at full contact (no constriction: exactly 0)."""
    spectrum = {"model": "self_affine", "H": 0.8, "q_L": "1e5 1/m", "q_r": "1e6 1/m",
                "q_1": "1e7 1/m", "h_rms": "1 nm"}  # fmt: skip
    rho = {"resistivity_1": "1.7e-8 ohm*m", "resistivity_2": "1.7e-8 ohm*m"}
    kappa = {"conductivity_1": "400 W/(m*K)", "conductivity_2": "400 W/(m*K)"}
    ds = xpersson_solve({
        "spectrum": spectrum, "material": {"E": "1 MPa", "nu": 0.5},
        "load": {"p0": ["1 kPa", "30 kPa", "0.1 MPa", "0.3 MPa"]},
        "analyses": {"electrical_contact": rho, "thermal_contact": kappa},
    })  # fmt: skip
    full = ds["contact_stiffness_status"].values == 1
    regime = f"1 nm on E = 1 MPa, p0 1 kPa .. 0.3 MPa ({int(full.sum())} at full contact)"
    return [
        *(_row(n, regime, "1 exactly where contact_stiffness_status is 1",
               float(np.sum((ds[n].values == 1) != full)), "mismatches")
          for n in ("electrical_contact_status", "thermal_contact_status")),
        _row("electrical_constriction_resistance (full contact)", regime, "0: no constriction",
             float(np.max(ds["electrical_constriction_resistance"].values[full])), "abs"),
    ]  # fmt: skip


def xpersson_solve(scene: dict):
    import xpersson

    return xpersson.solve(scene)


def rows(fast: bool) -> list[dict]:
    """Every transport row."""
    return [
        *gas_rows(fast),
        *gas_mixture_rows(fast),
        *bem_rows(fast),
        *constriction_rows(fast),
        *series_rows(fast),
        *holm_rows(fast),
        *holm_bem_rows(fast),
        *full_contact_rows(fast),
    ]


if __name__ == "__main__":
    for row in rows(fast=False):
        print(row)
