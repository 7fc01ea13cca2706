"""The analysis planner: transitive providers, dependency order and its refusals."""

from __future__ import annotations

import sys

import pytest
from xpersson_plugtest_helpers import M, fake_ep, install_eps

from xpersson.plugins import PlanError, PluginError, Registry, plan_analyses

CORE = {"area_fraction", "non_contact_fraction", "G"}


def _registry(monkeypatch, *names: str, extra=()) -> Registry:
    eps = [fake_ep("analyses", n.lower(), f"{M}:{n}", "ana-dist") for n in names]
    install_eps(monkeypatch, eps + list(extra))
    return Registry(autoload=True)


def test_transitive_providers_in_dependency_order(monkeypatch):
    reg = _registry(monkeypatch, "AnaA", "AnaB", "AnaC")
    plan = plan_analyses({"anac": {"k": 1}}, CORE, reg)
    assert [(n, c.__name__, p) for n, c, p in plan] == [
        ("anaa", "AnaA", {}),
        ("anab", "AnaB", {}),
        ("anac", "AnaC", {"k": 1}),
    ]


def test_requested_order_is_kept_when_independent(monkeypatch):
    reg = _registry(monkeypatch, "AnaA", "AnaB", "NeedsParam")
    plan = plan_analyses({"needsparam": {"scale": "1 m"}, "anaa": {}}, CORE, reg)
    assert [n for n, _, _ in plan] == ["needsparam", "anaa"]
    plan = plan_analyses({"anab": None, "anaa": {}}, CORE, reg)
    assert [n for n, _, _ in plan] == ["anaa", "anab"]


def test_no_provider_search_when_core_satisfies(monkeypatch):
    broken = fake_ep("analyses", "broken", "xpersson_fake_broken:BrokenWall", "broken-dist")
    reg = _registry(monkeypatch, "AnaA", extra=[broken])
    monkeypatch.delitem(sys.modules, "xpersson_fake_broken", raising=False)
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no "skipping broken plugin" warning either
        plan = plan_analyses({"anaa": {}}, CORE, reg)
    assert [n for n, _, _ in plan] == ["anaa"]
    assert "xpersson_fake_broken" not in sys.modules


def test_cycle_is_refused_with_the_cycle_listed(monkeypatch):
    reg = _registry(monkeypatch, "AnaP", "AnaQ", "AnaA")
    with pytest.raises(PlanError) as exc:
        plan_analyses({"anap": {}}, CORE, reg)
    msg = str(exc.value)
    assert "dependency cycle among analyses: anap -> anaq -> anap" in msg
    assert "anap requires 'q_out' from anaq" in msg and "anaq requires 'p_out' from anap" in msg
    # the registry and the other analyses stay usable
    assert [n for n, _, _ in plan_analyses({"anaa": {}}, CORE, reg)] == ["anaa"]


def test_two_registered_providers_are_refused(monkeypatch):
    reg = _registry(monkeypatch, "AnaA", "AnaA2", "AnaB")
    with pytest.raises(PlanError, match=r"'x' \(required by analysis 'anab'\).*'anaa' and 'anaa2'"):
        plan_analyses({"anab": {}}, CORE, reg)
    # choosing one explicitly resolves it
    plan = plan_analyses({"anaa2": {}, "anab": {}}, CORE, reg)
    assert [c.__name__ for _, c, _ in plan] == ["AnaA2", "AnaB"]


def test_two_requested_providers_are_refused(monkeypatch):
    reg = _registry(monkeypatch, "AnaA", "AnaA2")
    with pytest.raises(PlanError, match=r"'x' is provided by two analyses, 'anaa' and 'anaa2'"):
        plan_analyses({"anaa": {}, "anaa2": {}}, CORE, reg)


def test_unsatisfiable_requirement_names_variable_and_analysis(monkeypatch):
    reg = _registry(monkeypatch, "AnaW", "AnaA")
    with pytest.raises(PlanError, match=r"analysis 'anaw' requires variable 'w', which neither"):
        plan_analyses({"anaw": {}}, CORE, reg)


def test_broken_plugins_are_skipped_with_a_warning_during_provider_search(monkeypatch):
    broken = fake_ep("analyses", "broken", "xpersson_fake_broken:BrokenWall", "broken-dist")
    reg = _registry(monkeypatch, "AnaA", "AnaB", extra=[broken])
    with pytest.warns(UserWarning, match=r"skipping broken analysis plugin.*'broken-dist'"):
        plan = plan_analyses({"anab": {}}, CORE, reg)
    assert [n for n, _, _ in plan] == ["anaa", "anab"]


def test_requested_broken_or_unknown_analysis_is_fatal(monkeypatch):
    broken = fake_ep("analyses", "broken", "xpersson_fake_broken:BrokenWall", "broken-dist")
    reg = _registry(monkeypatch, "AnaA", extra=[broken])
    with pytest.raises(PluginError, match="broken-dist"):
        plan_analyses({"broken": {}}, CORE, reg)
    with pytest.raises(PluginError, match="no analyses plugin named 'nope'"):
        plan_analyses({"nope": {}}, CORE, reg)


def test_provider_with_required_parameters_is_not_added_silently(monkeypatch):
    from xpersson_fake_plugins import _analysis

    reg = _registry(monkeypatch, "NeedsParam")
    Consumer = _analysis("Consumer", ("v",), ("u",))
    reg.register("analyses", "consumer", Consumer)
    with pytest.raises(PlanError, match=r"'needsparam'.*needs parameter\(s\) \['scale'\]"):
        plan_analyses({"consumer": {}}, CORE, reg)


def test_class_keys_are_accepted(monkeypatch):
    from xpersson_fake_plugins import AnaA, AnaB

    reg = _registry(monkeypatch, "AnaA")
    plan = plan_analyses({AnaB: {}}, CORE, reg)
    assert [c for _, c, _ in plan] == [AnaA, AnaB]
