"""Scenes of a sphere and a cylinder on a rough flat (fresh dicts, as a user writes them)."""

from __future__ import annotations

from typing import Any

import pytest

from xpersson.plugins import get_registry


def body_scene(
    model: str = "sphere", force: Any = "1 mN", h_rms: str = "1 nm", **geometry: Any
) -> dict[str, Any]:
    """A soft flat (E = 1 MPa) with a self-affine roughness of ``h_rms`` under a body."""
    geo = {"model": model, "radius": "10 mm", **geometry}
    if model == "cylinder":
        geo.setdefault("length", "20 mm")
    return {
        "geometry": geo,
        "load": {"force": force},
        "spectrum": {
            "model": "self_affine",
            "H": 0.8,
            "q_L": "1e5 1/m",
            "q_r": "1e6 1/m",
            "q_1": "1e7 1/m",
            "h_rms": h_rms,
        },
        "material": {"E": "1 MPa", "nu": 0.5},
    }


@pytest.fixture(scope="session", autouse=True)
def _geometries_installed() -> None:
    names = get_registry().names("geometries")
    if not {"sphere", "cylinder"} <= set(names):
        pytest.fail(
            f"the built-in geometries are not registered (found {names}): the entry points of "
            "xpersson.geometries come from pyproject.toml; reinstall (pip install -e .)"
        )
