"""The kit's pytest plugin: fixtures for plugin authors' tests.

Registered through the ``pytest11`` entry point ``xpersson``, so installing xpersson makes the
fixtures available in every test-suite (no ``conftest.py`` needed). Fixtures:

``xpersson_registry``
    A function ``inject(**groups) -> Registry`` that makes plugin classes available by name
    (:func:`~xpersson.testing.registry_with`) until the test ends.
``xpersson_scene``
    The scene factory :func:`~xpersson.testing.scene` (fresh dicts on every call).
``xpersson_spectrum``
    The spectrum-section factory :func:`~xpersson.testing.spectrum`.
``xpersson_tiny_scene``
    A fresh copy of :data:`~xpersson.testing.TINY_SCENE`.
``xpersson_oracles``
    The closed forms (:func:`~xpersson.testing.oracles`).

Marker ``fast_paths``: the test checks a declared fast path (that it is taken, or what it
gives); skipped where fast paths are off (``XPERSSON_FAST_PATHS=off``: every solve takes the
plain path, which the rest of the suite then checks).

Importing this module imports neither numpy nor the core pipeline.
"""

from __future__ import annotations

import contextlib
import copy
from collections.abc import Callable, Iterator, Mapping
from types import SimpleNamespace
from typing import Any

import pytest

from ..plugins import Registry
from .oracles import oracles
from .registry import registry_with
from .scenes import TINY_SCENE, scene, spectrum

__all__ = [
    "xpersson_oracles",
    "xpersson_registry",
    "xpersson_scene",
    "xpersson_spectrum",
    "xpersson_tiny_scene",
]


@pytest.fixture
def xpersson_oracles() -> SimpleNamespace:
    """Closed-form oracles (:func:`~xpersson.testing.oracles`)."""
    return oracles()


@pytest.fixture
def xpersson_tiny_scene() -> dict[str, Any]:
    """A fresh copy of :data:`~xpersson.testing.TINY_SCENE`."""
    return copy.deepcopy(TINY_SCENE)


@pytest.fixture
def xpersson_scene() -> Callable[..., dict[str, Any]]:
    """The scene factory :func:`~xpersson.testing.scene`."""
    return scene


@pytest.fixture
def xpersson_spectrum() -> Callable[..., dict[str, Any]]:
    """The spectrum-section factory :func:`~xpersson.testing.spectrum`."""
    return spectrum


@pytest.fixture
def xpersson_registry() -> Iterator[Callable[..., Registry]]:
    """``inject(autoload=None, **groups)``: install a registry with ``groups`` for this test.

    Each call replaces the previous injection; the default registry is restored at teardown.
    """
    with contextlib.ExitStack() as stack:

        def inject(autoload: bool | None = None, **groups: Mapping[str, type]) -> Registry:
            return stack.enter_context(registry_with(autoload, **groups))

        yield inject


def pytest_configure(config: pytest.Config) -> None:
    """Register the ``fast_paths`` marker."""
    config.addinivalue_line(
        "markers", "fast_paths: checks a declared fast path (skipped with XPERSSON_FAST_PATHS=off)"
    )


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """Skip the ``fast_paths`` tests where fast paths are off."""
    from ..options import fast_paths_enabled

    if fast_paths_enabled():
        return
    skip = pytest.mark.skip(reason="XPERSSON_FAST_PATHS=off: every solve takes the plain path")
    for item in items:
        if item.get_closest_marker("fast_paths") is not None:
            item.add_marker(skip)
