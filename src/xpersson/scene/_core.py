"""The core sections of a scene (their parameters and limits) and the resolved scene."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..cache import Cache
from ..plugins import PLUGIN_GROUPS, ParamSpec, Plugin
from ..schema import METADATA_KEYS  # noqa: F401 - re-exported: the scene validates [metadata]

__all__ = [
    "CORE",
    "DEFAULT_MODEL",
    "MAX_POINTS",
    "MAX_PRESSURE",
    "MAX_ZETA",
    "PLUGIN_SECTIONS",
    "TOP_LEVEL",
    "ResolvedScene",
    "log_grid",
]

# -- the core sections and their parameters ---------------------------------------------------
MAX_PRESSURE = 1e13
"""Largest modulus or pressure a scene may give [Pa] (beyond any solid; keeps f ~ E*^2 finite)."""
MAX_ZETA = 1e12
"""Largest magnification q_1/q_L a scene may ask for [1]."""
MAX_POINTS = 100_000
"""Longest list of loads, magnifications or pressures (as the range form's ``num``)."""
CORE: dict[str, dict[str, ParamSpec]] = {
    "material": {
        "E": ParamSpec(
            "Pa",
            bounds=(0, MAX_PRESSURE),
            inclusive=(False, True),
            sweepable=True,
            description="Young's modulus of the elastic solid",
        ),
        "nu": ParamSpec(
            "1",
            bounds=(-1, 0.5),
            inclusive=(False, True),
            sweepable=True,
            description="Poisson ratio",
        ),
    },
    "load": {
        "p0": ParamSpec(
            "Pa",
            bounds=(0, MAX_PRESSURE),
            inclusive=(False, True),
            sweepable=True,
            description="nominal pressure: scalar, list or {start, stop, num}",
        ),
    },
    "output": {
        "zeta_per_decade": ParamSpec(
            "1",
            default=10,
            bounds=(1, 1000),
            kind="int",
            description="log-spaced output magnifications per decade",
        ),
        "zeta": ParamSpec(
            "1",
            default=None,
            bounds=(1, MAX_ZETA),
            array=True,
            description="explicit output magnifications (>= 1)",
        ),
        "zeta_max": ParamSpec(
            "1",
            default=None,
            bounds=(1, MAX_ZETA),
            description="largest magnification (default q_1/q_L)",
        ),
        "pressure_pdf": ParamSpec(
            "1", default=False, kind="bool", description="store the pressure PDF P(zeta, p)"
        ),
        "model_error": ParamSpec(
            "1",
            default=True,
            kind="bool",
            description="add each covered output's model-error band (X_exact_low/high, status)",
        ),
        "p_points": ParamSpec(
            "1",
            default=256,
            bounds=(8, 100000),
            kind="int",
            description="points of the default pressure grid",
        ),
        "p_max": ParamSpec(
            "Pa",
            default=None,
            bounds=(0, MAX_PRESSURE),
            inclusive=(False, True),
            description="upper end of the pressure grid",
        ),
        "p": ParamSpec(
            "Pa",
            default=None,
            bounds=(-MAX_PRESSURE, MAX_PRESSURE),
            array=True,
            description="explicit pressure grid (increasing)",
        ),
    },
    "solver": {
        "method": ParamSpec(
            "1",
            default="auto",
            kind="string",
            description="engine method (auto: exact path where one exists)",
        ),
        "rtol": ParamSpec(
            "1",
            default=1e-6,
            bounds=(1e-12, 0.1),
            inclusive=(True, False),
            description="relative tolerance on the contact area",
        ),
        "atol": ParamSpec(
            "1",
            default=1e-12,
            bounds=(0, 0.1),
            description="absolute tolerance on the contact area",
        ),
        "walkers": ParamSpec(
            "1",
            default=None,
            bounds=(1, 1e9),
            kind="int",
            description="walkers of the Monte Carlo method 'markov'",
        ),
        "seed": ParamSpec(
            "1",
            default=None,
            bounds=(0, None),
            kind="int",
            description="random seed of the Monte Carlo method 'markov'",
        ),
        "plugin_time_limit": ParamSpec(
            "s",
            default=None,
            bounds=(0, 1e6),
            inclusive=(False, True),
            description="wall-clock limit of each plugin call (none by default); a call "
            "running longer fails naming the plugin (a sweep marks the point failed)",
        ),
    },
}
PLUGIN_SECTIONS = {s: g for s, g in PLUGIN_GROUPS.items() if s not in ("analysis", "geometry")}
"""The scene's plugin sections -> their group (:data:`xpersson.plugins.PLUGIN_GROUPS`)."""
DEFAULT_MODEL = {"coefficient": "elastic", "boundary": "elastic"}
TOP_LEVEL = {
    "title", "description", "metadata", "analyses", "sweep", "geometry", *CORE, *PLUGIN_SECTIONS
}  # fmt: skip


@dataclass
class ResolvedScene:
    """A validated scene: plugin instances and SI arrays (no pint).

    Besides the values, resolution captures what the run needs of the registry:
    ``labels`` (section or ``"analyses.<name>"`` -> the plugin's label for messages, see
    :func:`xpersson.checks.plugin_label`) and ``plugin_records`` (``(record, name)`` per plugin
    in the order spectrum, coefficient, boundary, analyses: the shared read-only
    :meth:`xpersson.plugins.Registry.provenance` record and the name the scene used), with
    ``plugin_records_json``, their JSON text as the archive records it (``None``: made when
    needed).
    """

    scene: Any  # the Scene it was resolved from (a Scene; _scene imports this module)
    spectrum: Plugin
    coefficient: Plugin
    boundary: Plugin
    analyses: list[tuple[str, Plugin]]
    psd: Any
    E: float
    nu: float
    p0: np.ndarray
    p0_scalar: bool
    zeta: np.ndarray
    pressure_pdf: bool
    p: np.ndarray | None
    p_points: int
    p_max: float | None
    rtol: float
    atol: float
    method: Any
    plugin_names: dict[str, str] = field(default_factory=dict)
    resolved: dict[str, Any] = field(default_factory=dict)
    solver_options: dict[str, Any] = field(default_factory=dict)
    labels: dict[str, Any] = field(default_factory=dict)
    plugin_records: tuple[tuple[dict[str, Any], str | None], ...] = ()
    plugin_records_json: str | None = None
    plugin_time_limit: float | None = None
    #: A finite body (:mod:`._geometry`): the geometry plugin, the forces [N] and whether the
    #: force was a scalar; ``p0`` is then the grid of pressures the body samples.
    geometry: Plugin | None = None
    force: np.ndarray | None = None
    force_scalar: bool = False
    #: ``(resolved, its JSON text)`` when the text was made with the resolution (one reused by
    #: the solves of a scene, :func:`xpersson.pipeline.frontend.resolve`): the archive's
    #: ``xpersson_scene`` of that very dict (any other dict's text is made when needed).
    resolved_text: tuple[dict[str, Any], str] | None = None

    @property
    def E_star(self) -> float:
        """Plane-strain modulus ``E / (1 - nu^2)`` [Pa]."""
        return self.E / (1.0 - self.nu**2)


_GRIDS = Cache(
    "scene.zeta_grid",
    scope="process",
    maxsize=256,
    doc="the log-spaced output magnifications 1..zeta_max in n steps (read-only)",
)


def log_grid(n: int, zeta_max: float) -> np.ndarray:
    """``n + 1`` log-spaced magnifications from 1 to ``zeta_max`` [1], the ends exact
    (read-only: made once per ``n`` and ``zeta_max``)."""

    def make() -> np.ndarray:
        z = np.geomspace(1.0, zeta_max, n + 1)
        z[0], z[-1] = 1.0, zeta_max
        return z

    return _GRIDS.get((n, zeta_max), make)
