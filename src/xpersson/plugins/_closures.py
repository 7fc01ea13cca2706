"""The closure parameters, declared once for every coefficient that offers a closure.

The values (closure names, the package-wide ``gamma`` default and WM17's 5/9) are those of
:mod:`xpersson.physics.closures`, the one home of the closures' formulas.
"""

from __future__ import annotations

from ..physics.closures import CLOSURES, DEFAULT_GAMMA, GAMMA_DEFAULT
from ..specs import ParamSpec

__all__ = ["CLOSURE_PARAMETERS"]

_WM17 = "5/9" if DEFAULT_GAMMA["wm17"] == 5.0 / 9.0 else f"{DEFAULT_GAMMA['wm17']:g}"

CLOSURE_PARAMETERS: dict[str, ParamSpec] = {
    "closure": ParamSpec(
        "1",
        default="persson01",
        kind="choice",
        choices=CLOSURES,
        description="correction-factor closure of the variance",
    ),
    "gamma": ParamSpec(
        "1",
        default=None,
        bounds=(0, 1),
        inclusive=(False, True),
        sweepable=True,
        description=f"closure parameter (default {GAMMA_DEFAULT}; wm17: {_WM17})",
    ),
}
"""``closure`` (persson01, yp08, wm17, xu24) and its ``gamma`` (``None``: the closure's default,
:data:`xpersson.physics.closures.DEFAULT_GAMMA`), as a coefficient's ``parameters`` entries."""
