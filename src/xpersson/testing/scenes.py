"""Scenes for tests: the tiny scene of the checks, plugin parameters, and scene factories.

Every factory returns a fresh dict (no two calls share a nested section), written the way a user
writes a scene: quantities as strings with units.
"""

from __future__ import annotations

import copy
from collections.abc import Mapping
from typing import Any

from ..plugins import REQUIRED, Plugin
from ._names import CHECK_NAME, SECTION, qual

__all__ = [
    "TINY_SCENE",
    "material",
    "merge_scene",
    "pressures",
    "sample_params",
    "scene",
    "spectrum",
    "tiny_scene",
]

#: The tiny scene of the checks (about 10 zeta points, two loads; solves in milliseconds).
TINY_SCENE: dict[str, Any] = {
    "title": "xpersson.testing tiny scene",
    "spectrum": {
        "model": "self_affine",
        "H": 0.8,
        "q_L": "1e3 1/m",
        "q_r": "1e4 1/m",
        "q_1": "1e7 1/m",
        "h_rms": "1 um",
    },
    "material": {"E": "10 MPa", "nu": 0.5},
    "load": {"p0": ["1e4 Pa", "1e5 Pa"]},
    "coefficient": {"model": "elastic"},
    "boundary": {"model": "elastic"},
    "output": {"zeta_per_decade": 3},
    "solver": {"rtol": 1e-6},
}


# -- section factories -------------------------------------------------------------------------
def spectrum(
    *,
    H: float = 0.8,
    q_L: str = "1e3 1/m",
    q_r: str = "1e4 1/m",
    q_1: str = "1e7 1/m",
    h_rms: str = "1 um",
) -> dict[str, Any]:
    """A ``self_affine`` spectrum section; the defaults are the tiny scene's spectrum.

    Parameters
    ----------
    H : float
        Hurst exponent [1].
    q_L, q_r, q_1 : str
        Lower cut-off, roll-off and upper cut-off wavenumbers (quantity strings, [1/m]).
    h_rms : str
        Root-mean-square height (quantity string, [m]).
    """
    return {"model": "self_affine", "H": H, "q_L": q_L, "q_r": q_r, "q_1": q_1, "h_rms": h_rms}


def material(E: str = "10 MPa", nu: float = 0.5) -> dict[str, Any]:
    """A material section: Young's modulus ``E`` (quantity string, [Pa]) and Poisson ratio [1]."""
    return {"E": E, "nu": nu}


_spectrum_section = spectrum
_material_section = material


def pressures(p0: Any) -> list[str]:
    """Nominal pressures as scene strings: numbers [Pa] become ``"<repr> Pa"``, strings pass.

    ``p0`` is one value or a sequence (list, tuple or numpy array) of them.
    """
    import numpy as np

    values = [p0] if isinstance(p0, str) else np.atleast_1d(np.asarray(p0, dtype=object))
    return [v if isinstance(v, str) else f"{float(v)!r} Pa" for v in values]


def scene(
    spectrum: Mapping[str, Any] | None = None,
    material: Mapping[str, Any] | None = None,
    *,
    p0: Any = None,
    zeta_per_decade: int | None = None,
    **sections: Any,
) -> dict[str, Any]:
    """A scene dict built from sections; only the sections given appear in it.

    Parameters
    ----------
    spectrum, material : Mapping, optional
        The ``spectrum`` and ``material`` sections (default: :func:`spectrum` and
        :func:`material`, the tiny scene's).
    p0 : float, str or sequence, optional
        Nominal pressures (floats in Pa, or quantity strings); sets ``load.p0``.
    zeta_per_decade : int, optional
        Sets ``output.zeta_per_decade``.
    **sections
        Further sections (``load``, ``coefficient``, ``boundary``, ``analyses``, ``output``,
        ``solver``, ...), deep-copied in.
    """
    sc: dict[str, Any] = {
        "spectrum": dict(spectrum) if spectrum is not None else _spectrum_section(),
        "material": dict(material) if material is not None else _material_section(),
    }
    if p0 is not None:
        sc["load"] = {"p0": pressures(p0)}
    if zeta_per_decade is not None:
        sc["output"] = {"zeta_per_decade": zeta_per_decade}
    for key, value in sections.items():
        sc[key] = copy.deepcopy(value)
    return sc


def merge_scene(base: Mapping[str, Any], over: Mapping[str, Any]) -> dict[str, Any]:
    """A deep copy of ``base`` with ``over`` merged in key by key (nested mappings merged)."""
    out = copy.deepcopy(dict(base))
    for key, val in over.items():
        if isinstance(val, Mapping) and isinstance(out.get(key), dict):
            out[key] = merge_scene(out[key], val)
        else:
            out[key] = copy.deepcopy(val)
    return out


# -- a plugin under check in a scene -----------------------------------------------------------
def sample_params(cls: type[Plugin], params: Mapping[str, Any] | None = None) -> dict[str, Any]:
    """SI parameters for an instance: ``params``, else each spec's default or ``example``.

    Raises
    ------
    AssertionError
        A required parameter has no ``example`` and is not in ``params``.
    """
    out = dict(params or {})
    for name, spec in cls.parameters.items():
        if name in out:
            continue
        value = spec.sample
        if value is REQUIRED:
            raise AssertionError(
                f"{qual(cls)}: parameter {name!r} is required; pass params={{{name!r}: ...}} "
                f"to check_plugin or declare ParamSpec(example=...)"
            )
        out[name] = value
    return out


def _scene_value(spec: Any, value: Any) -> Any:
    """An SI value written the way a scene gives it (quantity strings with units)."""
    if spec.kind != "quantity" or value is None:
        return value
    if spec.array:
        from ..units import ureg

        return ureg().Quantity(list(value), spec.unit)
    if spec.unit in ("1", ""):
        return float(value)
    return f"{float(value)!r} {spec.unit}"


def _scene_params(cls: type[Plugin], params: Mapping[str, Any]) -> dict[str, Any]:
    return {
        k: _scene_value(cls.parameters[k], v)
        for k, v in params.items()
        if cls.parameters[k].required or v != cls.parameters[k].default
    }


def tiny_scene(
    cls: type[Plugin] | None = None,
    params: Mapping[str, Any] | None = None,
    scene: Mapping[str, Any] | None = None,
) -> dict[str, Any]:
    """:data:`TINY_SCENE` with ``scene`` merged in and ``cls`` selected as ``plugin_under_check``.

    ``params`` are SI values; they are written as quantity strings in the declared units.
    """
    sc = merge_scene(TINY_SCENE, scene or {})
    if cls is not None:
        section = SECTION[cls.group]
        raw = _scene_params(cls, params or {})
        if section == "analyses":
            sc.setdefault("analyses", {})[CHECK_NAME] = raw
        else:
            sc[section] = {"model": CHECK_NAME, **raw}
    return sc


def _tiny_context(p0: tuple[float, ...] = (1e5, 1e6)) -> Any:
    """The tiny scene's context (spectrum, material, loads ``p0`` [Pa], 10 zeta points) for
    the unit checks of plugin methods."""
    import numpy as np

    from ..physics.psd import SelfAffineRollOff
    from ..plugins import SceneContext

    psd = SelfAffineRollOff.from_h_rms(1e-6, 0.8, 1e3, 1e4, 1e6)
    E, nu = 1e7, 0.5
    return SceneContext(
        psd=psd,
        E=E,
        nu=nu,
        E_star=E / (1 - nu**2),
        p0=np.asarray(p0, dtype=float),
        zeta=np.geomspace(1.0, 1e3, 10),
    )
