"""Test doubles and scenes of the sweep tests (a unique module name: no clash with plugins)."""

from __future__ import annotations

import copy
from typing import Any

import numpy as np

from xpersson.builtin.elastic import ElasticCoefficient
from xpersson.plugins import ParamSpec

BASE: dict[str, Any] = {
    "spectrum": {
        "model": "self_affine",
        "H": 0.8,
        "q_L": "1e3 1/m",
        "q_r": "1e4 1/m",
        "q_1": "1e8 1/m",
        "h_rms": "1 um",
    },
    "material": {"E": "10 MPa", "nu": 0.5},
    "load": {"p0": ["1e4 Pa", "1e5 Pa", "1e6 Pa"]},
    "output": {"zeta_per_decade": 4},
}


def scene(**sections: dict[str, Any]) -> dict[str, Any]:
    """The base scene with some section entries replaced."""
    out = copy.deepcopy(BASE)
    for section, values in sections.items():
        out.setdefault(section, {}).update(values)
    return out


class SlidingCoefficient(ElasticCoefficient):
    """Elastic f scaled by (1 + velocity / (1 m/s)) (test double with its own dimensions)."""

    summary = "elastic f scaled by a sliding speed and a temperature (test double)"
    parameters = {
        **ElasticCoefficient.parameters,
        "velocity": ParamSpec(
            "m/s",
            default=0.0,
            bounds=(0, None),
            sweepable=True,
            dim="v",
            description="sliding speed",
        ),
        "temperature": ParamSpec(
            "K",
            default=293.0,
            bounds=(0, None),
            inclusive=(False, True),
            sweepable=True,
            dim="T",
            description="temperature",
        ),
    }

    def _scale(self) -> float:
        return (1.0 + self.params["velocity"]) * self.params["temperature"] / 293.0

    def f(self, ctx: Any, zeta: np.ndarray) -> np.ndarray:
        return self._scale() * super().f(ctx, zeta)

    def tau(self, ctx: Any, zeta: np.ndarray) -> np.ndarray:
        return self._scale() * super().tau(ctx, zeta)

    def effective_tau(self, ctx: Any, zeta: np.ndarray) -> np.ndarray:
        t = np.asarray(self.tau(ctx, zeta), dtype=float)
        return np.broadcast_to(t, (ctx.p0.size, t.size)).copy()
