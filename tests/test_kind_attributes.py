"""The global attributes a kind of scene shares, made once per kind (``provenance``'s process
cache ``provenance.kind_attributes``, issue 36): never stale. Whatever changes an attribute
(the user's metadata file, its contents or which file it is, the scene's title, description
and ``[metadata]``, a plugin's record such as its version) gives the attributes of a cold
cache; ``set_options(cache=False)`` keeps nothing; every attribute but the run's time equals
the one made with no cache at all."""

from __future__ import annotations

import copy
import dataclasses
import json

import pytest

import xpersson
from xpersson import provenance
from xpersson.cache import cache
from xpersson.scene import Scene
from xpersson.testing import TINY_SCENE

KIND = cache("provenance.kind_attributes")
TIMED = ("history", "date_created")  # the run's time


def _attrs(rs) -> dict[str, str]:
    out = provenance.global_attributes(rs)
    return {k: v for k, v in out.items() if k not in TIMED}


def _cold(rs) -> dict[str, str]:
    """The attributes made with no cache at all."""
    with xpersson.set_options(cache=False):
        return _attrs(rs)


@pytest.fixture
def rs(monkeypatch):
    monkeypatch.delenv("XPERSSON_METADATA", raising=False)
    monkeypatch.setenv("XDG_CONFIG_HOME", "/nonexistent-xpersson-test")  # no user's file
    return Scene(copy.deepcopy(TINY_SCENE)).resolve()


def _bumped(rs, version: str):
    """``rs`` with its spectrum plugin's record at another version (a plugin upgraded)."""
    (record, name), *rest = rs.plugin_records
    records = (({**record, "version": version}, name), *rest)
    used = [{**r, "name": n} if n else r for r, n in records]
    return dataclasses.replace(
        rs, plugin_records=records, plugin_records_json=json.dumps(used, sort_keys=True)
    )


def test_every_change_of_what_the_attributes_read_is_seen(rs, tmp_path, monkeypatch):
    with xpersson.set_options(cache=True):  # also in CI's run with XPERSSON_CACHE=off
        KIND.clear()
        first = _attrs(rs)
        assert first == _cold(rs) and len(KIND) == 1
        assert _attrs(rs) == first and KIND.info().hits == 1  # the same kind: from the cache
        # the user's metadata file: named, its contents changed, another file
        path = tmp_path / "metadata.toml"
        path.write_text('creator_name = "A. User"\n')
        monkeypatch.setenv("XPERSSON_METADATA", str(path))
        assert _attrs(rs)["creator_name"] == "A. User"
        path.write_text('creator_name = "B. User"\ninstitution = "Lab"\n')
        got = _attrs(rs)
        assert got["creator_name"] == "B. User" and got["institution"] == "Lab"
        other = tmp_path / "other.toml"
        other.write_text('creator_name = "C. User"\n')
        monkeypatch.setenv("XPERSSON_METADATA", str(other))
        got = _attrs(rs)
        assert got["creator_name"] == "C. User" and "institution" not in got
        assert got == _cold(rs)
        monkeypatch.setenv("XPERSSON_METADATA", "")  # no file: the first attributes again
        assert _attrs(rs) == first
        # a plugin's record (an upgraded plugin)
        bumped = _bumped(rs, "9.9.9")
        got = _attrs(bumped)
        assert json.loads(got["xpersson_plugins"])[0]["version"] == "9.9.9"
        assert got == _cold(bumped) and _attrs(rs) == first
        # the scene's title, description and [metadata]
        for key, value in [
            ("title", "another title"),
            ("description", "another summary"),
            ("metadata", {"project": "P", "license": "CC0-1.0"}),
            ("metadata", {"license": "CC0-1.0", "project": "P"}),  # the same, in another order
        ]:
            scene = copy.deepcopy(TINY_SCENE) | {key: value}
            other_rs = Scene(scene).resolve()
            got = _attrs(other_rs)
            assert got == _cold(other_rs), key
            assert list(got) == list(_cold(other_rs)), key  # in their order too
            assert got != first
        assert _attrs(rs) == first


def test_with_the_caches_off_nothing_is_kept(rs, monkeypatch):
    KIND.clear()
    with xpersson.set_options(cache=False):
        a, b = _attrs(rs), _attrs(rs)
    assert a == b and len(KIND) == 0 and KIND.info().hits == 0
    monkeypatch.setenv("XPERSSON_CACHE", "off")  # the environment's switch, read at each look-up
    assert _attrs(rs) == a and len(KIND) == 0 and KIND.info().hits == 0


def test_a_solve_sets_the_kind_attributes_and_its_own(rs):
    """The solve's own attributes (time, scene JSON, source) are set at every solve over the
    shared ones; a cached kind hands out a copy (a Dataset's attrs changed by its user leave
    the next solve's as they were)."""
    with xpersson.set_options(cache=True):
        KIND.clear()
        ds = xpersson.solve(copy.deepcopy(TINY_SCENE))
        ds.attrs["title"] = "changed by the user"
        scene = copy.deepcopy(TINY_SCENE) | {"load": {"p0": ["2e4 Pa"]}}
        again = xpersson.solve(scene)
    assert again.attrs["title"] == TINY_SCENE["title"]
    assert json.loads(again.attrs["xpersson_scene"])["load"] == {"p0": ["2e4 Pa"]}
    assert again.attrs["xpersson_scene_source"] == "<dict>"
    assert again.attrs["date_created"] and again.attrs["history"].startswith(
        again.attrs["date_created"]
    )
