"""Units as the ecosystem reads them (issue 26): pint-xarray's own ``ds.pint.quantify()`` on every
Dataset and archive, and pint Quantities (scalar or array, any registry) wherever a scene takes a
quantity."""

from __future__ import annotations

import tomllib
import warnings
from pathlib import Path

import numpy as np
import pint
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import xpersson
from xpersson.specs import caret_units

pint_xarray = pytest.importorskip("pint_xarray")
ROOT = Path(__file__).resolve().parents[1]


def _scene():
    with open(ROOT / "examples" / "elastic.toml", "rb") as fh:
        scene = tomllib.load(fh)
    scene["output"]["pressure_pdf"] = True
    return scene


def _solve(scene):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", xpersson.XperssonWarning)
        return xpersson.solve(scene)


_UREG = pint.UnitRegistry()


@settings(deadline=None, max_examples=60)
@given(
    st.lists(
        st.tuples(st.sampled_from(["m", "Pa", "s", "K", "J", "W", "S"]), st.integers(-4, 4)),
        min_size=1,
        max_size=4,
    )
)
def test_caret_units_means_the_same_unit_to_udunits_and_pint(terms):
    """The stored string parses in pint to the same unit as the compact UDUNITS form does."""
    cf_units = pytest.importorskip("cf_units")
    compact = " ".join(b if p == 1 else f"{b}{p}" for b, p in terms if p != 0) or "1"
    stored = caret_units(compact)
    assert cf_units.Unit(stored) == cf_units.Unit(compact)
    ureg = _UREG
    expected = ureg.Quantity(1.0, "dimensionless")
    for base, power in terms:
        expected = expected * ureg.Quantity(1.0, base) ** power
    got = ureg.Quantity(1.0, stored)
    assert got.dimensionality == expected.dimensionality
    assert (got / expected).to("dimensionless").magnitude == pytest.approx(1.0, rel=1e-12)


def test_pint_xarray_quantify_reads_every_variable(tmp_path):
    ds = _solve(_scene())
    q = ds.pint.quantify()
    assert str(q.P.data.units) == "1 / pascal"
    assert str(q.diffusion_time.data.units) == "pascal ** 2"
    assert str(q.psd_C.data.units) == "meter ** 4"
    # the archive too: written, re-opened, quantified, same magnitudes
    path = tmp_path / "a.nc"
    xpersson.to_netcdf(ds, path)
    back = xpersson.open_dataset(path).pint.quantify()
    np.testing.assert_array_equal(back.area_fraction.data.magnitude, ds.area_fraction.values)
    assert back.q.data.units == q.q.data.units


@pytest.mark.parametrize("registry", ["own", "xpersson"])
def test_pint_quantities_in_a_python_scene(registry):
    ureg = pint.UnitRegistry() if registry == "own" else xpersson.units.ureg()
    text = _scene()
    text["load"]["p0"] = ["0.1 MPa", "0.2 MPa"]
    text["material"]["E"] = "10 MPa"
    quantities = _scene()
    quantities["load"]["p0"] = ureg.Quantity(np.array([100.0, 200.0]), "kPa")
    quantities["material"]["E"] = ureg.Quantity(1e7, "Pa")
    a, b = _solve(text), _solve(quantities)
    np.testing.assert_array_equal(a.area_fraction.values, b.area_fraction.values)
    np.testing.assert_array_equal(a.p0.values, [1e5, 2e5])


def test_a_quantity_of_the_wrong_dimension_is_refused_naming_the_parameter():
    scene = _scene()
    scene["load"]["p0"] = pint.UnitRegistry().Quantity([1.0, 2.0], "m")
    with pytest.raises(xpersson.SceneError, match=r"load\.p0"):
        xpersson.solve(scene)
