"""Output declarations and the interpretation of engine results shared by both boundaries.

Both plasticity boundaries solve the same problem up to the wall law: probability absorbed at
``p = 0`` is non-contact area, probability absorbed at the yield wall ``p = Y(zeta)`` is plastic
contact area (carrying the pressure ``Y(zeta)``), and what stays in ``(0, Y)`` is elastic
contact area (physics.md §3).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from xpersson.plugins import SceneContext, VarSpec

__all__ = ["AREA_OUTPUTS", "assemble", "stack"]

_PZ = ("p0", "zeta")

AREA_OUTPUTS: dict[str, VarSpec] = {
    "elastic_area_fraction": VarSpec(
        _PZ,
        "1",
        "elastic contact area fraction A_el/A0",
        description="probability of the pressure lying strictly between 0 and the hardness",
    ),
    "plastic_area_fraction": VarSpec(
        _PZ,
        "1",
        "plastic contact area fraction A_pl/A0",
        description="probability absorbed at the yield wall p = Y(zeta) (cumulative)",
    ),
    "non_contact_area_fraction": VarSpec(
        _PZ,
        "1",
        "non-contact area fraction A_non/A0",
        description="probability absorbed at the wall p = 0 (cumulative)",
    ),
    "total_contact_fraction": VarSpec(
        _PZ,
        "1",
        "total contact area fraction (A_el + A_pl)/A0",
    ),
    "elastic_load_share": VarSpec(
        _PZ,
        "1",
        "fraction of the nominal load carried by elastic contact",
        description="int_0^Y p P dp / p0",
    ),
    "plastic_load_share": VarSpec(
        _PZ,
        "1",
        "fraction of the nominal load carried by plastic contact",
        description="Y(zeta) A_pl / p0",
    ),
    "plastic_force_balance_residual": VarSpec(
        _PZ,
        "1",
        "relative residual of the force balance",
        description="(int_0^Y p P dp + Y(zeta) A_pl - p0) / p0; zero for an exact solution",
    ),
    "yield_stress": VarSpec(
        ("zeta",),
        "Pa",
        "penetration hardness at magnification zeta",
        description="position Y(zeta) of the yield wall",
    ),
}


def assemble(
    ctx: SceneContext,
    yield_stress: np.ndarray,
    elastic: np.ndarray,
    plastic: np.ndarray,
    non_contact: np.ndarray,
    load: np.ndarray,
) -> dict[str, tuple[tuple[str, ...], np.ndarray]]:
    """Build the declared area variables from per-(p0, zeta) arrays.

    Parameters
    ----------
    ctx : SceneContext
        The scene (``ctx.p0`` [Pa], ``ctx.zeta`` [1]).
    yield_stress : numpy.ndarray
        Y(zeta) [Pa], shape ``(n_zeta,)``.
    elastic, plastic, non_contact : numpy.ndarray
        Area fractions [1], shape ``(n_load, n_zeta)``.
    load : numpy.ndarray
        Elastically carried load ``int_0^Y p P dp`` [Pa], shape ``(n_load, n_zeta)``.
    """
    p0 = np.asarray(ctx.p0, dtype=float)[:, None]
    y = np.asarray(yield_stress, dtype=float)[None, :]
    plastic_load = y * plastic
    # A_el + A_pl + A_non = 1 holds to the solver's tolerance; where a failed solve (its status
    # says so) leaves A_el + A_pl above 1, report the complement of the non-contact area instead
    # of an impossible fraction (the residual stays visible in probability_balance)
    total = elastic + plastic
    total = np.where(total > 1.0, 1.0 - non_contact, total)
    return {
        "elastic_area_fraction": (_PZ, elastic),
        "plastic_area_fraction": (_PZ, plastic),
        "non_contact_area_fraction": (_PZ, non_contact),
        "total_contact_fraction": (_PZ, total),
        "elastic_load_share": (_PZ, load / p0),
        "plastic_load_share": (_PZ, plastic_load / p0),
        "plastic_force_balance_residual": (_PZ, (load + plastic_load - p0) / p0),
        "yield_stress": (("zeta",), np.asarray(yield_stress, dtype=float).copy()),
    }


def stack(results: Sequence[Any], n_zeta: int) -> dict[str, np.ndarray]:
    """Stack per-load engine results into ``(n_load, n_zeta)`` arrays.

    Uses ``area`` (elastic), ``absorbed_upper`` (plastic), ``absorbed_lower`` (non-contact) and
    ``load`` of each :class:`xpersson.engine.EngineResult`.
    """

    batch = _batch_arrays(results, n_zeta)

    def get(name: str) -> np.ndarray:
        if batch is not None:  # an EngineBatch: a copy of its stacked (n_load, n_zeta) array
            return np.array(getattr(results, name), dtype=float)
        rows = [np.asarray(getattr(r, name), dtype=float).reshape(-1) for r in results]
        for row in rows:
            if row.size != n_zeta:
                raise ValueError(
                    f"engine result field {name!r} has {row.size} values, expected one per "
                    f"output magnification ({n_zeta})"
                )
        return np.vstack(rows) if rows else np.empty((0, n_zeta))

    return {
        "elastic": get("area"),
        "plastic": get("absorbed_upper"),
        "non_contact": get("absorbed_lower"),
        "load": get("load"),
        "tau": get("tau"),
    }


def _batch_arrays(results: Any, n_zeta: int) -> bool | None:
    """True when ``results`` is an :class:`xpersson.engine.EngineBatch` whose stacked arrays
    are ``(n_load, n_zeta)`` (no per-load result objects needed), else None."""
    from xpersson.engine import EngineBatch

    if not isinstance(results, EngineBatch):
        return None
    shape = (len(results), n_zeta)
    for name in ("area", "absorbed_upper", "absorbed_lower", "load", "tau"):
        if np.shape(getattr(results, name, None)) != shape:
            return None
    return True
