"""xpersson.testing.check_analysis: the analysis-side referee catches what fuzzing cannot."""

from __future__ import annotations

from typing import Any, ClassVar

import numpy as np
import pytest

from xpersson.plugins import Analysis, VarSpec
from xpersson.testing import check_analysis


class FinalArea(Analysis):
    """A/A0 at the largest magnification (correct)."""

    summary = "area at the finest scale (test double)"
    requires = ("area_fraction",)
    provides = ("final_area",)
    outputs: ClassVar = {"final_area": VarSpec(("p0",), "1", "final area (test)")}

    def compute(self, ctx: Any, ds: Any) -> dict[str, Any]:
        return {"final_area": (("p0",), ds["area_fraction"].transpose("p0", "zeta").values[:, -1])}


class BatchMean(FinalArea):
    """Wrong: mixes the loads (divides by the batch's mean)."""

    def compute(self, ctx: Any, ds: Any) -> dict[str, Any]:
        a = ds["area_fraction"].transpose("p0", "zeta").values[:, -1]
        return {"final_area": (("p0",), a / a.mean() * 0.1)}


class Overflows(FinalArea):
    """Wrong: a NaN without a declared meaning where the contact is full."""

    def compute(self, ctx: Any, ds: Any) -> dict[str, Any]:
        a = ds["area_fraction"].transpose("p0", "zeta").values[:, -1]
        return {"final_area": (("p0",), np.where(a > 0.999, np.nan, a))}


def _persson(ds):
    """Persson 2001 closed form A = erf(p0 / (2 sqrt(tau))) at the finest scale, computed from
    the diffusion time alone (another way than the engine's solve)."""
    from scipy.special import erf

    tau = float(ds["diffusion_time"].values[-1])
    return {"final_area": erf(ds["p0"].values / (2.0 * np.sqrt(tau)))}


def test_a_correct_analysis_passes_with_a_reference():
    rep = check_analysis(FinalArea, reference=_persson, rtol=1e-5, contract=False)
    assert rep["loads"].startswith("ok") and rep["edges"].startswith("ok")
    assert rep["reference"]["final_area"].startswith("ok")
    assert rep["paths"].startswith("ok")


def test_the_reference_catches_a_wrong_number():
    def off(ds):
        return {"final_area": 1.01 * _persson(ds)["final_area"]}

    with pytest.raises(AssertionError, match="'final_area' against the reference"):
        check_analysis(FinalArea, reference=off, rtol=1e-3, contract=False, paths=())


def test_load_mixing_is_caught():
    with pytest.raises(AssertionError, match="alone vs in a batch"):
        check_analysis(BatchMean, contract=False, paths=())


def test_undeclared_nan_at_the_edge_is_caught():
    with pytest.raises(AssertionError, match="every load was lost.*non-finite"):
        check_analysis(Overflows, contract=False, paths=())


def test_first_party_stiffness_is_refereed():
    """The first-party stiffness through the referee, against a central difference of the
    first-party mean gap solved at p0 (1 +- 1e-3) (virtual work, a different route than the
    analytic slope); every edge load returned, the full-contact ones as declared NaN."""
    import xpersson
    from xpersson.testing import TINY_SCENE
    from xpersson_interface.plugins import ContactStiffness

    def fd(ds):
        p, h = ds["p0"].values, 1e-3
        u = [xpersson.solve({**TINY_SCENE, "load": {"p0": [f"{float(x)!r} Pa" for x in p * f]},
                             "analyses": {"mean_gap": {}}})["mean_gap"].values
             for f in (1 + h, 1 - h)]  # fmt: skip
        return {"contact_stiffness": -2 * h * p / (u[0] - u[1])}

    rep = check_analysis(ContactStiffness, contract=False, paths=(), reference=fd, rtol=1e-4)
    assert "declared NaN" in rep["edges"] and rep["reference"]["contact_stiffness"][:2] == "ok"


@pytest.mark.parametrize("name", ["MeanGap", "GapPDF", "Leakage", "ElasticEnergy"])
def test_first_party_interface_analyses_pass_the_referee(name):
    """Per-load independence, the cn path within 1 %, every regime-edge load returned (each of
    these failed before issue 22: batch-sized EMT cells, a 5.7x cn mean gap, 0/0 flow factors)."""
    import xpersson_interface.plugins as itf

    rep = check_analysis(getattr(itf, name), contract=False)
    assert all(rep[k].startswith("ok") for k in ("loads", "paths", "edges"))
