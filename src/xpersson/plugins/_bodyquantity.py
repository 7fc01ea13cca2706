"""The local-quantity contract: what an analysis declares so that a finite body integrates it.

A scene with a ``[geometry]`` body solves the rough flat on a grid of nominal pressures ``p0``
and then the nominal pressure ``p(r)`` of each force (:mod:`xpersson.pipeline.body`). An
analysis whose output on that grid is a quantity **per unit nominal area as a function of the
local nominal pressure** (a contact conductance per area, a shear stress, a seal's sheet flow
conductance) declares, on its class,

.. code-block:: python

    body_quantities = {
        "body_electrical_conductance": BodyQuantity(
            "electrical_contact_conductance", "constriction", "S",
            "electrical conductance of the body's contact",
            bulk=lambda p: 0.5 * (p["resistivity_1"] + p["resistivity_2"]),
        ),
    }

and the core integrates it over ``p(r)`` for every force, from the analysis's own output on the
pressure grid (no new solve), writing ``body_electrical_conductance`` (dimension ``force``) and
its grid-doubling error ``body_electrical_conductance_grid_error``. The declaration is checked
when the class is created (:func:`check_body_quantities`, from
:func:`xpersson.plugins._classcheck.check_class`).

How a local value ``q(p)`` combines over the body (:data:`COMBINES`):

``"area"``
    In parallel over the nominal contact: ``Q = int q(p(r)) dA`` (a friction force from a
    shear stress, an energy from an energy per area). Units of ``Q``: those of ``q`` times m^2
    (a cylinder: times its length in m, per length integrated over ``x``).
``"constriction"``
    A conductance per area of the interface in series with the spreading (constriction)
    resistance of the two bodies, solved over the nominal contact: the flux density ``j(r)``
    through the interface satisfies ``V = j(r)/q(p(r)) + b int G(r, s) j(s) dA(s)`` with ``G``
    the half-space Green's function of the elastic solve and ``b`` the bulk factor
    (``bulk(params)``: ``(rho_1 + rho_2)/2`` [ohm m] for an electrical conductance, ``(1/k_1 +
    1/k_2)/2`` [m K/W] for a thermal one); ``Q = int j dA / V``. A smooth body (``q`` large
    inside the contact) gives Holm's constriction of the nominal contact, ``4 a / (rho_1 +
    rho_2)`` for a Hertz circle of radius ``a``; ``b = 0`` gives the areal sum. With Barber's
    local conductance ``q = 2 K(p)/((rho_1 + rho_2) E*)`` it equals ``2 k_body/((rho_1 +
    rho_2) E*)``, the body's normal stiffness by the same analogy (Barber 2003).
``"series"``
    In series across the contact of a line contact (a cylinder, e.g. an O-ring cord pressed on
    a flat, its length the seal's circumference): ``Q = L / int dx / q(p(x))`` with ``q`` a
    sheet conductance (e.g. a flow per unit pressure drop per square), ``L`` the cylinder's
    length. A uniform pressure over a width ``W`` gives ``L q / W``, the flat seal's value. Not
    defined for an axisymmetric body (NaN).

A conductance per area may be unbounded at some pressures (full contact: the interface has no
resistance, the analysis's value is NaN by its declared ``nan_meaning``). ``unbounded`` names
the analysis's status output (a CF flag variable on ``p0`` with the flag meaning
``full_contact``): where the status holds that flag and the local value is NaN, the core
combines the value as unbounded (``inf``: an interface without resistance; between grid
pressures it interpolates the local resistance ``1/q`` linearly), so a body pressed into full
contact conducts through its bulk constriction alone (Holm's value for a smooth disk).
"""

from __future__ import annotations

import dataclasses
import re
from collections.abc import Callable, Mapping
from typing import Any

from ..specs import SpecError, VarSpec

__all__ = ["BodyQuantity", "COMBINES", "FULL_CONTACT", "check_body_quantities"]

COMBINES = {
    "area": "in parallel over the nominal contact: int q dA",
    "constriction": "a conductance per area in series with the bodies' spreading resistance",
    "series": "in series across a line contact (a seal): L / int dx/q",
}
"""How a declared local quantity combines over the body (name -> meaning)."""

FULL_CONTACT = "full_contact"
"""The CF flag meaning of a ``BodyQuantity.unbounded`` status: the local value is unbounded."""

_NAME = re.compile(r"^body_[a-z][a-z0-9_]*$")
_Params = Callable[[Mapping[str, Any]], float]


@dataclasses.dataclass(frozen=True)
class BodyQuantity:
    """A local quantity of an analysis that a finite body integrates over its nominal contact.

    Parameters
    ----------
    local : str
        The analysis's own output (declared in ``outputs`` and ``provides``, dims ``("p0",)``)
        that is the local value ``q(p0)``: per nominal area for ``"area"`` and
        ``"constriction"``, per square (a sheet conductance) for ``"series"``.
    combine : {"area", "constriction", "series"}
        How ``q`` combines over the body (see :data:`COMBINES`).
    units : str
        CF units of the integrated body output (e.g. ``"S"``, ``"W K-1"``, ``"m3 s-1"``, ``"N"``).
    long_name : str
        Its long name.
    description : str
        Optional longer text (attribute ``description``).
    factor : callable, optional
        ``factor(params) -> float``: ``q = factor * local`` (e.g. a flat seal's leak rate times
        its width over its length gives the sheet conductance). Default 1.
    bulk : callable, optional
        ``"constriction"`` only (and required there): ``bulk(params) -> float``, the factor
        ``b`` of the bodies' spreading term in the units of ``1 / (q m)`` (a resistivity).
    times_pressure : bool
        ``q = local * p0`` (e.g. a shear stress from a friction coefficient).
    unbounded : str, optional
        A status output of the class (dims ``("p0",)``, CF ``flag_values``/``flag_meanings``
        with the meaning ``full_contact``): where it holds that flag, a NaN local value is
        unbounded (``inf``, no resistance) rather than undefined.
    """

    local: str
    combine: str
    units: str
    long_name: str
    description: str = ""
    factor: _Params | None = None
    bulk: _Params | None = None
    times_pressure: bool = False
    unbounded: str | None = None

    def spec(self) -> VarSpec:
        """The :class:`~xpersson.specs.VarSpec` of the integrated output (dimension force)."""
        nan = "not defined for an axisymmetric body" if self.combine == "series" else None
        return VarSpec(
            ("force",), self.units, self.long_name, description=self.description,
            nan_meaning=nan,
        )  # fmt: skip

    def local_values(self, params: Mapping[str, Any], values: Any, p0: Any) -> Any:
        """``q`` [per area or per square] on the pressure grid ``p0`` [Pa] from the analysis's
        ``local`` output ``values`` and the instance's ``params``."""
        q = values * (1.0 if self.factor is None else float(self.factor(params)))
        return q * p0 if self.times_pressure else q

    def unbounded_where(self, outputs: Mapping[str, VarSpec], status: Any) -> Any:
        """Where the local value is unbounded: ``status`` (the values of the ``unbounded``
        output on ``p0``) equals its ``full_contact`` flag in ``outputs`` (the class's);
        all False without ``unbounded``."""
        import numpy as np  # lazily: ``xpersson plugins list`` imports no numpy

        if self.unbounded is None:
            return np.zeros(np.shape(status), bool)
        return np.asarray(status) == _full_contact_flag(outputs[self.unbounded])


def _full_contact_flag(spec: VarSpec) -> int:
    """The flag value of meaning :data:`FULL_CONTACT` in a status output's CF attributes."""
    import numpy as np  # lazily: ``xpersson plugins list`` imports no numpy

    meanings = str(spec.extra.get("flag_meanings", "")).split()
    values = np.atleast_1d(np.asarray(spec.extra.get("flag_values", ()))).tolist()
    if FULL_CONTACT not in meanings or len(values) != len(meanings):
        raise SpecError(f"flag_meanings {meanings} / flag_values {values} have no {FULL_CONTACT!r}")
    return int(values[meanings.index(FULL_CONTACT)])


def _check_unbounded(cls: type[Any], where: str, bq: BodyQuantity) -> None:
    if bq.unbounded is None:
        return
    out = cls.outputs.get(bq.unbounded)
    if bq.unbounded not in cls.provides or out is None or tuple(out.dims) != ("p0",):
        raise SpecError(f"{where}: unbounded={bq.unbounded!r} must be an output the class "
                        "provides with dims ('p0',)")  # fmt: skip
    try:
        _full_contact_flag(out)
    except SpecError as exc:
        raise SpecError(f"{where}: unbounded={bq.unbounded!r}: {exc}") from None


def check_body_quantities(cls: type[Any], name: str) -> None:
    """Check the ``body_quantities`` declaration of analysis class ``cls`` (qualified ``name``)
    (raises :class:`~xpersson.specs.SpecError` naming the class and the quantity)."""
    decl = getattr(cls, "body_quantities", {})
    if not isinstance(decl, Mapping):
        raise SpecError(f"{name}: body_quantities must be a mapping name -> BodyQuantity")
    for bname, bq in decl.items():
        where = f"{name}.body_quantities[{bname!r}]"
        if not isinstance(bname, str) or not _NAME.match(bname):
            raise SpecError(f"{where}: the name must be snake_case starting with 'body_'")
        if not isinstance(bq, BodyQuantity):
            raise SpecError(f"{where} must be a BodyQuantity, got {bq!r}")
        if bname in cls.outputs:
            raise SpecError(f"{where}: the name is one of the class's outputs")
        out = cls.outputs.get(bq.local)
        if bq.local not in cls.provides or out is None or tuple(out.dims) != ("p0",):
            raise SpecError(
                f"{where}: local={bq.local!r} must be an output the class provides with dims "
                "('p0',)"
            )
        if bq.combine not in COMBINES:
            raise SpecError(f"{where}: combine={bq.combine!r}; allowed: {sorted(COMBINES)}")
        if (bq.bulk is not None) != (bq.combine == "constriction"):
            raise SpecError(f"{where}: bulk=callable(params) is required for, and only for, "
                            "combine='constriction'")  # fmt: skip
        for attr in ("factor", "bulk"):
            fn = getattr(bq, attr)
            if fn is not None and not callable(fn):
                raise SpecError(f"{where}: {attr} must be a callable params -> float")
        _check_unbounded(cls, where, bq)
        bq.spec().check(name, bname)
