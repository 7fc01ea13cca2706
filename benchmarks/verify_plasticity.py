"""Verification rows of ``plastic_scale_dependent`` (Lambert's moving yield wall, physics.md
§3.2) for ``benchmarks/verify.py``; ``plastic`` itself is in ``verify_core.plastic_rows``.

- ``n = 0`` (constant hardness): the image series of the two fixed walls, written in
  ``verify_core`` (not the engine's ``exact`` module);
- ``n > 0``: the Markov walkers of the same scene (``method = "markov"``, Monte Carlo, a path
  independent of the Crank-Nicolson solve with its moving last cell), area fractions in
  standard errors; ``yield_stress`` against ``Y1 zeta^n``; the conservation identities
  (total area, ``plastic_load_share = Y A_pl / p0``, the force-balance residual recomputed from
  the load shares) against what the Dataset claims.
"""

from __future__ import annotations

import warnings

import numpy as np
from verify_core import NU, E, Ref, _image_series, _row, _tau

import xpersson

REF = Ref(0.8, 1e3, 1e4, 1e6, 1e-6)
P0 = 1e5
AREAS = ("elastic_area_fraction", "plastic_area_fraction", "non_contact_area_fraction")
TAG = " (plastic_scale_dependent)"


def _solve(Y1: float, n: float, markov: int = 0):
    scene = {
        "spectrum": REF.scene_spectrum(),
        "material": {"E": f"{E} Pa", "nu": NU},
        "load": {"p0": f"{P0} Pa"},
        "boundary": {"model": "plastic_scale_dependent", "Y1": f"{Y1!r} Pa", "n": n},
        "output": {"zeta_per_decade": 3},
    }
    if markov:
        scene["solver"] = {"method": "markov", "walkers": markov, "seed": 1, "rtol": 0.09}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return xpersson.solve(scene)


def _v(ds, name: str) -> np.ndarray:
    return np.asarray(ds[name].values, float).reshape(-1)


def rows(fast: bool) -> list[dict]:
    """Constant-hardness limit, Markov referee, identities."""
    worst: dict[str, float] = {}

    def up(name: str, err: float) -> None:
        worst[name] = max(worst.get(name, 0.0), float(err))

    # n = 0: the exact two-wall image series
    for ratio in (1.5,) if fast else (1.01, 1.5, 10.0):
        ds = _solve(ratio * P0, 0.0)
        z = ds["zeta"].values[1:]
        el, load_el = _image_series(P0, ratio * P0, _tau(REF, z * REF.q_L))
        pl = (P0 - load_el) / (ratio * P0)
        for name, want in zip(AREAS, (el, pl, 1 - el - pl), strict=True):
            up(name + " n=0", np.max(np.abs(_v(ds, name)[1:] - want)))
        up(
            "elastic_load_share n=0",
            np.max(np.abs(_v(ds, "elastic_load_share")[1:] - load_el / P0)),
        )
    walkers = 20_000 if fast else 200_000
    cases = ((1.5, 0.2),) if fast else ((1.01, 0.1), (1.5, 0.2), (3.0, 0.5))
    for ratio, n in cases:
        Y1 = ratio * P0
        ds, mc = _solve(Y1, n), _solve(Y1, n, markov=walkers)
        for name in AREAS:
            a, m = _v(ds, name), _v(mc, name)
            se = np.sqrt(np.maximum(m * (1 - m), 1 / walkers) / walkers)
            up(name, np.max(np.abs(a - m) / se))
        up(
            "elastic_load_share",
            np.max(np.abs(_v(ds, "elastic_load_share") - _v(mc, "elastic_load_share"))),
        )
        z = ds["zeta"].values
        Y = Y1 * z**n
        up("yield_stress", np.max(np.abs(_v(ds, "yield_stress") / Y - 1)))
        el, pl, non = (_v(ds, x) for x in AREAS)
        up("total_contact_fraction", np.max(np.abs(_v(ds, "total_contact_fraction") - el - pl)))
        up("area conservation", np.max(np.abs(el + pl + non - 1)))
        up("plastic_load_share", np.max(np.abs(_v(ds, "plastic_load_share") - Y * pl / P0)))
        resid = _v(ds, "elastic_load_share") + _v(ds, "plastic_load_share") - 1
        claim = _v(ds, "plastic_force_balance_residual")
        up("plastic_force_balance_residual", np.max(np.abs(claim - resid)))
        up("force balance", np.max(np.abs(resid)))
    regime = f"Y1/p0 {cases[0][0]}-{cases[-1][0]}, n {cases[0][1]}-{cases[-1][1]}, H 0.8"
    mc_ref = f"Markov walkers ({walkers}) of the same scene"
    out = [
        _row(f"{name}{TAG}", regime, mc_ref, worst[name], "standard errors",
             f"n = 0 against the image series: {worst[name + ' n=0']:.1e} abs")
        for name in AREAS
    ]  # fmt: skip
    out += [
        _row(f"elastic_load_share{TAG}", regime, mc_ref, worst["elastic_load_share"], "abs",
             f"Monte Carlo noise ~ 1/sqrt(N); n = 0 against the image series: "
             f"{worst['elastic_load_share n=0']:.1e}"),
        _row(f"yield_stress{TAG}", regime, "Y1 zeta^n", worst["yield_stress"], "rel"),
        _row(f"total_contact_fraction{TAG}", regime, "elastic + plastic (identity)",
             worst["total_contact_fraction"], "abs",
             f"el + pl + non - 1 <= {worst['area conservation']:.1e}"),
        _row(f"plastic_load_share{TAG}", regime, "Y(zeta) A_pl / p0 (identity)",
             worst["plastic_load_share"], "abs"),
        _row(f"plastic_force_balance_residual{TAG}", regime,
             "elastic_load_share + plastic_load_share - 1 recomputed",
             worst["plastic_force_balance_residual"], "abs",
             f"the residual itself <= {worst['force balance']:.1e}"),
    ]  # fmt: skip
    return out


if __name__ == "__main__":
    import sys

    for r in rows("--fast" in sys.argv):
        print(f"{r['output']:52s} {r['worst']:10.3g} {r['measure']:16s} {r['note']}")
