"""Borders: one group mapping, labels and provenance captured at resolution, one closure spec."""

from __future__ import annotations

import json

import pytest
from xpersson_core_reference import REFERENCE_SCENE

from xpersson import errors, provenance, scene, units
from xpersson.plugins import (
    CLOSURE_PARAMETERS,
    GROUP_NAMES,
    GROUPS,
    PLUGIN_GROUPS,
    Registry,
    normalize_group,
    plugin_provenance,
)


def test_one_group_mapping_derives_every_group_list():
    assert GROUP_NAMES == ("spectra", "coefficients", "boundaries", "analyses", "geometries")
    assert tuple(GROUPS) == GROUP_NAMES
    assert all(base.group == group for group, base in GROUPS.items())
    for short, group in PLUGIN_GROUPS.items():
        assert normalize_group(short) == normalize_group(group) == group
        assert normalize_group(f"xpersson.{group}") == group
    assert scene.PLUGIN_SECTIONS == {
        "spectrum": "spectra",
        "coefficient": "coefficients",
        "boundary": "boundaries",
    }
    with pytest.raises(ValueError, match="plugin group must be one of"):
        normalize_group("walls")


def _resolved(reg: Registry) -> scene.ResolvedScene:
    data = dict(REFERENCE_SCENE, analyses={"contact_area": {}})
    return scene.Scene(data).resolve(reg)


def test_labels_and_records_are_captured_at_resolution():
    reg = Registry()
    rs = _resolved(reg)
    assert set(rs.labels) == {"spectrum", "coefficient", "boundary", "analyses.contact_area"}
    assert str(rs.labels["boundary"]).startswith("boundary plugin 'elastic' (distribution ")
    assert str(rs.labels["analyses.contact_area"]).startswith("analysis plugin 'contact_area' ")
    groups = [record["group"] for record, _ in rs.plugin_records]
    assert groups == ["spectra", "coefficients", "boundaries", "analyses"]
    plugins = [rs.spectrum, rs.coefficient, rs.boundary, rs.analyses[0][1]]
    for (record, _name), group, inst in zip(rs.plugin_records, groups, plugins, strict=True):
        assert record == plugin_provenance(group, type(inst), reg)
    # the records are the registry's shared ones: a second scene reuses them
    again = _resolved(reg)
    assert all(
        a is b for (a, _), (b, _) in zip(rs.plugin_records, again.plugin_records, strict=True)
    )
    reg.refresh()  # a new discovery computes them again
    third = _resolved(reg)
    assert all(
        a is not b for (a, _), (b, _) in zip(rs.plugin_records, third.plugin_records, strict=True)
    )


def test_global_attributes_need_only_the_resolved_scene():
    rs = _resolved(Registry())
    attrs = provenance.global_attributes(rs)
    used = json.loads(attrs["xpersson_plugins"])
    assert [p["name"] for p in used] == ["self_affine", "elastic", "elastic", "contact_area"]
    assert used == provenance.plugins_used(rs)
    refs = sorted({r for p in used for r in p["references"]})
    assert attrs["references"] == "; ".join(f"doi:{r}" if r.startswith("10.") else r for r in refs)


def test_errors_are_shared_and_re_exported():
    assert scene.SceneError is errors.SceneError
    assert units.UnitError is errors.UnitError
    assert issubclass(errors.SceneError, ValueError)


def test_closure_parameters_are_declared_once():
    from xpersson.builtin.elastic import ElasticCoefficient
    from xpersson.physics.closures import CLOSURES, GAMMA_DEFAULT

    for name, spec in CLOSURE_PARAMETERS.items():
        assert ElasticCoefficient.parameters[name] is spec
    assert CLOSURE_PARAMETERS["closure"].choices == CLOSURES
    assert CLOSURE_PARAMETERS["gamma"].default is None  # the closure's own default applies
    assert f"default {GAMMA_DEFAULT}" in CLOSURE_PARAMETERS["gamma"].description
