"""Independent references for the effective-medium leakage outputs (imported by ``verify.py``).

Two references for ``leak_flow_factor_emt``, ``leak_rate_emt`` and ``leak_sealed_emt``
(physics.md §6.2), written from the formulas, none of the library's EMT code:

1. **Continuous effective medium.** The gap distribution of {cite:p}`almqvist2011` is kept as a
   continuous mixture over the magnification (no bins): at each node of a composite
   Gauss-Legendre rule in ``t = ln(zeta - 1)`` the detached area ``-dA/dt`` is analytic (Persson's
   erf area, the spectrum's moment in closed form with ``expm1`` near ``zeta = 1``), ``u1 =
   d(A u_zeta)/dA`` is a central difference of the exponential-integral mean gap computed by
   adaptive quadrature (``verify_interface.mean_gap``), ``h(zeta)^2`` is the closed-form moment.
   Each node's folded normal is integrated against ``(u^3 - s)/(u^3 + s)`` by Gauss-Legendre
   panels split at the conductance knee ``s^(1/3)`` and at ``u1 +- k h``; the Bruggeman root
   ``s = <u^3>_EMT`` is found with ``brentq`` in ``ln s`` (the library uses geometric u-cells
   with midpoint conductances and a bracketed Newton iteration).
2. **Random-resistor network** (``network_rows``): bonds of a square lattice carry conductance
   ``u^3`` with ``u`` drawn from the same distribution (contact: 0); Kirchhoff's equations are
   solved with a sparse direct solver, and the network's conductance is compared with the
   Bruggeman value. This checks the *theory* (Bruggeman's EMT is accurate for such networks away
   from the bond percolation threshold 1/2), not the code.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.optimize import brentq
from scipy.special import erf, erfinv
from verify_core import E_STAR, _rel, _row
from verify_interface import I3, README, Ref, _solve, mean_gap

_GL_X, _GL_W = np.polynomial.legendre.leggauss(20)
#: leakage defaults: L_y / L_x, pressure drop [Pa], viscosity [Pa s]
_GEOM, _DP, _ETA = 1e-2 / 1e-3, 1e5, 1e-3


def _tau(ref: Ref, eps: float) -> float:
    """(pi/4) E*^2 int_{q_L}^{q_L(1+eps)} q^3 C, exact for tiny eps (expm1)."""
    q = ref.q_L * (1.0 + eps)
    if q <= ref.q_r:
        m = 0.25 * ref.C0 * ref.q_L**4 * math.expm1(4.0 * math.log1p(eps))
    else:
        m = float(I3(ref, q))
    return 0.25 * math.pi * E_STAR**2 * m


def _dtau_deps(ref: Ref, eps: float) -> float:
    q = ref.q_L * (1.0 + eps)
    return 0.25 * math.pi * E_STAR**2 * q**3 * float(ref.C(q)) * ref.q_L


def _h2(ref: Ref, eps: float) -> float:
    """2 pi int_{q_L(1+eps)}^{q_1} q C dq (closed form: plateau, then power law)."""
    qa = ref.q_L * (1.0 + eps)
    H, qr, q1 = ref.H, ref.q_r, ref.q_1
    plateau = 0.5 * (qr**2 - qa**2) if qa < qr else 0.0
    lo = max(qa, qr)
    tail = qr ** (2 + 2 * H) * (lo ** (-2 * H) - q1 ** (-2 * H)) / (2 * H)
    return 2.0 * math.pi * ref.C0 * (plateau + tail)


def _area(ref: Ref, p0: float, eps: float) -> float:
    t = _tau(ref, eps)
    return 1.0 if t <= 0 else float(erf(p0 / (2.0 * math.sqrt(t))))


def _neg_dA_dt(ref: Ref, p0: float, eps: float) -> float:
    """-dA/d ln(eps) (analytic)."""
    t = _tau(ref, eps)
    x = p0 / (2.0 * math.sqrt(t))
    dA_dtau = (2.0 / math.sqrt(math.pi)) * math.exp(-x * x) * x / (2.0 * t)
    return dA_dtau * _dtau_deps(ref, eps) * eps


def _u1(ref: Ref, p0: float, eps: float, dt: float = 2e-3) -> float:
    """d(A u_zeta)/dA: central difference of A u_zeta in ln(eps) (u_zeta by quadrature) over
    the analytic dA/d ln(eps) (a difference of A loses all digits where A is near 1, where
    the removal of roughness still lowers A u_zeta: tiny weights at large u1)."""
    vals = []
    for e in (eps * math.exp(-dt), eps * math.exp(dt)):
        A = _area(ref, p0, e)
        vals.append(A * mean_gap(ref, p0 / A, ref.q_L * (1.0 + e)))
    slope = _neg_dA_dt(ref, p0, eps)
    return (vals[0] - vals[1]) / (2.0 * dt) / slope if slope > 0 else 0.0


def mixture(ref: Ref, p0: float, panels: int = 24, order: int = 8) -> dict:
    """Nodes of the continuous gap distribution: weight (detached area), u1, h; contact A1."""
    eps1 = ref.q_1 / ref.q_L - 1.0
    tau1 = _tau(ref, eps1)
    A1 = float(erf(p0 / (2.0 * math.sqrt(tau1))))
    # lower end: A = 1 - 1e-14 (tau small, linear in eps there)
    tau_lo = (p0 / (2.0 * erfinv(1.0 - 1e-14))) ** 2
    eps_lo = math.exp(
        brentq(lambda t: _tau(ref, math.exp(t)) - tau_lo, -80.0, math.log(eps1), xtol=1e-12)
    )
    x, w = np.polynomial.legendre.leggauss(order)
    knot = math.log(ref.q_r / ref.q_L - 1.0) if ref.q_r > ref.q_L * (1 + eps_lo) else None
    if knot is not None and math.log(eps_lo) < knot < math.log(eps1):  # the roll-off kink
        n = max(2, round(panels * (knot - math.log(eps_lo)) / (math.log(eps1 / eps_lo))))
        edges = np.concatenate(
            (
                np.linspace(math.log(eps_lo), knot, n + 1)[:-1],
                np.linspace(knot, math.log(eps1), panels - n + 1),
            )
        )
    else:
        edges = np.linspace(math.log(eps_lo), math.log(eps1), panels + 1)
    # grade towards zeta_1, where h ~ sqrt(zeta_1 - zeta) (a square-root endpoint)
    a, b = edges[-2], edges[-1]
    edges = np.concatenate((edges[:-1], b - (b - a) * 0.25 ** np.arange(1, 16), [b]))
    t = (0.5 * (edges[1:] - edges[:-1])[:, None] * (x + 1) + edges[:-1, None]).ravel()
    wt = (0.5 * (edges[1:] - edges[:-1])[:, None] * w).ravel()
    eps = np.exp(t)
    weight = wt * np.array([_neg_dA_dt(ref, p0, e) for e in eps])
    u1 = np.array([_u1(ref, p0, e) if m > 1e-18 else 0.0 for e, m in zip(eps, weight, strict=True)])
    h = np.sqrt([_h2(ref, e) for e in eps])
    return {"A1": A1, "weight": weight, "u1": u1, "h": h, "mass": float(weight.sum()) + A1}


def _expect(u1: np.ndarray, h: np.ndarray, s: float, g=None) -> np.ndarray:
    """E[g(u)] per node over the folded normal |N(u1, h^2)|; g = (u^3 - s)/(u^3 + s)."""
    c = s ** (1.0 / 3.0)
    lo, hi = u1 - 9.0 * h, u1 + 9.0 * h
    ks = (-9.0, -4.0, -2.0, -1.0, 0.0, 1.0, 2.0, 4.0, 9.0)
    knots = [u1 + k * h for k in ks] + [np.full_like(u1, c * f) for f in (1 / 16, 0.25, 1, 4, 16)]
    b = np.sort(np.clip(np.stack([np.zeros_like(u1), *knots], axis=1), 0.0, hi[:, None]), axis=1)
    del lo
    a0, a1 = b[:, :-1, None], b[:, 1:, None]
    u = 0.5 * (a1 - a0) * (_GL_X + 1.0) + a0  # (n, panels, 20)
    wq = 0.5 * (a1 - a0) * _GL_W
    hh = h[:, None, None]
    m = u1[:, None, None]
    dens = (np.exp(-0.5 * ((u - m) / hh) ** 2) + np.exp(-0.5 * ((u + m) / hh) ** 2)) / (
        hh * math.sqrt(2 * math.pi)
    )
    u3 = u**3
    val = 1.0 - 2.0 * s / (u3 + s) if g is None else g(u)  # = (u^3 - s)/(u^3 + s)
    return np.sum(wq * dens * val, axis=(1, 2))


def emt(mix: dict, a_c: float | None = None) -> float:
    """<u^3>_EMT [m^3] of the continuous mixture (0 when the contact percolates)."""
    A1, w = mix["A1"], mix["weight"]
    if a_c is not None:  # contact weight x 0.5/a_c, open weights rescaled to unit total
        a_new = min(1.0, A1 * 0.5 / a_c)
        w = w * ((1.0 - a_new) / (1.0 - A1) if A1 < 1.0 else 0.0)
        A1 = a_new
    if A1 >= 0.5 * (1.0 - 1e-12):  # at the threshold itself sigma_eff -> 0
        return 0.0
    use = w > 0
    w, u1, h = w[use], mix["u1"][use], mix["h"][use]

    def res(ls: float) -> float:
        return -A1 + float(np.sum(w * _expect(u1, h, math.exp(ls))))

    scale = float(np.sum(w * (u1 + h)))
    lo, hi = 3 * math.log(scale) - 120.0, 3 * math.log(scale) + 30.0
    return math.exp(brentq(res, lo, hi, xtol=1e-13, rtol=1e-13, maxiter=300))


#: regimes of the EMT rows: (name, A/A0(zeta_1) targets full, fast, note)
_REGIMES = (
    (
        "A/A0 1e-6 .. 1e-2 (light)",
        (1e-6, 1e-4, 1e-2),
        (1e-3,),
        "was 13-16 % (the code's: the detachment bins' u(zeta), physics _subgap._sub_mean_gap, ran"
        " its rule across the roll-off kink, 5.6-6.7 % low; fixed by splitting at the PSD"
        " breakpoints); the library's EMT root on this reference's mixture agrees to 6e-5",
    ),
    ("A/A0 0.1 .. 0.3", (0.1, 0.3), (0.1, 0.3), ""),
    (
        "A/A0 0.41 .. 0.49 (near the threshold: 1/2, or a_c 0.42 rescaled to 1/2)",
        (0.41, 0.45, 0.49),
        (),
        "discretisation: sigma_eff ~ (1/2 - weight) amplifies the bin error; n_bins 400 gives"
        " 1 % at 0.45, 12 % at 0.49 (plain threshold)",
    ),
    ("sealed: A/A0 0.6 .. 1 - 1e-10", (0.6, 0.9, 1 - 1e-6, 1 - 1e-10), (0.7,), ""),
)


def _regime_errors(ref: Ref, targets: tuple, panels: int) -> dict:
    """Worst relative errors (flow factor, rate) and flag mismatches over both thresholds."""
    tau1 = _tau(ref, ref.q_1 / ref.q_L - 1.0)
    loads = [2 * math.sqrt(tau1) * erfinv(a) for a in targets]
    mixes = [mixture(ref, p, panels=panels) for p in loads]
    ubar = np.array([mean_gap(ref, p) for p in loads])
    out = {"ff": 0.0, "rate": 0.0, "sealed": 0.0, "zero": 0.0, "mass": 0.0, "at": ""}
    for thr, a_c in (("bruggeman", None), ("a_c", 0.42)):
        ds = _solve(ref, loads, {"leakage": {"emt_threshold": thr}})
        s = np.array([emt(m, a_c) for m in mixes])
        op = s > 0
        got_ff = ds["leak_flow_factor_emt"].values
        got_rate = ds["leak_rate_emt"].values
        for i in np.flatnonzero(op):
            e = abs(got_ff[i] / (s[i] / ubar[i] ** 3) - 1)
            if e > out["ff"]:
                out["ff"], out["at"] = e, f"worst at A/A0 {targets[i]:g} ({thr})"
        out["rate"] = max(out["rate"], _rel(got_rate[op], _GEOM * s[op] * _DP / (12 * _ETA)))
        out["zero"] = max(out["zero"], float(np.max(np.abs(got_rate[~op]), initial=0.0)))
        out["zero"] = max(out["zero"], float(np.max(np.abs(got_ff[~op]), initial=0.0)))
        out["sealed"] += float(np.sum(ds["leak_sealed_emt"].values != (~op).astype(int)))
    out["mass"] = max(abs(m["mass"] - 1.0) for m in mixes)
    return out


def emt_rows(fast: bool) -> list[dict]:
    """leak_*_emt against the continuous effective medium, plain and a_c thresholds."""
    rows = []
    flags = 0.0
    for name, full, small, note in _REGIMES:
        targets = small if fast else full
        if not targets:
            continue
        e = _regime_errors(README, targets, 16 if fast else 32)
        flags += e["sealed"]
        pts = ", ".join(f"{t:.10g}" for t in targets)
        regime = f"{name} [A/A0 = {pts}], README spectrum, thresholds 1/2 and a_c 0.42"
        refname = (
            f"continuous Bruggeman (GL in ln(zeta-1), u1 by quad, brentq; mass {e['mass']:.0e})"
        )
        if name.startswith("sealed"):
            rows.append(_row("leak_flow_factor_emt, leak_rate_emt", regime, "exactly 0 when"
                             " the contact weight reaches 1/2", e["zero"], "abs"))  # fmt: skip
            continue
        rows.append(_row("leak_flow_factor_emt", regime, refname, e["ff"], "rel",
                         "; ".join(x for x in (e["at"], note) if x)))  # fmt: skip
        rows.append(_row("leak_rate_emt", regime, refname, e["rate"], "rel"))
    tgt = [t for _, full, small, _ in _REGIMES for t in (small if fast else full)]
    regime = f"A/A0 {min(tgt):g} .. {max(tgt):.10g}, both thresholds"
    ref = "contact weight >= 1/2 (after the a_c rescaling)"
    rows.append(_row("leak_sealed_emt", regime, ref, flags, "mismatches"))
    return rows


def _sample_u(mix: dict, n: int, rng: np.random.Generator) -> np.ndarray:
    """n gaps drawn from the continuous mixture (0 for contact)."""
    p = np.append(mix["weight"], mix["A1"])
    p = np.maximum(p, 0.0) / p.sum()
    k = rng.choice(p.size, size=n, p=p)
    u = np.zeros(n)
    o = k < mix["weight"].size
    u[o] = np.abs(rng.normal(mix["u1"][k[o]], mix["h"][k[o]]))
    return u


def network_conductance(sigma_h: np.ndarray, sigma_v: np.ndarray) -> float:
    """Conductance of an L x L square bond network between two bus bars (periodic across).

    ``sigma_h[i, j]``: bond (i, j)-(i+1, j), i = 0..L-1 along the flow; ``sigma_v[i, j]``:
    (i, j)-(i, j+1 mod L), i = 1..L-1. Potential 1 at column 0, 0 at column L; returns the
    current, which for uniform bonds equals the bond conductance (a square network).
    """
    from scipy.sparse import coo_matrix
    from scipy.sparse.linalg import spsolve

    L = sigma_h.shape[1]
    n = (L - 1) * L  # unknown columns 1..L-1
    idx = lambda i, j: (i - 1) * L + (j % L)  # noqa: E731
    rows, cols, vals = [], [], []
    diag = np.zeros(n)
    rhs = np.zeros(n)
    for i in range(L):  # horizontal bonds between columns i and i+1
        for j in range(L):
            s = sigma_h[i, j]
            a, b = i, i + 1
            if 1 <= a <= L - 1:
                diag[idx(a, j)] += s
            if 1 <= b <= L - 1:
                diag[idx(b, j)] += s
            if 1 <= a <= L - 1 and 1 <= b <= L - 1:
                rows += [idx(a, j), idx(b, j)]
                cols += [idx(b, j), idx(a, j)]
                vals += [-s, -s]
            if a == 0 and 1 <= b <= L - 1:
                rhs[idx(b, j)] += s  # neighbour at potential 1
    for i in range(1, L):
        for j in range(L):
            s = sigma_v[i - 1, j]
            p, q = idx(i, j), idx(i, j + 1)
            diag[p] += s
            diag[q] += s
            rows += [p, q]
            cols += [q, p]
            vals += [-s, -s]
    m = coo_matrix((vals + list(diag), (rows + list(range(n)), cols + list(range(n)))), (n, n))
    V = spsolve(m.tocsc(), rhs).reshape(L - 1, L)
    return float(np.sum(sigma_h[0] * (1.0 - V[0])))


def network_rows(fast: bool) -> list[dict]:
    """Bruggeman (the model) against a random-resistor network of the same gap distribution."""
    targets = (0.1, 0.3) if fast else (1e-3, 0.1, 0.3, 0.4, 0.45)
    L, reps = (32, 2) if fast else (96, 4)
    tau1 = _tau(README, README.q_1 / README.q_L - 1.0)
    rng = np.random.default_rng(7)
    worst, where = 0.0, ""
    binary = []  # the code's check: 0/1 bonds, Bruggeman 1 - 2a, a = 0.25 -> 0.5
    for _ in range(reps):
        u = (rng.random(2 * L * L) > 0.25).astype(float) + 1e-14
        binary.append(network_conductance(u[: L * L].reshape(L, L), u[L * L :].reshape(L, L)[:-1]))
    for a in targets:
        mix = mixture(README, 2 * math.sqrt(tau1) * erfinv(a), panels=16)
        s = emt(mix)
        g = []
        for _ in range(reps):
            u = _sample_u(mix, 2 * L * L, rng) ** 3 / s
            sh = u[: L * L].reshape(L, L)
            sv = u[L * L :].reshape(L, L)[: L - 1]
            floor = 1e-14 * float(np.max(u))  # isolated clusters: a regular matrix
            g.append(network_conductance(sh + floor, sv + floor))
        ratio = float(np.exp(np.mean(np.log(g))))
        f = max(ratio, 1 / ratio)
        if f > worst:
            worst, where = f, f"worst at A/A0 {a:g}: network/EMT {ratio:.3g}"
    pts = ", ".join(f"{t:g}" for t in targets)
    return [
        _row(
            "leak_flow_factor_emt (network)",
            f"A/A0 = {pts}; {L}^2 bonds x {reps}, README spectrum, threshold 1/2",
            "random-resistor network, bonds u^3 drawn from the same gap mixture (spsolve;"
            f" 0/1 bonds at a = 0.25 give {np.mean(binary):.3f}, Bruggeman 0.5)",
            worst,
            "factor",
            f"{where}; the theory's: Bruggeman is exact only for narrow distributions, and"
            " u^3 spans decades here",
        )
    ]
