"""Verification rows of the adhesion boundaries' own outputs (``jkr``, ``dmt``, ``adhesive``).

Imported by ``verify.py`` (contract ``rows(fast) -> list[dict]``, keys output, regime,
reference, worst, measure, note). ``verify_adhesion.py`` referees the contact areas against the
BEM; this module referees every other output against a reference computed another way, written
here from physics.md §2 and never by calling the plugin's helpers:

- the scene's geometry (true-area ratio, full-contact energy of the finer scales, gamma_eff,
  sigma_a, Tabor parameter, stickiness w_eff) by adaptive quadrature of the spectrum written
  from its definition (``verify_core.Ref``, roll-off as a breakpoint) and
  ``A*/A0 = int_0^inf exp(-x) sqrt(1 + xi^2 x) dx`` by ``quad``;
- the constant detachment wall (a flat ``sigma_a`` table) by its image solution (§2.2);
- ``p_att`` as the traction law written here integrated over the gap distribution of
  ``verify_leakage.mixture`` at the loads ``p_rep``: the continuous mixture over the
  magnification written from {cite:p}`almqvist2011` (Gauss-Legendre in ``ln(zeta - 1)``, each node's
  folded normal by Gauss-Legendre panels), none of the library's gap code (before: the
  ``gap_pdf`` analysis's density, the project's own gap distribution); the mean gap at
  ``p_rep`` by the exponential-integral quadrature (``verify_interface.mean_gap``); the
  diagnostics against what they claim.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
from scipy.integrate import quad
from scipy.optimize import brentq
from scipy.stats import norm
from verify_core import E_STAR, NU, E, Ref, _lnquad, _row, _tau

import xpersson

SPEC = Ref(0.8, 1e3, 1e4, 1e6, 1e-6)
ZETA_1 = SPEC.q_1 / SPEC.q_L


def _solve(loads, boundary: dict | None = None, analyses: dict | None = None):
    scene = {
        "spectrum": SPEC.scene_spectrum(),
        "material": {"E": f"{E} Pa", "nu": NU},
        "load": {"p0": [f"{float(p)!r} Pa" for p in loads]},
        "output": {"zeta_per_decade": 4},
    }
    if boundary:
        scene["boundary"] = boundary
    if analyses:
        scene["analyses"] = analyses
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return xpersson.solve(scene)


def _moment(n: int, a: float, b: float) -> float:
    """int_a^b q^n C dq with the roll-off as a breakpoint."""
    a, b = max(a, SPEC.q_L), min(b, SPEC.q_1)
    if b <= a:
        return 0.0
    if a < SPEC.q_r < b:
        return _lnquad(SPEC, n, a, SPEC.q_r) + _lnquad(SPEC, n, SPEC.q_r, b)
    return _lnquad(SPEC, n, a, b)


def true_area(zeta: float) -> float:
    """A*/A0 of the roughness resolved up to zeta (physics.md §2.1), by quad over x."""
    xi2 = 2 * math.pi * _moment(3, SPEC.q_L, zeta * SPEC.q_L)
    return quad(lambda x: math.exp(-x) * math.sqrt(1 + xi2 * x), 0, math.inf, epsrel=1e-13)[0]


def finer_energy(zeta: float) -> float:
    """U_el(zeta)/A0 = (pi E*/2) int_{zeta q_L}^{q_1} q^2 C dq [J/m^2]."""
    return 0.5 * math.pi * E_STAR * _moment(2, zeta * SPEC.q_L, SPEC.q_1)


def tabor(zeta: float, work: float, rng: float) -> float:
    """[R dgamma^2 / (E*^2 dr^3)]^(1/3), 1/R^2 = 2 pi int_{q/sqrt2}^{sqrt2 q} q^5 C."""
    q = zeta * SPEC.q_L
    radius = (2 * math.pi * _moment(5, q / math.sqrt(2), q * math.sqrt(2))) ** -0.5
    return (radius * work**2 / (E_STAR**2 * rng**3)) ** (1 / 3)


def w_eff(work: float) -> float:
    """Persson-Tosatti stickiness dgamma A*(zeta_1)/A0 - U_el,full/A0 [J/m^2] (§2.5)."""
    return work * true_area(ZETA_1) - finer_energy(1.0)


def _rel(got, want, floor: float = 0.0) -> float:
    got, want = np.asarray(got, float), np.asarray(want, float)
    scale = np.maximum(np.abs(want), floor) if floor else np.abs(want)
    return float(np.max(np.abs(got - want) / scale))


def _geometry_err(ds, work: float, rng: float, worst: dict) -> None:
    """tabor_parameter and w_eff of any adhesion scene."""
    z = ds["zeta"].values
    mu = [tabor(float(x), work, rng) for x in z]
    worst["tabor_parameter"] = max(
        worst.get("tabor_parameter", 0.0), _rel(ds["tabor_parameter"].values, mu)
    )
    worst["w_eff"] = max(
        worst.get("w_eff", 0.0), _rel(ds["w_eff"].values, w_eff(work), floor=0.05 * work)
    )


def jkr_rows(fast: bool) -> list[dict]:
    """jkr: geometry by quadrature; the wall's outputs against the image solution."""
    works = (0.05, 0.2) if fast else (0.02, 0.05, 0.1, 0.2, 1.0)
    rng = 1e-9
    worst: dict[str, float] = {}
    for w in works:
        ds = _solve([1e3, 1e5], {"model": "jkr", "work_of_adhesion": f"{w} J/m**2"})
        z = ds["zeta"].values
        a_star = np.array([true_area(float(x)) for x in z])
        u_el = np.array([finer_energy(float(x)) for x in z])
        gam = np.maximum((w * true_area(ZETA_1) - u_el) / a_star, 0.0)
        sig = np.sqrt(gam * E_STAR * z * SPEC.q_L)  # c_a = 1 (the default)
        for name, want in (
            ("true_area_ratio", a_star),
            ("finer_scale_energy", u_el),
            ("gamma_eff", gam),
            ("sigma_a", sig),
        ):
            err = _rel(ds[name].values, want, floor=1e-3 * float(np.max(want)))
            worst[name] = max(worst.get(name, 0.0), err)
        _geometry_err(ds, w, rng, worst)
    out = [
        _row(
            f"{n} (jkr)",
            f"H 0.8, zeta 1-1e3, dgamma {works[0]}-{works[-1]} J/m^2 (gamma_eff clipped to 0 "
            "at the coarse scales)",
            "{cite:p}`persson2001adhesion,persson2006,derjaguin1975` by quad (this file)",
            worst[n],
            "rel",
        )
        for n in ("true_area_ratio", "finer_scale_energy", "gamma_eff", "sigma_a")
    ]
    out += _wall_rows(fast)
    out += _tabor_rows("jkr", worst, f"dgamma {works[0]}-{works[-1]} J/m^2, dr 1 nm")
    return out


def wall_exact(p0: float, s0: float, c: float, tau: float) -> tuple[float, float, float]:
    """Wall at -(s0 + c tau) (physics.md §2.2, exact): A, int p P dp, int sigma_a |dA|.

    The contact stress is the Gaussian partial first moment of the image solution; the
    detached stress is ``s0 - sigma_a A + c int_0^tau A`` (by parts, ``quad``): two paths, so
    their identity is a check. Reproduces the §2.2 check values (0.9185595730, 0.5217495952).
    """
    if tau <= 0:
        return 1.0, p0, 0.0
    y0, k, pw = p0 + s0, math.exp(-c * (p0 + s0)), -(s0 + c * tau)

    def area(t: float) -> float:
        sd = math.sqrt(2 * t)
        return 1.0 if t <= 0 else norm.cdf((y0 + c * t) / sd) - k * norm.cdf((c * t - y0) / sd)

    def moment(m: float) -> float:  # int_pw^inf p N(p; m, 2 tau) dp
        sd = math.sqrt(2 * tau)
        z = (pw - m) / sd
        return m * norm.sf(z) + sd * norm.pdf(z)

    a = area(tau)
    stress = moment(p0) - k * moment(-p0 - 2 * s0)
    lost = c * _int_area(area, tau) if c else 0.0
    return a, stress, s0 - (s0 + c * tau) * a + lost


def _int_area(area, tau: float) -> float:
    """int_0^tau A dt, over ln t below tau (A = 1 to 1e-300 below 1e-14 tau)."""
    lo = 1e-14 * tau
    f = lambda s: area(math.exp(s)) * math.exp(s)  # noqa: E731
    with warnings.catch_warnings():  # roundoff at 1e-10 where A is 1 - 1e-16 over decades
        warnings.simplefilter("ignore")
        return lo + quad(f, math.log(lo), math.log(tau), epsabs=0.0, epsrel=1e-10, limit=400)[0]


def _wall_rows(fast: bool) -> list[dict]:
    """Constant and linearly moving sigma_a tables against the exact image solutions."""
    s0 = 2e4
    tau1 = float(_tau(SPEC, [SPEC.q_1])[0])
    out, worst = [], {}
    for c in (0.0, 3 * s0 / tau1):
        loads = np.array([-0.5, 0.25, 2.5] if fast else [-0.9, -0.5, 0, 0.25, 1, 5]) * s0
        zt = np.array([1.0, math.sqrt(ZETA_1), ZETA_1])  # PCHIP in tau: exact for a linear law
        table = [f"{float(s0 + c * t)!r} Pa" for t in _tau(SPEC, zt * SPEC.q_L)]
        bnd = {"model": "jkr", "work_of_adhesion": "0.05 J/m**2"}
        ds = _solve(loads, {**bnd, "sigma_a": table, "sigma_a_zeta": [float(x) for x in zt]})
        tau = _tau(SPEC, ds["zeta"].values * SPEC.q_L)
        ref = np.array([[wall_exact(p, s0, c, t) for t in tau] for p in loads])
        scale = np.maximum(np.abs(loads), s0 + c * tau1)[:, None]
        got = {n: ds[n].transpose("p0", "zeta").values for n in _WALL[:3]}
        _up(worst, "detached_fraction", np.max(np.abs(got["detached_fraction"] - 1 + ref[..., 0])))
        _up(worst, "contact_stress", np.max(np.abs(got["contact_stress"] - ref[..., 1]) / scale))
        _up(worst, "detached_stress", np.max(np.abs(got["detached_stress"] - ref[..., 2]) / scale))
        actual = np.max(np.abs(got["contact_stress"] - ref[..., 1]) / scale, axis=1)
        claimed = ds["load_identity_residual"].values
        _up(worst, "load_identity_residual", np.max(np.abs(claimed - actual)))
        _up(worst, "claimed", np.max(claimed))
        _up(worst, "actual", np.max(actual))
        _up(worst, "pull_off_stress", abs(ds["pull_off_stress"].item() / s0 - 1))  # sigma_a(1)
    _up(worst, "pull_off_stress", _pull_off_err(s0, c, tau1))
    regime = (
        f"walls sigma_a = {s0:g} Pa + c tau, c tau_1/s0 0 and 3, p0/s0 "
        f"{loads[0] / s0:g}..{loads[-1] / s0:g} (tensile to compressive)"
    )
    ref = "exact image solution of the moving wall ({doc}`/theory/03_absorbing_wall`), tau by quad"
    notes = {
        "detached_fraction": "1 - A",
        "contact_stress": "Gaussian partial moment; relative to max(|p0|, sigma_a)",
        "detached_stress": "s0 - sigma_a A + c int A dtau (quad); relative to max(|p0|, sigma_a)",
        "pull_off_stress": "pull_off_area 0: sigma_a(1) = s0; 0.05: the root -p0 of exact "
        "A(zeta_1) = 0.05 (brentq; the plugin's own root has xtol 1e-6 s0, engine rtol 1e-4)",
        "load_identity_residual": f"its claim vs the actual error of contact_stress: claimed <= "
        f"{worst['claimed']:.2g}, actual <= {worst['actual']:.2g}",
    }
    for n in _WALL:
        measure = "rel" if n.endswith("stress") else "abs"
        out.append(_row(f"{n} (jkr)", regime, ref, worst[n], measure, notes[n]))
    return out


_WALL = (
    "detached_fraction",
    "contact_stress",
    "detached_stress",
    "load_identity_residual",
    "pull_off_stress",
)


def _pull_off_err(s0: float, c: float, tau1: float) -> float:
    """pull_off_area = 0.05 on the moving wall: -p0 where the exact A(zeta_1) = 0.05."""
    zt = np.array([1.0, math.sqrt(ZETA_1), ZETA_1])
    table = [f"{float(s0 + c * t)!r} Pa" for t in _tau(SPEC, zt * SPEC.q_L)]
    bnd = {"model": "jkr", "work_of_adhesion": "0.05 J/m**2", "pull_off_area": 0.05}
    ds = _solve([1e3], {**bnd, "sigma_a": table, "sigma_a_zeta": [float(x) for x in zt]})
    excess = lambda p: wall_exact(p, s0, c, tau1)[0] - 0.05  # noqa: E731
    want = -brentq(excess, -s0 * (1 - 1e-12), 0.0, xtol=1e-12 * s0) if excess(0.0) > 0 else 0.0
    return abs(ds["pull_off_stress"].item() - want) / s0


def _tabor_rows(model: str, worst: dict, regime: str) -> list[dict]:
    return [
        _row(
            f"tabor_parameter ({model})",
            regime,
            "[R dgamma^2/(E*^2 dr^3)]^(1/3), R from the half-octave band moment by quad",
            worst["tabor_parameter"],
            "rel",
        ),
        _row(
            f"w_eff ({model})",
            regime,
            "dgamma A*(zeta_1)/A0 - (pi E*/2) int q^2 C by quad",
            worst["w_eff"],
            "rel",
            "relative to max(|w_eff|, 0.05 dgamma)",
        ),
    ]


def _law(law: str, u: np.ndarray, w: float, rng: float) -> np.ndarray:
    """The traction-gap laws of physics.md §2.3, written here [Pa]."""
    if law == "exponential":
        return w / rng * np.exp(-u / rng)
    if law == "dugdale":
        return np.where(u <= rng, w / rng, 0.0)
    s = rng / (rng + u)
    return 8 * w / (3 * rng) * (s**3 - s**9)


def reference_p_att(law: str, p_rep, w: float, rng: float, fast: bool):
    """int sigma(u) rho(u) du at p_rep, rho the independent continuous gap mixture.

    Returns p_att [Pa] per load and Persson's mean separation at p_rep [m] (quadrature).
    """
    from verify_interface import mean_gap
    from verify_leakage import _expect, mixture

    panels, order = (6, 6) if fast else (24, 8)
    att, ugap = [], []
    for p in np.atleast_1d(np.asarray(p_rep, float)):
        mix = mixture(SPEC, float(p), panels=panels, order=order)
        dens = _expect(mix["u1"], mix["h"], rng**3, lambda u: _law(law, u, w, rng))
        att.append(float(np.sum(mix["weight"] * dens)))  # beyond u1 + 9 h: < e^-40
        ugap.append(mean_gap(SPEC, float(p)))
    return np.array(att), np.array(ugap)


def _dmt_cases(fast: bool):
    laws = ("exponential", "lj93") if fast else ("exponential", "dugdale", "lj93")
    # dr spans the finest-scale Tabor parameter 0.1-10 at dgamma 0.05 J/m^2 (2.1 at 50 nm)
    ranges = (50e-9, 1e-6) if fast else (10e-9, 50e-9, 200e-9, 1e-6)
    return [(law, 0.05, r) for law in laws for r in ranges]


def dmt_rows(fast: bool) -> list[dict]:
    """dmt: p_att by quadrature at p_rep, the identity p_rep = p0 + p_att, the diagnostics."""
    loads = [-5e2, 1e3, 1e5] if fast else [-5e2, -1e2, 1e3, 1e4, 1e5, 1e6]
    worst: dict[str, float] = {}
    tabors, where = [], {"p_att": "-", "p_att high": "-"}
    for law, w, rng in _dmt_cases(fast):
        bnd = {"model": "dmt", "law": law, "work_of_adhesion": f"{w} J/m**2", "range": f"{rng} m"}
        ds = _solve(loads, bnd)
        p0 = np.asarray(loads, float)
        prep, patt = ds["p_rep"].values, ds["p_att"].values
        ref, ugap = reference_p_att(law, prep, w, rng, fast)
        actual = np.abs(patt / ref - 1)
        est = ds["p_att_discretization_error"].values
        high = p0 >= 1e6  # the far tail of the gap distribution matters (see the row)
        for key, err in (
            ("p_att", np.max(actual[~high])),
            ("p_att high", np.max(actual[high], initial=0.0)),
        ):
            if err >= worst.get(key, 0.0):
                where[key] = f"{law}, dr {rng:g} m"
            _up(worst, key, float(err))
        actual, est = actual[~high], est[~high]
        _up(worst, "p_rep", float(np.max(np.abs(prep - p0 - ref) / prep)))
        _up(worst, "mean_gap", _rel(ds["mean_gap"].values, ugap))
        resid = np.abs(prep - p0 - patt) / prep
        _up(worst, "dmt_residual", float(np.max(np.abs(ds["dmt_residual"].values - resid))))
        ratio = np.maximum(actual, 1e-4) / np.maximum(est, 1e-4)
        _up(worst, "p_att_discretization_error", float(np.max(ratio)))
        _up(worst, "gap_quadrature_error", float(np.max(np.abs(ds["gap_quadrature_error"].values))))
        it = ds["dmt_iterations"].values
        _up(worst, "dmt_iterations", float(np.sum((it < 1) | (it != np.round(it)))))
        tabors.append(tabor(ZETA_1, w, rng))
        _geometry_err(ds, w, rng, worst)
    it0 = _solve([1e4], {"model": "dmt", "work_of_adhesion": "0 J/m**2"})["dmt_iterations"].values
    _up(worst, "dmt_iterations", float(np.sum(it0 != 1)))
    regime = (
        f"laws {'/'.join(sorted({c[0] for c in _dmt_cases(fast)}))}, Tabor(zeta_1) "
        f"{min(tabors):.2g}-{max(tabors):.2g}, p0 {loads[0]:g}..{min(loads[-1], 1e5):g} Pa"
    )
    ref = "sigma(u) over the continuous gap mixture at p_rep (verify_leakage.mixture; no gap code)"
    return [
        _row(
            "p_att (dmt)",
            regime,
            ref,
            worst["p_att"],
            "rel",
            f"worst at {where['p_att']}; the mixture is Almqvist's separation (the plugins'); "
            "see the 1e6 Pa row for the far tail",
        ),
        *(
            [
                _row(
                    "p_att (dmt), p0 1e6 Pa",
                    regime.split(", p0")[0] + ", p0 = 1e6 Pa (p0/E* 0.075, A/A0 0.3-0.5)",
                    ref,
                    worst["p_att high"],
                    "rel",
                    f"worst at {where['p_att high']}; at high load the plugin's detachment "
                    "bins on its own area curve and the continuous mixture differ (see 'Gap "
                    "PDF at high load' below); p_att is 1e-4 of p_rep there",
                )
            ]
            if not fast
            else []
        ),
        _row("p_rep (dmt)", regime, "p0 + the reference p_att(p_rep)", worst["p_rep"], "rel"),
        _row(
            "mean_gap (dmt)",
            regime,
            "exponential-integral mean gap at p_rep by quad (verify_interface.mean_gap)",
            worst["mean_gap"],
            "rel",
        ),
        _row(
            "dmt_residual",
            regime,
            "|p_rep - p0 - p_att| / p_rep recomputed from the Dataset",
            worst["dmt_residual"],
            "abs",
        ),
        _row(
            "p_att_discretization_error",
            regime,
            "the actual error |p_att/reference - 1| (as in the p_att row)",
            worst["p_att_discretization_error"],
            "actual/estimate",
            "floors 1e-4; where the magnification sampling dominates (short range) the estimate"
            " is the error's order (within 2.2x); it does not see the far-tail difference of "
            "long-range laws at high load (dr 1 um, 1e5 Pa: 6.7e-4 vs 4e-5)",
        ),
        _row(
            "gap_quadrature_error",
            regime,
            "exact mass 1 - A (closed-form bins: 0)",
            worst["gap_quadrature_error"],
            "abs",
        ),
        _row(
            "dmt_iterations",
            regime + "; dgamma 0",
            "integer >= 1; exactly 1 without adhesion",
            worst["dmt_iterations"],
            "count",
            "violations counted",
        ),
        *_tabor_rows("dmt", worst, regime),
    ]


def _up(worst: dict, name: str, err: float) -> None:
    worst[name] = max(worst.get(name, 0.0), float(err))


def rows(fast: bool) -> list[dict]:
    """Every row of this module."""
    import verify_adhesive

    return jkr_rows(fast) + dmt_rows(fast) + verify_adhesive.rows(fast)


if __name__ == "__main__":
    import sys

    for r in rows("--fast" in sys.argv):
        print(f"{r['output']:36s} {r['worst']:10.3g} {r['measure']:8s} {r['note']}")
