"""Test helpers of xpersson-transport (a uniquely named module, importable from any layout)."""

from __future__ import annotations

import numpy as np

#: physics.md §1.4: E = 10 MPa, nu = 0.5 -> E* = 13.33 MPa
E_STAR = 10e6 / (1.0 - 0.5**2)
CU_RHO = 1.7e-8  # copper resistivity [ohm m]
AIR = {"gap_medium": "gas", "gas_conductivity": "0.026 W/(m*K)", "gas_mean_free_path": "68 nm"}


def scene(p0, analyses, *, E="10 MPa", nu=0.5, boundary=None, **spectrum):
    """A scene dict on the physics.md §1.4 spectrum (overridable) with the given analyses."""
    spec = {"model": "self_affine", "H": 0.8, "q_L": "1e3 1/m", "q_r": "1e4 1/m",
            "q_1": "1e8 1/m", "h_rms": "1 um"}  # fmt: skip
    spec.update(spectrum)
    return {
        "spectrum": spec,
        "material": {"E": E, "nu": nu},
        "load": {
            "p0": f"{float(p0)!r} Pa" if np.ndim(p0) == 0 else [f"{float(p)!r} Pa" for p in p0]
        },
        "boundary": boundary or {"model": "elastic"},
        "analyses": analyses,
    }


def electrical(rho1=CU_RHO, rho2=CU_RHO, **extra):
    """Parameters of ``electrical_contact`` with resistivities in ohm m."""
    return {"resistivity_1": f"{rho1!r} ohm*m", "resistivity_2": f"{rho2!r} ohm*m", **extra}


def thermal(k1=400.0, k2=400.0, **extra):
    """Parameters of ``thermal_contact`` with conductivities in W/(m K)."""
    return {"conductivity_1": f"{k1!r} W/(m*K)", "conductivity_2": f"{k2!r} W/(m*K)", **extra}
