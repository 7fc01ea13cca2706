"""The leakage load table's first level (private): loads it would compute directly anyway.

Measured on the speed design at 1000 loads (``benchmarks/leakage_loads.py``): the loads near the
junction's sealing (``zeta_c > NEAR_SEALING zeta_max``: each a key of its own, so computed
directly by design) and, where fewer than :data:`SHORT`, the loads the junction alone seals
(the effective medium still open: too few to table) are all computed directly, but only once
refinement reaches them, in the table's third or fourth direct call (each call ~2.5 ms fixed).
Predicted from the stored curve's crossing of ``a_c``, they are nodes of the first level
instead (:func:`._by_load.by_load`'s ``free``): computed in the first call, with the grid,
which is :data:`PER_DECADE` nodes per decade on a spectrum with a roll-off. Up to :data:`FEW`
loads: beyond, the table's loads cost more than the calls this saves.
On a roll-off spectrum the loads whose ``zeta_c`` lies near the breakpoint are keys of their
own (:func:`at_kinks`: ``u1``'s kink and the area spline's ringing, which the check at the
nodes cannot see), and the effective medium, smooth there, is tabled in a group of its own,
with nodes of its own (:mod:`._by_group`: the predicted loads near the sealing are the
junction's nodes only, those the junction alone seals both groups').
A load predicted wrongly costs one direct evaluation (its values are then exact); one missed
is found by the table's refinement, as before: the prediction changes which loads are
computed, never the accuracy claim.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from xpersson import physics
from xpersson.plugins.solved import per_solve
from xpersson.plugins.stored import spectrum_of

from ._by_load import LEAK_GROUPS, LEAK_MIN, LEAK_ORDERS, LEAK_PER_DECADE, tabled
from ._leakage import NEAR_SEALING, _contact_area

__all__ = [
    "FEW",
    "KINK",
    "MARGIN",
    "PER_DECADE",
    "SHORT",
    "at_kinks",
    "first_level",
    "predicted",
    "table_min",
]

#: Up to this many loads the first level is :data:`PER_DECADE` nodes per decade and holds the
#: :func:`predicted` loads. Measured (``benchmarks/leakage_loads.py``, the four worst scenes):
#: at 2000 loads 954 loads in 14 calls against 978 in 19; at 3000 loads 1199 in 16 against
#: 1027 in 20, at 1e4 774 against 656 on roll H=0.31 5dec: there the loads cost more than the
#: calls they save (a call's fixed cost is ~28 loads' worth).
FEW = 2500
#: The first level's nodes per decade up to :data:`FEW` loads on a spectrum with a breakpoint
#: between ``q_L`` and the curve's last magnification (a roll-off). At 16 (``LEAK_PER_DECADE``)
#: the check's table at twice the spacing (8 per decade, ~ the period of the effective
#: medium's ripple, 0.12-0.17 decade: the Almqvist far tail's detachment bins) misses the
#: medium by 7e-4 - 8e-2 over most of the range (32: 3e-5 - 3e-4), and the segment below the
#: roll-off (0.5 decade on several scenes) is too short for the check's 16 nodes: with the
#: medium's own group and the roll-off windows (:func:`at_kinks`), 16 per decade took 62 direct
#: calls and 24 took 55 against 48 at 32 on the 24 design and held-out scenes at 1000 loads
#: (``benchmarks/leakage_rolloff.py``, ``leakage_loads.py``). Elsewhere it fails near the
#: sealing only, and 32 would cost loads without saving a call.
PER_DECADE = 32

#: Relative margin of the prediction on ``zeta_c / zeta_max`` (the stored curve's crossing
#: lies within 6 % of the dense re-solve's on the speed design).
MARGIN = 0.1
#: Loads sealed by the junction alone (the medium open) fewer than this: too few to table (a
#: segment of the table needs twice its ``2 m`` check nodes), each computed directly.
SHORT = 4 * max(LEAK_ORDERS)


def table_min(p0: NDArray[np.float64], sealed: NDArray[np.bool_]) -> int:
    """The leak table's minimum number of loads for the loads ``p0`` [Pa]: ``LEAK_MIN``
    where the loads not ``sealed`` by both theories (the direct path computes those only: the
    sealed cost nothing) go through the table (:func:`._by_load.tabled`); else one more than
    the loads (every load computed directly)."""
    p0 = np.atleast_1d(np.asarray(p0, dtype=float))
    return LEAK_MIN if tabled(p0[~np.asarray(sealed, dtype=bool)], LEAK_MIN) else p0.size + 1


def first_level(
    ctx: Any, ds: Any, a_c: float, sealed: NDArray[np.bool_], least: int = LEAK_MIN
) -> tuple[float, NDArray[np.bool_], NDArray[np.bool_]]:
    """The leak table's first level for the loads of the solved Dataset ``ds`` (the analysis
    context ``ctx``: its boundary): its nodes per decade (:data:`PER_DECADE` on a spectrum
    with a breakpoint inside the curve) and the :func:`predicted` loads (the Dataset's order;
    from its stored contact area), near the junction's sealing and sealed by the junction
    alone, from ``least`` (the table's minimum) to :data:`FEW` loads; else
    ``LEAK_PER_DECADE`` and none."""
    n = int(np.size(sealed))
    if not least <= n <= FEW:
        return LEAK_PER_DECADE, np.zeros(n, dtype=bool), np.zeros(n, dtype=bool)
    zeta = np.asarray(ds.variables["zeta"].values, dtype=float)  # (no DataArray)
    inside = bool(_interior_breaks(ctx, ds).size)
    area = _contact_area(ds, ctx.boundary)
    near, shut = predicted(zeta, area, a_c, sealed, split=True)
    return (PER_DECADE if inside else LEAK_PER_DECADE), near, shut


def _interior_breaks(ctx: Any, ds: Any) -> NDArray[np.float64]:
    """The breakpoints of the spectrum the Dataset ``ds`` was solved with (the direct path's,
    once per solve), as magnifications strictly inside its curve (1, ``zeta_max``)."""
    psd = per_solve(ctx, ("stored_spectrum",), lambda: spectrum_of(ds))
    breaks = np.asarray(psd.nodes(), dtype=float) / float(psd.q_L)
    return breaks[(breaks > 1.0) & (breaks < float(ds.variables["zeta"].values[-1]))]


def predicted(
    zeta: NDArray[np.float64],
    area: NDArray[np.float64],
    a_c: float,
    sealed: NDArray[np.bool_],
    split: bool = False,
) -> Any:
    """Per load (its row of the contact area ``area`` (n_load, n_zeta) [1] on the
    magnifications ``zeta``, increasing from 1): not ``sealed`` by both theories, and the
    curve's crossing of ``a_c`` above ``(1 - MARGIN) NEAR_SEALING zeta_max`` or, where fewer
    than :data:`SHORT` loads have none (the junction sealed), none. ``split``: the two kinds
    apart, ``(near sealing, sealed by the junction alone)``."""
    near, crossed = _beyond(zeta, area, a_c, (1.0 - MARGIN) * NEAR_SEALING * float(zeta[-1]))
    shut = ~crossed & ~sealed
    if np.count_nonzero(shut) >= SHORT:
        shut = np.zeros_like(shut)
    if split:
        return near & ~sealed & ~shut, shut & ~sealed
    return (near | shut) & ~sealed


def _beyond(
    zeta: NDArray[np.float64], area: NDArray[np.float64], a_c: float, zeta_min: float
) -> tuple[NDArray[np.bool_], NDArray[np.bool_]]:
    """Per load: whether :func:`~xpersson.physics.critical_magnification` of its row of
    ``area`` on ``zeta`` exceeds ``zeta_min``, and whether it is finite, each the same as
    from the crossings of every load; computed only for the loads whose crossing interval
    holds ``zeta_min`` (or whose row is not finite; ~5 % of 1000 loads on the speed design:
    0.57 ms of the first level's 0.8 ms before). Elsewhere the crossing's side is that of its
    interval ``[zeta_{j-1}, zeta_j]`` (the Newton steps stay inside; ``exp(ln zeta)`` within
    ``1e-9`` of ``zeta``)."""
    A = np.atleast_2d(np.asarray(area, dtype=float))
    below = A <= a_c
    crossed = below.any(axis=1)
    j = np.clip(np.where(crossed, np.argmax(below, axis=1), 1), 1, zeta.size - 1)
    fine = crossed & np.isfinite(A).all(axis=1)
    near = fine & (zeta[j - 1] * (1.0 - 1e-9) > zeta_min)
    rest = np.flatnonzero(crossed & ~near & ~(fine & (zeta[j] * (1.0 + 1e-9) <= zeta_min)))
    if rest.size:  # (each load's crossing its own: the same on a subset of the loads)
        zc = physics.critical_magnification(zeta, A[rest], a_c)
        with np.errstate(invalid="ignore"):
            near[rest] = zc > zeta_min
        crossed[rest] = np.isfinite(zc)
    return near, crossed


#: Relative half-width, in ``zeta_c``, of the window around a breakpoint of the spectrum inside
#: the curve (a roll-off) where the junction's outputs are not smooth in the load (``u1``'s
#: kink and the area spline's ringing: second differences of ``ln u1`` 2-15x their level
#: within 0.93-1.035 of the breakpoint, ``benchmarks/leakage_rolloff.py``). Measured at 1000
#: loads on the 44 scenes of ``benchmarks/load_table_check.py`` (largest error / estimate on
#: the roll-off scenes; loads computed on the 24 of ``benchmarks/leakage_loads.py``, 48
#: calls each): 0.03 0.78 (3494 loads), 0.05 0.52 (3584), 0.07 0.40 (3579), 0.1 0.40 (3681).
KINK = 0.07


def at_kinks(
    ctx: Any, ds: Any, direct: Any, least: int = LEAK_MIN
) -> tuple[Any, tuple[frozenset[str], ...]]:
    """``direct`` (the leak outputs of rows of loads), with each load whose ``zeta_c`` lies
    within :data:`KINK` of a breakpoint of the spectrum inside the curve a ``piece`` of its
    own (computed directly: no stencil crosses or enters the window), and the table's groups
    (``LEAK_GROUPS``: the effective medium's stencils then cross the window), from
    ``least`` (the table's minimum) to :data:`FEW` loads on a spectrum with such a
    breakpoint; else ``direct``
    itself and one group. (Without the window, the medium's stencils cut there had covered
    the junction's kink: with groups alone its estimate fell short, 1.2-1.7x.)"""
    p0 = np.atleast_1d(np.asarray(ctx.p0, dtype=float))
    if not least <= p0.size <= FEW:
        return direct, ()
    breaks = _interior_breaks(ctx, ds)
    if not breaks.size:
        return direct, ()
    width = np.log1p(KINK)

    def marked(rows: NDArray[np.intp], which: Any = None) -> dict[str, NDArray[np.float64]]:
        out = direct(rows, which)
        with np.errstate(divide="ignore", invalid="ignore"):
            lz = np.log(out["leak_zeta_c"])
        near = np.any(np.abs(lz[:, None] - np.log(breaks)) < width, axis=1)
        out["piece"] = np.where(near, -p0[rows], out["piece"])
        return out

    return marked, LEAK_GROUPS
