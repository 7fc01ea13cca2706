"""Loads so light that their contact area leaves full contact before the dense sampling's first
magnification above 1 (``zeta - 1 = 1e-9``): the zeta integrals of the analyses cannot resolve
that drop, and ``solved_curve`` says so (``xpersson.plugins.solved.UNRESOLVED``) for exactly
those loads whose mean gap a grid reaching ``zeta - 1 = 1e-15`` changes."""

from __future__ import annotations

import re
import warnings

import numpy as np
import pytest

import xpersson
from xpersson.plugins import solved

SPECTRUM = {"model": "self_affine", "H": 0.8, "q_L": "1e3 1/m", "q_r": "1e3 1/m",
            "q_1": "1e10 1/m", "h_rms": "1 um"}  # fmt: skip
LOADS = np.geomspace(1e-3, 1e2, 16)  # Pa: contact areas from ~1e-8 at zeta_max up


def _scene() -> dict:
    return {
        "spectrum": SPECTRUM,
        "material": {"E": "10 MPa", "nu": 0.5},
        "load": {"p0": [f"{float(p)!r} Pa" for p in LOADS]},
        "output": {"zeta": [float(z) for z in np.geomspace(1.0, 1e7, 40)]},
        "analyses": {"mean_gap": {}},
    }


def _lower(zeta: np.ndarray, per_decade: int) -> np.ndarray:
    """:func:`solved.dense_zeta` from ``zeta - 1 = 1e-15`` (the last decades double resolves)."""
    z_max = float(zeta[-1])
    extra = 1.0 + np.geomspace(1e-15, z_max - 1.0, int(per_decade * (15 + np.log10(z_max))))
    z = np.unique(np.concatenate((zeta, extra[extra < z_max])))
    return z[z >= 1.0]


def test_the_warning_names_the_light_loads_whose_zeta_integrals_are_off():
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        coarse = xpersson.solve(_scene())["mean_gap"].values
    said = [str(r.message) for r in rec if "leave full contact" in str(r.message)]
    assert len(said) == 1
    count, top = re.search(r"(\d+) load\(s\) \(p0 <= ([0-9.e+-]+) Pa\)", said[0]).groups()
    with pytest.MonkeyPatch.context() as mp, xpersson.set_options(cache=False):
        mp.setattr(solved, "dense_zeta", _lower)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            fine = xpersson.solve(_scene())["mean_gap"].values
    off = np.abs(coarse / fine - 1.0)
    warned = LOADS <= float(top) * 1.01  # (printed to 3 digits; the loads 2.1x apart)
    assert int(count) == warned.sum() > 0 and np.all(warned[: warned.sum()])
    assert off[warned].max() > 0.1  # the lightest: many times off
    assert off[~warned].max() < 1e-3  # the others: the two grids agree


def test_a_finite_body_is_not_warned_about_its_edge_rings():
    """The bundled sphere: its flat solve's lightest pressures (its contact's edge) are
    unresolved, but they weigh ~nothing in the body's integrals (<= 2e-5 moved with the drop
    resolved): the body's pipeline silences the warning, and only it."""
    import tomllib
    from pathlib import Path

    scene = tomllib.loads((Path(__file__).parents[3] / "examples" / "sphere.toml").read_text())
    with warnings.catch_warnings():
        warnings.simplefilter("error", solved.UnresolvedDrop)
        xpersson.solve(scene)
    with pytest.warns(solved.UnresolvedDrop):  # the same warning outside a body: still given
        xpersson.solve(_scene())
