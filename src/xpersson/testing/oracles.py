"""Independent closed forms (:cite:p:`persson2001,persson2006`, :doc:`/theory/03_absorbing_wall`)
to test solutions against.

Plain functions of SI floats or arrays; numpy and scipy are imported when called.
"""

from __future__ import annotations

import math
from types import SimpleNamespace
from typing import Any

__all__ = [
    "constant_wall_area",
    "constant_wall_load",
    "linear_wall_area",
    "linear_wall_load",
    "mirrored_gaussian_area",
    "oracles",
    "two_wall_areas",
]


def _erf(x: Any) -> Any:
    from scipy.special import erf

    return erf(x)


def mirrored_gaussian_area(p0: Any, tau: Any) -> Any:
    """Elastic contact area A/A0 = erf(p0 / (2 sqrt(tau))) (:cite:p:`persson2001`).

    Parameters
    ----------
    p0 : float or array
        Nominal pressure [Pa].
    tau : float or array
        Diffusion time [Pa^2] (tau = G p0^2).
    """
    import numpy as np

    t = np.asarray(tau, dtype=float)
    with np.errstate(divide="ignore"):
        return _erf(np.asarray(p0, dtype=float) / (2.0 * np.sqrt(t)))


def constant_wall_area(p0: Any, s: Any, tau: Any) -> Any:
    """Area with an absorbing wall at p = -s: erf((p0 + s) / (2 sqrt(tau))) (§2.2).

    ``s`` [Pa] is a constant adhesive stress sigma_a; ``s = 0`` is the elastic case.
    """
    return mirrored_gaussian_area(_add(p0, s), tau)


def constant_wall_load(p0: Any, s: Any, tau: Any) -> Any:
    """Load in the domain, int p P dp = p0 + s (1 - A) [Pa], for the wall at p = -s (§2.2)."""
    import numpy as np

    return np.asarray(p0, dtype=float) + np.asarray(s, dtype=float) * (
        1.0 - constant_wall_area(p0, s, tau)
    )


def _add(a: Any, b: Any) -> Any:
    import numpy as np

    return np.asarray(a, dtype=float) + np.asarray(b, dtype=float)


def _linear_wall_terms(p0: Any, s0: Any, c: Any, tau: Any) -> tuple[Any, ...]:
    import numpy as np

    p0, s0, c, tau = (np.asarray(v, dtype=float) for v in (p0, s0, c, tau))
    y0 = p0 + s0
    sig = np.sqrt(2.0 * tau)
    a1 = (y0 + c * tau) / sig
    a2 = (c * tau - y0) / sig
    return p0, s0, c, tau, y0, sig, a1, a2, np.exp(-c * y0)


def linear_wall_area(p0: Any, s0: Any, c: Any, tau: Any) -> Any:
    """Exact area for the absorbing wall p_w(tau) = -(s0 + c tau)
    (:doc:`/theory/03_absorbing_wall`).

    A/A0 = Phi((y0 + c tau)/sqrt(2 tau)) - exp(-c y0) Phi((c tau - y0)/sqrt(2 tau)),
    y0 = p0 + s0. Units: p0, s0 [Pa], c [1/Pa], tau [Pa^2].
    """
    from scipy.special import ndtr

    *_, a1, a2, k = _linear_wall_terms(p0, s0, c, tau)
    return ndtr(a1) - k * ndtr(a2)


def linear_wall_load(p0: Any, s0: Any, c: Any, tau: Any) -> Any:
    """Exact load in the domain, int p P dp [Pa], for the linearly moving wall (§2.2)."""
    import numpy as np
    from scipy.special import ndtr

    p0, s0, c, tau, y0, sig, a1, a2, k = _linear_wall_terms(p0, s0, c, tau)
    phi = lambda x: np.exp(-0.5 * x * x) / math.sqrt(2.0 * math.pi)  # noqa: E731
    return p0 * ndtr(a1) + sig * phi(a1) - k * ((-p0 - 2.0 * s0) * ndtr(a2) + sig * phi(a2))


def two_wall_areas(p0: float, sigma_y: float, tau: Any) -> tuple[Any, Any]:
    """Elastic and plastic area for fixed walls at 0 and sigma_y (:cite:p:`persson2006`).

    Sine series ``A_el = sum_odd 4/(n pi) sin(n pi p0/sY) exp(-(n pi/sY)^2 tau)`` and
    ``A_pl = p0/sY - sum_n 2/(n pi) (-1)^(n+1) sin(n pi p0/sY) exp(-(n pi/sY)^2 tau)`` (image
    series at small tau), from :mod:`xpersson.engine.exact`, their one home. Units: p0, sigma_y
    [Pa], tau [Pa^2].

    Returns
    -------
    (A_el, A_pl) : arrays shaped like ``tau``
    """
    import numpy as np

    from ..engine import exact  # the one home of the two-wall series

    t = np.asarray(tau, dtype=float)
    a_el, _, a_pl = exact.two_wall(t, float(p0), 0.0, float(sigma_y))
    return np.asarray(a_el).reshape(np.shape(tau)), np.asarray(a_pl).reshape(np.shape(tau))


def oracles() -> SimpleNamespace:
    """The closed forms as one namespace (what the ``xpersson_oracles`` fixture returns)."""
    return SimpleNamespace(
        mirrored_gaussian_area=mirrored_gaussian_area,
        constant_wall_area=constant_wall_area,
        constant_wall_load=constant_wall_load,
        linear_wall_area=linear_wall_area,
        linear_wall_load=linear_wall_load,
        two_wall_areas=two_wall_areas,
    )
