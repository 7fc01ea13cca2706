"""How smooth the leak outputs are in the load: the table's interpolation error, every load direct.

Per scene (``--scenes SEED:NAME``, ``SEED`` 36 the speed design, else ``held_out(12, SEED)``;
``NAME`` a substring of the scene's name): the leak analysis computed directly at 961 loads
1 kPa - 1 MPa (320 per decade; the load table bypassed), then, per half decade of load, the
largest error of the 8-point Lagrange polynomial through nodes at 8, 16 and 32 per decade (every
40th, 20th, 10th load) at the loads between, on the table's regularised logarithm of the output
(``leak_rate_emt``: ``ln q - 3 ln(1 - A/A_seal)``, ``_leakage.table_weights``). The load table's
check at ``n`` nodes per decade is the error at ``n/2`` times ``LEAK_SAFETY 2^-8`` (= 4): for 16
nodes per decade to pass ``LEAK_TOL`` (2e-3) unrefined, the 8-per-decade column must stay below
5e-4. ``--split-above X --split R``: the medium's detachment bins above ``zeta - 1 = X`` split in
``R`` (geometric; an experiment, not the library's bins); ``--n-bins``: the analysis's own
parameter.

    python benchmarks/leakage_ripple.py --scenes "36:roll H=0.39 4dec" "2718:roll H=0.35 4dec"
"""

from __future__ import annotations

import argparse
import warnings

import numpy as np
from summary_design import design, held_out, scene

import xpersson
from xpersson_interface import _leak_direct, plugins

STEPS = {8: 40, 16: 20, 32: 10}  # nodes per decade: every n-th of the 961 loads
ORDER = 8


def _all_direct(p0, direct, *args):  # noqa: ANN001, ANN202
    """``by_load``/``by_group`` replaced: every load computed directly."""
    n = np.atleast_1d(p0).size
    out = direct(np.arange(n))
    return {k: v for k, v in out.items() if k != "piece"}, np.zeros(n)


def _split_edges(above: float, r: int):  # noqa: ANN202
    """``bin_edges`` with every bin above ``zeta - 1 = above`` split in ``r`` (geometric)."""
    base = _leak_direct.bin_edges

    def edges(s, n_bins):  # noqa: ANN001, ANN202
        e = base(s, n_bins)
        if r <= 1 or e.size < 3:
            return e
        x = np.log(e[1:] - 1.0)
        top = np.exp(x[:-1]) >= above
        t = np.arange(1, r) / r
        extra = (x[:-1, None] + np.diff(x)[:, None] * t)[top].ravel()
        return np.unique(np.concatenate((e, 1.0 + np.exp(extra))))

    return edges


def lagrange_errors(x: np.ndarray, y: np.ndarray, step: int) -> np.ndarray:
    """|error| at every load not a node of the ``ORDER``-point interpolation through every
    ``step``-th load (centred stencils, one-sided at the ends; NaN at the nodes)."""
    nodes = np.arange(0, x.size, step)
    err = np.full(x.size, np.nan)
    for i in range(x.size):
        if i % step == 0:
            continue
        j = int(np.searchsorted(nodes, i))
        lo = min(max(j - ORDER // 2, 0), nodes.size - ORDER)
        nd = nodes[lo : lo + ORDER]
        if not np.all(np.isfinite(y[nd])):
            continue
        xn, yn = x[nd], y[nd]
        w = np.array([np.prod([(x[i] - xn[b]) / (xn[a] - xn[b]) for b in range(ORDER) if b != a])
                      for a in range(ORDER)])  # fmt: skip
        err[i] = abs(float(w @ yn) - y[i])
    return err


def one(seed: int, name: str, leak: dict) -> list[str]:
    """The table's rows of one scene."""
    scenes = design(12, seed) if seed == 36 else held_out(12, seed)
    label, spec = next((n, s) for n, s in scenes if name in n)
    loads = {"start": "1000.0 Pa", "stop": "1000000.0 Pa", "num": 961}
    ds = xpersson.solve(scene(spec, loads, analyses={"leakage": leak}))
    q = ds["leak_rate_emt"].values
    area = ds["area_fraction"].values[:, -1]
    seal = float(leak.get("a_c", 0.42)) if leak.get("emt_threshold") == "a_c" else 0.5
    x = np.log10(ds["p0"].values)
    with np.errstate(divide="ignore", invalid="ignore"):
        y = np.log(np.where(q > 0, q, np.nan)) - 3.0 * np.log(1.0 - area / seal)
    rows = []
    for per, step in STEPS.items():
        e = lagrange_errors(x, y, step)
        cells = []
        for lo in np.arange(3.0, 6.0, 0.5):
            sel = (x >= lo) & (x < lo + 0.5) & np.isfinite(e)
            cells.append(f"{np.max(e[sel]):.1e}" if sel.any() else "-")
        rows.append(f"| {label} | {per} | " + " | ".join(cells) + " |")
    return rows


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scenes", nargs="+", default=["36:roll H=0.39 4dec"])
    ap.add_argument("--n-bins", type=int, default=None)
    ap.add_argument("--split-above", type=float, default=1.0)
    ap.add_argument("--split", type=int, default=1)
    a = ap.parse_args(argv)
    warnings.simplefilter("ignore")
    plugins.by_load = _all_direct
    plugins.by_group = lambda *args: _all_direct(*args[:-1])
    if a.split > 1:
        _leak_direct.bin_edges = _split_edges(a.split_above, a.split)
    leak = {} if a.n_bins is None else {"n_bins": a.n_bins}
    print("| scene | nodes/decade | 1e3 | 3e3 | 1e4 | 3e4 | 1e5 | 3e5 Pa (half decades) |")
    print("|---|---|---|---|---|---|---|---|")
    for arg in a.scenes:
        seed, name = arg.split(":", 1)
        for row in one(int(seed), name, leak):
            print(row, flush=True)


if __name__ == "__main__":
    main()
