"""A plain reference for one grid level of the engine's ``cn`` march: the same front-fixed
finite-volume Crank-Nicolson discretisation, written with dense matrices and
``numpy.linalg.solve``, one load at a time, no buffers, no tricks.

It shares nothing with the engine but its inputs (:class:`xpersson.engine._moving.LevelInputs`:
the nodes ``x``, the times, theta per step, and the window's edges and their speeds per step),
so that the engine's march (concatenated loads, block operators by one BLAS product, LAPACK
``dgtsv`` in place, wall fluxes summed after the march) can be checked against it.

The scheme (units: tau in Pa^2, p in Pa, speeds in 1/Pa; ``R = W P`` dimensionless), per
load, on nodes ``p_j = l + W x_j`` with control volumes ``w_j`` (trapezoid weights):

* face fluxes ``F_{j+1/2} = D (R_{j+1} - R_j) + A (R_j + R_{j+1})``, ``D = 1 / (W^2 dx)``,
  ``A = (l' + x_f W') / (2 W)``, with the edges at the start (old) or end (new) of the step;
* interior rows: ``w_j R'_j - wn (F'_{j+1/2} - F'_{j-1/2}) = w_j R_j + wo (F_{j+1/2} -
  F_{j-1/2})``, ``wn = theta dt``, ``wo = (1 - theta) dt``;
* wall rows ``R_0 = R_N = 0`` (absorbing walls and the window's artificial edges);
* a real yield wall ``Y`` at the upper edge: ``R_N = g A_pl`` (``g = W Y'`` at the end of the
  step), ``w_N R'_N + A'_pl + wn F'_{N-1/2} = w_N R_N + A_pl - wo F_{N-1/2}``;
* absorbed per step: ``wn F'_{1/2} + wo F_{1/2}`` by a real lower wall, ``-(wn F'_{N-1/2} +
  wo F_{N-1/2})`` by a real upper wall; their moments weight each half by the wall's position
  at its end of the step.
"""

from __future__ import annotations

import math

import numpy as np


def _weights(x):
    """Face midpoints, spacings and control volumes of the nodes ``x``."""
    dx = np.diff(x)
    w = np.zeros(x.size)
    for j in range(x.size - 1):
        w[j] += dx[j] / 2
        w[j + 1] += dx[j] / 2
    return (x[1:] + x[:-1]) / 2, dx, w


def _flux_matrix(xf, dx, l, W, lv, wv, W2=None):
    """``F = Phi R``: the face fluxes (faces x nodes) for the edges ``l, W`` [Pa] moving at
    ``lv, wv`` [1/Pa]; ``W2`` [Pa^2] in ``D = 1 / (W2 dx)`` if given (else ``W^2``)."""
    nf = xf.size
    D = 1.0 / ((W**2 if W2 is None else W2) * dx)
    A = (lv + xf * wv) / (2.0 * W)
    phi = np.zeros((nf, nf + 1))
    phi[np.arange(nf), np.arange(nf)] = A - D
    phi[np.arange(nf), np.arange(nf) + 1] = A + D
    return phi


def _divergence(nn):
    """``(F_{j+1/2} - F_{j-1/2})`` per node (nodes x faces); the wall rows are replaced."""
    div = np.zeros((nn, nn - 1))
    for j in range(1, nn - 1):
        div[j, j] = 1.0
        div[j, j - 1] = -1.0
    return div


def reference_level(inp) -> dict[str, np.ndarray]:
    """The outputs ``(loads, outputs)`` of one level: ``area``, ``absorbed_lower``,
    ``absorbed_upper``, ``load``, ``moment_lower``, ``moment_upper``."""
    x = np.asarray(inp.nodes.x, dtype=float)
    taus, theta, out_at = inp.taus, inp.theta, list(inp.out_at)
    win = inp.window
    nb = win.real_lower.shape[0]
    names = ("area", "absorbed_lower", "absorbed_upper", "load", "moment_lower", "moment_upper")
    out = {k: np.zeros((nb, len(out_at))) for k in names}
    for b in range(nb):
        rows = _one_load(x, taus, theta, out_at, win, b, float(inp.p0[b, 0]), inp.k, inp.yield_wall)
        for k in names:
            out[k][b] = rows[k]
    return out


def _one_load(x, taus, theta, out_at, win, b, p0, k, yield_wall):
    xf, dx, w = _weights(x)
    nn = x.size
    N = nn - 1
    M = np.diag(w)
    div = _divergence(nn)
    s, e = win.start, win.end
    # the free Gaussian at the first time, normalised to the window mass erf(k / sqrt 2)
    t0 = taus[0]
    p = s.lower[b, 0] + s.width[b, 0] * x
    R = s.width[b, 0] * np.exp(-((p - p0) ** 2) / (4 * t0)) / math.sqrt(4 * math.pi * t0)
    R[0] = R[-1] = 0.0
    R *= math.erf(k / math.sqrt(2.0)) / (w @ R)
    a_pl = abs_l = abs_u = mom_l = mom_u = 0.0
    res = {key: [] for key in ("area", "absorbed_lower", "absorbed_upper", "load")}
    res.update(moment_lower=[], moment_upper=[])

    def record(m):
        if m == 0:
            lo, wd = s.lower[b, 0], s.width[b, 0]
        else:
            lo, wd = e.lower[b, m - 1], e.width[b, m - 1]
        res["area"].append(w @ R)
        res["load"].append(w @ ((lo + wd * x) * R))
        res["absorbed_lower"].append(abs_l)
        res["moment_lower"].append(mom_l)
        res["absorbed_upper"].append(a_pl if yield_wall else abs_u)
        res["moment_upper"].append((lo + wd) * a_pl if yield_wall else mom_u)

    for j in [j for j in out_at if j == 0]:
        record(j)
    for m in range(taus.size - 1):
        dt = taus[m + 1] - taus[m]
        wn, wo = theta[m] * dt, (1.0 - theta[m]) * dt
        old = (s.lower[b, m], s.width[b, m], s.lower_speed[b, m], s.width_speed[b, m])
        new = (e.lower[b, m], e.width[b, m], e.lower_speed[b, m], e.width_speed[b, m])
        # a real yield wall: the diffusion of both halves takes 1 / (W_start W_end)
        # (``_moving_block.symmetrize``)
        sym = yield_wall and bool(win.real_upper[b, m])
        w2 = s.width[b, m] * e.width[b, m] if sym else None
        phi_old, phi_new = _flux_matrix(xf, dx, *old, w2), _flux_matrix(xf, dx, *new, w2)
        F_old = phi_old @ R
        lhs = M - wn * div @ phi_new
        rhs = M @ R + wo * div @ F_old
        # the wall rows: R_0 = R_N = 0
        lhs[0, :] = 0.0
        lhs[0, 0] = 1.0
        rhs[0] = 0.0
        lhs[N, :] = 0.0
        lhs[N, N] = 1.0
        rhs[N] = 0.0
        real_yield = yield_wall and bool(win.real_upper[b, m])
        if real_yield:  # R_N = g A_pl with the half cell's mass balance, times g
            g = e.width[b, m] * e.yield_speed[b, m]
            lhs[N, :] = g * wn * phi_new[N - 1]
            lhs[N, N] += 1.0 + g * w[N]
            rhs[N] = g * (w[N] * R[N] + a_pl - wo * F_old[N - 1])
        R_new = np.linalg.solve(lhs, rhs)
        F_new = phi_new @ R_new
        if real_yield:
            a_pl += w[N] * (R[N] - R_new[N]) - wo * F_old[N - 1] - wn * F_new[N - 1]
        if win.real_lower[b, m]:
            abs_l += wn * F_new[0] + wo * F_old[0]
            mom_l += e.lower[b, m] * wn * F_new[0] + s.lower[b, m] * wo * F_old[0]
        if win.real_upper[b, m] and not yield_wall:
            abs_u -= wn * F_new[N - 1] + wo * F_old[N - 1]
            up_new, up_old = e.lower[b, m] + e.width[b, m], s.lower[b, m] + s.width[b, m]
            mom_u -= up_new * wn * F_new[N - 1] + up_old * wo * F_old[N - 1]
        R = R_new
        for _ in [j for j in out_at if j == m + 1]:
            record(m + 1)
    return {key: np.array(v) for key, v in res.items()}
