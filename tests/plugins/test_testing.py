"""The plugin-author kit: check_plugin, registry_with, assert_schema and the oracles."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr
from xpersson_fake_kit import (
    DriftingWall,
    FileWall,
    HalfCoefficient,
    InlineFileWall,
    NoExampleWall,
    ShiftedWall,
    UnpicklableWall,
)

from xpersson import testing
from xpersson.plugins import get_registry
from xpersson.testing import (  # noqa: F401 - the last two are fixtures
    assert_schema,
    check_plugin,
    registry_with,
    xpersson_oracles,
    xpersson_tiny_scene,
)
from xpersson.testing.pytest_plugin import (  # noqa: F401 - fixtures
    xpersson_registry,
    xpersson_scene,
    xpersson_spectrum,
)


def _solve_available() -> bool:
    try:
        from xpersson import solve  # noqa: F401
    except Exception:
        return False
    return True


needs_solve = pytest.mark.skipif(not _solve_available(), reason="xpersson.solve not importable")


def test_check_plugin_unit_checks_pass_for_a_good_plugin():
    report = check_plugin(ShiftedWall, engine=False)
    assert report["metadata"] == "ok" and report["pickle"] == "ok"
    assert report["methods"] == "ok" and report["import"].startswith("ok")


def test_check_plugin_detects_non_determinism():
    with pytest.raises(AssertionError, match="two identical calls differ"):
        check_plugin(DriftingWall, engine=False, cheap_import=False)


def test_check_plugin_detects_unpicklable_instances():
    with pytest.raises(AssertionError, match=r"instances must pickle.*lambda"):
        check_plugin(UnpicklableWall, engine=False, cheap_import=False)


def test_check_plugin_asks_for_required_parameters():
    with pytest.raises(AssertionError, match=r"parameter 's' is required; pass params="):
        check_plugin(NoExampleWall, engine=False, cheap_import=False)


def test_check_plugin_asks_file_plugins_for_archived_params():
    """A class with a ``kind="path"`` parameter must give the file inline to archives."""
    with pytest.raises(AssertionError, match=r"\['table'\] name files.*archived_params\(\)"):
        check_plugin(FileWall, engine=False, cheap_import=False)
    assert check_plugin(InlineFileWall, engine=False, cheap_import=False)["metadata"] == "ok"


def test_check_plugin_refuses_local_classes():
    class Local(ShiftedWall):
        summary = "local"

    with pytest.raises(AssertionError, match="must be defined at module level"):
        check_plugin(Local, engine=False)


def test_check_plugin_coefficient_unit_checks():
    assert check_plugin(HalfCoefficient, engine=False, cheap_import=False)["methods"] == "ok"


@needs_solve
def test_check_plugin_end_to_end_boundary():
    report = check_plugin(ShiftedWall, cheap_import=False)
    assert report["engine"].startswith("ok (probability balance")


@needs_solve
def test_check_plugin_end_to_end_coefficient():
    assert check_plugin(HalfCoefficient, cheap_import=False)["engine"].startswith("ok")


@needs_solve
def test_shifted_wall_matches_constant_wall_oracle():
    import xpersson

    with registry_with(boundaries={"shifted": ShiftedWall}):
        sc = testing.tiny_scene()
        sc["boundary"] = {"model": "shifted", "s": "2e4 Pa"}
        ds = xpersson.solve(sc)
    p0 = ds["p0"].values[:, None]
    tau = ds["diffusion_time"].values[None, :]
    exact = testing.constant_wall_area(p0, 2e4, tau)
    np.testing.assert_allclose(ds["area_fraction"].values, exact, rtol=1e-5, atol=1e-12)
    np.testing.assert_allclose(ds["detached_fraction"].values, 1 - exact, rtol=1e-5, atol=1e-9)


def test_registry_with_installs_and_restores():
    before = get_registry()
    with registry_with(boundary={"shifted": ShiftedWall}) as reg:
        assert get_registry() is reg
        assert reg.load("boundaries", "shifted") is ShiftedWall
    assert get_registry() is before


def _good_ds() -> xr.Dataset:
    ds = xr.Dataset(
        {"area_fraction": (("p0", "zeta"), np.ones((1, 2)))},
        coords={"p0": [1e5], "zeta": [1.0, 10.0]},
    )
    ds["area_fraction"].attrs.update(units="1", long_name="contact area fraction")
    ds["p0"].attrs.update(units="Pa", long_name="nominal pressure")
    ds["zeta"].attrs.update(units="1", long_name="magnification")
    return ds


def test_assert_schema_accepts_a_good_dataset():
    assert_schema(_good_ds())


def test_assert_schema_reports_every_problem():
    ds = _good_ds()
    ds["zeta"].attrs.pop("long_name")
    ds["w"] = (("mystery",), np.zeros(3), {"units": "Pa2", "long_name": "w"})
    with pytest.raises(AssertionError) as exc:
        assert_schema(ds)
    msg = str(exc.value)
    assert "zeta: missing 'long_name'" in msg
    assert "w: unknown dimension 'mystery'" in msg
    ds2 = _good_ds()
    ds2["u"] = (("p0",), np.zeros(1), {"units": "not_a_unit", "long_name": "u"})
    with pytest.raises(AssertionError, match=r"u: units 'not_a_unit' do not parse"):
        assert_schema(ds2)


@needs_solve
def test_assert_schema_on_a_real_solve():
    import xpersson

    assert_schema(xpersson.solve(testing.tiny_scene()))


def test_oracles_reproduce_physics_reference_numbers(xpersson_oracles):  # noqa: F811
    o = xpersson_oracles
    assert o.constant_wall_area(0.5, 0.2, 0.1) == pytest.approx(0.8824751, abs=1e-7)
    assert o.constant_wall_load(0.5, 0.2, 0.1) == pytest.approx(0.5235050, abs=1e-7)
    np.testing.assert_allclose(
        o.linear_wall_area(0.5, 0.2, 1.0, [0.01, 0.1, 1.0]),
        [0.9999994776, 0.9185595730, 0.5953292117],
        atol=1e-10,
    )
    assert o.linear_wall_load(0.5, 0.2, 1.0, 0.1) == pytest.approx(0.5217495952, abs=1e-10)
    assert o.linear_wall_area(0.5, 0.2, 0.0, 0.1) == pytest.approx(0.8824751, abs=1e-7)
    a_el, a_pl = o.two_wall_areas(0.3, 1.0, np.array([0.01, 0.1, 1.0]))
    np.testing.assert_allclose(a_el, [0.9661044, 0.3839343, 5.32786e-5], rtol=2e-6)
    np.testing.assert_allclose(a_pl, [7.43e-7, 0.1138744, 0.2999734], rtol=1e-3)
    # physics.md §1.4: p0 = 1e5 Pa, G = 19.30095 -> A = 0.1278686
    assert o.mirrored_gaussian_area(1e5, 19.30095 * 1e10) == pytest.approx(0.1278686, abs=1e-7)


def test_tiny_scene_fixture_is_a_fresh_copy(xpersson_tiny_scene):  # noqa: F811
    xpersson_tiny_scene["load"]["p0"] = "1 Pa"
    assert testing.TINY_SCENE["load"]["p0"] == ["1e4 Pa", "1e5 Pa"]


def test_scene_factories_write_the_tiny_scene_sections():
    assert testing.spectrum() == testing.TINY_SCENE["spectrum"]
    assert testing.material() == testing.TINY_SCENE["material"]
    sc = testing.scene(p0=[1e4, "1e5 Pa"], zeta_per_decade=3, boundary={"model": "elastic"})
    assert list(sc) == ["spectrum", "material", "load", "output", "boundary"]
    assert sc["load"] == testing.TINY_SCENE["load"] | {"p0": ["10000.0 Pa", "1e5 Pa"]}
    assert testing.pressures(np.array([2.5e3])) == ["2500.0 Pa"]
    assert testing.pressures(1e5) == ["100000.0 Pa"] == testing.pressures(np.float64(1e5))


def test_scene_factory_returns_independent_sections():
    boundary = {"model": "x", "s": ["1 Pa"]}
    a = testing.scene(boundary=boundary)
    b = testing.scene(boundary=boundary)
    a["spectrum"]["H"] = 0.1
    a["boundary"]["s"].append("2 Pa")
    assert b["spectrum"]["H"] == 0.8 and boundary["s"] == ["1 Pa"] == b["boundary"]["s"]


def test_merge_scene_merges_nested_sections():
    sc = testing.merge_scene(testing.TINY_SCENE, {"boundary": {"s": "1 kPa"}, "load": {}})
    assert sc["boundary"] == {"model": "elastic", "s": "1 kPa"}
    assert sc["load"] == testing.TINY_SCENE["load"]
    assert "s" not in testing.TINY_SCENE["boundary"]


_BEFORE = get_registry()


def test_xpersson_registry_fixture_installs(xpersson_registry, xpersson_scene, xpersson_spectrum):  # noqa: F811
    reg = xpersson_registry(boundaries={"shifted": ShiftedWall})
    assert get_registry() is reg and reg.load("boundaries", "shifted") is ShiftedWall
    again = xpersson_registry(coefficients={"half": HalfCoefficient})
    assert get_registry() is again and again.load("coefficients", "half") is HalfCoefficient
    assert xpersson_scene()["spectrum"] == xpersson_spectrum() == testing.TINY_SCENE["spectrum"]


def test_xpersson_registry_fixture_restored_the_default_registry():
    assert get_registry() is _BEFORE
