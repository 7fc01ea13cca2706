"""Entry-point discovery, broken plugins, duplicates, autoload switch and provenance."""

from __future__ import annotations

import sys
import warnings

import pytest
from xpersson_plugtest_helpers import FAKE_MODULES, M, fake_ep, install_eps, make_standard_registry

from xpersson.plugins import (
    GROUP_NAMES,
    Boundary,
    PluginError,
    Registry,
    SpecError,
    _discovery,
    _registry,
    plugin_provenance,
)


def _imported() -> list[str]:
    return [m for m in FAKE_MODULES if m in sys.modules]


def test_listing_imports_no_plugin(monkeypatch):
    standard_registry = make_standard_registry(monkeypatch)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        infos = list(standard_registry.infos())
    assert {i.name for i in infos} >= {"offset", "wall", "broken", "future", "badspec", "scaled"}
    assert all(i.status == "not loaded" for i in infos)
    assert _imported() == []


def test_discovery_is_cached_until_refresh(monkeypatch):
    calls = []
    install_eps(monkeypatch, [fake_ep("boundaries", "offset", f"{M}:OffsetWall")])
    inner = _discovery._entry_points
    monkeypatch.setattr(
        _discovery, "_entry_points", lambda g, installed=None: calls.append(g) or inner(g)
    )
    reg = Registry(autoload=True)
    reg.names("boundaries")
    reg.names("coefficients")
    assert len(calls) == len(GROUP_NAMES)  # one discovery pass over the groups
    reg.refresh()
    reg.names("boundaries")
    assert len(calls) == 2 * len(GROUP_NAMES)


def test_duplicate_names_warn_and_require_dist_prefix(monkeypatch):
    standard_registry = make_standard_registry(monkeypatch)
    with pytest.warns(UserWarning, match=r"named 'wall'.*'dist-a'.*'dist-b'.*'dist-a:wall'"):
        standard_registry.names("boundaries")
    with pytest.raises(PluginError, match=r"ambiguous.*'dist-a'.*'dist-b'.*'dist-b:wall'"):
        standard_registry.load("boundaries", "wall")
    from xpersson_fake_plugins import OffsetWall, OtherWall

    assert standard_registry.load("boundaries", "dist-a:wall") is OffsetWall
    assert standard_registry.load("boundaries", "dist_B:wall") is OtherWall  # normalised name
    assert standard_registry.load("boundaries", "offset") is OffsetWall  # others unaffected
    with pytest.raises(PluginError, match=r"no boundaries plugin 'wall' in distribution 'dist-c'"):
        standard_registry.load("boundaries", "dist-c:wall")


@pytest.mark.filterwarnings("ignore:two boundaries plugins")
def test_import_error_names_distribution_and_missing_dependency(monkeypatch):
    standard_registry = make_standard_registry(monkeypatch)
    with pytest.raises(PluginError) as exc:
        standard_registry.load("boundaries", "broken")
    msg = str(exc.value)
    assert "'broken-dist' 0.1" in msg
    assert "missing optional dependency 'xpersson_nonexistent_optional_dependency'" in msg
    info = standard_registry.info("boundaries", "broken")
    assert info.status.startswith("broken: import failed")
    # the listing and the other plugins still work
    assert "broken" in standard_registry.names("boundaries")
    assert standard_registry.load("coefficients", "scaled").__name__ == "ScaledCoefficient"
    with pytest.raises(PluginError):  # the failure is remembered, not retried
        standard_registry.load("boundaries", "broken")


def test_missing_plugin_module_is_reported(monkeypatch):
    ghost = fake_ep("boundaries", "ghost", "xpersson_no_such_module:Wall", "ghost-dist")
    install_eps(monkeypatch, [ghost])
    with pytest.raises(PluginError, match=r"'ghost-dist'.*module 'xpersson_no_such_module' not"):
        Registry(autoload=True).load("boundaries", "ghost")


@pytest.mark.filterwarnings("ignore:two boundaries plugins")
def test_too_new_api_version(monkeypatch):
    standard_registry = make_standard_registry(monkeypatch)
    with pytest.raises(PluginError, match=r"'future-dist' 9.0.*needs plugin API v99.*upgrade"):
        standard_registry.load("boundaries", "future")
    assert standard_registry.load("boundaries", "offset").__name__ == "OffsetWall"


@pytest.mark.filterwarnings("ignore:two boundaries plugins")
def test_malformed_paramspec_plugin(monkeypatch):
    standard_registry = make_standard_registry(monkeypatch)
    with pytest.raises(PluginError) as exc:
        standard_registry.load("boundaries", "badspec")
    msg = str(exc.value)
    assert "'bad-dist'" in msg and "SpecError" in msg
    assert "BadSpecWall.parameters['s']" in msg and "outside the declared range" in msg
    assert standard_registry.load("boundaries", "offset").__name__ == "OffsetWall"


@pytest.mark.filterwarnings("ignore:two boundaries plugins")
def test_check_reports_every_status(monkeypatch):
    standard_registry = make_standard_registry(monkeypatch)
    infos = {i.qualified: i for i in standard_registry.check("boundaries")}
    assert infos["xpersson-offset:offset"].status == "ok"
    assert infos["broken-dist:broken"].status.startswith("broken:")
    assert "API v99" in infos["future-dist:future"].status
    assert infos["dist-a:wall"].status == "ok" and infos["dist-b:wall"].status == "ok"


def test_autoload_switch_keeps_core_only(monkeypatch):
    from xpersson_plugtest_helpers import STANDARD

    install_eps(monkeypatch, STANDARD)
    monkeypatch.setenv(_registry.AUTOLOAD_ENV, "1")
    reg = Registry()
    assert reg.autoload is False
    assert reg.names("boundaries") == ["elastic"]
    assert reg.names("coefficients") == []
    monkeypatch.setenv(_registry.AUTOLOAD_ENV, "0")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert "offset" in Registry().names("boundaries")


def test_direct_class_and_register(monkeypatch):
    from xpersson_fake_plugins import OffsetWall, ScaledCoefficient

    install_eps(monkeypatch, [])
    reg = Registry(extra={"boundary": {"mine": OffsetWall}})
    assert reg.load("boundaries", "mine") is OffsetWall
    assert reg.info("boundaries", "mine").dist == "<direct>"
    assert reg.resolve("boundaries", OffsetWall) is OffsetWall
    with pytest.raises(PluginError, match="is not a Boundary"):
        reg.resolve("boundaries", ScaledCoefficient)
    reg.register("coefficients", "lin", ScaledCoefficient)
    assert reg.names("coefficients") == ["lin"]
    with pytest.raises(ValueError, match="plugin names must match"):
        reg.register("coefficients", "Bad-Name", ScaledCoefficient)
    reg.register("boundaries", "notaplugin", dict)
    with pytest.raises(PluginError, match="is not a Boundary"):
        reg.load("boundaries", "notaplugin")
    with pytest.raises(ValueError, match="plugin group must be one of"):
        reg.names("walls")


def test_unknown_name_lists_installed(monkeypatch):
    install_eps(monkeypatch, [fake_ep("boundaries", "offset", f"{M}:OffsetWall")])
    with pytest.raises(PluginError, match=r"no boundaries plugin named 'nope' \(installed: offset"):
        Registry(autoload=True).load("boundaries", "nope")


def test_invalid_entry_point_name_is_skipped_with_warning(monkeypatch):
    install_eps(monkeypatch, [fake_ep("boundaries", "Bad-Name", f"{M}:OffsetWall", "odd-dist")])
    with pytest.warns(UserWarning, match="ignoring boundaries plugin 'Bad-Name' of distribution"):
        assert Registry(autoload=True).names("boundaries") == []


@pytest.mark.filterwarnings("ignore:two boundaries plugins")
def test_plugin_provenance(monkeypatch):
    standard_registry = make_standard_registry(monkeypatch)
    cls = standard_registry.load("boundaries", "offset")
    prov = plugin_provenance("boundaries", cls, standard_registry)
    assert prov == {
        "group": "boundaries",
        "name": "offset",
        "distribution": "xpersson-offset",
        "version": "0.3",
        "class": f"{M}:OffsetWall",
        "api_version": 1,
        "summary": cls.summary,
        "references": ["10.1063/1.1388626"],
    }


def test_plugin_provenance_of_direct_class(monkeypatch):
    class Local(Boundary):
        summary = "local wall"

    install_eps(monkeypatch, [])
    prov = plugin_provenance("boundary", Local, Registry(autoload=True))
    assert prov["name"].endswith("Local") and prov["distribution"] == "<direct>"
    assert prov["references"] == [] and prov["group"] == "boundaries"


def test_class_definition_errors_name_class_and_field():
    from xpersson.plugins import ParamSpec

    with pytest.raises(SpecError, match=r"Bad\.parameters\['H'\]: default 2.0 lies outside"):

        class Bad(Boundary):
            summary = "bad"
            parameters = {"H": ParamSpec("1", default=2.0, bounds=(0, 1))}
