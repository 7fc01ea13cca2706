"""The friction integral on graded panels (_graded): the kernel's friction_curve to ~1e-9,
the output magnifications as panel edges, node values shared with the output grid's integrals
equal to fresh ones, and Prony.parts independent of where a frequency sits in a call."""

from __future__ import annotations

import numpy as np
import pytest

from xpersson.physics import SelfAffineRollOff, area_fraction
from xpersson_viscoelastic import _graded, friction_curve, kernel, sls, synthetic_tread
from xpersson_viscoelastic._paired import block_integrals

PSD = SelfAffineRollOff.from_h_rms(6e-5, 0.8, 600.0, 3000.0, 1e7)
ZETA = np.geomspace(1.0, 1e4, 81)  # 20 per decade
NU = 0.5
P0 = np.array([1e5, 3e5])


def _graded_mu(model, scale: float, top: int) -> tuple[np.ndarray, _graded.Layout, np.ndarray]:
    """mu_visc_cumulative at ZETA[: top + 1] on graded panels with the Persson 2001 area."""
    G = kernel.diffusion_time(PSD, model, NU, ZETA, scale, 1.0)[None, :] / P0[:, None] ** 2
    lay = _graded.layout(PSD, ZETA, top, _graded.rungs(ZETA, G, top), 4)
    tau, dL = _graded.integrals(PSD, model, NU, lay, scale * lay.qn[None, :])
    A, _ = area_fraction(P0[:, None], tau)
    return _graded.running(A, np.repeat(dL, P0.size, axis=0), lay, P0), lay, tau[0]


@pytest.mark.parametrize("model", [synthetic_tread(), sls(3e6, 3e9, 1e-3)])
@pytest.mark.parametrize("scale", [1e-6, 1e-2, 1.0, 30.0])
def test_graded_panels_give_the_kernel_friction(model, scale):
    top = 40  # zeta = 100
    mu, lay, tau = _graded_mu(model, scale, top)
    ref = friction_curve(PSD, model, NU, P0, [scale], [1.0], zeta_max=ZETA[top])["mu_visc"]
    np.testing.assert_allclose(mu[:, -1], ref[0, 0], rtol=1e-9)
    # every output magnification up to the top is a panel edge, nodes strictly inside
    np.testing.assert_array_equal(lay.edges[lay.out], ZETA[: top + 1] * PSD.q_L)
    assert np.all(np.diff(lay.qn) > 0) and lay.qn[0] > PSD.q_L
    # tau at the nodes is the diffusion time there (away from q_L, where I3 loses digits), to
    # the spectral running integral's accuracy inside the 8-node panels (as in the kernel)
    far = lay.zeta > 1.1
    want = kernel.diffusion_time(PSD, model, NU, lay.zeta[far], scale, 1.0)
    np.testing.assert_allclose(tau[far], want, rtol=5e-8)
    # the running integral at each output point: the kernel up to that magnification (each
    # ~1e-9 from an independent quadrature, benchmarks/verify_friction.py)
    for j in (5, 20):
        ref_j = friction_curve(PSD, model, NU, P0, [scale], [1.0], zeta_max=ZETA[j])["mu_visc"]
        np.testing.assert_allclose(mu[:, j], ref_j[0, 0], rtol=1e-8)


def test_rungs_reach_small_G_and_grow_with_the_slope():
    G = np.outer([1.0], ZETA - 1.0)  # dG/dzeta = 1
    n1 = _graded.rungs(ZETA, G, 40)
    assert n1 % 2 == 0  # even: fewer groups of shared panels
    assert 10.0 ** (-n1 / 2.0) <= _graded.FIRST_G < 10.0 ** (-(n1 - 2) / 2.0)
    assert _graded.rungs(ZETA, 100.0 * G, 40) == n1 + 4  # two rungs per decade of slope
    assert _graded.rungs(ZETA, 0.0 * G, 40) == 2


def test_shared_node_values_equal_fresh_ones():
    model = synthetic_tread()
    v, aT = np.array([1e-3, 0.1, 10.0]), np.array([1.0, 2.0, 0.5])
    keep: dict = {}
    block_integrals(PSD, model, NU, ZETA, v, aT, 4, keep)
    lay = _graded.layout(PSD, ZETA, 40, 6, 4)
    assert (lay.block >= 0).sum() > 20  # most panels above 2 q_L are the output grid's
    rows = np.array([2, 0])
    w = (v * aT)[rows, None] * lay.qn[None, :]
    known = _graded.known_nodes((v, aT, keep), v[rows], aT[rows], rows)
    shared = _graded.integrals(PSD, model, NU, lay, w, known)
    fresh = _graded.integrals(PSD, model, NU, lay, w)
    for a, b in zip(shared, fresh, strict=True):
        np.testing.assert_array_equal(a, b)
    # another block's values are not taken
    assert _graded.known_nodes((v, aT, keep), v[:2], aT[:2], rows) is None


def test_prony_parts_do_not_depend_on_the_position_in_a_call():
    model = synthetic_tread()
    w = np.geomspace(1e-4, 1e10, 9001)  # > one pass of 4096
    excess, loss = model.parts(w)
    rng = np.random.default_rng(3)
    for _ in range(30):
        a = int(rng.integers(0, w.size - 1))
        b = int(rng.integers(a + 1, min(w.size, a + 300) + 1))
        e, s = model.parts(w[a:b])
        np.testing.assert_array_equal(e, excess[a:b])
        np.testing.assert_array_equal(s, loss[a:b])
    e, s = model.parts(w[:9000].reshape(9, 20, 50))  # any shape
    np.testing.assert_array_equal(e, excess[:9000].reshape(9, 20, 50))
    assert model.parts(np.empty((0, 3)))[0].shape == (0, 3)
