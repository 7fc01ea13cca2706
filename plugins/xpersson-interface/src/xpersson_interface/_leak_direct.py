"""The leak analysis's outputs of some loads, computed directly (private, ``Leakage._direct``).

Per load: the critical junction (``zeta_c``, ``u1`` and the flow factor over the mean gap) and
the effective medium (the detachment bins and the Bruggeman mean over the gap cells: ~2/3 of
a load's cost). ``which`` (the load table per group, :mod:`._by_group`) asks for the medium
only at some loads: the others' medium outputs are then NaN and left uncomputed. A load's
values are those of the load alone (:mod:`._chunks`), whichever loads share its call and
whichever groups are asked for.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from xpersson import physics

from ._by_load import COMPUTED
from ._chunks import Part, bin_edges, joined
from ._leakage import NEGLIGIBLE, bruggeman_gap, junction_piece, leak_rate

#: Below this share of a chunk's loads asking for the effective medium, the medium's loads get
#: a SolvedContact of their own (the chunk's curve, ``Phi`` and mean gap sliced to their rows,
#: :meth:`~xpersson.physics.SolvedContact.rows`; ``Phi``'s table built for them alone); above,
#: the medium is computed for every load of the chunk (the extra loads' values unread).
#: Measured at 1000 loads (roll-off scenes of seeds 2026 and 4242), when the own SolvedContact
#: was built again: for any share 1.2-3.4 ms more per solve.
SPLIT = 0.5


def outputs(
    p: dict[str, Any],
    dp: float,
    s: Any,
    parts: list[Part],
    p0: NDArray[np.float64],
    medium: NDArray[np.bool_] | None = None,
) -> dict[str, NDArray[np.float64]]:
    """The leak outputs of the loads of the solved curve ``s`` in chunks ``parts`` (``p``: the
    analysis's parameters, ``dp`` the effective pressure drop [Pa], ``p0`` the loads [Pa]);
    the flags as floats; ``piece``: the pieces of the spectrum, between its breakpoints, that
    ``u1``'s difference quotient around ``zeta_c`` reaches (``u1`` has a step where it crosses
    one, e.g. the roll-off). ``medium`` (per load): the loads whose effective medium is
    asked for (None: every load); it is computed for them, and for every load of a chunk
    most of whose loads ask (:data:`SPLIT`), the others' NaN; with ``medium``, the groups
    computed per load are ``COMPUTED`` (:data:`._by_load.COMPUTED`: (n_load, 2), the
    junction's and the medium's), for the load table to keep."""
    a_c = float(p["a_c"])
    edges, thr = bin_edges(s, int(p["n_bins"])), a_c if p["emt_threshold"] == "a_c" else None

    def full(part: Part) -> tuple[NDArray[np.float64], ...]:
        _, sub, sc = part  # the crossing on the chunk's own curve (as each load alone)
        zc = physics.critical_magnification(sub.zeta, sub.contact, a_c)
        det = sc.detachment(edges, negligible=NEGLIGIBLE)  # (the bins the medium counts)
        # per load: the cells span that load's gaps, never the batch's (all loads at once)
        u3 = bruggeman_gap(det, a_c=thr, per_load=True)
        return zc, sc.separation_at(zc), det.mean_gap, u3

    def junction(part: Part) -> tuple[NDArray[np.float64], ...]:
        _, sub, sc = part
        zc = physics.critical_magnification(sub.zeta, sub.contact, a_c)
        return zc, sc.separation_at(zc), sc.mean_gap(), np.full(zc.size, np.nan)

    def one(part: Part) -> tuple[NDArray[np.float64], ...]:
        rows, sub, sc = part
        ask = np.ones(sub.p0.size, dtype=bool) if medium is None else medium[rows]
        if np.count_nonzero(ask) >= SPLIT * ask.size:  # (the medium of a few more loads:
            # cheaper than a detachment and gap cells of their own; computed for every load)
            return *full(part), np.ones(ask.size, dtype=bool)
        zc, u1, ubar, u3 = junction(part)  # every load's junction on the call's contact
        sel = np.flatnonzero(ask)
        if sel.size:  # the medium's loads on a SolvedContact of their own: the call's
            # curve, Phi and mean gap sliced to their rows (built for the junction already)
            det = sc.rows(sel).detachment(edges, negligible=NEGLIGIBLE)
            u3[sel] = bruggeman_gap(det, a_c=thr, per_load=True)
        return zc, u1, ubar, u3, ask

    zc, u1, ubar, u3, done = joined(parts, one)  # (done: the loads whose medium is computed)
    out = _leak_outputs(p, dp, zc, u1, ubar, u3, None if done.all() else ~done) | {
        "piece": junction_piece(s.psd, zc, float(s.zeta[-1]), p0)
    }
    if medium is not None:  # the groups computed (the junction always), asked for or not
        out[COMPUTED] = np.stack([np.ones(done.size, dtype=bool), done], axis=1)
    return out


def _leak_outputs(
    p: dict[str, Any],
    dp: float,
    zc: NDArray[np.float64],
    u1: NDArray[np.float64],
    ubar: NDArray[np.float64],
    u3: NDArray[np.float64],
    skip: NDArray[np.bool_] | None = None,
) -> dict[str, NDArray[np.float64]]:
    """The outputs from ``zeta_c``, ``u1``, the mean gap and ``<u^3>_EMT`` of each load
    (``skip``: the loads whose medium was not computed, its outputs NaN)."""
    sealed = ~np.isfinite(zc)
    u3 = np.where(np.isfinite(u3), u3, 0.0)
    args = (float(p["seal_width"]), float(p["seal_length"]), dp, float(p["viscosity"]))
    u1_3 = np.where(sealed, 0.0, np.nan_to_num(u1, nan=0.0) ** 3)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):  # ratios first:
        safe = np.where(ubar > 0, ubar, 1.0)  # u^3 underflows near full contact
        ff = np.where(ubar > 0, (np.where(sealed, 0.0, np.nan_to_num(u1)) / safe) ** 3, 0.0)
        ff_emt = np.where(ubar > 0, (np.cbrt(u3) / safe) ** 3, 0.0)
    out = {
        "leak_zeta_c": zc,
        "leak_u1": np.where(sealed, np.nan, u1),
        "leak_flow_factor": ff,
        "leak_rate": leak_rate(u1_3, *args),
        "leak_sealed": sealed.astype(float),
        "leak_flow_factor_emt": ff_emt,
        "leak_rate_emt": leak_rate(u3, *args),
        "leak_sealed_emt": (u3 <= 0).astype(float),
    }
    if skip is not None:
        for k in ("leak_flow_factor_emt", "leak_rate_emt", "leak_sealed_emt"):
            out[k] = np.where(skip, np.nan, out[k])
    return out
