"""Where the effective medium's discretisation error is: per load, against the converged reference.

For every scene of ``leakage_reference.py`` (same ``--seeds``/``--held-out``, same ``--cache``
of references: 480 bins, 160 magnifications per decade, ``--ref-cells`` gap cells), at
``--loads`` loads (below ``LEAK_MIN``: every load direct): ``leak_rate_emt`` of the default
(60 bins) against the reference, beside the load's A/A0 (at ``zeta_max``), its flow relative
to the scene's lowest load, the medium's flow factor ``sigma_eff / sigma(u)`` (-> 0 at the
medium's sealing), the 60-bin vs 30-bin difference (a candidate per-load estimate) and the
critical-junction over effective-medium ratio (the spread of the two models). Prints tables
binned by the flow ratio and by A/A0, and the worst loads.

    python benchmarks/leakage_emt_error.py --loads 40 --seeds 36 --held-out 2026 4242 5151 6161
        --ref-cells 3840 --cache DIR
"""

from __future__ import annotations

import argparse
import warnings
from pathlib import Path

import numpy as np
from leakage_reference import reference
from summary_design import labelled, load_range, scene

import xpersson


def rows(name: str, spec: dict, n: int, cache: Path | None, cells: int | None) -> list[tuple]:
    """Per load of one scene: (name, p0, A/A0, q/q_low, ff_emt, err, |q60/q30 - 1|, cj/emt)."""
    ref = reference(spec, n, cache, name, cells)

    def run(bins: int | None) -> object:
        leak = {} if bins is None else {"n_bins": bins}
        return xpersson.solve(scene(spec, load_range(n), analyses={"leakage": leak}))

    ds, coarse = run(None), run(30)
    r = ref["leak_rate_emt"]
    q, q30 = ds["leak_rate_emt"].values, coarse["leak_rate_emt"].values
    area = ds["area_fraction"].values[:, -1]
    with np.errstate(all="ignore"):
        err = np.abs(q / r - 1.0)
        est = np.abs(q / q30 - 1.0)
        flow = r / r[0]
        cj = ds["leak_rate"].values / q
    ff = ds["leak_flow_factor_emt"].values
    p0 = ds["p0"].values
    return [
        (name, p0[i], area[i], flow[i], ff[i], err[i], est[i], cj[i])
        for i in range(p0.size)
        if r[i] > 0 and q[i] > 0
    ]


def table(data: np.ndarray, col: int, edges: list[float], label: str) -> None:
    """Max and median error (and estimate ratio) of the loads binned by column ``col``."""
    print(
        f"\n| {label} | loads | err max | err median | est/err median | est >= err | CJ/EMT range |"
    )
    print("|---|---|---|---|---|---|---|")
    for lo, hi in zip(edges[:-1], edges[1:], strict=True):
        v = data[:, col]
        sel = (v >= lo) & (v < hi)
        if not sel.any():
            continue
        e, s, c = data[sel, 4], data[sel, 5], data[sel, 6]
        print(
            f"| {lo:.3g} - {hi:.3g} | {sel.sum()} | {e.max():.2e} | {np.median(e):.2e} | "
            f"{np.median(s / e):.2g} | {np.mean(s >= e):.2f} | {np.nanmin(c):.2g} - "
            f"{np.nanmax(c):.2g} |"
        )


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--loads", type=int, default=40)
    ap.add_argument("--seeds", type=int, nargs="*", default=[36])
    ap.add_argument("--held-out", type=int, nargs="*", default=[2026])
    ap.add_argument("--cache", type=Path, default=None)
    ap.add_argument("--ref-cells", type=int, default=None)
    args = ap.parse_args(argv)
    warnings.simplefilter("ignore")
    out: list[tuple] = []
    for name, spec in labelled(args.seeds, args.held_out):
        out += rows(name, spec, args.loads, args.cache, args.ref_cells)
    names = [o[0] for o in out]
    data = np.array([o[1:] for o in out], dtype=float)
    table(data, 2, [1e-300, 1e-9, 1e-6, 1e-4, 1e-2, 1.01], "flow / flow at 1 kPa")
    table(data, 1, [0.0, 0.01, 0.05, 0.1, 0.2, 0.3, 0.4, 0.45, 0.5], "A/A0")
    table(data, 3, [0.0, 1e-3, 1e-2, 0.1, 0.3, 1.01], "sigma_eff / sigma(u)")
    worst(data, names, np.ones(len(data), dtype=bool), "every load")
    worst(data, names, data[:, 2] >= 1e-6, "flow >= 1e-6 of the lowest load's")
    useful = data[:, 2] >= 1e-6
    print(f"\nloads: {len(data)}; flow >= 1e-6 of the lowest load's: {useful.sum()}")
    for lab, m in (("all", np.ones(len(data), bool)), (">=1e-6", useful), ("<1e-6", ~useful)):
        if m.any():
            e = data[m, 4]
            print(f"{lab}: err max {e.max():.3e} median {np.median(e):.3e}")


def worst(data: np.ndarray, names: list[str], use: np.ndarray, label: str) -> None:
    """The 10 loads of ``use`` with the largest error."""
    print(f"\nworst loads ({label}):")
    print(
        "\n| scene | p0 [Pa] | A/A0 | flow / flow at 1 kPa | sigma_eff/sigma(u) | err | est "
        "| CJ/EMT |"
    )
    print("|---|---|---|---|---|---|---|---|")
    for i in [j for j in np.argsort(-data[:, 4]) if use[j]][:10]:
        d = data[i]
        print(
            f"| {names[i]} | {d[0]:.3g} | {d[1]:.3f} | {d[2]:.2e} | {d[3]:.2e} | {d[4]:.2e} | "
            f"{d[5]:.2e} | {d[6]:.2g} |"
        )


if __name__ == "__main__":
    main()
