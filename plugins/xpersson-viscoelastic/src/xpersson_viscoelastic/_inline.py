"""The ``viscoelastic`` coefficient's tables given inline (private): the parameters that take
a master curve's or a shift table's rows in the scene itself, and the archived form of a
coefficient whose tables came from files (:meth:`.ViscoelasticCoefficient.archived_params`:
no machine-specific path goes into an archive, and the archive rebuilds the coefficient
without the files)."""

from __future__ import annotations

from typing import Any

import numpy as np

from xpersson.plugins import ParamSpec

from ._modulus import MasterCurve
from ._shift import TabulatedShift

__all__ = ["INLINE_TABLES", "archived", "inline_curve", "inline_shift"]


def _column(unit: str, what: str, zero: bool = False) -> ParamSpec:
    """A table column given inline: values > 0 (``zero``: >= 0) in ``unit``."""
    inclusive = (zero, True)
    return ParamSpec(unit, default=None, array=True, bounds=(0, None), inclusive=inclusive,
                     description=what)  # fmt: skip


#: The inline tables' parameters (each table's columns given together, instead of its file).
INLINE_TABLES = {
    "master_omega": _column("1/s", "master curve inline: angular frequencies [rad/s]"),
    "master_E_storage": _column("Pa", "master curve inline: storage modulus E'"),
    "master_E_loss": _column("Pa", "master curve inline: loss modulus E''", zero=True),
    "shift_T": _column("K", "shift table inline: temperatures (strictly increasing)"),
    "shift_a_T": _column("1", "shift table inline: shift factors a_T"),
}

_CURVE = ("master_omega", "master_E_storage", "master_E_loss")
_SHIFT = ("shift_T", "shift_a_T")


def _given(p: dict[str, Any], names: tuple[str, ...], file: str) -> bool:
    """Whether the inline columns ``names`` are given (all of them, and not the ``file``)."""
    given = [p.get(n) is not None for n in names]
    if not any(given):
        return False
    if not all(given):
        raise ValueError(f"{', '.join(names)} must be given together")
    if p.get(file) is not None:
        raise ValueError(f"{file}: give either {file} or {', '.join(names)}")
    return True


def inline_curve(p: dict[str, Any]) -> MasterCurve | None:
    """The master curve given inline in ``p`` (SI), or None."""
    if not _given(p, _CURVE, "master_curve"):
        return None
    w, e1, e2 = (np.atleast_1d(np.asarray(p[n], dtype=float)) for n in _CURVE)
    return MasterCurve(w, e1, e2, phi_nodes=int(p["phi_nodes"]))


def inline_shift(p: dict[str, Any]) -> TabulatedShift | None:
    """The shift table given inline in ``p`` (SI), or None (checked: a_T > 0, T increasing)."""
    if not _given(p, _SHIFT, "shift_table"):
        return None
    T, aT = (np.atleast_1d(np.asarray(p[n], dtype=float)) for n in _SHIFT)
    if not (T.ndim == 1 and T.shape == aT.shape and T.size >= 2):
        raise ValueError("shift_T and shift_a_T: at least two rows of the same length")
    if not (np.all(np.isfinite(T)) and np.all(np.diff(T) > 0)):
        raise ValueError("shift_T: temperatures must be finite and strictly increasing (K)")
    if not (np.all(np.isfinite(aT)) and np.all(aT > 0)):
        raise ValueError("shift_a_T: shift factors must be finite and > 0")
    return TabulatedShift(T, aT, source="shift_T")


def archived(p: dict[str, Any], model: Any, shift: Any) -> dict[str, Any]:
    """The parameters ``p`` (SI) with each table read from a file (``prony_file``,
    ``master_curve``, ``shift_table``) given inline instead, from the built ``model`` and
    ``shift`` (the values the coefficient computes with, bit for bit)."""
    out = dict(p)
    if out.get("prony_file") is not None:
        out["delta_E"], out["relaxation_times"] = model.delta_E, model.tau
        out["prony_file"] = None
    if out.get("master_curve") is not None:
        out.update(zip(_CURVE, (model.omega, model.storage, model.loss_modulus), strict=True))
        out["master_curve"] = None
    if out.get("shift_table") is not None:
        out.update(zip(_SHIFT, (shift.T, shift.aT_values), strict=True))
        out["shift_table"] = None
    return out
