"""check_plugin on every first-party plugin (core built-ins and the plugins/ distributions)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from xpersson.plugins import get_registry
from xpersson.testing import check_plugin

FIRST_PARTY = (
    "xpersson",
    "xpersson-plasticity",
    "xpersson-interface",
    "xpersson-viscoelastic",
    "xpersson-adhesion",
)


def _first_party():
    reg = get_registry()
    out = []
    for group in ("spectra", "coefficients", "boundaries", "analyses"):
        for name, bucket in reg.entries(group).items():
            for info in bucket:
                if info.dist in FIRST_PARTY:
                    out.append((group, name))
    return out


PLUGINS = _first_party()
#: SI parameters of plugins whose required parameters declare no example
PARAMS = {
    "self_affine": {"H": 0.8, "q_L": 1e3, "q_r": 1e4, "q_1": 1e7, "h_rms": 1e-6},
    "plastic_scale_dependent": {"Y1": 3e6, "n": 0.2},
    "viscoelastic": {"velocity": 0.01},
    "jkr": {"work_of_adhesion": 0.05},
    "dmt": {"work_of_adhesion": 1e-3, "range": 5e-9, "law": "exponential"},
    # inline PSD table (the file path needs SurfaceTopography)
    "topography": {
        "q": [float(q) for q in np.geomspace(1e3, 1e7, 30)],
        "C": [1e-20 * (float(q) / 1e3) ** -3.6 for q in np.geomspace(1e3, 1e7, 30)],
    },
}
#: scene sections a plugin needs (the friction analysis needs the viscoelastic coefficient)
SCENES = {"friction": {"coefficient": {"model": "viscoelastic", "velocity": "1 cm/s"}}}
#: probability-balance tolerance of boundaries solved on the moving-wall path
BALANCE = {"jkr": 1e-5, "dmt": 1e-5}


def _table(tmp_path):
    q = np.geomspace(1e3, 1e7, 30)
    path = tmp_path / "psd.csv"
    np.savetxt(path, np.column_stack((q, 1e-20 * (q / 1e3) ** -3.6)), delimiter=",")
    return {"file": str(path)}


def test_every_first_party_distribution_is_found():
    dists = {get_registry().info(g, n).dist for g, n in PLUGINS}
    assert set(FIRST_PARTY) <= dists
    assert len(PLUGINS) >= 12


@pytest.mark.fast_paths
@pytest.mark.parametrize(("group", "name"), PLUGINS, ids=[f"{g}:{n}" for g, n in PLUGINS])
def test_check_plugin(group, name, tmp_path):
    cls = get_registry().load(group, name)
    scene = {"load": {"p0": ["1e4 Pa", "1e5 Pa"]}, **SCENES.get(name, {})}
    params = _table(tmp_path) if name == "tabulated" else PARAMS.get(name)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)  # validity notes of approximations
        report = check_plugin(
            cls, params, scene=scene, cheap_import=False, balance_tol=BALANCE.get(name)
        )
    assert report["metadata"] == "ok" and report["pickle"] == "ok"
    assert report["engine"].startswith("ok")
    for path in cls.fast_paths.declared():  # each declared fast path run against the plain path
        assert report[f"fast_paths.{path}"].startswith("ok"), report
