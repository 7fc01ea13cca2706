"""One realisation of a cross-check (synthesise, solve every load), and running N of them
serially or on dask (the same numbers either way: realisation ``i`` is seeded ``[seed, i]``).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ._surfaces import band_limited
from .derived import adhesive_path, gap_pdf, retraction_branch, stiffness
from .solve import solve
from .synthesis import map_moments, synthesise

__all__ = ["Task", "realise", "run_all"]


class Task:
    """Everything one realisation needs, picklable (SI floats and arrays)."""

    def __init__(self, plan: Any, index: int, gap_edges: np.ndarray | None) -> None:
        from ._plan import STIFFNESS_STEP

        self.psd = plan.psd
        self.L, self.n, self.seed, self.index = plan.L, plan.grid, plan.seed, index
        self.q_L, self.q_max = plan.q_L, plan.q_max
        self.E_star, self.p0, self.kind = plan.E_star, plan.p0, plan.kind
        self.hardness, self.work, self.rho = plan.hardness, plan.work, plan.rho
        self.step = STIFFNESS_STEP
        self.gap_edges = gap_edges
        src = plan.source
        self.q_min = plan.q_L if src is None else src.q_min
        self.map = None if src is None or src.kind != "map" else src.heights
        self.q_cut = None if src is None else src.q_cut
        self.grid_check = bool(plan.grid_check)


def _surface(t: Task) -> np.ndarray:
    """Realisation ``t.index``: the measured map (index 0 of a map source), band-limited to
    the grid's band, or a synthesis seeded ``[seed, index]``."""
    if t.map is not None and t.index == 0:
        return band_limited(t.map, t.n, t.L, t.q_cut, t.q_max)
    return synthesise(t.psd.C, t.L, t.n, seed=t.seed, first=t.index, q_min=t.q_min, q_max=t.q_max)[
        0
    ]


def _pressure_controlled(t: Task, h: np.ndarray) -> dict[str, np.ndarray]:
    """Area, mean gap, stiffness, gap pdf, plastic area and pressure moments per load."""
    keys = ("area_fraction", "mean_gap", "contact_stiffness", "plastic_area_fraction",
            "pressure_m2", "pressure_max", "gap_contact_weight", "bem_error")  # fmt: skip
    out: dict[str, Any] = {k: np.full(t.p0.size, np.nan) for k in keys}
    out["converged"] = np.zeros(t.p0.size, dtype=bool)
    out["full_contact"] = np.zeros(t.p0.size, dtype=bool)
    ne = 0 if t.gap_edges is None else t.gap_edges.size - 1
    out["gap_pdf"] = np.full((t.p0.size, ne), np.nan)
    f = math.exp(t.step)
    for j, p in enumerate(t.p0):
        lo, mid, hi = solve(h, t.L, t.E_star, [p / f, p, p * f], hardness=t.hardness,
                            strict=False, keep_fields=True)  # fmt: skip
        ok = lo.converged and mid.converged and hi.converged
        out["converged"][j] = ok
        out["bem_error"][j] = max(lo.error, mid.error, hi.error)
        if not ok:  # a non-converged solve is never a reference value
            continue
        out["area_fraction"][j] = mid.area_fraction
        out["gap_contact_weight"][j] = mid.area_fraction
        out["full_contact"][j] = hi.area_fraction >= 1.0
        if hi.area_fraction >= 1.0:  # rigid in the BEM: no gap, stiffness or conductance
            continue
        out["mean_gap"][j] = mid.mean_gap
        out["contact_stiffness"][j] = stiffness(lo.p0, hi.p0, lo.mean_gap, hi.mean_gap)
        out["plastic_area_fraction"][j] = mid.plastic_area_fraction
        out["pressure_m2"][j] = mid.pressure_m2
        out["pressure_max"][j] = mid.pressure_max
        if ne:
            out["gap_pdf"][j] = gap_pdf(mid.gap, mid.contact, t.gap_edges)
    return out


def _adhesive(t: Task, h: np.ndarray) -> dict[str, np.ndarray]:
    """Area on the stable retraction branch at the loads, and the pull-off stress."""
    path = adhesive_path(h, t.L, t.E_star, t.work, t.rho, p_max=float(t.p0.max()), strict=False)
    retract = path["retract"]
    p = np.array([s.p0 for s in retract])
    # the reference is the retraction (from the deepest approach state) up to its most
    # tensile state: every solve there must have converged (the approach before it is the
    # warm-up; states past the pull-off are not used)
    used = retract[: int(np.nanargmin(p)) + 1] if np.isfinite(p).any() else retract
    ok = all(s.converged for s in used)
    area, pull = retraction_branch(retract, t.p0)
    return {
        "area_fraction": area if ok else np.full(t.p0.size, np.nan),
        "pull_off_stress": np.array(pull if ok else np.nan),
        "converged": np.array(ok),
        "bem_error": np.array(max(s.error for s in used)),
        "path_steps": np.array(len(path["approach"]) + len(retract)),
    }


def _solve_map(t: Task, h: np.ndarray) -> dict[str, Any]:
    out = _adhesive(t, h) if t.kind == "adhesive" else _pressure_controlled(t, h)
    out["h_rms"], out["rms_slope"] = (np.array(v) for v in map_moments(h, t.L))
    return out


def realise(t: Task) -> dict[str, Any]:
    """Make realisation ``t.index`` and solve it at every load (SI arrays); with the grid
    check, solve the same surface (exactly interpolated: it is band-limited) on a grid twice
    as fine too, under the key ``"fine"``."""
    h = _surface(t)
    out = _solve_map(t, h)
    if t.grid_check:
        out["fine"] = _solve_map(t, band_limited(h, 2 * t.n, t.L))
    return out


def run_all(tasks: list[Task], scheduler: Any = None) -> list[dict[str, np.ndarray]]:
    """Run the realisations: serially (``None``/``"serial"``), with ``dask.compute`` on a
    local scheduler (``"threads"``, ``"processes"``, ``"synchronous"``), or on a
    ``distributed.Client`` / scheduler address. Results are in realisation order."""
    if scheduler in (None, "serial"):
        return [realise(t) for t in tasks]
    if isinstance(scheduler, str) and scheduler in ("threads", "processes", "synchronous"):
        import dask

        return list(dask.compute(*[dask.delayed(realise)(t) for t in tasks],
                                 scheduler=scheduler))  # fmt: skip
    if isinstance(scheduler, str) and ":" not in scheduler:
        raise ValueError(
            f"scheduler: {scheduler!r} is not allowed; one of None/'serial', 'threads', "
            "'processes', 'synchronous', a scheduler address 'tcp://host:port' or a Client"
        )
    from distributed import Client

    client = scheduler if isinstance(scheduler, Client) else Client(scheduler)
    try:
        return list(client.gather(client.map(realise, tasks, pure=False)))
    finally:
        if client is not scheduler:
            client.close()
