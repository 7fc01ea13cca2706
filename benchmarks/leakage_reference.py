"""The leakage outputs at many loads against a converged reference.

For every scene of the speed design (``summary_design.design``, seed 36; ``--seeds`` adds
others) and of ``summary.py --held-out 2026``, at ``--loads`` loads (1 kPa - 1 MPa): the
outputs as ``xpersson.solve`` gives them (through the load table) against the direct path
with 480 detachment bins and 160 magnifications per decade (the reference; every load
computed). Per output: the largest and the median relative error over the loads where the
reference is at least 1e-6 of its largest, the scene of the largest, and how many loads'
sealed flags differ. Run it on two source trees (``PYTHONPATH``) and compare the JSON files
(``--cache``: the reference computed once, by the first tree, read by the second).
``--ref-cells N``: the reference's effective medium on ``N`` gap cells
(``bruggeman_gap(n_u=N)``; default: the tree's own cells). Below ``LEAK_MIN`` loads (e.g.
``--loads 40``) every load is computed directly: the direct path against the reference.

    python benchmarks/leakage_reference.py [--loads 1000] [--seeds 36] [--held-out 2026]
        [--cache DIR] [--ref-cells N] [--out results/leakage_reference.json]
"""

from __future__ import annotations

import argparse
import functools
import json
import warnings
from pathlib import Path

import numpy as np
from summary_design import labelled, load_range, scene

import xpersson
from xpersson_interface import _by_load, _leak_direct

OUTPUTS = ("leak_zeta_c", "leak_u1", "leak_flow_factor", "leak_rate_emt", "leak_flow_factor_emt")
FLAGS = ("leak_sealed", "leak_sealed_emt")
REFERENCE = {"n_bins": 480, "zeta_per_decade": 160}


def reference(
    spec: dict, n: int, cache: Path | None, name: str, cells: int | None = None
) -> dict[str, np.ndarray]:
    """The reference outputs (every load directly, 480 bins, 160 per decade, ``cells`` gap
    cells if given); kept in ``cache`` (an ``.npz`` per scene and load count) where given."""
    path = None if cache is None else cache / f"{name.replace(' ', '_').replace(':', '')}_{n}.npz"
    if path is not None and path.is_file():
        with np.load(path) as f:
            return dict(f)
    least, medium = _by_load.TABLE_MIN, _leak_direct.bruggeman_gap
    _by_load.TABLE_MIN = 10**9
    if cells is not None:
        _leak_direct.bruggeman_gap = functools.partial(medium, n_u=cells)
    try:
        ds = xpersson.solve(scene(spec, load_range(n), analyses={"leakage": dict(REFERENCE)}))
    finally:
        _by_load.TABLE_MIN, _leak_direct.bruggeman_gap = least, medium
    out = {k: ds[k].values.astype(float) for k in OUTPUTS + FLAGS}
    if path is not None:
        path.parent.mkdir(parents=True, exist_ok=True)
        np.savez(path, **out)
    return out


def errors(got: dict[str, np.ndarray], ref: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """Per output, the relative error of each load where the reference is >= 1e-6 of its
    largest (NaN elsewhere)."""
    out = {}
    for k in OUTPUTS:
        r, g = ref[k], got[k]
        with np.errstate(all="ignore"):
            top = np.nanmax(np.abs(np.where(np.isfinite(r), r, 0.0)))
            use = np.isfinite(r) & (np.abs(r) >= 1e-6 * top) & (np.abs(r) > 0)
            out[k] = np.where(use, np.abs(g / np.where(use, r, 1.0) - 1.0), np.nan)
    return out


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--loads", type=int, default=1000)
    ap.add_argument("--seeds", type=int, nargs="*", default=[36])
    ap.add_argument("--held-out", type=int, nargs="*", default=[2026])
    ap.add_argument("--cache", type=Path, default=None)
    ap.add_argument("--ref-cells", type=int, default=None)
    ap.add_argument("--out", type=Path, default=None)
    args = ap.parse_args(argv)
    warnings.simplefilter("ignore")
    scenes = labelled(args.seeds, args.held_out)
    worst = {k: (0.0, "") for k in OUTPUTS}
    pooled: dict[str, list[np.ndarray]] = {k: [] for k in OUTPUTS}
    flags = 0
    per_scene = {}
    for name, spec in scenes:
        ref = reference(spec, args.loads, args.cache, name, args.ref_cells)
        ds = xpersson.solve(scene(spec, load_range(args.loads), analyses={"leakage": {}}))
        got = {k: ds[k].values.astype(float) for k in OUTPUTS + FLAGS}
        err = errors(got, ref)
        flags += sum(int(np.count_nonzero(got[f] != ref[f])) for f in FLAGS)
        per_scene[name] = {k: float(np.nanmax(e, initial=0.0)) for k, e in err.items()}
        for k, e in err.items():
            pooled[k].append(e[np.isfinite(e)])
            if per_scene[name][k] > worst[k][0]:
                worst[k] = (per_scene[name][k], name)
        print(name, {k: f"{v:.2e}" for k, v in per_scene[name].items()}, flush=True)
    summary = {
        k: {
            "max": worst[k][0],
            "scene": worst[k][1],
            "median": float(np.median(np.concatenate(pooled[k]))),
        }
        for k in OUTPUTS
    }
    summary["flags_differing"] = flags
    for k in OUTPUTS:
        s = summary[k]
        print(f"{k:22s} max {s['max']:.3e} ({s['scene']}), median {s['median']:.3e}")
    print(f"sealed flags differing from the reference: {flags}")
    if args.out:
        args.out.write_text(json.dumps({"summary": summary, "scenes": per_scene}, indent=1) + "\n")


if __name__ == "__main__":
    main()
