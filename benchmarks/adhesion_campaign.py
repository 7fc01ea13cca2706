"""The adhesive part of the validation campaign (``benchmarks/campaign.py``,
``benchmarks/campaign_adhesive.py``).

Theory: the ``adhesive`` boundary (exponential law, range ``0.1 h_rms``), the work of adhesion
set so that the plugin's finest-scale Tabor parameter is the design's target; loads: the light
loads ``p0/(E* h'_rms)`` 2e-4, 5e-4 and 1e-3 (below the old calibration), four compressive ones
of the campaign's grid, and half the theory's pull-off (tensile).

BEM: :class:`xpersson.bem.GapSolver` with the same law, approach from a mean gap of
``2.4 h_rms`` in steps of ``0.15 h_rms`` (``0.05 h_rms`` below ``0.3 h_rms``) until the largest
compressive load is exceeded, then retraction in steps of ``0.05 h_rms`` until the contact is
lost or the stress has come back from its most tensile value to half of it. The retraction
branch down to its most tensile mean stress (pull-off under load control) is the reference: it
is stored per realisation (``bem.branches``), the area is interpolated on it at the theory's
loads and the pull-off is ``-min p``. Only converged solves are kept: a non-converged step is
dropped (the path continues from it), two in a row end the path there; a realisation whose
approach never reached the largest load, or whose branch holds fewer than 3 states, has no
reference (NaN). A scene whose cohesive zone ``E* rho^2 / w`` (Maugis) is below one grid
spacing is not solved at all (``excluded``): the BEM cannot resolve its adhesion
(:mod:`xpersson.bem` refuses such a cross-check), so it is no reference.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

E_STAR = 1e6
SLOPE = 0.1
Q_L = 2 * math.pi / 1e-4
#: compressive loads p0 / (E* h'_rms): the light loads of issue 34, then the campaign's grid
COMPRESSIVE = np.concatenate(([2e-4, 5e-4, 1e-3], np.geomspace(0.002, 0.25, 6)[:4]))
#: grid spacings the cohesive zone must span for a BEM reference (xpersson.bem refuses < 1)
MIN_ZONE_PIXELS = 1.0


def _theory(
    sc: dict[str, Any], p0: np.ndarray, work: float, rng: float, base: Callable, solve: Callable
) -> Any:
    scene = base(sc, p0)
    scene["boundary"] = {
        "model": "adhesive",
        "work_of_adhesion": f"{float(work)!r} J/m^2",
        "range": f"{float(rng)!r} m",
    }
    return solve(scene)


def tuned_work(sc: dict[str, Any], h_rms: float, base: Callable, solve: Callable) -> float:
    """Work of adhesion [J/m^2] giving the design's finest-scale Tabor parameter."""
    rng = 0.1 * h_rms
    p0 = COMPRESSIVE[-1:] * E_STAR * SLOPE
    work = 1e-4
    for _ in range(3):  # mu ~ w^(2/3): converges in a step or two
        mu = float(_theory(sc, p0, work, rng, base, solve)["tabor_parameter"].values[-1])
        work *= (sc["tabor"] / mu) ** 1.5
    return work


def _approach(path: Any, h_rms: float, p_max: float) -> tuple[list, float] | None:
    """Gap-controlled approach until the mean stress exceeds ``1.1 p_max`` [Pa]; the states
    and the last gap [m] (None: not reached with converged solves)."""
    gaps = [g * h_rms for g in np.arange(2.4, 0.29, -0.15)]
    gaps += [g * h_rms for g in np.arange(0.25, 0.0, -0.05)]
    last = None
    for g in gaps:
        st = path.at(g)
        if st.converged:
            last = (st, g)
            if st.p0 > 1.1 * p_max:
                return last
    return None


def bem_path(h: np.ndarray, work: float, rng: float, h_rms: float, p_max: float) -> dict:
    """Approach then retraction (gap control, one solver: each step starts from the previous
    state): the converged retraction states up to the most tensile."""
    from xpersson import bem

    L = 2 * math.pi / Q_L
    path = bem.GapSolver(h, L, E_STAR, work=work, rho=rng, strict=False)
    start = _approach(path, h_rms, p_max)
    if start is None:
        return {"converged": False}
    st, g0 = start
    p, a, misses = [st.p0], [st.area_fraction], 0
    for k in range(1, 61):
        st = path.at(g0 + k * 0.05 * h_rms)
        if not st.converged:
            misses += 1
            if misses == 2:
                break
            continue
        misses = 0
        p.append(st.p0)
        a.append(st.area_fraction)
        if st.area_fraction == 0.0 or (min(p) < 0 and st.p0 > 0.5 * min(p)):
            break
    if len(p) < 3:
        return {"converged": False}
    k = int(np.argmin(p))
    return {"converged": True, "p": p[: k + 1], "area": a[: k + 1], "pull_off": max(-min(p), 0.0)}


def area_at(branch: dict, loads: np.ndarray) -> list[float]:
    """Area on the retraction branch at ``loads`` [Pa] (0 beyond its pull-off, NaN above it)."""
    if not branch.get("converged"):
        return [math.nan] * len(loads)
    p = np.asarray(branch["p"])[::-1]
    a = np.asarray(branch["area"])[::-1]
    order = np.argsort(p)
    p, a = p[order], a[order]
    # below the most tensile stress the BEM cell has detached (area 0); above the deepest
    # approach state it is unknown (NaN)
    return [
        float(np.interp(x, p, a)) if p[0] <= x <= p[-1] else (0.0 if x < p[0] else math.nan)
        for x in loads
    ]


def zone_pixels(work: float, rng: float, grid: int) -> float:
    """Maugis' cohesive zone ``E* rho^2 / w`` in grid spacings of the ``grid^2`` cell [1]."""
    return E_STAR * rng**2 / work / (2 * math.pi / Q_L / grid)


def theory_side(
    sc: dict[str, Any], work: float, rng: float, base: Callable, solve: Callable
) -> tuple[np.ndarray, dict[str, Any]]:
    """The theory's loads [Pa] (compressive, and half its pull-off when it holds tension) and
    outputs there."""
    comp = COMPRESSIVE * E_STAR * SLOPE
    ds = _theory(sc, comp, work, rng, base, solve)
    pull = float(ds["pull_off_stress"].values)
    loads = np.concatenate(([-0.5 * pull], comp)) if pull > 0 else comp
    ds = _theory(sc, loads, work, rng, base, solve)
    return loads, {
        "area_fraction": ds["area_fraction"].isel(zeta=-1).values.tolist(),
        "pull_off_stress": pull,
        "tabor": float(ds["tabor_parameter"].values[-1]),
        "regime": ds["regime"].values.tolist(),
    }


def bem_side(branches: list[dict], loads: np.ndarray) -> dict[str, Any]:
    """The BEM reference at ``loads`` [Pa] from the stored retraction branches."""
    a = np.asarray([area_at(b, loads) for b in branches], float)
    pulls = [b.get("pull_off", math.nan) if b.get("converged") else math.nan for b in branches]
    n = a.shape[0]
    return {
        "area_fraction": {
            "mean": a.mean(axis=0).tolist(),
            "se": (a.std(axis=0, ddof=1) / math.sqrt(n)).tolist() if n > 1 else None,
        },
        "pull_off_stress": {"mean": float(np.mean(pulls)), "values": pulls},
        "branches": branches,
    }


def adhesive_record(
    sc: dict[str, Any], maps: np.ndarray, base: Callable, solve: Callable
) -> dict[str, Any]:
    """The adhesive scene's record: theory and BEM (area per load, pull-off)."""
    from xpersson.scene import Scene

    h_rms = float(Scene(base(sc, np.array([1.0]))).resolve().psd.h_rms())
    rng = 0.1 * h_rms
    work = tuned_work(sc, h_rms, base, solve)
    loads, theory = theory_side(sc, work, rng, base, solve)
    zone = zone_pixels(work, rng, maps.shape[-1])
    rec = {"p0": loads.tolist(), "work": work, "range": rng, "zone_pixels": zone}
    if zone < MIN_ZONE_PIXELS:
        branches = [{"converged": False}] * len(maps)
        rec["excluded"] = "cohesive zone below one grid spacing: the BEM cannot resolve it"
    else:
        p_max = float(COMPRESSIVE[-1] * E_STAR * SLOPE)
        branches = [bem_path(h, work, rng, h_rms, p_max) for h in maps]
    return {**rec, "theory": theory, "bem": bem_side(branches, loads)}


def elastic_areas(maps: np.ndarray, loads: np.ndarray) -> dict[str, list[float]]:
    """The non-adhesive BEM area on the same maps at compressive ``loads`` [Pa] (mean, se over
    the maps; NaN where a solve did not converge): the denominator of the enhancement."""
    from xpersson import bem

    L = 2 * math.pi / Q_L
    rows = []
    for h in maps:
        states = bem.solve(h, L, E_STAR, loads, strict=False)
        rows.append([s.area_fraction if s.converged else math.nan for s in states])
    a = np.asarray(rows, float)
    se = a.std(axis=0, ddof=1) / math.sqrt(a.shape[0]) if a.shape[0] > 1 else a[0] * math.nan
    return {"mean": a.mean(axis=0).tolist(), "se": se.tolist()}
