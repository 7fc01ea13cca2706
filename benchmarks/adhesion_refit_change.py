"""How much the refit of ``BUMPS`` (2.7 -> 1.25) changes existing results.

Re-solves every generated scene of ``benchmarks/bitwise.py`` (seed 33, 600 scenes) whose
fingerprint changed with the refit, with the constants before and after
(:func:`adhesion_fit.set_constants`), and prints per output the largest relative change.

Usage::

    python benchmarks/adhesion_refit_change.py gen-33-124 gen-33-133 ...
"""

from __future__ import annotations

import sys
import tempfile
import warnings
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import adhesion_fit as af  # noqa: E402
import bitwise  # noqa: E402

OUTPUTS = ("pull_off_stress", "floor_stress", "area_fraction", "p_att", "mean_gap", "P")


def _solve(scene: object) -> object:
    import xpersson

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            return xpersson.solve(scene)
        except (xpersson.SceneError, xpersson.PluginFailure) as exc:
            return str(exc)[:120]


def main(names: list[str]) -> None:
    with tempfile.TemporaryDirectory() as tmp:
        scenes = bitwise.generated_scenes(600, 33, tmp)
        worst: dict[str, float] = {}
        for name in names:
            out = []
            for consts in (af.BEFORE, (af.BEFORE[0], 1.25)):
                af.set_constants(*consts)
                out.append(_solve(scenes[name]))
            a, b = out
            if isinstance(a, str) or isinstance(b, str):
                print(
                    f"{name}: before {a if isinstance(a, str) else 'solved'}; after "
                    f"{b if isinstance(b, str) else 'solved'}"
                )
                continue
            row = []
            for v in OUTPUTS:
                if v in a and v in b:
                    x, y = np.asarray(a[v].values, float), np.asarray(b[v].values, float)
                    ok = np.isfinite(x) & np.isfinite(y) & (np.abs(x) > 0)
                    r = float(np.max(np.abs(y[ok] / x[ok] - 1))) if ok.any() else 0.0
                    worst[v] = max(worst.get(v, 0.0), r)
                    row.append(f"{v} {r:.3g}")
            print(f"{name}: " + ", ".join(row), flush=True)
        print("largest relative change:", {k: round(v, 4) for k, v in worst.items()})


if __name__ == "__main__":
    main(sys.argv[1:])
