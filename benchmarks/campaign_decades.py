"""Exact/theory against the number of decades of roughness: the trend, its uncertainty, the
bands along it and their extrapolation beyond the campaign's cells (used by
``campaign_report.py``).

The campaign's cells hold ``log10(q_1/q_r)`` = 0.6-1.2 decades at 128^2 and up to 1.8 / 2.1
decades at 512^2 / 1024^2 (8 grid points per shortest wavelength). Per output and regime:

* **trend**: ordinary least squares of the per-scene mean of ``ln(exact/theory)`` (over the
  scene's points in the regime: the loads of one scene are not independent draws) against the
  scene's decades; the slope ``b`` per decade, its standard error ``se`` (``n_scenes - 2``
  degrees of freedom), ``k`` the two-sided 95 % Student quantile. Also reported with the
  roll-off (0/1) as a second regressor (decades and roll-off are partly confounded on one
  grid).
* **band along the trend**: the 90 %/95 % tolerance interval of the detrended ratios
  ``ln r - b (d - d_ref)`` (``campaign_report.tolerance_band``), so that at ``d`` the band is
  ``[low, high] exp(b (d - d_ref))``; beyond the covered decades widened by ``k se`` per
  decade of distance (status ``extrapolated``).
* **extrapolation check**: the same bands fitted on the calibration points of the 128^2 cells
  only (0.6-1.2 decades), tested on every point with more decades (any split: none of them was
  seen by that fit). Where at least :data:`MIN_CHECK` such points exist and >= 90 % lie in
  their extrapolated band, the packaged table may extrapolate that output as far beyond its
  covered decades as the check did (``max d_test - 1.2``); elsewhere it does not (not
  verified beyond the covered decades).
* **large-cell test** (:func:`large_cell_test`): the verified band beyond 1.2 decades must
  hold >= 90 % of the large cells' own held-out and new-seed points; otherwise that output
  keeps only the 128^2 cells' band (not verified beyond 1.2 decades).
* **confirmation** (:func:`confirm`): the table's own extrapolated band must also hold >= 90 %
  of the held-out and new-seed points beyond the table's calibration decades, where there are
  any; otherwise that output is not extrapolated either.
"""

from __future__ import annotations

import math
from collections import defaultdict
from typing import Any

import numpy as np

#: The packaged table's bands follow a trend only where the calibration cells span this many
#: decades (the large cells: 0.6-1.8); on the 128^2 cells alone (0.6 decade, the constant-
#: hardness and adhesive scenes) the slope is not determined (e.g. 1.9 +- 2.7 per decade for
#: the plastic area), and the band stays constant, as it was, with no extrapolation.
MIN_SPAN = 0.9
#: Points an output needs beyond the check's decades for its extrapolation to be tested.
MIN_CHECK = 10
#: The check fits on cells up to this many decades (the 128^2 campaign: 1.204).
CHECK_FIT_MAX = 1.21
COVERAGE = 0.9
#: Barber's analogy: the constriction conductances are c K, so their ratio is the stiffness's
CONDUCTANCES = ("electrical_constriction_conductance", "thermal_constriction_conductance")


def per_scene(pts: list[dict[str, Any]]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(decades, roll-off, mean ln r)`` per scene of ``pts``."""
    by: dict[str, list[dict[str, Any]]] = defaultdict(list)
    for p in pts:
        if p["ratio"] > 0:  # an adhesive BEM value of 0 (a coverage miss) has no logarithm
            by[p["id"]].append(p)
    d = np.array([v[0]["decades"] for v in by.values()])
    roll = np.array([v[0]["rolloff"] for v in by.values()])
    y = np.array([np.mean([math.log(p["ratio"]) for p in v]) for v in by.values()])
    return d, roll, y


def ols(x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray, int]:
    """Coefficients, their standard errors and the residual degrees of freedom of ``y ~ x``."""
    dof = x.shape[0] - x.shape[1]
    coef, *_ = np.linalg.lstsq(x, y, rcond=None)
    s2 = float(np.sum((y - x @ coef) ** 2)) / dof
    cov = s2 * np.linalg.inv(x.T @ x)
    return coef, np.sqrt(np.diag(cov)), dof


def fit_trend(
    pts: list[dict[str, Any]], rolloff: bool = True, min_span: float = 0.25
) -> dict[str, Any] | None:
    """The slope of ``ln(exact/theory)`` per decade over ``pts``, with the roll-off (0/1) as a
    second regressor where the scenes identify it and ``rolloff`` (None: fewer than 4 scenes
    or less than ``min_span`` decades between them)."""
    from scipy.stats import t as student

    d, roll, y = per_scene(pts)
    if d.size < 4 or np.ptp(d) < min_span:
        return None
    ref, roll_ref = float(d.mean()), float(roll.mean())
    cols = [np.ones_like(d), d - ref]
    with_roll = rolloff and d.size >= 5 and np.ptp(roll) > 0
    if with_roll:
        cols.append(roll - roll_ref)
        with_roll = np.linalg.matrix_rank(np.column_stack(cols)) == 3
        cols = cols if with_roll else cols[:2]
    coef, se, dof = ols(np.column_stack(cols), y)
    out = {
        "feature": "decades",
        "slope": float(coef[1]),
        "slope_se": float(se[1]),
        "reference": ref,
        "k": float(student.ppf(0.975, dof)),
        "scenes": int(d.size),
    }
    if with_roll:
        out["other"] = {"rolloff": [float(coef[2]), roll_ref]}
    return out


def detrended(pts: list[dict[str, Any]], trend: dict[str, Any] | None) -> np.ndarray:
    """The ratios of ``pts`` moved to the trend's reference decades."""
    r = np.array([p["ratio"] for p in pts])
    if trend is None:
        return r
    d = np.array([p["decades"] for p in pts])
    shift = trend["slope"] * (d - trend["reference"])
    for key, (slope, ref) in trend.get("other", {}).items():
        shift = shift + slope * (np.array([p[key] for p in pts]) - ref)
    return r * np.exp(-shift)


def with_extrapolation(
    entry: dict[str, Any], trend: dict[str, Any] | None, covered: list[float], to: float | None
) -> list[dict[str, Any]]:
    """The verified entry (along ``trend`` over ``covered`` decades) and, with ``to``, the
    extrapolated one over ``[covered[1], to)`` (status 2)."""
    if trend is None:
        return [entry]
    tr = {
        k: trend[k]
        for k in ("feature", "slope", "slope_se", "reference", "k", "other")
        if k in trend
    }
    tr["covered"] = list(covered)
    out = [{**entry, "trend": tr}]
    if to is not None and to > covered[1]:
        ranges = {**entry["ranges"], "decades": [covered[1], to]}
        out.append({**entry, "ranges": ranges, "trend": tr, "status": 2})
    return out


def judge(p: dict[str, Any], entries: list[dict[str, Any]]) -> tuple[int, float, float]:
    """``(status, low, high)`` of campaign point ``p`` under ``entries`` (one campaign output's
    bands), evaluated by the package's own code (:func:`xpersson.pipeline.model_error.bands_of`)."""
    from xpersson.pipeline import model_error

    if not entries:
        return 0, math.nan, math.nan
    feats = {
        k: p[k]
        for k in ("hurst", "rolloff", "decades", "area_fraction", "tensile", "tabor")
        if not (isinstance(p[k], float) and math.isnan(p[k]))
    }
    feats.update(entries[0]["match"])
    table = {"bands": [{**e, "variable": "x"} for e in entries]}
    low, high, status = model_error.bands_of("x", feats, {}, (), table)
    return int(status), float(low), float(high)


def coverage_of(pts: list[dict[str, Any]], table: list[dict[str, Any]]) -> dict[str, Any]:
    """Per output and split: ``{"verified": [inside, n], "extrapolated": [inside, n],
    "not_verified": n}`` under ``table`` (entries with ``campaign_output``)."""
    by_out: dict[str, list[dict[str, Any]]] = defaultdict(list)
    for e in table:
        if e["variable"] not in CONDUCTANCES:  # copies of the stiffness's entries
            by_out[e["campaign_output"]].append(e)
    res: dict[str, dict[str, dict[str, Any]]] = defaultdict(dict)
    for p in pts:
        status, low, high = judge(p, by_out.get(p["output"], []))
        c = res[p["output"]].setdefault(
            p["split"], {"verified": [0, 0], "extrapolated": [0, 0], "not_verified": 0}
        )
        if status == 0:
            c["not_verified"] += 1
            continue
        key = "verified" if status == 1 else "extrapolated"
        c[key][1] += 1
        c[key][0] += int(low <= p["ratio"] <= high)
    return {k: dict(v) for k, v in res.items()}


def check(pts: list[dict[str, Any]], bands: Any) -> tuple[dict[str, Any], dict[str, float]]:
    """The extrapolation check: bands fitted on the calibration points up to
    :data:`CHECK_FIT_MAX` decades, extrapolated without limit, judged on every point beyond.

    Returns the per-output counts ``{output: [inside, n]}`` with the distance tested, and
    ``{output: distance}`` for the outputs that passed (the extrapolation limits)."""
    fit = [p for p in pts if p["split"] == "calibration" and p["decades"] <= CHECK_FIT_MAX]
    test = [{**p, "split": "beyond"} for p in pts if p["decades"] > CHECK_FIT_MAX]
    table = bands(fit, extrapolate={"*": math.inf}, min_span=0.25)
    cov = coverage_of(test, table)
    out, limits = {}, {}
    for name, splits in cov.items():
        inside, n = splits["beyond"]["extrapolated"]
        dist = max(p["decades"] for p in test if p["output"] == name) - CHECK_FIT_MAX
        out[name] = {"inside": inside, "n": n, "distance": round(dist, 3)}
        if n >= MIN_CHECK and inside >= COVERAGE * n:
            limits[name] = round(dist, 3)
    return out, limits


def confirm(limits: dict[str, float], cov: dict[str, Any]) -> tuple[dict[str, float], dict]:
    """The second test of an extrapolation: the table's own extrapolated bands on the held-out
    and new-seed points beyond its calibration decades (``cov``: :func:`coverage_of` under
    the table extrapolated to ``limits``). An output whose points there are not >= 90 %
    inside keeps no extrapolated band (its points beyond: not verified), however few they
    are: a failed test is evidence, a missing one is not.

    Returns the confirmed limits and per output ``{"inside", "n", "kept"}``."""
    kept, tests = {}, {}
    for name, dist in limits.items():
        splits = cov.get(name, {})
        inside = sum(splits[s]["extrapolated"][0] for s in ("held_out", "new_seed") if s in splits)
        n = sum(splits[s]["extrapolated"][1] for s in ("held_out", "new_seed") if s in splits)
        ok = inside >= COVERAGE * n
        tests[name] = {"inside": inside, "n": n, "kept": ok}
        if ok:
            kept[name] = dist
    return kept, tests


def large_cell_test(pts: list[dict[str, Any]], table: list[dict[str, Any]]) -> dict[str, Any]:
    """The verified bands beyond the 128^2 cells' decades on their own: per output, the
    held-out and new-seed points with more than :data:`CHECK_FIT_MAX` decades that the table
    verifies (status 1), ``{"inside", "n", "kept"}`` (kept: >= 90 % inside, or no such point)."""
    by_out: dict[str, list[dict[str, Any]]] = defaultdict(list)
    for e in table:
        if e["variable"] not in CONDUCTANCES:
            by_out[e["campaign_output"]].append(e)
    out: dict[str, Any] = {}
    for p in pts:
        if p["split"] == "calibration" or p["decades"] <= CHECK_FIT_MAX:
            continue
        status, low, high = judge(p, by_out.get(p["output"], []))
        if status != 1:
            continue
        c = out.setdefault(p["output"], {"inside": 0, "n": 0})
        c["n"] += 1
        c["inside"] += int(low <= p["ratio"] <= high)
    for c in out.values():
        c["kept"] = c["inside"] >= COVERAGE * c["n"]
    return out


def trend_rows(pts: list[dict[str, Any]], regimes: Any) -> list[str]:
    """The docs' table of the trend per output and regime (all splits, and calibration only)."""
    lines = [
        "| output | regime | slope of ln(exact/theory) per decade, all points (scenes) "
        "| the same, roll-off (0/1) as a second regressor | calibration only, with roll-off "
        "(the table's) | decades |",
        "|---|---|---|---|---|---|",
    ]
    for name, rng, label in regimes:
        mine = [p for p in pts if p["output"] == name and rng(p)]
        tr = fit_trend(mine, rolloff=False)
        if tr is None:
            continue
        sr = fit_trend(mine)
        cal = fit_trend([p for p in mine if p["split"] == "calibration"])
        d = [p["decades"] for p in mine]
        cells = [
            f"{tr['slope']:+.3f} ± {tr['slope_se']:.3f} ({tr['scenes']})",
            "-"
            if sr is None or "other" not in sr
            else f"{sr['slope']:+.3f} ± {sr['slope_se']:.3f}",
            "-" if cal is None else f"{cal['slope']:+.3f} ± {cal['slope_se']:.3f}",
            f"{min(d):.2f}-{max(d):.2f}",
        ]
        lines.append(f"| {name} | {label} | " + " | ".join(cells) + " |")
    return lines
