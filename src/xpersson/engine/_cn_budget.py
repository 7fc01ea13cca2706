"""The ``cn`` control's answer when a budget ended the search (:mod:`._cn_control`): the
finest solved level that has a coarser partner, with the partners' second-order estimate."""

from __future__ import annotations

from typing import Any

import numpy as np

from ._level import Outputs, combine

__all__ = ["_finest_pair"]


def _finest_pair(solved: dict[tuple[int, int, int], Outputs], fit: Any) -> None:
    """Budget spent: the finest level that has a coarser partner (same ``n_base`` and time
    plan), with the second-order estimate of the pair, flagged (into ``fit``, the control's
    ``_cn_control._Fit``: its ``best``, ``err`` and ``n_used`` are set).

    A finer level whose partner was never reached has no error estimate: the finest level
    *with* a coarser partner is used instead.
    """

    def partners(c: tuple[int, int, int]) -> list[tuple[int, int, int]]:
        return [o for o in solved if o[0] == c[0] and o[2] == c[2] and o[1] < c[1]]

    paired = [c for c in solved if partners(c)]
    key = max(paired or solved, key=lambda c: (c[0] * c[1], c[2]))
    fine = solved[key]
    fit.best = combine(fine, fine, False)
    if partners(key):
        ck = max(partners(key), key=lambda c: c[1])
        # second order: R_f - R = (R_f - R_c) / ((m_f / m_c)^2 - 1); twice that
        fit.err = 2.0 * np.abs(fine.area - solved[ck].area) / ((key[1] / ck[1]) ** 2 - 1.0)
    fit.n_used = key[0] * key[1]
