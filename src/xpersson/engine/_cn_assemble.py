"""The outputs of a ``cn`` solve from its fitted levels (:mod:`._cn`): the analytic start
up to ``tau_s``, the fit's fields projected onto admissible probabilities after it, their
error estimates and the densities; the fields in one compiled pass where the compiled march
is in force (:func:`._cn_outputs.assembled`, the numpy steps' numbers), else by numpy.
Units: tau in Pa^2, pressures in Pa."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

from . import _compiled
from ._cn_control import _Fit
from ._cn_outputs import EST_FLOOR
from ._level import Outputs
from ._problem import Problem
from ._project import project
from ._result import Raw

__all__ = ["_assemble"]

Array = NDArray[np.float64]

_EPS = float(np.finfo(float).eps)


def _assemble(pbs: list[Problem], k: float, analytic: Array, fit: _Fit, lv: Any) -> Raw:
    """The Raw of a batch: analytic start where ``analytic``, the fitted levels elsewhere.

    The output times are strictly increasing (checked), so ``analytic`` (``tau <= tau_s``)
    is their first ``n_a`` and the march's outputs are the columns ``n_a:`` (a slice: the same
    elements as the mask, without its index arrays)."""
    pb = pbs[0]
    tau = pb.tau
    n_a = int(np.count_nonzero(analytic))
    best, n_used = fit.best, fit.n_used
    status, message, nsteps = fit.status, fit.message, lv.nsteps
    trunc = 2.0 * math.erfc(k / math.sqrt(2.0))
    # the probabilities are projected onto their admissible set (area, absorbed >= 0,
    # area <= 1, absorbed_lower + absorbed_upper <= 1); the distance moved is a lower
    # bound of the error, so the estimate is raised to it, and a distance beyond the
    # estimate (round-off of the step sums included) is reported, not hidden
    roundoff = 16.0 * _EPS * (nsteps + math.sqrt(max(n_used, 1)))
    fast = None
    if best is not None and lv.image is None and n_a < tau.size:
        fast = _compiled.built("assembled")  # (every field in one compiled pass, the same numbers)
    tols = (pb.rtol, pb.atol)
    fields = None if fast is None else _fields_of(fast, pbs, fit, tau, trunc, roundoff, *tols)
    if fields is None:  # (the compiled pass raised the start's estimates itself)
        *fields, status, message = _fields(pbs, analytic, fit, lv, n_a, trunc, roundoff)
        _start_floor(fields[5], fields[0], tau, n_a, *tols)
    area, ab_l, ab_u, load, wall_term, e_all, non_area = fields
    P = _densities(pbs, analytic, best) if pb.p_out is not None else None
    if status == "success" and not message:
        message = (
            f"{len(lv.solved)} grids, finest N = {n_used}"
            if lv.solved
            else "analytic start covers every output"
        )
    return Raw(
        area=area,
        non_area=non_area,
        absorbed_lower=ab_l,
        absorbed_upper=ab_u,
        load=load,
        wall_term=wall_term,
        error_estimate=e_all,
        P=P,
        status=status,
        message=message,
        nsteps=nsteps,
        n_nodes=n_used + 1 if n_used else 0,
        nfev=nsteps,
    )


def _start_floor(e_all: Array, area: Array, tau: Array, n_a: int, rtol: float, atol: float) -> None:
    """Raise the estimate of the analytic start's outputs at ``tau > 0`` (its first ``n_a``)
    in place to ``EST_FLOOR`` x their tolerance ``rtol |area| + atol`` [1] (as the march's).

    Their error is the probability that a path crossed a real wall that stayed outside the
    window, which a moving wall makes larger than the window's ``trunc``: it accumulates over
    every decade of tau the wall spends near the window's edge (a linearly receding wall
    within 6.98 diffusion lengths at rtol 1e-2: 2.6e-11 against ``trunc`` 2e-11; the ``jkr``
    scene "flat H=0.64 6dec" of ``summary_design.held_out(12, 1313)`` at rtol 1e-2: 1.7x)."""
    lo = 0 if tau[0] > 0 else 1
    if n_a > lo:
        start = e_all[:, lo:n_a]
        tol = rtol * np.abs(area[:, lo:n_a]) + atol
        np.maximum(start, EST_FLOOR * tol, out=start)


def _fields_of(
    fast: Any,
    pbs: list[Problem],
    fit: _Fit,
    tau: Array,
    trunc: float,
    roundoff: float,
    rtol: float,
    atol: float,
) -> Array | None:
    """:func:`_fields` (its first seven) and :func:`_start_floor` (tolerance ``rtol``,
    ``atol`` [1]) by ``fast`` (:func:`._cn_outputs.assembled`, compiled) as one (7, loads,
    outputs) array, or None where it declines (the numpy steps then answer: a value it leaves
    to numpy, or a distance moved beyond the estimate)."""
    best, err = fit.best, fit.err
    shape = best.area.shape
    if len(shape) != 2 or np.shape(err) != shape or shape[0] != len(pbs):
        return None
    out = np.empty((7, shape[0], tau.size))
    p0 = np.array([p.p0 for p in pbs])
    check = fit.status == "success"
    if fast(best.area, best.absorbed_lower, best.absorbed_upper, best.load, best.moment_lower,
            best.moment_upper, err, p0, tau, trunc, roundoff, check, rtol, atol,
            out):  # fmt: skip
        return out
    return None


def _fields(
    pbs: list[Problem],
    analytic: Array,
    fit: _Fit,
    lv: Any,
    n_a: int,
    trunc: float,
    roundoff: float,
) -> tuple:
    """The fields of :func:`_assemble` by numpy: ``(area, absorbed_lower, absorbed_upper,
    load, wall_term, error_estimate, non_area, status, message)`` (the status and message
    of ``fit``, or the first distance moved beyond its estimate)."""
    tau = pbs[0].tau
    num = slice(n_a, None)
    best, err = fit.best, fit.err
    status, message = fit.status, fit.message
    shape = (len(pbs), tau.size)
    area = np.ones(shape)
    ab_l = np.zeros(shape)
    ab_u = np.zeros(shape)
    load = np.empty(shape)
    load[...] = np.array([p.p0 for p in pbs])[:, None]
    wall_term = np.zeros(shape)
    e_all = np.zeros(shape)
    if n_a:  # (``analytic & (tau > 0)``: the columns from the first positive time to n_a)
        e_all[:, 0 if tau[0] > 0 else 1 : n_a] = trunc
    if lv.image is not None:  # a one-wall start: the closed form (exact) up to the march
        _one_wall_start(pbs, analytic, lv.image, area, ab_l, load, wall_term)
    if best is not None and n_a < tau.size:
        ab_lower, moment_lower = best.absorbed_lower, best.moment_lower
        if lv.image is not None:  # what the wall absorbed before the march (closed form)
            a0, m0 = _one_wall_absorbed(pbs, lv.tau_s, lv.image)
            ab_lower, moment_lower = ab_lower + a0, moment_lower + m0
        proj, dist = project(best.area, ab_lower, best.absorbed_upper)
        if status == "success":
            bound = err + trunc
            bound += roundoff
            status, message = _beyond(dist, bound, status, message)
        err = np.maximum(err, dist["area"])
        area[:, num], ab_l[:, num], ab_u[:, num] = proj
        load[:, num] = best.load
        wall_term[:, num] = moment_lower + best.moment_upper
        e_all[:, num] = err + trunc
    return area, ab_l, ab_u, load, wall_term, e_all, ab_l + ab_u, status, message


def _beyond(dist: dict[str, Array], bound: Array, status: str, message: str) -> tuple[str, str]:
    """``(status, message)`` of a projection that moved a probability by more than ``bound``
    (its error estimate, round-off included): the first such one is reported."""
    for key, d in dist.items():
        if np.count_nonzero(d > bound):
            msg = f"{key} outside [0, 1] by {float(np.max(d)):.2e}, beyond its error estimate"
            return "tolerance_not_met", msg
    return status, message


def _one_wall_start(
    pbs: list[Problem],
    analytic: Array,
    wall: float,
    area: Array,
    ab_l: Array,
    load: Array,
    wall_term: Array,
) -> None:
    """The outputs at ``analytic`` of a one-wall start (absorbing wall at rest at ``wall``
    [Pa]) from its closed form, into ``area``, ``ab_l``, ``load``, ``wall_term``."""
    from .exact import one_wall

    tau = pbs[0].tau[analytic]
    p0 = np.array([p.p0 for p in pbs])[:, None]
    a, non, ld = one_wall(tau[None, :], p0, wall)
    area[:, analytic], ab_l[:, analytic], load[:, analytic] = a, non, ld
    wall_term[:, analytic] = p0 - ld


def _one_wall_absorbed(pbs: list[Problem], tau_w: float, wall: float) -> tuple[Array, Array]:
    """``(absorbed, wall moment)`` ``(loads, 1)`` [1, Pa] of a one-wall start at its end
    ``tau_w`` [Pa^2] (wall at ``wall`` [Pa]): the march counts from there on."""
    from .exact import one_wall

    p0 = np.array([p.p0 for p in pbs])[:, None]
    _, non, _ = one_wall(np.full((len(pbs), 1), tau_w), p0, wall)
    return non, wall * non


def _densities(pbs: list[Problem], analytic: Array, best: Outputs | None) -> Array:
    """Density [1/Pa] at ``p_out``: the free Gaussian in the analytic start, the march after."""
    pb = pbs[0]
    tau = pb.tau
    num = ~analytic
    P = np.zeros((len(pbs), tau.size, pb.p_out.size))
    for i, p in enumerate(pbs):
        for j in np.flatnonzero(analytic & (tau > 0)):
            t = tau[j]
            P[i, j] = np.exp(-((p.p_out - p.p0) ** 2) / (4 * t)) / math.sqrt(4 * math.pi * t)
    if best is not None and np.count_nonzero(num):
        P[:, num] = np.maximum(best.P, 0.0)
    return P
