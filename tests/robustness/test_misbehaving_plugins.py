"""Misbehaving plugins: every bad contribution or exception is caught and named.

Each fake plugin breaks one rule (NaN, inf, shapes, dims, exceptions, clobbering a core
variable, ...). The pipeline must refuse the result with :class:`xpersson.PluginFailure` (or,
for ``Boundary.validate``, a :class:`SceneError`) whose message names the plugin's group and
registered name, its distribution, and the call or variable at fault.
"""

from __future__ import annotations

import copy
from typing import Any

import numpy as np
import pytest
from xpersson_core_reference import REFERENCE_SCENE

import xpersson
from xpersson.builtin.elastic import ElasticBoundary, ElasticCoefficient
from xpersson.builtin.spectra import SelfAffine
from xpersson.engine import Wall
from xpersson.plugins import Analysis, VarSpec
from xpersson.scene import SceneError
from xpersson.testing import registry_with

PZ = ("p0", "zeta")


def _scene(**sections: Any) -> dict[str, Any]:
    scene = copy.deepcopy(REFERENCE_SCENE)
    scene["output"] = {"zeta_per_decade": 2}
    for key, value in sections.items():
        scene[key] = value
    return scene


# -- coefficients ---------------------------------------------------------------------------------
def _coef(name: str, **methods: Any) -> type:
    return type(name, (ElasticCoefficient,), {"summary": "misbehaving coefficient", **methods})


def _tau(ctx, z):
    return ElasticCoefficient.tau(ElasticCoefficient(), ctx, z)


def _f(ctx, z):
    return ElasticCoefficient.f(ElasticCoefficient(), ctx, z)


def _raise(*a, **k):
    raise ZeroDivisionError("a bug inside the plugin")


COEFFICIENTS = {
    "nan_f": (
        {"f": lambda self, ctx, z: np.full(z.shape, np.nan)},
        ["f(zeta)", "non-finite", "nan"],
    ),
    "inf_tau": ({"tau": lambda self, ctx, z: np.full(z.shape, np.inf)}, ["tau(zeta)", "inf"]),
    "short_tau": ({"tau": lambda self, ctx, z: _tau(ctx, z)[:-1]}, ["tau(zeta)", "shape"]),
    "matrix_f": ({"f": lambda self, ctx, z: np.ones((2, z.size))}, ["f(zeta)", "shape"]),
    "negative_f": ({"f": lambda self, ctx, z: -_f(ctx, z)}, ["f(zeta)", "negative"]),
    "decreasing_tau": (
        {"tau": lambda self, ctx, z: _tau(ctx, z)[::-1].copy()},
        ["tau(zeta)", "decreases"],
    ),
    "text_f": ({"f": lambda self, ctx, z: ["a"] * z.size}, ["f(zeta)", "non-numeric"]),
    "raising_tau": ({"tau": _raise}, ["tau(zeta)", "ZeroDivisionError", "a bug inside"]),
    "raising_f": ({"f": _raise}, ["f(zeta)", "ZeroDivisionError"]),
    "raising_eff": ({"effective_tau": _raise}, ["effective_tau(zeta)", "ZeroDivisionError"]),
    "eff_shape": (
        {"effective_tau": lambda self, ctx, z: np.ones((ctx.p0.size + 1, z.size))},
        ["effective_tau(zeta)", "shape"],
    ),
    "eff_nan": (
        {"effective_tau": lambda self, ctx, z: np.full((ctx.p0.size, z.size), np.nan)},
        ["effective_tau(zeta)", "non-finite"],
    ),
}


@pytest.mark.parametrize("case", sorted(COEFFICIENTS))
def test_misbehaving_coefficient_is_caught_and_named(case):
    methods, words = COEFFICIENTS[case]
    cls = _coef(f"Bad_{case}", **methods)
    with registry_with(coefficients={case: cls}), pytest.raises(xpersson.PluginFailure) as info:
        xpersson.solve(_scene(coefficient={"model": case}))
    _assert_named(info.value, "coefficient plugin", case, words)


# -- boundaries ------------------------------------------------------------------------------------
def _boundary(name: str, outputs: dict[str, VarSpec] | None = None, **methods: Any) -> type:
    body = {"summary": "misbehaving boundary", "outputs": outputs or {}, **methods}
    return type(name, (ElasticBoundary,), body)


def _interpret(value: Any):
    return lambda self, ctx, results: value(ctx) if callable(value) else value


DECLARED = {
    "contact_extra": VarSpec(PZ, "1", "an extra area fraction", valid_min=0, valid_max=1),
    "area_fraction": VarSpec(PZ, "1", "the core's area, declared again"),
}


def _grid(ctx, fill=0.5):
    return np.full((ctx.p0.size, ctx.zeta.size), fill)


BOUNDARIES = {
    "nan_out": (
        {"interpret": _interpret(lambda c: {"contact_extra": (PZ, _grid(c, np.nan))})},
        ["'contact_extra'", "non-finite", "nan at p0="],
    ),
    "inf_out": (
        {"interpret": _interpret(lambda c: {"contact_extra": (PZ, _grid(c, np.inf))})},
        ["'contact_extra'", "non-finite", "inf"],
    ),
    "above_max": (
        {"interpret": _interpret(lambda c: {"contact_extra": (PZ, _grid(c, 1.5))})},
        ["'contact_extra'", "above valid_max", "1.5"],
    ),
    "below_min": (
        {"interpret": _interpret(lambda c: {"contact_extra": (PZ, _grid(c, -0.1))})},
        ["'contact_extra'", "below valid_min", "-0.1"],
    ),
    "wrong_dims": (
        {"interpret": _interpret(lambda c: {"contact_extra": (("load", "zeta"), _grid(c))})},
        ["'contact_extra'", "dims", "load"],
    ),
    "missing_dim": (
        {"interpret": _interpret(lambda c: {"contact_extra": (("zeta",), np.zeros(c.zeta.size))})},
        ["'contact_extra'", "missing ['p0']"],
    ),
    "wrong_shape": (
        {
            "interpret": _interpret(
                lambda c: {"contact_extra": (PZ, np.zeros((c.p0.size, c.zeta.size + 2)))}
            )
        },
        ["'contact_extra'", "entries along 'zeta'"],
    ),
    "bad_pair": (
        {"interpret": _interpret(lambda c: {"contact_extra": (PZ, np.zeros(c.zeta.size))})},
        ["'contact_extra'", "(dims, data)"],
    ),
    "undeclared": (
        {"interpret": _interpret(lambda c: {"secret": (PZ, _grid(c))})},
        ["'secret'", "without declaring"],
    ),
    "clobber": (
        {"interpret": _interpret(lambda c: {"area_fraction": (PZ, _grid(c))})},
        ["'area_fraction'", "already has"],
    ),
    "not_mapping": ({"interpret": _interpret([1, 2])}, ["list", "mapping"]),
    "raising_interpret": ({"interpret": _raise}, ["interpret()", "ZeroDivisionError"]),
    "raising_walls": ({"walls": _raise}, ["walls()", "ZeroDivisionError"]),
    "walls_type": (
        {"walls": lambda self, ctx, p0, clock: Wall.absorbing(0.0)},
        ["walls()", "Wall"],
    ),
    "walls_above_load": (
        {"walls": lambda self, ctx, p0, clock: (Wall.absorbing(2 * p0), None)},
        ["lower wall", "not strictly below"],
    ),
    "walls_nan": (
        {"walls": lambda self, ctx, p0, clock: (Wall.absorbing(0.0), Wall.absorbing(np.nan))},
        ["upper wall", "finite"],
    ),
    "raising_validate": ({"validate": _raise}, ["validate()", "ZeroDivisionError"]),
    "text_out": (
        {
            "interpret": _interpret(
                lambda c: {"contact_extra": (PZ, np.full((c.p0.size, c.zeta.size), "x"))}
            )
        },
        ["'contact_extra'", "non-numeric"],
    ),
}


@pytest.mark.parametrize("case", sorted(BOUNDARIES))
def test_misbehaving_boundary_is_caught_and_named(case):
    methods, words = BOUNDARIES[case]
    cls = _boundary(f"Bad_{case}", DECLARED, **methods)
    with registry_with(boundaries={case: cls}), pytest.raises(xpersson.PluginFailure) as info:
        xpersson.solve(_scene(boundary={"model": case}))
    _assert_named(info.value, "boundary plugin", case, words)


def test_boundary_validate_value_error_is_a_scene_error_naming_the_plugin():
    def validate(self, ctx):
        raise ValueError("p0 must stay below 1 Pa")

    cls = _boundary("Picky", validate=validate)
    with registry_with(boundaries={"picky": cls}), pytest.raises(SceneError) as info:
        xpersson.solve(_scene(boundary={"model": "picky"}))
    assert "p0 must stay below 1 Pa" in str(info.value)
    assert "boundary plugin 'picky'" in str(info.value)


# -- spectra ---------------------------------------------------------------------------------------
class _BadPSD:
    def __init__(self, good: Any, **over: Any) -> None:
        self._good, self._over = good, over

    def __getattr__(self, name: str) -> Any:
        if name in self._over:
            return self._over[name]
        return getattr(self._good, name)


def _spectrum(name: str, **over: Any) -> type:
    def build(self):
        good = SelfAffine.build(self)
        if "raise" in over:
            raise RuntimeError("spectrum bug")
        return _BadPSD(good, **over)

    return type(name, (SelfAffine,), {"summary": "misbehaving spectrum", "build": build})


SPECTRA = {
    "nan_c": ({"C": lambda q: np.full(np.shape(q), np.nan)}, ["C(q)", "non-finite"]),
    "negative_c": ({"C": lambda q: -np.ones(np.shape(q))}, ["C(q)", "negative"]),
    "short_c": ({"C": lambda q: np.ones(np.size(q) - 1)}, ["C(q)", "shape"]),
    "swapped_cutoffs": ({"q_1": 1.0}, ["q_L < q_1"]),
    "nan_nodes": ({"nodes": lambda: np.array([1.0, np.nan])}, ["nodes()", "non-finite"]),
    "raising_build": ({"raise": True}, ["build()", "RuntimeError", "spectrum bug"]),
    "nan_h_rms": ({"h_rms": lambda: np.nan}, ["h_rms()", "non-finite"]),
    "raising_slope": ({"rms_slope": _raise}, ["rms_slope()", "ZeroDivisionError"]),
}


@pytest.mark.parametrize("case", sorted(SPECTRA))
def test_misbehaving_spectrum_is_caught_and_named(case):
    over, words = SPECTRA[case]
    cls = _spectrum(f"Bad_{case}", **over)
    spectrum = dict(REFERENCE_SCENE["spectrum"], model=case)
    with registry_with(spectra={case: cls}), pytest.raises(xpersson.PluginFailure) as info:
        xpersson.solve(_scene(spectrum=spectrum))
    _assert_named(info.value, "spectrum plugin", case, words)


# -- analyses --------------------------------------------------------------------------------------
def _analysis(name: str, compute: Any, outputs: dict[str, VarSpec] | None = None) -> type:
    outputs = outputs or {"extra": VarSpec(PZ, "Pa", "an extra quantity", valid_min=0)}
    requires = ("non_contact_fraction",) if "area_fraction" in outputs else ("area_fraction",)
    return type(
        name,
        (Analysis,),
        {
            "summary": "misbehaving analysis",
            "requires": requires,
            "provides": tuple(outputs),
            "outputs": outputs,
            "compute": compute,
        },
    )


def _area(ds):
    return ds["area_fraction"].transpose("p0", "zeta").values


def _inplace(self, ctx, ds):
    ds["area_fraction"].values[...] = 0.5
    return {"extra": (PZ, np.ones_like(_area(ds)))}


def _replace(self, ctx, ds):
    ds["area_fraction"] = ds["area_fraction"] * 0 + 0.5
    return {"extra": (PZ, np.ones_like(_area(ds)))}


def _add_in_place(self, ctx, ds):
    ds["sneaky"] = ds["area_fraction"] * 2
    return {"extra": (PZ, np.ones_like(_area(ds)))}


def _delete(self, ctx, ds):
    del ds["non_contact_fraction"]
    return {"extra": (PZ, np.ones_like(_area(ds)))}


NAN_OK = {"extra": VarSpec(PZ, "Pa", "an extra quantity", nan_meaning="no contact")}
ANALYSES = {
    "nan": (
        lambda self, ctx, ds: {"extra": (PZ, _area(ds) * np.nan)},
        None,
        ["'extra'", "non-finite"],
    ),
    "inf_where_nan_allowed": (
        lambda self, ctx, ds: {"extra": (PZ, _area(ds) * np.inf)},
        NAN_OK,
        ["'extra'", "NaN is allowed, inf is not"],
    ),
    "negative": (
        lambda self, ctx, ds: {"extra": (PZ, -_area(ds))},
        None,
        ["'extra'", "below valid_min"],
    ),
    "dims": (
        lambda self, ctx, ds: {"extra": (("zeta", "p0"), _area(ds).T[:, :1])},
        None,
        ["'extra'", "entries along 'p0'"],
    ),
    "undeclared_dim": (
        lambda self, ctx, ds: {"extra": (("p0", "zeta", "k"), _area(ds)[..., None])},
        None,
        ["'extra'", "undeclared ['k']"],
    ),
    "missing": (lambda self, ctx, ds: {}, None, ["did not provide", "extra"]),
    "raising": (_raise, None, ["compute()", "ZeroDivisionError"]),
    "in_place_write": (_inplace, None, ["compute()", "read-only"]),
    "replaces_core": (_replace, None, ["'area_fraction'", "replaced or removed"]),
    "deletes_core": (_delete, None, ["'non_contact_fraction'", "replaced or removed"]),
    "adds_in_place": (_add_in_place, None, ["'sneaky'", "added"]),
    "declares_core": (
        lambda self, ctx, ds: {"area_fraction": (PZ, _area(ds))},
        {"area_fraction": VarSpec(PZ, "1", "area again")},
        ["'area_fraction'", "already has"],
    ),
    "complex": (
        lambda self, ctx, ds: {"extra": (PZ, _area(ds) + 1j)},
        None,
        ["'extra'", "complex"],
    ),
    "none": (lambda self, ctx, ds: None, None, ["did not provide"]),
}


@pytest.mark.parametrize("case", sorted(ANALYSES))
def test_misbehaving_analysis_is_caught_and_named(case):
    compute, outputs, words = ANALYSES[case]
    cls = _analysis(f"Bad_{case}", compute, outputs)
    with registry_with(analyses={case: cls}), pytest.raises(xpersson.PluginFailure) as info:
        xpersson.solve(_scene(analyses={case: {}}))
    _assert_named(info.value, "analysis plugin", case, words)


def test_core_variables_stay_writable_and_intact_after_a_caught_in_place_write():
    cls = _analysis("InPlace", _inplace)
    ds_ok = xpersson.solve(_scene())
    with registry_with(analyses={"inplace": cls}), pytest.raises(xpersson.PluginFailure):
        xpersson.solve(_scene(analyses={"inplace": {}}))
    ds = xpersson.solve(_scene())
    np.testing.assert_array_equal(ds["area_fraction"].values, ds_ok["area_fraction"].values)
    ds["area_fraction"].values[...] = 0.0  # the user's Dataset is writable


@pytest.mark.parametrize("view_first", [True, False])
def test_the_guard_restores_variables_that_are_views_of_one_another(view_first):
    import xarray as xr

    from xpersson import checks

    owner = np.arange(12.0).reshape(3, 4).copy()  # (owning its memory)
    items = [("last", ("p0",), owner[:, -1]), ("whole", ("p0", "zeta"), owner)]
    ds = xr.Dataset({n: (d, a) for n, d, a in (items if view_first else items[::-1])})
    with checks.guard_dataset(ds, "test") as seen:
        for name in ("last", "whole"):  # read-only while an analysis holds them
            with pytest.raises(ValueError, match="read-only"):
                seen[name].values[0] = -1.0
    ds["last"].values[0] = -1.0  # writable again, and still a view of its owner
    assert owner[0, -1] == -1.0
    ds["whole"].values[...] = 0.0
    assert ds["last"].values[0] == 0.0


def test_nan_with_a_documented_meaning_is_accepted_and_documented():
    def compute(self, ctx, ds):
        a = _area(ds)
        return {"extra": (PZ, np.where(a > 0.5, np.nan, a))}

    cls = _analysis("NanOk", compute, NAN_OK)
    with registry_with(analyses={"nan_ok": cls}):
        ds = xpersson.solve(_scene(analyses={"nan_ok": {}}))
    assert np.isnan(ds["extra"].values).any()
    assert "NaN means: no contact" in ds["extra"].attrs["comment"]


def _assert_named(exc: BaseException, group_word: str, name: str, words: list[str]) -> None:
    msg = str(exc)
    assert f"{group_word} {name!r}" in msg, msg
    assert "distribution" in msg, msg
    for w in words:
        assert w in msg, f"{w!r} not in {msg!r}"


def test_cli_reports_a_plugin_failure_in_one_line_and_writes_nothing(tmp_path, capsys):
    from xpersson.cli import main

    methods, _ = BOUNDARIES["nan_out"]
    cls = _boundary("CliNan", DECLARED, **methods)
    scene = tmp_path / "s.toml"
    scene.write_text(
        '[spectrum]\nmodel = "self_affine"\nH = 0.8\nq_L = "1e3 1/m"\nq_1 = "1e6 1/m"\n'
        'h_rms = "1 um"\n[material]\nE = "10 MPa"\nnu = 0.5\n[load]\np0 = "0.1 MPa"\n'
        '[boundary]\nmodel = "cli_nan"\n'
    )
    out = tmp_path / "o.nc"
    with registry_with(boundaries={"cli_nan": cls}):
        code = main(["run", str(scene), "-o", str(out)])
    err = capsys.readouterr().err
    assert code == 2
    assert "boundary plugin 'cli_nan'" in err and "'contact_extra'" in err
    assert "Traceback" not in err and len(err.strip().splitlines()) == 1
    assert not out.exists()
