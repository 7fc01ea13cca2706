"""The compiled set-up of the sub-problems' nodes (:mod:`xpersson.physics._sub_nodes`): the
numpy path's bits (``_sub_prep``: the panels, ``I3`` and ``C`` from one segment search,
``_delta_I3``'s midpoint form near the cut-off, the kernel), with the kernels as plain Python
and compiled."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from xpersson_core_reference import random_spectrum

import xpersson
from xpersson.physics import _compiled, _sub_nodes, _subgap
from xpersson.physics._self_affine import SelfAffineRollOff

_PLAIN = {fn.__name__: fn for fn in _sub_nodes.KERNELS}


def _kernels(compiled: bool):
    """The kernels by name: numba's (skipped without it) or their plain-Python forms."""
    if not compiled:
        return lambda work, name: _PLAIN[name]
    pytest.importorskip("numba")
    if _compiled.kernel(math.inf, "node_segments") is None:
        pytest.skip("compiled kernels are off (XPERSSON_COMPILED=off)")
    return lambda work, name: _compiled.kernel(math.inf, name)


def _numpy_prep(psd, E_star, qa, q_hi):
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(_subgap, "_compiled_prep", lambda *args: None)
        return _subgap._sub_prep(psd, E_star, qa, q_hi)


@pytest.mark.parametrize("compiled", [False, True])
@settings(max_examples=25, deadline=None)
@given(st.integers(0, 2**32 - 1), st.booleans(), st.integers(1, 12), st.booleans())
def test_kernels_give_the_numpy_bits(compiled, seed, table, n_load, per_load):
    """Per-load pairs of cut-offs (``separation_at``) and cut-offs shared by every load (the
    detachment's edges), some at ``q_L``, at ``q_hi`` (``V = 0``) and at breakpoints: every
    ``ln tau_c`` and kernel value bit for bit the numpy path's."""
    fns = _kernels(compiled)
    rng = np.random.default_rng(seed)
    psd = random_spectrum(rng, table)
    q_hi = psd.q_L * (psd.q_1 / psd.q_L) ** rng.uniform(0.3, 1.0)
    zeta = (q_hi / psd.q_L) ** rng.uniform(0, 1.0, (n_load, 2) if per_load else (1, n_load))
    qa = zeta * psd.q_L
    flat = qa.reshape(-1)
    flat[rng.random(flat.size) < 0.1] = psd.q_L
    flat[rng.random(flat.size) < 0.1] = q_hi
    inside = psd.nodes()[(psd.nodes() >= psd.q_L) & (psd.nodes() <= q_hi)]
    flat[rng.random(flat.size) < 0.1] = rng.choice(inside)
    want = _numpy_prep(psd, 1e9, qa, q_hi)
    V = np.log(np.maximum(q_hi / qa, 1.0))
    rule = (_subgap._SUB_EDGES, *_subgap._gauss(_subgap._SUB_ORDER))
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(_subgap, "kernel", fns)
        got = _subgap._compiled_prep(psd, 1e9, qa, V, rule)
    assert got is not None
    for g, w in zip(got, want, strict=True):
        assert g.shape == w.shape and g.tobytes() == w.tobytes()


@pytest.mark.parametrize("compiled", [False, True])
@settings(max_examples=25, deadline=None)
@given(st.integers(0, 2**32 - 1), st.booleans())
def test_nodes_outside_the_support_give_the_numpy_bits(compiled, seed, table):
    """Cut-offs at and beyond the support's ends, ``q_hi = q_1`` (the zero-width panel at
    ``s = 1``: nodes rounded above ``q_1``) and ``q_hi`` beyond it: ``I3`` clipped and
    ``C = 0`` there, as ``PowerSpectrum.I3`` and ``C`` (the numpy path's bits); a NaN
    cut-off: no compiled set-up."""
    fns = _kernels(compiled)
    rng = np.random.default_rng(seed)
    psd = random_spectrum(rng, table)
    q_hi = psd.q_1 * rng.choice([1.0, 1.0, 1.3])
    qa = psd.q_L * (q_hi / psd.q_L) ** rng.uniform(0.0, 1.0, (3, 2))
    qa.flat[:4] = [psd.q_L, psd.q_1, psd.q_L * 0.9, psd.q_1 * 1.1]
    rng.shuffle(qa.reshape(-1))
    want = _numpy_prep(psd, 1e9, qa, q_hi)
    V = np.log(np.maximum(q_hi / qa, 1.0))
    rule = (_subgap._SUB_EDGES, *_subgap._gauss(_subgap._SUB_ORDER))
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(_subgap, "kernel", fns)
        got = _subgap._compiled_prep(psd, 1e9, qa, V, rule)
        assert got is not None
        for g, w in zip(got, want, strict=True):
            assert g.tobytes() == w.tobytes()
        qa[0, 1] = np.nan
        assert _subgap._compiled_prep(psd, 1e9, qa, V, rule) is None


def test_off_switch_and_unbuilt_kernels_keep_numpy():
    """With the kernels off, or not built yet (the set-up never builds them: its callers count
    the work), the numpy path."""
    psd = SelfAffineRollOff.from_h_rms(1e-6, 0.8, 1e3, 1e4, 1e7)
    qa = np.array([[2e3, 3e3]])
    V = np.log(np.maximum(1e7 / qa, 1.0))
    rule = (_subgap._SUB_EDGES, *_subgap._gauss(_subgap._SUB_ORDER))
    with xpersson.set_options(compiled=False):
        assert _subgap._compiled_prep(psd, 1e9, qa, V, rule) is None
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(_compiled, "_STATE", {})  # nothing built, no numpy work counted
        assert _subgap._compiled_prep(psd, 1e9, qa, V, rule) is None
        assert _compiled._STATE.get("numpy", 0.0) == 0.0
