"""Where the leakage load table's directly computed loads come from (per call, per cause).

For every scene of the speed design (``summary_design.design``, seed 36) and of
``summary.py --held-out 2026``, at ``--loads`` loads (1 kPa - 1 MPa): the loads of each direct
call of the table (one per refinement level), split by cause: sealed by both theories (free:
no direct work), sealed by the junction alone with the effective medium open, the junction
near sealing (``zeta_c > 2/3 zeta_max``: each a key of its own, computed directly by design),
and the others (the first level's grid; the refinement). Totals per cause and per call, and
(``(Nm)``) how many had their effective medium computed (the table per group on roll-off
spectra, ``xpersson_interface._by_group``: the junction's loads without the medium's cost).

    python benchmarks/leakage_loads.py [--loads 1000] [--seeds 36] [--held-out 2026]
"""

from __future__ import annotations

import argparse
import warnings

import numpy as np
from summary_design import labelled, load_range, scene

import xpersson
from xpersson_interface import _by_load, plugins

CAUSES = ("sealed by both (free)", "junction sealed, medium open", "near sealing", "other")


def account(spec: dict, n: int) -> list[np.ndarray]:
    """Per direct call of a leakage solve at ``n`` loads: its loads by cause (:data:`CAUSES`)
    and, last, how many of them had their effective medium computed (on roll-off spectra the
    table per group, ``_by_group``, asks for it at fewer loads than the junction)."""
    calls: list[np.ndarray] = []
    runs = {cls: cls.run for cls in (_by_load._Direct,)}  # (by_load and by_group: one table)

    def recording(direct) -> None:  # noqa: ANN001
        exact = direct.exact

        def call(rows, which):  # noqa: ANN001, ANN202 - each direct call: its rows
            got = exact(rows, which)
            v = {k: got[k] for k in ("leak_sealed", "leak_sealed_emt", "piece")}
            free = (v["leak_sealed"] == 1) & (v["leak_sealed_emt"] == 1)
            shut = (v["leak_sealed"] == 1) & ~free
            near = (v["piece"] < 0) & ~free & ~shut
            medium = int(np.atleast_2d(which)[-1].sum())  # (asked for)
            calls.append(np.array([free.sum(), shut.sum(), near.sum(), rows.size, medium]))
            calls[-1][3] -= calls[-1][:3].sum()
            return got

        direct.exact = call
        try:
            runs[type(direct)](direct)
        finally:
            direct.exact = exact

    for cls in runs:
        cls.run = recording
    try:
        xpersson.solve(scene(spec, load_range(n), analyses={"leakage": {}}))
    finally:
        for cls, run in runs.items():
            cls.run = run
    return calls


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--loads", type=int, default=1000)
    ap.add_argument("--seeds", type=int, nargs="*", default=[36])
    ap.add_argument("--held-out", type=int, nargs="*", default=[2026])
    ap.add_argument(
        "--no-kinks", action="store_true", help="no roll-off windows, one group (_first_level)"
    )
    args = ap.parse_args(argv)
    if args.no_kinks:
        plugins.at_kinks = lambda ctx, ds, direct: (direct, ())
    warnings.simplefilter("ignore")
    scenes = labelled(args.seeds, args.held_out)
    total, per_call, n_calls = np.zeros(5, dtype=int), {}, 0
    for name, spec in scenes:
        calls = account(spec, args.loads)
        n_calls += len(calls)
        for i, c in enumerate(calls):
            total += c
            per_call[i] = per_call.get(i, np.zeros(5, dtype=int)) + c
        computed = sum(int(c[1:4].sum()) for c in calls)
        parts = " | ".join(f"{int(c[3])}+{int(c[2])}n+{int(c[1])}j ({int(c[4])}m)" for c in calls)
        print(f"{name:32s} calls {len(calls)} computed {computed:4d}: {parts}", flush=True)
    print(f"{n_calls} calls, {int(total[1:4].sum())} loads computed directly")
    print("total:", ", ".join(f"{a} {b}" for a, b in zip(CAUSES, total[:4], strict=True)))
    print(f"their effective medium computed: {int(total[4])} (the others' tabled)")
    for i, v in sorted(per_call.items()):
        print(f"call {i + 1}:", ", ".join(f"{a} {b}" for a, b in zip(CAUSES, v[:4], strict=True)))


if __name__ == "__main__":
    main()
