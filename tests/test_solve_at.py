"""``ctx.solve_at`` gives the same numbers on the fast and on the plain paths (issue 36).

An analysis that has tau(zeta) at its own magnifications (a block's stacked integral) passes it
as ``tau=``. Its numbers may differ from the coefficient's ``tau`` in the last digits (another
quadrature). The fast path (``shared_tau``) uses the given tau; the plain path asks every load's
effective tau and, where that is tau(zeta) (each row equal to the coefficient's tau), uses the
given tau too. A closure's effective tau depends on the load: both paths ignore the given tau.
"""

from __future__ import annotations

from typing import Any, ClassVar

import numpy as np
import pytest

import xpersson
from xpersson.plugins import Analysis, VarSpec, plain_paths
from xpersson.testing import registry_with

#: What the probe saw, per solve: (the coefficient's own tau, the given tau, the answer).
SEEN: list[tuple[np.ndarray, np.ndarray, dict[str, np.ndarray]]] = []
OFFSET = 1.0 + 3e-9
"""The given tau is the coefficient's times this (a stacked integral's last digits, enlarged)."""


class GivenTau(Analysis):
    """Samples the solve densely with a tau(zeta) of its own (test double)."""

    summary = "solve_at with a given tau (test double)"
    requires = ("area_fraction",)
    provides = ("probe_area",)
    outputs: ClassVar = {"probe_area": VarSpec(("p0",), "1", "dense area at the top (test)")}

    def compute(self, ctx: Any, ds: Any) -> dict[str, Any]:
        z = np.geomspace(1.0, float(ds["zeta"].values[-1]), 41)[1:]
        own = np.array(ctx.solve_at(z)["diffusion_time"])
        got = ctx.solve_at(z, tau=own * OFFSET)
        SEEN.append((own, own * OFFSET, {k: np.array(v) for k, v in got.items()}))
        return {"probe_area": (("p0",), np.asarray(got["area_fraction"])[:, -1])}


def _scene(closure: str) -> dict[str, Any]:
    spec = {"model": "self_affine", "H": 0.8, "q_L": "1e3 1/m", "q_1": "1e6 1/m", "h_rms": "1 um"}
    return {
        "spectrum": spec,
        "material": {"E": "10 MPa", "nu": 0.5},
        "coefficient": {"model": "elastic", "closure": closure},
        "load": {"p0": ["30 kPa", "300 kPa", "3 MPa"]},
        "analyses": {"given_tau": {}},
    }


@pytest.mark.parametrize("closure", ["persson01", "yp08"])
def test_solve_at_with_a_given_tau_is_the_same_on_fast_and_plain_paths(closure):
    SEEN.clear()
    with registry_with(analyses={"given_tau": GivenTau}):
        fast = xpersson.solve(_scene(closure))
        with plain_paths():
            plain = xpersson.solve(_scene(closure))
    (own, given, a), (_, _, b) = SEEN
    for name in a:
        np.testing.assert_array_equal(a[name], b[name], err_msg=name)
    np.testing.assert_array_equal(fast["probe_area"].values, plain["probe_area"].values)
    # the given tau was used where the effective tau is tau(zeta), and only there
    used = closure == "persson01"
    np.testing.assert_array_equal(a["diffusion_time"], given if used else own)
    rows = np.broadcast_to(given, a["effective_diffusion_time"].shape)
    assert np.array_equal(a["effective_diffusion_time"], rows) == used
