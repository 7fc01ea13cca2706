"""A scene's resolution reused by its later solves (:func:`xpersson.pipeline.frontend.resolve`):
the same resolved values as a fresh resolution, never a stale one (another registry's class, a
changed scene, a file read again), the caller's scene, and the same archive."""

from __future__ import annotations

import json

import numpy as np
import pytest

import xpersson
from xpersson.builtin.elastic import ElasticBoundary
from xpersson.options import cache_enabled
from xpersson.pipeline.frontend import resolve
from xpersson.plugins import Registry, fast_paths_on, get_registry, plain_paths

SCENE = {
    "spectrum": {"model": "self_affine", "H": 0.8, "q_L": "1e4 1/m", "q_1": "1e8 1/m",
                 "h_rms": "1 um"},
    "material": {"E": "10 MPa", "nu": 0.5},
    "load": {"p0": "100 kPa"},
    "output": {"zeta_per_decade": 5},
}  # fmt: skip


def _fresh(scene: xpersson.Scene, registry: Registry) -> xpersson.ResolvedScene:
    return scene.resolve(registry)


def test_a_reused_resolution_equals_a_fresh_one():
    reg = get_registry()
    first = resolve(xpersson.Scene(SCENE), reg)
    scene = xpersson.Scene(SCENE, source="/somewhere/study.toml")
    again, fresh = resolve(scene, reg), _fresh(scene, reg)
    assert again.scene is scene  # the caller's scene (its source), not the first one's
    assert again.resolved == fresh.resolved
    assert again.plugin_records_json == fresh.plugin_records_json
    assert {k: str(v) for k, v in again.labels.items()} == {
        k: str(v) for k, v in fresh.labels.items()
    }
    np.testing.assert_array_equal(again.zeta, fresh.zeta)
    np.testing.assert_array_equal(again.p0, fresh.p0)
    assert (again.E, again.nu, again.rtol, again.atol) == (fresh.E, fresh.nu, 1e-6, 1e-12)
    assert first.scene is not scene


def test_the_archive_is_the_same_with_the_caches_off():
    ds = xpersson.solve(SCENE)
    ds = xpersson.solve(SCENE)  # the reused resolution
    with xpersson.set_options(cache=False):
        off = xpersson.solve(SCENE)
    assert ds.attrs["xpersson_scene"] == off.attrs["xpersson_scene"]
    assert json.loads(ds.attrs["xpersson_scene"])["load"]["p0"] == "100000.0 Pa"
    np.testing.assert_array_equal(ds.area_fraction.values, off.area_fraction.values)


def test_a_changed_scene_is_resolved_again():
    scene = xpersson.Scene(SCENE)
    a = xpersson.solve(scene)
    scene.data["load"]["p0"] = "200 kPa"  # the same Scene object, changed in place
    b = xpersson.solve(scene)
    assert float(a.p0) == 1e5 and float(b.p0) == 2e5
    assert float(b.area_fraction[-1]) > float(a.area_fraction[-1])


def test_another_registry_class_is_never_taken_from_a_reused_resolution():
    class Shifted(ElasticBoundary):  # a registry shadowing the built-in name
        pass

    reg = Registry(extra={"boundaries": {"elastic": Shifted}})
    assert type(resolve(xpersson.Scene(SCENE), get_registry()).boundary) is ElasticBoundary
    assert type(resolve(xpersson.Scene(SCENE), reg).boundary) is Shifted
    assert type(resolve(xpersson.Scene(SCENE), get_registry()).boundary) is ElasticBoundary


def test_only_plugins_declaring_reuse_are_reused():
    class Undeclared(ElasticBoundary):  # fast_paths are not inherited: no promise
        pass

    reg = Registry(extra={"boundaries": {"elastic": Undeclared}})
    a, b = resolve(xpersson.Scene(SCENE), reg), resolve(xpersson.Scene(SCENE), reg)
    assert a.boundary is not b.boundary and a.spectrum is not b.spectrum  # resolved afresh
    reg = get_registry()
    a, b = resolve(xpersson.Scene(SCENE), reg), resolve(xpersson.Scene(SCENE), reg)
    # the declared built-ins: reused (with the caches and the fast paths on)
    kept = cache_enabled() and fast_paths_on()
    assert (a.boundary is b.boundary) == kept
    assert a.psd is b.psd or not kept  # (the spectrum's own cache may keep it regardless)
    with plain_paths():
        assert resolve(xpersson.Scene(SCENE), reg).boundary is not a.boundary
    with xpersson.set_options(cache=False):
        assert resolve(xpersson.Scene(SCENE), reg).boundary is not a.boundary


def test_a_file_read_by_a_plugin_is_read_at_every_solve(tmp_path):
    path = tmp_path / "psd.csv"
    q = np.geomspace(1e4, 1e8, 9).tolist()

    def write(c0: float) -> None:
        path.write_text("\n".join(f"{x!r}, {c0 * (x / 1e4) ** -3.6!r}" for x in q))

    scene = {**SCENE, "spectrum": {"model": "tabulated", "file": str(path)}}
    write(1e-20)
    a = xpersson.solve(scene)
    write(4e-20)  # the same scene, the file changed: four times the power
    b = xpersson.solve(scene)
    assert float(b.h_rms) == pytest.approx(2 * float(a.h_rms), rel=1e-12)


def test_an_inline_table_is_reused_and_its_file_form_is_not(tmp_path):
    q = np.geomspace(1e4, 1e8, 9)
    c = 1e-20 * (q / 1e4) ** -3.6
    inline = {
        **SCENE,
        "spectrum": {
            "model": "tabulated",
            "q": [f"{x!r} 1/m" for x in q.tolist()],
            "C": [f"{y!r} m**4" for y in c.tolist()],
        },
    }
    path = tmp_path / "psd.csv"
    path.write_text("\n".join(f"{x!r}, {y!r}" for x, y in zip(q.tolist(), c.tolist(), strict=True)))
    on_file = {**SCENE, "spectrum": {"model": "tabulated", "file": str(path)}}
    reg = get_registry()
    a, b = resolve(xpersson.Scene(inline), reg), resolve(xpersson.Scene(inline), reg)
    # no file given: nothing read (reused with the caches and the fast paths on)
    assert (a.spectrum is b.spectrum) == (cache_enabled() and fast_paths_on())
    a, b = resolve(xpersson.Scene(on_file), reg), resolve(xpersson.Scene(on_file), reg)
    assert a.spectrum is not b.spectrum  # a file given: read at every solve
    np.testing.assert_array_equal(a.psd.C(q), b.psd.C(q))


def test_a_kept_resolution_refuses_edits_in_place():
    """The arrays a reused resolution shares with the later solves are read-only (an edit in
    place would change every later solve of the scene); the solves themselves never edit them
    (the solve below runs on the kept arrays)."""
    if not (cache_enabled() and fast_paths_on()):
        pytest.skip("nothing is kept with the caches or the fast paths off")
    reg = get_registry()
    resolve(xpersson.Scene(SCENE), reg)
    again = resolve(xpersson.Scene(SCENE), reg)
    for name in ("p0", "zeta"):
        with pytest.raises(ValueError, match="read-only"):
            getattr(again, name)[...] = 0.0
    ds = xpersson.solve(SCENE)
    assert np.all(np.isfinite(ds.area_fraction.values))


#: electrical_contact pulls in contact_stiffness as its provider (from xpersson-interface)
ANALYSED = {
    **SCENE,
    "analyses": {
        "gap_pdf": {"u_points": 64},
        "electrical_contact": {"resistivity_1": "1e-7 ohm*m", "resistivity_2": "2e-7 ohm*m"},
    },
}


def test_a_scene_with_analyses_reuses_them_and_their_providers():
    pytest.importorskip("xpersson_transport")
    reg = get_registry()
    a, b = resolve(xpersson.Scene(ANALYSED), reg), resolve(xpersson.Scene(ANALYSED), reg)
    fresh = _fresh(xpersson.Scene(ANALYSED), reg)
    assert [n for n, _ in b.analyses] == [n for n, _ in fresh.analyses]
    assert "contact_stiffness" in dict(b.analyses)  # the provider pulled in
    for (_, x), (_, y) in zip(a.analyses, b.analyses, strict=True):
        assert (x is y) == (cache_enabled() and fast_paths_on())
    assert b.resolved == fresh.resolved
    assert b.plugin_records_json == fresh.plugin_records_json
    assert {k: str(v) for k, v in b.labels.items()} == {k: str(v) for k, v in fresh.labels.items()}
    assert b.analyses is not a.analyses  # the list is the solve's own


def test_another_plan_is_never_taken_from_a_reused_resolution():
    """A registry whose provider of a required variable is another class, or whose analysis
    does not declare reuse, resolves afresh."""
    pytest.importorskip("xpersson_transport")
    from xpersson_interface.plugins import ContactStiffness, GapPDF

    class Provider(ContactStiffness):  # declares nothing (not inherited)
        pass

    class Declared(ContactStiffness):
        fast_paths = ContactStiffness.fast_paths

    reg = get_registry()
    first = resolve(xpersson.Scene(ANALYSED), reg)
    for cls in (Provider, Declared):
        other = Registry(extra={"analyses": {"contact_stiffness": cls}})
        got = dict(resolve(xpersson.Scene(ANALYSED), other).analyses)
        assert type(got["contact_stiffness"]) is cls
        assert got["gap_pdf"] is not dict(first.analyses)["gap_pdf"]
    undeclared = Registry(extra={"analyses": {"gap_pdf": type("Plain", (GapPDF,), {})}})
    a = resolve(xpersson.Scene(ANALYSED), undeclared)
    b = resolve(xpersson.Scene(ANALYSED), undeclared)
    assert dict(a.analyses)["gap_pdf"] is not dict(b.analyses)["gap_pdf"]


def test_a_scene_with_analyses_solved_again_is_the_same_bit_for_bit():
    pytest.importorskip("xpersson_transport")
    first, again = xpersson.solve(ANALYSED), xpersson.solve(ANALYSED)
    with plain_paths():
        plain = xpersson.solve(ANALYSED)
    timed = ("date_created", "history", "xpersson_solver")  # (the solver's wall time)
    for ds in (again, plain):
        assert ds.attrs == first.attrs | {k: ds.attrs[k] for k in timed}
        for name, var in first.variables.items():
            np.testing.assert_array_equal(ds[name].values, var.values, err_msg=name)
