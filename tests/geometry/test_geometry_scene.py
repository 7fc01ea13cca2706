"""The ``[geometry]`` table and ``load.force``: one clear line before any work; flat unchanged."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
import xarray as xr

import xpersson
from xpersson.builtin.geometry import Sphere
from xpersson.errors import SceneError
from xpersson.plugins import Geometry, Registry, SpecError
from xpersson.testing import scenes

from .conftest import body_scene


def _refused(scene: dict[str, Any], *words: str) -> str:
    with pytest.raises(SceneError) as info:
        xpersson.solve(scene)
    msg = str(info.value)
    assert "\n" not in msg
    for w in words:
        assert w in msg, msg
    return msg


def test_wrong_units_are_refused() -> None:
    _refused(body_scene(radius="10 MPa"), "geometry.radius", "m")
    _refused(body_scene(force="1 Pa"), "load.force", "N")
    _refused(body_scene(force="-1 N"), "load.force")
    _refused(body_scene(force=["10 mN", "1 mN"]), "load.force", "increasing")


def test_a_cylinder_needs_its_length() -> None:
    scene = body_scene("cylinder")
    del scene["geometry"]["length"]
    _refused(scene, "geometry.length", "required")


def test_a_force_beyond_the_small_slope_theory_is_refused() -> None:
    msg = _refused(body_scene(force=["1 mN", "10 N"]), "load.force", "allowed force in (0,")
    assert "10 N" in msg and "sphere" in msg
    _refused(body_scene("cylinder", force="100 N", length="1 mm"), "load.force")


def test_a_force_too_light_for_the_asymptotic_separation_is_refused() -> None:
    # 1 nN on a 10 mm sphere over 1 um of roughness: A/A0 ~ 2e-4 at twice the peak pressure,
    # below the 1e-3 where the body starts Persson's asymptotic u(p): a clear line, not a
    # ValueError from inside (the fuzz campaign of 2026-12-01 with bodies)
    msg = _refused(body_scene(force=["1 nN", "2 nN"], h_rms="1 um"), "load.force", "2e-09 N")
    area = float(msg.split("A/A0 = ")[1].split(" ")[0])
    assert 0 < area < 1e-3 and "larger force" in msg


def test_pressure_and_force_belong_to_their_geometry() -> None:
    scene = body_scene()
    scene["load"] = {"p0": "1 kPa"}
    _refused(scene, "load.p0", "load.force")
    flat = scenes.scene()
    flat["load"] = {"force": "1 N"}
    _refused(flat, "load.force", "geometry")
    flat["geometry"] = {"model": "flat", "radius": "1 m"}
    flat["load"] = {"p0": "1 kPa"}
    _refused(flat, "geometry.radius")
    _refused(body_scene("wedge"), "geometry.model", "sphere")


def test_flat_geometry_is_the_default_bit_for_bit() -> None:
    plain = xpersson.solve(scenes.scene(p0=["10 kPa", "1 MPa"]))
    flat = scenes.scene(p0=["10 kPa", "1 MPa"])
    flat["geometry"] = {"model": "flat"}
    same = xpersson.solve(flat)
    xr.testing.assert_equal(plain, same)  # values, bit for bit; attributes below
    assert all(str(plain[v].attrs) == str(same[v].attrs) for v in plain.variables)
    timing = {"xpersson_solver", "date_created", "history"}  # wall-clock parts differ
    assert {k for k in plain.attrs if str(plain.attrs[k]) != str(same.attrs.get(k))} <= timing
    assert "force" not in plain.dims and "geometry" not in plain.attrs


class Paraboloid(Geometry):
    """A third party's body: a sphere given by its curvature (the plugin route of a punch)."""

    summary = "paraboloid of curvature c"
    references = ("10.1017/CBO9781139171731",)
    parameters = {"curvature": Sphere.parameters["radius"].__class__("1/m", example=100.0)}

    def _sphere(self) -> Sphere:
        return Sphere(radius=1.0 / self.params["curvature"])

    def profile(self, r: np.ndarray) -> np.ndarray:
        return self._sphere().profile(r)

    def extent(self) -> float:
        return self._sphere().extent()

    def reference(self, load: float, E_star: float) -> tuple[float, float, float]:
        return self._sphere().reference(load, E_star)


def test_a_third_party_geometry_is_a_plugin() -> None:
    reg = Registry(extra={"geometries": {"paraboloid": Paraboloid, "sphere": Sphere}})
    scene = body_scene(force="1 mN", h_rms="100 nm")
    ds = xpersson.solve(scene, registry=reg)
    scene["geometry"] = {"model": "paraboloid", "curvature": "100 1/m"}
    other = xpersson.solve(scene, registry=reg)
    for v in ("nominal_contact_radius", "real_contact_area", "approach"):  # grids differ:
        tol = 3 * float(ds["body_grid_error"]) + 1e-9  # its alpha is NaN, so its first guess
        assert float(other[v]) == pytest.approx(float(ds[v]), rel=tol)
    assert np.isnan(float(other["johnson_parameter"]))  # not defined by this plugin


def test_a_malformed_geometry_fails_at_class_creation() -> None:
    with pytest.raises(SpecError, match="symmetry"):

        class Twisted(Geometry):
            summary = "x"
            references = ("10.1017/CBO9781139171731",)
            symmetry = "helical"


def test_a_body_sweeps_only_its_forces() -> None:
    scene = body_scene()
    scene["material"]["E"] = ["1 MPa", "2 MPa"]
    _refused(scene, "sweep", "load.force", "material.E")


def test_the_archived_scene_solves_again_to_the_same_body() -> None:
    import json

    ds = xpersson.solve(body_scene(force=["1 mN", "3 mN"], h_rms="100 nm"))
    archived = json.loads(ds.attrs["xpersson_scene"])
    assert archived["geometry"] == {"model": "sphere", "radius": "0.01 m"}
    assert archived["load"]["force"] == ["0.001 N", "0.003 N"]
    again = xpersson.solve(archived)
    xr.testing.assert_equal(ds["nominal_pressure"], again["nominal_pressure"])
