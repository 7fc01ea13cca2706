"""The modulus model and the shift law of the ``viscoelastic`` coefficient from its SI
parameters (split from :mod:`.coefficient`)."""

from __future__ import annotations

from typing import Any

import numpy as np

from xpersson.cache import memoize

from ._inline import inline_curve, inline_shift
from ._modulus import ModulusModel, Prony, sls, synthetic_tread
from ._shift import WLF, Arrhenius, NoShift, ShiftLaw
from ._tables import load_master_curve, load_prony, load_shift_table

__all__ = ["build_model", "build_shift"]


def build_model(p: dict[str, Any]) -> ModulusModel:
    """The modulus model named by ``p["modulus"]`` (SI parameters), checked."""
    kind = p["modulus"]
    if kind == "sls":
        if not p["E_g"] >= p["E_r"]:
            raise ValueError(
                f"E_g: {p['E_g']:g} Pa is below E_r = {p['E_r']:g} Pa; allowed [E_r, inf) Pa"
            )
        return sls(p["E_r"], p["E_g"], p["relaxation_time"])
    if kind == "master_curve":
        curve = inline_curve(p)
        if curve is not None:
            return curve
        if p["master_curve"] is None:
            raise ValueError(
                "master_curve: required for modulus = 'master_curve' (a file path; or "
                "master_omega, master_E_storage, master_E_loss)"
            )
        return load_master_curve(p["master_curve"], phi_nodes=int(p["phi_nodes"]))
    inline = p["delta_E"] is not None or p["relaxation_times"] is not None
    if inline and p["prony_file"] is not None:
        raise ValueError("prony_file: give either prony_file or delta_E/relaxation_times")
    if inline:
        if p["delta_E"] is None or p["relaxation_times"] is None:
            raise ValueError("delta_E and relaxation_times must be given together")
        dE = np.atleast_1d(np.asarray(p["delta_E"], dtype=float))
        tau = np.atleast_1d(np.asarray(p["relaxation_times"], dtype=float))
        if dE.shape != tau.shape:
            raise ValueError(
                f"delta_E ({dE.size} values, Pa) and relaxation_times ({tau.size} values, s) "
                "must have the same length"
            )
        return Prony(p["E_r"], dE, tau)
    if p["prony_file"] is not None:
        dE, tau = load_prony(p["prony_file"])
        return Prony(p["E_r"], dE, tau)
    if not p["E_g"] >= p["E_r"]:
        raise ValueError(
            f"E_g: {p['E_g']:g} Pa is below E_r = {p['E_r']:g} Pa; allowed [E_r, inf) Pa"
        )
    return _synthetic(float(p["E_r"]), float(p["E_g"]))


@memoize("viscoelastic.synthetic_tread", scope="process", maxsize=64)
def _synthetic(E_r: float, E_g: float) -> Prony:
    """The synthetic tread default between ``E_r`` and ``E_g`` [Pa], built once per pair (a
    sweep over speed and temperature builds one coefficient per point; the model is immutable
    and shared)."""
    return synthetic_tread(E_r, E_g)


def build_shift(p: dict[str, Any]) -> ShiftLaw:
    """The shift law named by ``p["shift"]`` (SI parameters)."""
    kind = p["shift"]
    if kind == "wlf":
        return WLF(float(p["C1"]), float(p["C2"]), float(p["T_ref"]))
    if kind == "arrhenius":
        if p["activation_energy"] is None:
            raise ValueError("activation_energy: required for shift = 'arrhenius' (J/mol, >= 0)")
        return Arrhenius(float(p["activation_energy"]), float(p["T_ref"]))
    if kind == "table":
        table = inline_shift(p)
        if table is not None:
            return table
        if p["shift_table"] is None:
            raise ValueError(
                "shift_table: required for shift = 'table' (a file path; or shift_T, shift_a_T)"
            )
        return load_shift_table(p["shift_table"])
    return NoShift()
