"""The model error of an output: the band in which exact contact lies, from the validation campaign.

The theory is an approximation of the contact it describes. How far it is was measured by the
validation campaign (``benchmarks/campaign.py``): scenes drawn from a seeded random design, each
solved by the theory and by a boundary-element solution of the same spectrum (exact contact
within its discretisation). The campaign writes the packaged table ``xpersson/data/
model_error.json``: per output variable and regime, the interval ``[low, high]`` of the ratio
``exact / theory`` that holds 90 % of the campaign's calibration points (with its median, the
number of points, and the provenance: seed, size, date, solver and versions).

:func:`attach` adds to every covered output ``X`` of a Dataset three CF ancillary variables
(named in ``X.attrs["ancillary_variables"]``):

* ``X_exact_low``, ``X_exact_high`` (units of ``X``): ``low X`` and ``high X``, the interval
  where exact contact lies (for a variable over ``zeta``: at the largest magnification, the full
  roughness, which is what the campaign compared);
* ``X_model_error_status`` (flag: ``0 not_verified``, ``1 verified``, ``2 extrapolated``):
  ``verified`` inside what the campaign measured; ``extrapolated`` beyond the decades of
  roughness its cells held, within the distance it checked (the band along the measured trend,
  widened by the trend's uncertainty times the distance); ``not_verified`` elsewhere: the
  bounds are NaN there (their ``comment`` says so), never a made-up band.

The table is data keyed by variable name and by the scene's plugin names and options: the core
never names a plugin. A band entry is ``{"variable", "match", "ranges", "low", "high",
"median", "n"}``: ``match`` maps a feature (``boundary``, ``closure``, ``spectrum``, or an option
of the analysis that provides the variable, e.g. ``s_factor``) to its required value; ``ranges``
maps a numeric feature (``hurst``, ``rolloff``, ``decades``, ``area_fraction``, ``tabor``,
``tensile``) to ``[lo, hi)``. The first matching entry of a variable wins. Optional:
``"status"`` (the flag value of its points, default 1) and ``"trend"`` ``{"feature", "slope",
"reference", "slope_se", "k", "covered", "other"}``: at a value ``v`` of the feature the
factors are ``low exp(s - w)`` and ``high exp(s + w)`` with ``s = slope (v - reference)`` plus
``c (u - u_ref)`` for every ``other`` feature ``u: [c, u_ref]``, and ``w = k slope_se d`` with
``d`` the distance from ``v`` to the ``covered`` interval (0 inside).

:func:`xpersson.solve` attaches them to single scenes, a sweep to every block it solves (any
path; features once per distinct scene, bands as array operations over the points). ``[output]
model_error = false`` leaves them out (default ``true``: a table look-up, nothing solved).
"""

from __future__ import annotations

import json
import math
from importlib import resources
from typing import Any

import numpy as np
import xarray as xr

from ..cache import Cache
from ._insert import insert_or_set, nan_meaning, new_variable, values_of

__all__ = [
    "FLAG",
    "SUFFIXES",
    "attach",
    "covered",
    "covered_names",
    "band_table",
    "bands_of",
    "nan_meaning",
    "scene_features",
]

#: Suffixes of the three ancillary variables of an output.
SUFFIXES = ("_exact_low", "_exact_high", "_model_error_status")
#: CF flag attributes of ``X_model_error_status``.
FLAG = {
    "flag_values": np.array([0, 1, 2], dtype=np.int8),
    "flag_meanings": "not_verified verified extrapolated",
}

#: The ``comment`` of every ``X_model_error_status`` (the same for every scene and point).
STATUS_COMMENT = (
    "verified: inside the decades of roughness log10(q_1/q_r) and the regimes the validation "
    "campaign's cells held; extrapolated: more decades than its cells held, the band along the "
    "measured trend in decades widened by the trend's uncertainty times the distance, up to "
    "the distance the campaign checked; not_verified: elsewhere, bounds NaN "
    "(docs/verification.md, part II)"
)


_TABLE = Cache(
    "model_error.table",
    scope="process",
    maxsize=2,
    doc="the packaged model-error table (xpersson/data/model_error.json), read once",
)


def band_table(path: str | None = None) -> dict[str, Any]:
    """The model-error table (the packaged one, or the JSON file ``path``), read once."""

    def read() -> dict[str, Any]:
        if path is not None:
            with open(path, encoding="utf-8") as fh:
                return json.load(fh)
        text = resources.files("xpersson").joinpath("data", "model_error.json").read_text("utf-8")
        return json.loads(text)

    return _TABLE.get(path or "", read)


def scene_features(rs: Any) -> dict[str, Any]:
    """The scene-level features of a resolved scene: plugin names, closure, spectrum numbers.

    ``hurst`` [1], ``rolloff`` (1 with a roll-off ``q_r > q_L``, else 0), ``decades`` (log10 of
    ``q_1/q_r``, the self-affine range) for a spectrum with these attributes; absent otherwise
    (then every range on them fails: not verified).
    """
    feats: dict[str, Any] = {
        "spectrum": rs.plugin_names.get("spectrum"),
        "boundary": rs.plugin_names.get("boundary"),
        "coefficient": rs.plugin_names.get("coefficient"),
        "closure": rs.resolved.get("coefficient", {}).get("closure"),
    }
    for key, value in rs.resolved.get("boundary", {}).items():
        if key != "model" and isinstance(value, (str, int, float, bool)):
            feats[f"boundary.{key}"] = value  # e.g. match {"boundary.nominal_size": "0.0 m"}
    psd = rs.psd
    hurst = getattr(psd, "H", None)
    q_l, q_r, q_1 = (getattr(psd, n, None) for n in ("q_L", "q_r", "q_1"))
    if hurst is not None and None not in (q_l, q_r, q_1):
        feats["hurst"] = float(hurst)
        feats["rolloff"] = 1.0 if float(q_r) > float(q_l) * (1.0 + 1e-9) else 0.0
        feats["decades"] = math.log10(float(q_1) / float(q_r))
    return feats


def _finest(var: Any) -> tuple[tuple[str, ...], np.ndarray]:
    """``(dims, values)`` of a Variable at the largest magnification (numpy indexing: xarray's
    ``isel`` would import dask.array)."""
    values = np.asarray(var.values, float)
    if "zeta" not in var.dims:
        return tuple(var.dims), values
    axis = var.dims.index("zeta")  # a view: the values are only read
    return tuple(d for d in var.dims if d != "zeta"), values[(slice(None),) * axis + (-1,)]


def bands_of(
    variable: str,
    feats: dict[str, Any],
    options: dict[str, Any],
    shape: tuple[int, ...],
    table: dict[str, Any] | None = None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(low, high, status)`` of ``variable`` over ``shape`` (the loads, or ``()``).

    ``low``/``high`` are the factors on the theory's value (NaN where not verified); ``status``
    is 1 where an entry of ``table`` (default the packaged one) covers the point, else 0.
    ``feats``: scene features (:func:`scene_features`) and per-load ones (``area_fraction``,
    ``tensile``, ``tabor``: numbers or arrays of ``shape``); ``options``: the analyses'
    parameters. The first entry that matches a point wins (:func:`attach` evaluates the same
    over a sweep's points).
    """
    dims = tuple(f"dim_{i}" for i in range(len(shape)))
    fixed = {k: v for k, v in feats.items() if np.ndim(v) == 0}
    numeric = {
        k: (dims, np.broadcast_to(np.asarray(v, float), shape))
        for k, v in feats.items()
        if not isinstance(v, str) and v is not None
    }
    groups = [(fixed, dict(options), ((), np.bool_(True)))]
    return _bands(variable, dims, shape, numeric, groups, _index(table)[1].get(variable, []))


def _options_of(rs: Any, variable: str) -> dict[str, Any]:
    """The analyses' parameters: ``"<analysis>.<param>"`` for every analysis of the scene, and
    the bare names of the one that provides ``variable`` (e.g. the conductance's band matches
    ``contact_stiffness.s_factor``, the stiffness's ``s_factor``)."""
    out: dict[str, Any] = {}
    own: dict[str, Any] = {}
    for name, analysis in rs.analyses:
        out.update({f"{name}.{k}": v for k, v in analysis.params.items()})
        if variable in type(analysis).outputs:
            own = dict(analysis.params)
    return {**out, **own}


def covered(ds: xr.Dataset, table: dict[str, Any] | None = None) -> list[str]:
    """The outputs of ``ds`` that the table lists (the variables :func:`attach` annotates)."""
    names = _index(table)[0]
    have = ds.data_vars
    return sorted(n for n in names if n in have)


_OVER = " over its calibration points in the scene's regime (docs/verification.md)"
_INDEX = Cache(
    "model_error.index",
    scope="process",
    maxsize=2,
    doc="the packaged model-error table's output names (a sorted tuple), its entries by "
    "output and the ancillaries' comment",
)


def _index(table: dict[str, Any] | None) -> tuple[tuple[str, ...], dict[str, list[Any]], str]:
    """The output names ``table`` lists, its band entries by output (in the table's order)
    and the ancillaries' ``comment``: of the packaged table once per process (``table`` None
    or empty), of another table each time."""

    def make(of: dict[str, Any]) -> tuple[tuple[str, ...], dict[str, list[Any]], str]:
        entries: dict[str, list[dict[str, Any]]] = {}
        for entry in of["bands"]:
            entries.setdefault(entry["variable"], []).append(entry)
        prov = {"campaign": "?", "date": "?", **of.get("provenance", {})}
        head = f"validation campaign {prov['campaign']} ({prov['date']}): 90 % of exact/theory"
        return covered_names(of), entries, head + _OVER

    if not table:
        return _INDEX.get("", lambda: make(band_table()))
    return make(table)


def covered_names(table: dict[str, Any]) -> tuple[str, ...]:
    """The output names ``table`` lists (its bands' variables and its ``variables``)."""
    return tuple(sorted({e["variable"] for e in table["bands"]} | set(table.get("variables", ()))))


def attach(
    ds: xr.Dataset,
    points: Any,
    dims: tuple[str, ...] = (),
    table: dict[str, Any] | None = None,
    index: Any = None,
) -> list[str]:
    """Add the model-error ancillary variables of every covered output of ``ds`` (in place).

    ``points`` is the resolved scene of ``ds`` (a single scene), or for a sweep over ``dims``
    its points' resolved scenes: all of them in C order of ``dims``, or the distinct ones with
    ``index`` (an int array of the sweep's shape: the entry of ``points`` of every point, e.g.
    one scene for every material value). The features are computed once per distinct scene and
    the bands evaluated as array operations over the points (no per-point loop), so a sweep
    gets, point by point, the values a single solve of that point gets. ``table``: the
    packaged one by default. Does nothing when the scene sets ``[output] model_error = false``.

    Returns
    -------
    list of str
        The names of the variables added.
    """
    points = list(points) if dims else [points]
    if not points or not points[0].resolved.get("output", {}).get("model_error", True):
        return []
    listed = _index(table)
    have = ds.data_vars
    names = [n for n in listed[0] if n in have]  # covered(ds, table): listed[0] is sorted
    if not names:
        return []
    shape = tuple(ds.sizes[d] for d in dims)
    scenes = [scene_features(rs) for rs in points]
    if not dims and index is None:  # one scene (a single solve): its values, 0-d arrays
        index = np.intp(0)
        numeric = {k: ((), np.array(float(scenes[0].get(k, np.nan)))) for k in _NUMERIC}
    else:
        index = np.arange(len(points)).reshape(shape) if index is None else np.asarray(index)
        numeric = {
            k: (dims, np.asarray(np.array([s.get(k, np.nan) for s in scenes], float)[index]))
            for k in _NUMERIC
        }
    numeric.update(_load_features(ds, dims))
    new: dict[str, xr.Variable] = {}
    for name in names:
        groups = _groups(name, scenes, points, index, dims)
        new.update(_ancillaries(ds, name, numeric, groups, listed))
    insert_or_set(ds, new, aligned=True)  # all at once, on their outputs' dims and sizes
    for name in names:
        ds.variables[name].attrs["ancillary_variables"] = " ".join(name + s for s in SUFFIXES)
    return list(new)


#: Scene features that vary from point to point of a sweep: arrays over its points.
_NUMERIC = ("hurst", "rolloff", "decades")


def _load_features(ds: xr.Dataset, dims: tuple[str, ...]) -> dict[str, Any]:
    """``name -> (dims, values)`` of the per-load features: ``area_fraction`` (at the largest
    magnification; the total, elastic plus plastic, where a boundary reports
    ``total_contact_fraction``, as the campaign's regimes are), ``tensile`` (1 where
    ``p0 < 0``) and ``tabor`` (each point's first finest-scale ``tabor_parameter``)."""
    out: dict[str, Any] = {}
    for area in ("total_contact_fraction", "area_fraction"):
        if area in ds.variables:
            out["area_fraction"] = _finest(ds.variables[area])
            break
    if "p0" in ds.variables:
        p0 = ds.variables["p0"]
        out["tensile"] = (tuple(p0.dims), (np.asarray(values_of(p0), float) < 0).astype(float))
    if "tabor_parameter" in ds.variables:
        tdims, values = _finest(ds.variables["tabor_parameter"])
        for ax in reversed(range(len(tdims))):
            if tdims[ax] not in dims:
                values = np.take(values, 0, axis=ax)
        out["tabor"] = (tuple(d for d in tdims if d in dims), values)
    return out


def _groups(
    name: str, scenes: list[dict[str, Any]], points: list[Any], index: np.ndarray, dims: Any
) -> list[tuple[dict[str, Any], dict[str, Any], tuple[tuple[str, ...], Any]]]:
    """``(scene features, options, (dims, mask))`` per group of points whose plugin names,
    options and other non-numeric features agree (one group in most sweeps: mask ``True``)."""
    if len(points) == 1:  # one scene (a single solve): one group, nothing to compare
        fixed = {k: v for k, v in scenes[0].items() if k not in _NUMERIC}
        return [(fixed, _options_of(points[0], name), ((), np.bool_(True)))]
    keys: dict[str, int] = {}
    found: list[tuple[dict[str, Any], dict[str, Any]]] = []
    gid = np.empty(len(points), dtype=np.intp)
    for j, (feats, rs) in enumerate(zip(scenes, points, strict=True)):
        opts = _options_of(rs, name)
        fixed = {k: v for k, v in feats.items() if k not in _NUMERIC}
        key = json.dumps([fixed, opts], sort_keys=True, default=repr)
        if key not in keys:
            keys[key] = len(found)
            found.append((fixed, opts))
        gid[j] = keys[key]
    if len(found) == 1:
        return [(*found[0], ((), np.bool_(True)))]
    of_point = gid[index]
    return [(f, o, (tuple(dims), of_point == g)) for g, (f, o) in enumerate(found)]


def _on(src: tuple[str, ...], values: Any, dims: tuple[str, ...], shape: tuple[int, ...]) -> Any:
    """``values`` over ``src`` broadcastable to ``dims`` (a dim of ``src`` that ``dims`` lacks
    is taken at its first index, as a sweep's output that does not span every sweep dim)."""
    values = np.asarray(values)
    for ax in reversed(range(len(src))):
        if src[ax] not in dims:
            values = np.take(values, 0, axis=ax)
    kept = [d for d in src if d in dims]
    values = np.transpose(values, sorted(range(len(kept)), key=lambda i: dims.index(kept[i])))
    return values.reshape([n if d in kept else 1 for d, n in zip(dims, shape, strict=True)])


def _bands(
    name: str,
    vdims: tuple[str, ...],
    shape: tuple[int, ...],
    numeric: dict[str, Any],
    groups: list[Any],
    entries: list[dict[str, Any]],
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(low, high, status)`` of output ``name`` over ``shape``: per group, the first of its
    ``entries`` (the table's, in order) that matches each point (as :func:`bands_of`, over
    arrays)."""
    over = _Over(numeric, vdims, shape)
    if shape == ():  # one point (a single solve's scalar): the same, without array operations
        return _band_of_point(entries, over, groups)
    low, high = np.full(shape, np.nan), np.full(shape, np.nan)
    done = np.zeros(shape, dtype=bool)
    status = np.zeros(shape, dtype=np.int8)
    for feats, opts, (mdims, mask) in groups:
        where = _on(mdims, mask, vdims, shape)
        for entry in entries:
            if not _matches(entry, feats, opts) or _misses(entry, over, feats):
                continue
            ok = where & ~done
            for key, (lo, hi) in entry.get("ranges", {}).items():  # (the others: _misses)
                if key in numeric and numeric[key][0] and ok.any():  # one value per point
                    ok = ok & (over[key] >= lo) & (over[key] < hi)
            hit = np.broadcast_to(ok, shape)
            if not hit.any():  # nothing to write (its trend is not evaluated)
                continue
            lo_f, hi_f = _trend(entry, over, feats, shape)
            low[hit], high[hit] = lo_f[hit], hi_f[hit]
            status[hit] = entry.get("status", 1)
            done |= hit
            if done.all():  # every point has its entry: the later ones would hit nothing
                break
    return low, high, status


def _matches(entry: dict[str, Any], feats: dict[str, Any], opts: dict[str, Any]) -> bool:
    """Whether the plugin names, options and features of a group match ``entry["match"]``."""
    for k, v in entry.get("match", {}).items():  # a loop: no generator per entry
        if not opts.get(k, feats.get(k)) == v:
            return False
    return True


def _band_of_point(
    entries: list[dict[str, Any]], over: _Over, groups: list[Any]
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`_bands` of one point (``shape == ()``): the first entry of the point's group
    whose ranges hold it, compared as Python floats (as the array comparisons compare)."""
    for feats, opts, (_, mask) in groups:
        if not bool(mask):
            continue
        for entry in entries:
            if _matches(entry, feats, opts) and not _misses(entry, over, feats):
                lo_f, hi_f = _trend(entry, over, feats, ())
                return lo_f, hi_f, np.array(entry.get("status", 1), dtype=np.int8)
    return np.array(np.nan), np.array(np.nan), np.array(0, dtype=np.int8)


def _misses(entry: dict[str, Any], over: _Over, feats: dict[str, Any]) -> bool:
    """Whether a feature of ``entry["ranges"]`` with one value for all the points (the scene's;
    any feature of a single point) lies outside its ``[lo, hi)``, or is missing: the entry
    hits nothing (compared as Python floats, as the array comparisons compare)."""
    for key, (lo, hi) in entry.get("ranges", {}).items():
        if key in over.numeric:
            src, values = over.numeric[key]
            if src and over.shape:  # one value per point: compared over the arrays
                continue
            v = float(over[key] if src else values)
        elif key in feats:
            v = float(np.asarray(feats[key], float))  # as the array path reads it (None: NaN)
        else:
            return True
        if not (v >= lo and v < hi):
            return True
    return False


class _Over(dict):
    """The numeric features over ``shape`` (:func:`_on` of each), evaluated once per key."""

    def __init__(self, numeric: dict[str, Any], vdims: tuple[str, ...], shape: tuple[int, ...]):
        super().__init__()
        self.numeric, self.vdims, self.shape = numeric, vdims, shape

    def __missing__(self, key: str) -> np.ndarray:
        src, values = self.numeric[key]  # one point's value (a single solve): _on's, as it is
        on = np.asarray(values) if not src and not self.shape else None
        value = self[key] = _on(src, values, self.vdims, self.shape) if on is None else on
        return value


def _trend(
    entry: dict[str, Any], over: _Over, feats: dict[str, Any], shape: tuple[int, ...]
) -> tuple[np.ndarray, np.ndarray]:
    """The factors ``(low, high)`` of ``entry`` over ``shape``: constant, or along its
    ``trend`` (shifted by ``slope (v - reference)``, widened by ``k slope_se`` per unit of
    distance from the ``covered`` interval of the feature ``v``; ``over``: the numeric
    features over ``shape``)."""
    trend = entry.get("trend")
    if not trend:
        return np.full(shape, float(entry["low"])), np.full(shape, float(entry["high"]))

    def values(key: str) -> np.ndarray:
        if key in over.numeric:
            return np.broadcast_to(over[key], shape)
        return np.full(shape, float(feats.get(key, np.nan)))

    v = values(trend["feature"])
    lo_c, hi_c = trend["covered"]
    dist = np.maximum(np.maximum(lo_c - v, v - hi_c), 0.0)
    shift = trend["slope"] * (v - trend["reference"])
    for key, (slope, ref) in trend.get("other", {}).items():
        shift = shift + slope * (values(key) - ref)
    wide = trend["k"] * trend["slope_se"] * dist
    return entry["low"] * np.exp(shift - wide), entry["high"] * np.exp(shift + wide)


def _ancillaries(
    ds: xr.Dataset,
    name: str,
    numeric: dict[str, Any],
    groups: list[Any],
    index: tuple[Any, dict[str, list[dict[str, Any]]], str],
) -> dict[str, xr.Variable]:
    """The three ancillary variables of output ``name`` (array operations over the points;
    ``index``: the table's :func:`_index`)."""
    var = ds.variables[name]
    vdims, x = _finest(var)
    low, high, status = _bands(name, vdims, x.shape, numeric, groups, index[1].get(name, []))
    units = var.attrs.get("units", "1")
    where = " at the largest magnification (the full roughness)" if "zeta" in var.dims else ""
    source = index[2]
    new = {}
    for suffix, factor, side in (("_exact_low", low, "lower"), ("_exact_high", high, "upper")):
        new[name + suffix] = new_variable(
            tuple(vdims),
            np.asarray(x * factor, float),
            {
                "units": units,
                "long_name": f"{side} end of the interval where exact contact's {name} lies"
                + where,
                "comment": f"{source} {nan_meaning(name)}",
                "coverage_content_type": "qualityInformation",
            },
        )
    new[name + "_model_error_status"] = new_variable(
        tuple(vdims),
        status,
        {
            "units": "1",
            "long_name": f"whether the validation campaign covers {name} in this regime",
            "flag_values": FLAG["flag_values"],
            "flag_meanings": FLAG["flag_meanings"],
            "comment": STATUS_COMMENT,
            "coverage_content_type": "qualityInformation",
        },
    )
    return new
