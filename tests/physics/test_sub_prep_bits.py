"""The sub-problems' set-up (``_sub_prep``) takes ``I3`` and ``C`` from one segment search
(``PowerSpectrum._I3_and_C``) and sorts the panel edges once where every cut-off shares them:
the same bits as the plain formulas (``I3``, ``C``, ``_delta_I3``, each cut-off's own sort)."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from xpersson_core_reference import random_spectrum

from xpersson.physics._curve import _delta_I3, _gauss
from xpersson.physics._subgap import _SUB_EDGES, _SUB_ORDER, _sub_prep


def _plain_prep(psd, E_star, qa, q_hi):
    """The plain form: each cut-off's own sorted edges, ``_delta_I3`` and ``C``."""
    V = np.log(np.maximum(q_hi / qa, 1.0))
    nodes = psd.nodes()
    with np.errstate(divide="ignore", invalid="ignore"):
        sk = np.sqrt(np.clip(np.log(nodes / qa[..., None]) / V[..., None], 0.0, 1.0))
    sk = np.where(V[..., None] > 0.0, sk, 0.0)
    base = np.broadcast_to(_SUB_EDGES, qa.shape + _SUB_EDGES.shape)
    edges = np.sort(np.concatenate((base, sk), axis=-1), axis=-1)
    x, w = _gauss(_SUB_ORDER)
    a, b = edges[..., :-1, None], edges[..., 1:, None]
    s, ws = (a + (b - a) * x).reshape(qa.shape + (-1,)), ((b - a) * w).reshape(qa.shape + (-1,))
    q = qa[..., None] * np.exp(V[..., None] * s * s)
    dq = q * (2.0 * V[..., None] * s) * ws
    dI3 = _delta_I3(psd, qa[..., None], q)
    C = np.asarray(psd.C(q.ravel()), dtype=float).reshape(q.shape)
    kern = dq * q**2 * C / np.sqrt(np.pi * dI3)
    return np.log(0.25 * np.pi * E_star**2 * dI3), kern


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 2**32 - 1), st.booleans(), st.integers(0, 400))
def test_I3_and_C_are_I3_and_C_bit_for_bit(seed, table, n_q):
    rng = np.random.default_rng(seed)
    psd = random_spectrum(rng, table)
    nodes = psd.nodes()
    if rng.random() < 0.5:  # inside one segment
        k = rng.integers(nodes.size - 1)
        qs = nodes[k] * (nodes[k + 1] / nodes[k]) ** rng.uniform(0, 1, n_q)
    else:
        qs = psd.q_L * (psd.q_1 / psd.q_L) ** rng.uniform(0, 1, n_q)
        if n_q:  # the ends and the breakpoints themselves
            qs[rng.integers(n_q)] = nodes[rng.integers(nodes.size)]
    both = psd._I3_and_C(qs)
    if n_q == 0:
        assert both is None
        return
    assert both[0].tobytes() == np.asarray(psd.I3(qs)).tobytes()
    assert both[1].tobytes() == np.asarray(psd.C(qs)).tobytes()
    assert psd._I3_and_C(qs, moment=False)[1].tobytes() == both[1].tobytes()
    qs[rng.integers(n_q)] = psd.q_1 * 1.5 if rng.random() < 0.5 else np.nan
    assert psd._I3_and_C(qs) is None  # outside the support: I3's clip and C's zero


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2**32 - 1), st.booleans(), st.integers(1, 30), st.booleans())
def test_sub_prep_is_the_plain_form_bit_for_bit(seed, table, n_load, per_load):
    rng = np.random.default_rng(seed)
    psd = random_spectrum(rng, table)
    q_hi = psd.q_1 / 10 ** rng.uniform(0, 1)
    zeta = (q_hi / psd.q_L) ** rng.uniform(0, 1.05, (n_load, 2) if per_load else (1, n_load))
    qa = zeta * psd.q_L
    got, want = _sub_prep(psd, 1e9, qa, q_hi), _plain_prep(psd, 1e9, qa, q_hi)
    for g, w in zip(got, want, strict=True):
        assert g.shape == w.shape and g.tobytes() == w.tobytes()
