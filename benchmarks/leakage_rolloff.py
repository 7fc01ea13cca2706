"""Which leakage outputs fail the load table's check, where, and why (roll-off spectra).

For the roll-off scenes of the speed design (``summary_design.design``, seed 36) and of
``summary.py --held-out 2026``, at ``--loads`` loads (1 kPa - 1 MPa): every load computed
directly once, then the table's first level at ``--per-decade`` nodes per decade (no
predicted loads) as :mod:`xpersson_interface._by_load` builds it: per output, the check's
residual at the odd nodes (the even nodes' 8-point table at the odd ones, relative), the
loads whose estimate misses the tolerance, and the true error of the interpolated loads. Each
failing stretch is printed with ``zeta_c`` over the spectrum's breakpoint (the roll-off) and
``zeta_c / zeta_max``, so a kink at a predictable load (``zeta_c`` crossing the breakpoint)
can be told from a curvature, the sealing or the ripple.

    python benchmarks/leakage_rolloff.py [--loads 1000] [--per-decade 16 32] [--scenes ...]
"""

from __future__ import annotations

import argparse
import math
import warnings

import numpy as np
from summary_design import labelled, load_range, scene

import xpersson
from xpersson.plugins.stored import spectrum_of
from xpersson_interface import _by_load, plugins
from xpersson_interface._stencils import _interpolate, _logs, _relative, _segments

OUTS = ("leak_zeta_c", "leak_u1", "leak_flow_factor", "leak_flow_factor_emt")
SHORT = dict(zip(OUTS, ("zc", "u1", "ff", "emt"), strict=True))


def capture(spec: dict, n: int) -> dict:
    """The table's inputs of one leakage solve: loads, the direct call (every group),
    weights, breakpoints (the table per group of roll-off spectra: recorded as ``by_load``'s,
    its first level the groups' together)."""
    got: dict = {}
    by_load, by_group, first_level = plugins.by_load, plugins.by_group, plugins.first_level

    def rec_first(ctx, ds, a_c, sealed, *more):  # noqa: ANN001, ANN002, ANN202
        psd = spectrum_of(ds)
        got["breaks"] = np.asarray(psd.nodes(), dtype=float) / float(psd.q_L)
        got["z_max"] = float(ds["zeta"].values[-1])
        return first_level(ctx, ds, a_c, sealed, *more)

    def rec_by_load(p0, exact, tol, keys, *more, **kw):  # noqa: ANN001, ANN002, ANN003, ANN202
        noise, _least, orders, safety, _per_decade, w, _free = more[:7]
        got.update(p0=np.asarray(p0, float), exact=exact, keys=keys, weights=w, orders=orders)
        got["safety"], got["noise"], got["tol"] = safety, noise, tol
        got.setdefault("groups", ())  # (set first by rec_by_group: the table per group)
        return by_load(p0, exact, tol, keys, *more, **kw)

    def rec_by_group(p0, exact, tol, keys, *more):  # noqa: ANN001, ANN002, ANN202
        got["groups"] = more[7]
        rec_by_load(p0, lambda r: exact(r, np.ones((2, r.size), dtype=bool)), tol, keys,
                    *more[:6], np.asarray(more[6]).any(axis=0))  # fmt: skip
        return by_group(p0, exact, tol, keys, *more)

    saved = by_load, by_group, first_level
    plugins.by_load, plugins.by_group, plugins.first_level = rec_by_load, rec_by_group, rec_first
    try:
        xpersson.solve(scene(spec, load_range(n), analyses={"leakage": {}}))
    finally:
        plugins.by_load, plugins.by_group, plugins.first_level = saved
    got["all"] = got["exact"](np.arange(got["p0"].size))
    return got


def per_output_check(xn, at, logs, roles, m: int) -> dict[str, np.ndarray]:  # noqa: ANN001
    """Per output, ``_by_load._check``'s residual at the odd nodes (0 at the even ones)."""
    odd, even = np.arange(1, xn.size, 2), np.arange(0, xn.size, 2)
    seg = _segments(at, roles[0])
    sub = {k: v[even] for k, v in at.items()}
    le = {k: v[even] for k, v in logs.items()}
    vals, bad, _, _, _ = _interpolate(xn[even], sub, le, xn[odd], roles, m, (seg[even], seg[odd]))
    out = {}
    for k in OUTS:
        top = float(np.abs(np.where(np.isfinite(at[k]), at[k], 0.0)).max())
        r = np.zeros(xn.size)
        r[odd] = np.where(bad, np.inf, _relative(vals[k], at[k][odd], top))
        out[k] = r
    return out


def _grouped(xn, at, logs, x, roles, tol, groups):  # noqa: ANN001, ANN202
    """``_by_load._one_group`` for each group of outputs (each on its own keys, as
    ``_by_group.by_group``; () one group, every output), the estimate the largest."""
    if not groups:
        return _by_load._one_group(xn, at, logs, x, roles, tol)
    out, est = {}, np.zeros(x.size)
    for g in groups:
        sub = {k: v for k, v in at.items() if k in g}
        lg = {k: v for k, v in logs.items() if k in g}
        vals, e = _by_load._one_group(xn, sub, lg, x, _by_load.own_roles(roles, g), tol)
        out.update(vals)
        est = np.maximum(est, e)
    return out, est


def study(name: str, got: dict, per_decade: float) -> None:
    """Print where the first level at ``per_decade`` misses the tolerance, and why."""
    x, allv = np.log(got["p0"]), got["all"]
    roles = (got["keys"], got["weights"])
    tol = (got["tol"], got["noise"], got["orders"], got["safety"])
    nodes = _by_load._nodes(x, math.log(10.0) / per_decade)
    rest = np.setdiff1d(np.arange(x.size), nodes)
    at = {k: v[nodes] for k, v in allv.items()}
    logs = _logs(at, roles, x[nodes])
    chk = per_output_check(x[nodes], at, logs, roles, max(got["orders"]))
    vals, est = _grouped(x[nodes], at, logs, x[rest], roles, tol, got["groups"])
    # which output's check drives each flagged load: the largest among its stencil's odd nodes
    seg = _segments(at, roles[0])
    from xpersson_interface._stencils import _stencil

    idx = _stencil(x[nodes], x[rest], seg, max(got["orders"]))[0]
    zb = [b for b in got["breaks"] if 1.0 < b < got["z_max"]]
    zc = allv["leak_zeta_c"]
    fail = est > tol[0]
    ok = np.isfinite(est)
    true = {k: np.where(ok, _relative(vals[k], allv[k][rest]), 0.0) for k in OUTS}
    worst = max(float(np.max(t)) for t in true.values())
    print(
        f"\n== {name}: {per_decade:g}/decade, {nodes.size} nodes, breakpoints {zb}, "
        f"z_max {got['z_max']:.3g}; {fail.sum()} of {rest.size} loads fail "
        f"(true error max {worst:.2e})"
    )
    # runs of failing loads
    f = np.flatnonzero(fail)
    if not f.size:
        return
    drv = np.stack([np.max(chk[k][idx[f]], axis=1) for k in OUTS])  # (output, load)
    kind = np.where(np.isinf(est[f]), "no stencil (segment)", np.array(OUTS)[np.argmax(drv, 0)])
    cuts = np.flatnonzero((np.diff(f) > 1) | (kind[1:] != kind[:-1])) + 1
    for part, lab in zip(np.split(np.arange(f.size), cuts), np.split(kind, cuts), strict=True):
        r = rest[f[part]]
        z = zc[r]
        zr = z / zb[0] if zb else np.full(z.size, np.nan)
        why = " ".join(f"{SHORT[k]}={np.max(drv[i, part]):.1e}" for i, k in enumerate(OUTS))
        tr = " ".join(f"{SHORT[k]}={np.max(true[k][f[part]]):.1e}" for k in OUTS)
        print(
            f"  p0 {got['p0'][r[0]]:9.4g}-{got['p0'][r[-1]]:9.4g} ({r.size:3d}) "
            f"zc/zb {np.nanmin(zr):7.3f}-{np.nanmax(zr):7.3f} zc/zmax "
            f"{np.nanmin(z) / got['z_max']:.3f}-{np.nanmax(z) / got['z_max']:.3f} "
            f"[{lab[0]}] check {why} | true {tr}"
        )


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--loads", type=int, default=1000)
    ap.add_argument("--per-decade", type=float, nargs="*", default=[16, 32])
    ap.add_argument("--scenes", nargs="*", default=None, help="substrings of scene names")
    args = ap.parse_args(argv)
    warnings.simplefilter("ignore")
    scenes = labelled([36], [2026])
    scenes = [(n, s) for n, s in scenes if "roll" in n]
    if args.scenes:
        scenes = [(n, s) for n, s in scenes if any(t in n for t in args.scenes)]
    for name, spec in scenes:
        got = capture(spec, args.loads)
        for d in args.per_decade:
            study(name, got, d)


if __name__ == "__main__":
    main()
