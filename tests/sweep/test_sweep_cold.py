"""A sweep's first run in a process: no work a plain solve does not do either (``dask.array``,
pint's registry); its coordinates' CF units written without pint equal pint's."""

from __future__ import annotations

import json
import os
import subprocess
import sys

import pytest

from xpersson.plugins import GROUP_NAMES, get_registry
from xpersson.scene._core import CORE
from xpersson.sweep import plan as sweep_plan

SWEEP = {
    "spectrum": {
        "model": "self_affine",
        "H": {"start": 0.6, "stop": 0.8, "num": 3, "spacing": "linear"},
        "q_L": "1e3 1/m",
        "q_r": "1e4 1/m",
        "q_1": "1e7 1/m",
        "h_rms": "1 um",
    },
    "material": {"E": {"start": "1 MPa", "stop": "100 MPa", "num": 4}, "nu": 0.5},
    "load": {"p0": "100 kPa"},
}


def test_first_sweep_imports_no_dask_array_and_builds_no_unit_registry():
    """``dask.array`` is what xarray's duck-array probes import (about 0.3 s); pint's
    registry another 0.3 s: a sweep of a closed-form scene needs neither (nor does a plain
    solve, :mod:`tests.test_lazy_imports`)."""
    code = (
        "import sys, json, xpersson\n"
        "from xpersson import units\n"
        f"ds = xpersson.solve({SWEEP!r})\n"
        "print(json.dumps([ds.sizes['H'], ds.sizes['E'], 'dask.array' in sys.modules,"
        " len(units._UREG)]))"
    )
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path))
    out = subprocess.run(
        [sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True
    )
    assert json.loads(out.stdout.strip().splitlines()[-1]) == [3, 4, False, 0]


def _declared_units() -> set[str]:
    units = {p.unit for section in CORE.values() for p in section.values()}
    registry = get_registry()
    for group in GROUP_NAMES:
        for name in registry.names(group):
            units |= {p.unit for p in (registry.load(group, name).parameters or {}).values()}
    return units


@pytest.mark.parametrize(
    "extra", [["Pa**-1", "m**-1*s", "1/m**2", "Pa*s/m", "m*m", "MPa", "ohm*m", "Pa^2"]]
)
def test_cf_units_without_pint_equal_pint(monkeypatch, extra):
    """Every declared unit (core and installed plugins) and a few others: the direct
    writing (:func:`~xpersson.sweep.plan._simple_cf`) gives pint's string or defers to it."""
    units = sorted(_declared_units() | set(extra))
    fast = {u: sweep_plan.cf_units(u) for u in units}
    assert sum(sweep_plan._simple_cf(u) is not None for u in units) >= 8
    monkeypatch.setattr(sweep_plan, "_simple_cf", lambda unit: None)
    assert fast == {u: sweep_plan.cf_units(u) for u in units}
