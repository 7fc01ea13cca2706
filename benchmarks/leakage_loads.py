"""Where the leakage load table's directly computed loads come from (per level, per cause).

For every scene of the speed design (``summary_design.design``, seed 36) and of
``summary.py --held-out 2026``, at ``--loads`` loads (1 kPa - 1 MPa): the loads the table
computes directly, per direct call (one per refinement level), split by cause: sealed by both
theories (free: no direct work), sealed by the junction alone with the effective medium open,
the junction near sealing (``zeta_c > 2/3 zeta_max``: computed directly by design), and the
others (the first level's nodes; the refinement). For the refinement it also counts what the
table computes with the junction's outputs alone and with the effective medium's alone (which
group drives it).

    python benchmarks/leakage_loads.py [--loads 1000] [--seeds 36] [--held-out 2026]
"""

from __future__ import annotations

import argparse
import warnings

import numpy as np
from summary_design import design, held_out, load_range, scene

import xpersson
from xpersson_interface import _by_load, plugins

JUNCTION = ("leak_zeta_c", "leak_u1", "leak_flow_factor", "leak_rate")
EMT = ("leak_flow_factor_emt", "leak_rate_emt")
KEYS = ("leak_sealed", "leak_sealed_emt", "piece")


class _Record:
    """Wraps ``_Direct.run`` and ``by_load``: the rows and key values of every direct call."""

    def __init__(self) -> None:
        self.calls: list[dict[str, np.ndarray]] = []
        self.groups: dict[str, int] = {}
        self._run = _by_load._Direct.run
        self._by_load = plugins.by_load

    def __enter__(self) -> _Record:
        rec = self

        def run(direct: _by_load._Direct) -> None:
            rows = np.flatnonzero(direct.pending & ~direct.done)
            rec._run(direct)
            if rows.size and rec.calls is not None:
                rec.calls.append({k: direct.vals[k][rows] for k in KEYS})

        def by_load(p0, exact, tol, keys, noise, least, orders, safety, per_decade, weights, free):
            out = rec._by_load(
                p0, exact, tol, keys, noise, least, orders, safety, per_decade, weights, free
            )
            saved, rec.calls = rec.calls, None
            try:
                for name, group in (("junction", JUNCTION), ("emt", EMT)):
                    names = set(group) | set(KEYS)
                    n = [0]

                    def part(rows, names=names, n=n):
                        got = exact(rows)
                        n[0] += int(np.count_nonzero(got["leak_sealed_emt"] == 0) + np.count_nonzero(got["leak_sealed"] == 0))
                        return {k: v for k, v in got.items() if k in names}

                    ws = tuple(
                        (frozenset(a & names), f) for a, f in weights if a & names
                    )
                    counted = [0]

                    def counting(rows, part=part, counted=counted):
                        got = part(rows)
                        both = (got["leak_sealed"] == 1) & (got.get("leak_sealed_emt", got["leak_sealed"]) == 1)
                        counted[0] += int(np.count_nonzero(~both))
                        return got

                    rec._by_load(
                        p0, counting, tol, keys, noise, least, orders, safety, per_decade, ws, free
                    )
                    rec.groups[name] = counted[0]
            finally:
                rec.calls = saved
            return out

        _by_load._Direct.run = run
        plugins.by_load = by_load
        return self

    def __exit__(self, *exc: object) -> None:
        _by_load._Direct.run = self._run
        plugins.by_load = self._by_load


def account(spec: dict, n: int) -> dict:
    with _Record() as rec:
        xpersson.solve(scene(spec, load_range(n), analyses={"leakage": {}}))
    levels = []
    for c in rec.calls:
        free = (c["leak_sealed"] == 1) & (c["leak_sealed_emt"] == 1)
        jonly = (c["leak_sealed"] == 1) & (c["leak_sealed_emt"] == 0)
        near = (c["piece"] < 0) & ~free & ~jonly
        rest = ~free & ~jonly & ~near
        levels.append(
            {
                "free": int(free.sum()),
                "junction_sealed": int(jonly.sum()),
                "near_sealing": int(near.sum()),
                "other": int(rest.sum()),
            }
        )
    return {"levels": levels, "groups": rec.groups}


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--loads", type=int, default=1000)
    ap.add_argument("--seeds", type=int, nargs="*", default=[36])
    ap.add_argument("--held-out", type=int, nargs="*", default=[2026])
    args = ap.parse_args(argv)
    warnings.simplefilter("ignore")
    scenes = [(n, s) for seed in args.seeds for n, s in design(12, seed)]
    scenes += [(f"held-out {seed}: {n}", s) for seed in args.held_out for n, s in held_out(12, seed)]
    total = np.zeros(4, dtype=int)
    per_level = {}
    groups = {"junction": 0, "emt": 0}
    for name, spec in scenes:
        r = account(spec, args.loads)
        computed = 0
        for i, lv in enumerate(r["levels"]):
            v = np.array([lv["free"], lv["junction_sealed"], lv["near_sealing"], lv["other"]])
            total += v
            per_level[i] = per_level.get(i, np.zeros(4, dtype=int)) + v
            computed += int(v[1:].sum())
        for g in groups:
            groups[g] += r["groups"].get(g, 0)
        print(
            f"{name:32s} calls {len(r['levels'])} computed {computed:4d} "
            + " | ".join(
                f"L{i}: {lv['other']}+{lv['near_sealing']}n+{lv['junction_sealed']}j"
                for i, lv in enumerate(r["levels"])
            )
            + f" | alone: junction {r['groups'].get('junction')} emt {r['groups'].get('emt')}",
            flush=True,
        )
    names = ("free (sealed by both)", "junction sealed, medium open", "near sealing", "other")
    print("total:", ", ".join(f"{a} {b}" for a, b in zip(names, total)))
    for i, v in sorted(per_level.items()):
        print(f"level {i}:", ", ".join(f"{a} {b}" for a, b in zip(names, v)))
    print(f"the table on one group alone (computed loads): {groups}")


if __name__ == "__main__":
    main()
