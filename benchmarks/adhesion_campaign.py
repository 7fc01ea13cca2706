"""The adhesive part of the validation campaign (``benchmarks/campaign.py``).

Theory: the ``adhesive`` boundary (exponential law, range ``0.1 h_rms``), the work of adhesion
set so that the plugin's finest-scale Tabor parameter is the design's target; loads: four
compressive ones of the campaign's grid and half the theory's pull-off (tensile).
BEM: :func:`xpersson.bem.solve_gaps` with the same law, approach from a mean gap of
``2.4 h_rms`` until the largest compressive load is exceeded, then retraction in steps of
``0.05 h_rms`` until the contact is lost; the retraction branch down to its most tensile mean
stress (pull-off under load control) is the reference: the area there is interpolated at the
theory's loads, the pull-off is ``-min p``. A non-converged gap step ends the path there (the
points beyond are not compared).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

E_STAR = 1e6
SLOPE = 0.1
Q_L = 2 * math.pi / 1e-4
COMPRESSIVE = np.geomspace(0.002, 0.25, 6)[:4]  # p0 / (E* h'_rms)


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


def bem_path(h: np.ndarray, work: float, rng: float, h_rms: float) -> dict:
    """Approach to ``0.3 h_rms`` then retraction to ``2.3 h_rms`` (gap control, one solver:
    each step starts from the previous state): the retraction states up to the most tensile."""
    from xpersson import bem

    L = 2 * math.pi / Q_L
    approach = [g * h_rms for g in np.arange(2.4, 0.29, -0.15)]
    retract = [approach[-1] + k * 0.05 * h_rms for k in range(1, 41)]
    states = bem.solve_gaps(h, L, E_STAR, approach + retract, work=work, rho=rng, strict=False)
    if not all(st.converged for st in states[: len(approach)]):
        return {"converged": False}
    p, a = [states[len(approach) - 1].p0], [states[len(approach) - 1].area_fraction]
    for st in states[len(approach) :]:
        if not st.converged:
            break
        p.append(st.p0)
        a.append(st.area_fraction)
        if st.area_fraction == 0.0:
            break
    if len(p) < 3:
        return {"converged": False}
    k = int(np.argmin(p))
    return {"converged": True, "p": p[: k + 1], "area": a[: k + 1], "pull_off": max(-min(p), 0.0)}


def _area_at(path: dict, loads: np.ndarray) -> list[float]:
    """Area on the retraction branch at ``loads`` [Pa] (NaN outside the branch)."""
    if not path.get("converged"):
        return [math.nan] * len(loads)
    p = np.asarray(path["p"])[::-1]
    a = np.asarray(path["area"])[::-1]
    order = np.argsort(p)
    p, a = p[order], a[order]
    return [float(np.interp(x, p, a)) if p[0] <= x <= p[-1] else math.nan for x in loads]


def adhesive_record(
    sc: dict[str, Any], maps: np.ndarray, base: Callable, solve: Callable
) -> dict[str, Any]:
    """The adhesive scene's record: theory and BEM (area per load, pull-off)."""
    from xpersson.scene import Scene

    h_rms = float(Scene(base(sc, np.array([1.0]))).resolve().psd.h_rms())
    rng = 0.1 * h_rms
    work = tuned_work(sc, h_rms, base, solve)
    comp = COMPRESSIVE * E_STAR * SLOPE
    ds = _theory(sc, comp, work, rng, base, solve)
    pull = float(ds["pull_off_stress"].values)
    loads = np.concatenate(([-0.5 * pull], comp)) if pull > 0 else comp
    ds = _theory(sc, loads, work, rng, base, solve)
    theory = {
        "area_fraction": ds["area_fraction"].isel(zeta=-1).values.tolist(),
        "pull_off_stress": pull,
        "tabor": float(ds["tabor_parameter"].values[-1]),
        "regime": ds["regime"].values.tolist(),
    }
    areas, pulls = [], []
    for h in maps:
        path = bem_path(h, work, rng, h_rms)
        areas.append(_area_at(path, loads))
        pulls.append(path.get("pull_off", math.nan))
    a = np.asarray(areas, float)
    n = a.shape[0]
    return {
        "p0": loads.tolist(),
        "work": work,
        "range": rng,
        "theory": theory,
        "bem": {
            "area_fraction": {
                "mean": a.mean(axis=0).tolist(),
                "se": (a.std(axis=0, ddof=1) / math.sqrt(n)).tolist() if n > 1 else None,
            },
            "pull_off_stress": {"mean": float(np.mean(pulls)), "values": pulls},
        },
    }
