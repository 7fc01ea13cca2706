"""Fake entry points and distributions for the plugin-machinery tests."""

from __future__ import annotations

import sys
from importlib.metadata import EntryPoint

from xpersson.plugins import _discovery, _registry

FAKE_MODULES = (
    "xpersson_fake_plugins",
    "xpersson_fake_broken",
    "xpersson_fake_toonew",
    "xpersson_fake_badspec",
)


class FakeDist:
    """Just enough of ``importlib.metadata.Distribution`` for the registry."""

    def __init__(self, name: str, version: str = "1.0") -> None:
        self.metadata = {"Name": name}
        self.version = version
        self.name = name


def fake_ep(group: str, name: str, value: str, dist: str = "fake-dist", version: str = "1.0"):
    """An entry point of group ``xpersson.<group>`` belonging to a fake distribution."""
    return EntryPoint(name, value, "xpersson." + group)._for(FakeDist(dist, version))


M = "xpersson_fake_plugins"
STANDARD = [
    fake_ep("boundaries", "offset", f"{M}:OffsetWall", "xpersson-offset", "0.3"),
    fake_ep("boundaries", "wall", f"{M}:OffsetWall", "dist-a", "1.0"),
    fake_ep("boundaries", "wall", f"{M}:OtherWall", "dist-b", "2.0"),
    fake_ep("boundaries", "broken", "xpersson_fake_broken:BrokenWall", "broken-dist", "0.1"),
    fake_ep("boundaries", "future", "xpersson_fake_toonew:FutureWall", "future-dist", "9.0"),
    fake_ep("boundaries", "badspec", "xpersson_fake_badspec:BadSpecWall", "bad-dist", "0.0"),
    fake_ep("boundaries", "elastic", f"{M}:OffsetWall", "xpersson", "0.1.0"),
    fake_ep("coefficients", "scaled", f"{M}:ScaledCoefficient", "xpersson-offset", "0.3"),
]


def install_eps(monkeypatch, eps):
    """Make the registry discover exactly ``eps`` (for the duration of the test)."""

    def entry_points(group: str, installed: object = None):
        return [ep for ep in eps if ep.group == group]

    monkeypatch.setattr(_discovery, "_entry_points", entry_points)
    return eps


def make_standard_registry(monkeypatch):
    """A registry over :data:`STANDARD` with autoload on and the fake modules unimported."""
    monkeypatch.delenv(_registry.AUTOLOAD_ENV, raising=False)
    for mod in FAKE_MODULES:
        monkeypatch.delitem(sys.modules, mod, raising=False)
    install_eps(monkeypatch, STANDARD)
    return _registry.Registry()
