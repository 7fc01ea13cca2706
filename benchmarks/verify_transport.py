"""Verification rows of ``xpersson-transport`` (issue 27) for ``benchmarks/verify.py``.

``rows(fast)`` follows the matrix's contract (keys output, regime, reference, worst, measure,
note):

- the gas part against an independent quadrature of the same model: the ``gap_pdf``
  analysis's density on a fine *linear* grid (trapezoid, plus its contact weight), integrated
  with ``kappa_g / (u + Lambda)`` -- the plugin integrates the closed-form cumulative mass on a
  geometric grid instead;
- the constriction conductance (Barber's analogy) against the conduction problem solved
  directly on boundary-element contact sets, read from ``results/transport_bem.md`` (made by
  ``transport_bem.py``; tamaas);
- resistances against their conductances (exact identities).
"""

from __future__ import annotations

import math
import re
import tomllib
import warnings
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
EXAMPLE = HERE.parent / "plugins" / "xpersson-transport" / "examples" / "heat_sink.toml"


def _row(output, regime, reference, worst, measure, note=""):
    return {
        "output": output,
        "regime": regime,
        "reference": reference,
        "worst": worst,
        "measure": measure,
        "note": note,
    }


def _solve(fast: bool):
    import xpersson

    with open(EXAMPLE, "rb") as fh:
        scene = tomllib.load(fh)
    scene["load"]["p0"] = {"start": "10 kPa", "stop": "10 MPa", "num": 4 if fast else 13}
    scene["analyses"]["gap_pdf"] = {"u_points": 8001 if fast else 40001, "u_max": "15 um"}
    scene["analyses"]["thermal_contact"]["emissivity_1"] = 0.0  # the gas part alone below
    scene["analyses"]["thermal_contact"]["emissivity_2"] = 0.0
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return xpersson.solve(scene)


def gas_rows(fast: bool) -> list[dict]:
    """thermal_gas_conductance against the trapezoid of gap_pdf's density on a linear grid."""
    ds = _solve(fast)
    kappa = 0.026
    lam = np.asarray(ds["gas_jump_length"].values, float).reshape(-1)
    u = np.asarray(ds["u"].values, float)
    pdf = np.asarray(ds["gap_pdf"].transpose("p0", "u").values, float)
    lam = np.broadcast_to(lam, (pdf.shape[0],))
    ref = np.array([np.trapezoid(pdf[i] * kappa / (u + lam[i]), u) for i in range(pdf.shape[0])])
    got = np.asarray(ds["thermal_gas_conductance"].values, float).reshape(-1)
    err = float(np.max(np.abs(got / ref - 1.0)))
    return [
        _row(
            "thermal_gas_conductance",
            "heat-sink scene (Al on Al in air), p0 10 kPa-10 MPa (A/A0 1e-4-0.1)",
            f"trapezoid of gap_pdf on {u.size} linear points x kappa_g/(u + Lambda)",
            err,
            "rel",
            "converges with the linear grid (5.5e-2 at 8001, 1.5e-2 at 40001 points): the"
            " smallest gaps dominate 1/(u + Lambda)",
        )
    ]


def bem_rows(fast: bool) -> list[dict]:
    """Barber's analogy against conduction solved on BEM contact sets (stored results)."""
    del fast
    path = HERE / "results" / "transport_bem.md"
    text = path.read_text() if path.is_file() else ""
    ratios = [
        float(m) for m in re.findall(r"^\| [0-9.e-]+ \|(?:[^|]*\|){4} ([0-9.]+) \|", text, re.M)
    ]
    worst = max((abs(r - 1.0) for r in ratios), default=math.nan)
    note = (
        "the analogy holds on the rough contact; the theory's stiffness is 0.36-0.47 (Persson "
        "2007) or 0.81-0.90 (Yang-Persson) of the BEM's: the theory's, see transport_bem.md"
    )
    return [
        _row(
            "electrical_constriction_conductance, thermal_constriction_conductance",
            "self-affine H 0.8, A/A0 0.5-5 %, 512^2, 3 surfaces",
            "conduction solved on the BEM contact sets (transport_bem.py, tamaas)",
            worst,
            "rel",
            note,
        )
    ]


def identity_rows(fast: bool) -> list[dict]:
    """Resistances are the inverse conductances times the nominal area (exact)."""
    ds = _solve(True)
    area = 16e-4
    pairs = (
        ("electrical_contact_resistance", "electrical_contact_conductance"),
        ("thermal_contact_resistance", "thermal_contact_conductance"),
    )
    worst = 0.0
    for r, g in pairs:
        rr = np.asarray(ds[r].values, float)
        gg = np.asarray(ds[g].values, float)
        worst = max(worst, float(np.max(np.abs(rr * gg * area - 1.0))))
    return [
        _row("*_resistance", "heat-sink scene", "1 / (conductance x nominal area)", worst, "rel")
    ]


def rows(fast: bool) -> list[dict]:
    """Every transport row; the Holm picture has no independent reference here."""
    missing = _row(
        "holm_conductance, holm_magnification, holm_ratio, holm_spot_radius",
        "-",
        "-",
        math.nan,
        "-",
        "missing: Holm's spot picture has no independent reference here (a model beside Barber's)",
    )
    return [*gas_rows(fast), *bem_rows(fast), *identity_rows(fast), missing]


if __name__ == "__main__":
    for row in rows(fast=False):
        print(row)
