"""Verification rows of the ``adhesive`` boundary's own outputs (the scaled mean field).

Part of ``verify_boundaries.py`` (same references, written from physics.md §2): ``p_att`` as
``ATTRACTION_SCALE`` (the documented constant, written here) times the exponential law over
the independent continuous gap mixture at ``p_rep`` (``verify_boundaries.reference_p_att``),
the ratio and the regime code from their definitions, and the small-load ratio from the
reference at light load. (How far the model is from exact contact is part II of
docs/verification.md: the validation campaign, ``campaign.py``.)
"""

from __future__ import annotations

import math

import numpy as np
from verify_boundaries import (
    SPEC,
    ZETA_1,
    _geometry_err,
    _moment,
    _rel,
    _row,
    _solve,
    _tabor_rows,
    _tau,
    _up,
    finer_energy,
    reference_p_att,
    tabor,
    true_area,
)

#: adhesive's calibration constants as documented (docs/adhesion_bem.md, the VarSpecs)
ATTRACTION_SCALE = 0.85
CALIBRATED_TABOR = (0.1, 1.0)


def rows(fast: bool) -> list[dict]:
    """adhesive: ATTRACTION_SCALE x the reference p_att at p_rep, its ratio, regime, factor."""
    loads = [-50.0, 1e3, 1e5] if fast else [-200.0, -50.0, 1e3, 1e4, 1e5, 1e6]
    ranges = (50e-9, 1e-6) if fast else (10e-9, 50e-9, 200e-9, 1e-6)
    w = 0.05
    worst: dict[str, float] = {}
    tabors, skipped = [], 0
    for rng in ranges:
        bnd = {"model": "adhesive", "work_of_adhesion": f"{w} J/m**2", "range": f"{rng} m"}
        ds = _solve(loads, bnd)
        p0 = np.asarray(loads, float)
        prep, patt = ds["p_rep"].values, ds["p_att"].values
        code = ds["regime"].values
        mean_field = code != 4  # regime 4: the floor (highest bumps) carries the load
        skipped += int(np.sum(~mean_field))
        ref = ATTRACTION_SCALE * reference_p_att("exponential", prep, w, rng, fast)[0]
        tail = ref / prep < 1e-3  # the table's interpolation where p_att is negligible
        keep = mean_field & ~tail
        rel = np.abs(patt / ref - 1)
        _up(worst, "p_att", float(np.max(rel[keep], initial=0.0)))
        _up(worst, "tail rel", float(np.max(rel[tail], initial=0.0)))
        _up(worst, "tail", float(np.max(np.abs(patt - ref)[tail] / prep[tail], initial=0.0)))
        _up(worst, "p_rep", float(np.max(np.abs(prep - p0 - patt) / prep)))
        got = ds["adhesion_ratio"].values
        _up(worst, "adhesion_ratio", float(np.max(np.abs(got / (ref / prep) - 1)[keep])))
        mu1 = tabor(ZETA_1, w, rng)
        tabors.append(mu1)
        lo, hi = CALIBRATED_TABOR
        scene = 1 if mu1 < lo else (3 if mu1 > hi else 2)
        want = np.where(ref / prep < 0.1, 0, scene)
        _up(worst, "regime", float(np.sum((code != want) & mean_field)))
        p_small = np.array([1e-3, 3e-3]) * math.sqrt(float(_tau(SPEC, [SPEC.q_1])[0]))
        small = ATTRACTION_SCALE * reference_p_att("exponential", p_small, w, rng, fast)[0]
        _up(worst, "small_load_ratio", _rel(ds["small_load_ratio"].values, small[0] / p_small[0]))
        _geometry_err(ds, w, rng, worst)
    regime = (
        f"exponential law, Tabor(zeta_1) {min(tabors):.2g}-{max(tabors):.2g}, "
        f"p0 {loads[0]:g}..{loads[-1]:g} Pa"
    )
    ref = f"{ATTRACTION_SCALE} x sigma(u) over the continuous gap mixture at p_rep (this file)"
    return [
        _row(
            "p_att (adhesive)",
            regime,
            ref,
            worst["p_att"],
            "rel",
            f"mean-field loads with p_att/p_rep >= 1e-3 ({skipped} floor loads, regime 4, "
            "left out; the tail in the next row)",
        ),
        *(
            [
                _row(
                    "p_att (adhesive), tail",
                    regime + " where p_att/p_rep < 1e-3 (p0 1e6 Pa)",
                    ref,
                    worst["tail"],
                    "abs / p_rep",
                    f"relative error up to {worst['tail rel']:.2g}: the mean-field table "
                    "interpolates a p_att of 1e-5 p_rep (it depends on the load set); p_rep "
                    "unaffected at this level",
                )
            ]
            if worst["tail rel"] > 0
            else []
        ),
        _row("p_rep (adhesive)", regime, "p0 + p_att (identity)", worst["p_rep"], "rel"),
        _row(
            "adhesion_ratio (adhesive)",
            regime,
            "reference p_att / p_rep",
            worst["adhesion_ratio"],
            "rel",
        ),
        _row(
            "regime (adhesive)",
            regime,
            "its definition: 0 if p_att/p_rep < 0.1, else 1/2/3 by Tabor(zeta_1) vs 0.1, 1.0",
            worst["regime"],
            "count",
            "mismatching loads counted",
        ),
        _row(
            "small_load_ratio (adhesive)",
            regime,
            "reference p_att(p)/p at p = 1e-3 sqrt(tau_1) (3e-3: converged to the row's worst)",
            worst["small_load_ratio"],
            "rel",
            "the limit against the reference at the lightest loads",
        ),
        _floor_row(fast),
        *_tabor_rows("adhesive", worst, regime),
    ]


#: adhesive's floor constant (bumps holding at pull-off): a fitted model constant, not code, so
#: the reference takes the plugin's (refitted 2.7 -> 1.25 on 2026-11-29, docs/adhesion_bem.md;
#: the reference kept 2.7 until a full run of this matrix showed the floor 0.46x "off")
from xpersson_adhesion._bump import BUMPS  # noqa: E402


def floor_reference(work: float, n: int) -> float:
    """``BUMPS max_zeta 2 pi gamma_eff(zeta) R(zeta) / L^2`` [Pa] by quadrature (physics.md §2.1).

    ``gamma_eff = (w A*(zeta_1) - U_el(zeta)) / A*(zeta)``, ``R^-2 = 2 pi int_{q_L}^{zeta q_L}
    q^5 C dq``, ``L = 2 pi/q_L``, over the scales with ``sqrt(2 R h_f) <= pi/(2 zeta q_L)``
    (``h_f^2 = 2 pi int_{zeta q_L}^{q_1} q C dq``); the maximum over ``n`` log-spaced
    magnifications from 2 to ``zeta_1``, refined by a bounded scalar search around the best one.
    """
    from scipy.optimize import minimize_scalar

    a1 = true_area(ZETA_1)

    def force(lnz: float) -> float:
        z = math.exp(lnz)
        gamma = max((work * a1 - finer_energy(z)) / true_area(z), 0.0)
        radius = 1.0 / math.sqrt(2 * math.pi * _moment(5, SPEC.q_L, z * SPEC.q_L))
        h_f = math.sqrt(2 * math.pi * _moment(1, z * SPEC.q_L, SPEC.q_1))
        if math.sqrt(2 * radius * h_f) > math.pi / (2 * z * SPEC.q_L):
            return 0.0  # the interaction zone does not fit the bump (Derjaguin)
        return 2 * math.pi * gamma * radius

    grid = np.linspace(math.log(2.0), math.log(ZETA_1), n)
    vals = [force(x) for x in grid]
    i = int(np.argmax(vals))
    lo, hi = grid[max(i - 1, 0)], grid[min(i + 1, n - 1)]
    best = max(vals[i], -minimize_scalar(lambda x: -force(x), bounds=(lo, hi)).fun)
    return BUMPS * best * (SPEC.q_L / (2 * math.pi)) ** 2


def _floor_row(fast: bool) -> dict:
    """floor_stress where the mean field holds no tension (there it is the floor's pull-off);
    0 where the mean field's own pull-off is the larger (the sticky scenes)."""
    works = (1e-3, 0.01, 0.1) if fast else (1e-4, 1e-3, 3e-3, 0.01, 0.03, 0.1)
    worst, sticky_bad, n_ok = 0.0, 0, 0
    for w in works:
        for rng in (50e-9, 1e-6):
            bnd = {"model": "adhesive", "work_of_adhesion": f"{w} J/m**2", "range": f"{rng} m"}
            ds = _solve([1e3], bnd)
            d, pull = float(ds["floor_stress"]), float(ds["pull_off_stress"])
            ref = floor_reference(w, 24 if fast else 96)
            if d > 0 and abs(d - pull) <= 1e-6 * pull:  # mean field holds ~nothing: d = P_f
                worst = max(worst, abs(d / ref - 1))
                n_ok += 1
            elif pull > ref * (1 + 1e-3):  # the mean field holds more: no extra attraction
                sticky_bad += d != 0.0
    return _row(
        "floor_stress (adhesive)",
        f"SPEC scene, work {works[0]:g}-{works[-1]:g} J/m^2, range 50 nm and 1 um "
        f"({n_ok} non-sticky scenes)",
        "BUMPS max_zeta 2 pi gamma_eff R / L^2 by quadrature of C "
        "({cite:p}`persson2001adhesion,persson2006`, this file)",
        worst if n_ok else math.nan,
        "rel",
        f"the plugin scans 48 magnifications; sticky scenes with d != 0: {sticky_bad}",
    )
