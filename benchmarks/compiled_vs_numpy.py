"""How far the compiled march's results are from the numpy path's, on whole scenes.

The compiled ``cn`` level (numba: ``xpersson.engine._moving_fused``) eliminates as LAPACK's
``dgtsv`` does but back-substitutes by the pivots' reciprocals and sums the outputs in its
loop, so its results equal the numpy path's (``XPERSSON_COMPILED=off``) to rounding, not bit
for bit. For the named scenes of ``benchmarks/bitwise.py`` (its generated scenes and the
examples), this solves each scene with the compiled march off and then built, and prints per
scene the largest difference of every numeric output variable relative to that variable's
largest magnitude, separately for the error estimates (a normalised difference of levels,
see ``xpersson.engine._cn_control``); the balances and residuals, which measure round-off
itself, are left out.

Usage: ``python benchmarks/compiled_vs_numpy.py NAME [NAME ...]`` (names as ``bitwise.py
compare`` prints them, e.g. ``gen-33-41`` or ``examples/elastic.toml``).
"""

from __future__ import annotations

import os

os.environ["OPENBLAS_NUM_THREADS"] = "1"

import sys  # noqa: E402
import tempfile  # noqa: E402
import warnings  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

ESTIMATES = ("error_estimate", "model_error")
ROUNDOFF = ("balance", "residual")  # round-off measures themselves (~1e-16): not compared


def scenes(names: list[str]) -> dict:
    """The named scenes of ``bitwise.py`` (generated ones by their seed and index)."""
    from bitwise import ROOT, example_scenes, generated_scenes

    out, gen = {}, {}
    examples = example_scenes()
    for name in names:
        if name.startswith("gen-"):
            _, seed, i = name.split("-")
            gen.setdefault(int(seed), []).append(int(i))
        else:
            out[name] = examples.get(name, ROOT / name)
    tmp = Path(tempfile.gettempdir()) / "xpersson-bitwise"
    tmp.mkdir(exist_ok=True)
    for seed, idx in gen.items():
        made = generated_scenes(max(idx) + 1, seed, str(tmp))
        out.update({f"gen-{seed}-{i}": made[f"gen-{seed}-{i}"] for i in idx})
    return out


def differences(a, b) -> dict[str, float]:
    """Largest |b - a| / max |a| of every numeric variable both Datasets hold."""
    out = {}
    for name, va in a.data_vars.items():
        if name not in b or va.dtype.kind not in "fc" or any(r in name for r in ROUNDOFF):
            continue
        x, y = np.asarray(va.values, dtype=float), np.asarray(b[name].values, dtype=float)
        ok = np.isfinite(x) & np.isfinite(y)
        if not ok.any():
            continue
        scale = max(float(np.max(np.abs(x[ok]))), 1e-300)
        out[name] = float(np.max(np.abs(y[ok] - x[ok]))) / scale
    return out


def main(names: list[str]) -> None:
    import xpersson
    from xpersson.engine import _compiled

    warnings.simplefilter("ignore")
    worst_out, worst_est = (0.0, ""), (0.0, "")
    for name, sc in scenes(names).items():
        with xpersson.set_options(compiled=False):
            ref = xpersson.solve(sc)
        assert _compiled.build(), "numba is needed"
        got = xpersson.solve(sc)
        d = differences(ref, got)
        outs = {k: v for k, v in d.items() if not any(e in k for e in ESTIMATES)}
        ests = {k: v for k, v in d.items() if any(e in k for e in ESTIMATES)}
        k_o = max(outs, key=outs.get) if outs else ""
        k_e = max(ests, key=ests.get) if ests else ""
        print(
            f"{name:55s} outputs {outs.get(k_o, 0.0):.1e} ({k_o}); "
            f"estimates {ests.get(k_e, 0.0):.1e} ({k_e})",
            flush=True,
        )
        worst_out = max(worst_out, (outs.get(k_o, 0.0), f"{name}: {k_o}"))
        worst_est = max(worst_est, (ests.get(k_e, 0.0), f"{name}: {k_e}"))
    print(f"worst output difference: {worst_out[0]:.1e} ({worst_out[1]})")
    print(f"worst estimate difference: {worst_est[0]:.1e} ({worst_est[1]})")


if __name__ == "__main__":
    main(sys.argv[1:])
