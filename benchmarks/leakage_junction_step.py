"""``u1``'s difference quotient near ``zeta = 1``: the step against the converged derivative.

``u1 = d(A u)/dA`` at ``zeta_c`` (``SolvedContact.separation_at``) is a central difference
quotient in ``ln zeta``. Near ``zeta = 1`` (steep spectra at low load, seals at low pressure)
the area falls from 1 to ``a_c`` within ``ln zeta_c`` itself, down to 1e-8: a fixed step of
1e-3 (clipped at ``zeta = 1``) then reads a secant over most of the fall. For each scene and
each load whose ``zeta_c`` is finite, this prints ``u1`` with the fixed step
(``STEP_SHARE = inf``), with the step of at most ``STEP_SHARE`` of ``ln zeta_c`` (the
library's), against the converged derivative (Richardson extrapolation of steps of 0.2 % and
0.1 % of ``ln zeta_c``), as relative errors, per ``ln zeta_c`` decade.

    python benchmarks/leakage_junction_step.py [--loads 200] [--held-out 4242] [--example]
"""

from __future__ import annotations

import argparse
import math
import warnings
from pathlib import Path

import numpy as np
from summary_design import held_out, load_range, scene

import xpersson
from xpersson.physics import _solved_contact as S

EXAMPLE = Path(__file__).resolve().parents[1] / "plugins/xpersson-interface/examples/oring.toml"


def quotients(spec: object) -> list[tuple[np.ndarray, ...]]:
    """Per ``separation_at`` call of a leakage solve of ``spec`` (a scene): ``ln zeta_c``,
    ``u1`` with the fixed step, with the library's step, and the converged derivative."""
    calls = []
    orig = S.SolvedContact.separation_at

    def rec(self, za, **kw):  # noqa: ANN001, ANN003, ANN202
        calls.append((self, np.array(za, dtype=float)))
        return orig(self, za, **kw)

    S.SolvedContact.separation_at = rec
    try:
        xpersson.solve(spec)
    finally:
        S.SolvedContact.separation_at = orig
    out = []
    for sc, za in calls:
        lz = np.log(za)
        share = S.STEP_SHARE
        try:
            S.STEP_SHARE = math.inf  # the fixed step (before)
            fixed = orig(sc, za)
        finally:
            S.STEP_SHARE = share
        now = orig(sc, za)

        a, b = _step(orig, sc, za, 2e-3), _step(orig, sc, za, 1e-3)
        out.append((lz, fixed, now, b + (b - a) / 3.0))
    return out


def _step(orig, sc, za: np.ndarray, f: float) -> np.ndarray:  # noqa: ANN001
    """``u1`` of each load alone with a step of ``f ln zeta_c`` (at most 1e-4)."""
    lz = np.log(za)
    u = np.full(za.size, np.nan)
    for i in np.flatnonzero(np.isfinite(za)):
        z = np.full(za.size, np.nan)
        z[i] = za[i]
        u[i] = orig(sc, z, rel_step=float(max(min(1e-4, f * lz[i]), 1e-14)))[i]
    return u


def report(name: str, spec: object) -> None:
    """Print the largest relative errors per ``ln zeta_c`` decade."""
    rows = [np.concatenate(v) for v in zip(*quotients(spec), strict=True)]
    lz, fixed, now, lim = rows
    ok = np.isfinite(lz) & np.isfinite(lim) & (lim > 0)
    print(f"== {name}: {int(ok.sum())} loads with a finite zeta_c")
    edges = [0.0, 1e-6, 1e-4, 1e-3, 1e-2, 0.1, 1.0, np.inf]
    for lo, hi in zip(edges[:-1], edges[1:], strict=True):
        s = ok & (lz >= lo) & (lz < hi)
        if s.any():
            e_f = np.max(np.abs(fixed[s] / lim[s] - 1.0))
            e_n = np.max(np.abs(now[s] / lim[s] - 1.0))
            print(
                f"  ln zeta_c in [{lo:g}, {hi:g}): {int(s.sum()):4d} loads, "
                f"fixed step {e_f:.2e}, step <= {S.STEP_SHARE:g} ln zeta_c {e_n:.2e}"
            )


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--loads", type=int, default=200)
    ap.add_argument("--held-out", type=int, nargs="*", default=[4242])
    ap.add_argument("--scenes", nargs="*", default=["flat H=0.87 4dec"])
    ap.add_argument("--example", action="store_true", help="also the o-ring example")
    args = ap.parse_args(argv)
    warnings.simplefilter("ignore")
    for seed in args.held_out:
        for name, spec in held_out(12, seed):
            if name in args.scenes:
                sc = scene(spec, load_range(args.loads), analyses={"leakage": {}})
                report(f"held-out {seed}: {name}", sc)
    if args.example:
        report("examples/oring.toml", EXAMPLE)


if __name__ == "__main__":
    main()
