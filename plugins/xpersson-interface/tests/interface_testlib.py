"""Test helpers of xpersson-interface (a uniquely named module, importable from any layout)."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest

from xpersson import testing

E_STAR = 10e6 / (1.0 - 0.5**2)  # §1.4: E = 10 MPa, nu = 0.5
H_RMS_ZHOU = 6e-6

#: <repo>/plugins/xpersson-interface/tests -> <repo>/../shared/refdata/xu2024-gfmd
REFDATA = (
    Path(
        os.environ.get(
            "XPERSSON_REFDATA",
            Path(__file__).resolve().parents[4] / "shared" / "refdata",
        )
    )
    / "xu2024-gfmd"
)


def read_csv(name: str) -> dict[str, np.ndarray]:
    """Read one reference CSV (``#`` comments, one header line); skip when absent."""
    path = REFDATA / name
    if not path.is_file():
        pytest.skip(f"reference data not found: {path} (set XPERSSON_REFDATA)")
    lines = [ln for ln in path.read_text().splitlines() if ln and not ln.startswith("#")]
    names = lines[0].split(",")
    data = np.array([[float(x) for x in ln.split(",")] for ln in lines[1:]])
    return {n: data[:, i] for i, n in enumerate(names)}


def scene(p0, *, psd="persson", closure="persson01", boundary=None, analyses=None, **out):
    """A scene dict on the physics.md §1.4 spectrum ("persson") or the Zhou GFMD one ("zhou")."""
    if psd == "persson":
        spectrum = testing.spectrum(q_1="1e8 1/m")
        material = testing.material("10 MPa")
    else:
        spectrum = testing.spectrum(q_L="1e4 1/m", q_r="1e4 1/m", q_1="1e6 1/m", h_rms="6 um")
        material = testing.material("0.75 Pa")  # E* = 1 Pa
    return testing.scene(
        spectrum,
        material,
        p0=p0,
        coefficient={"model": "elastic", "closure": closure},
        boundary=boundary or {"model": "elastic"},
        analyses=analyses or {},
        **({"output": out} if out else {}),
    )


def dense_zeta(zeta_1: float, n: int = 300) -> np.ndarray:
    """``1`` and ``1 + geomspace(1e-9, zeta_1 - 1, n)``: a curve grid resolving zeta -> 1."""
    return np.concatenate(([1.0], 1.0 + np.geomspace(1e-9, zeta_1 - 1.0, n)))


def persson_curve(psd, E_star, p0, zeta):
    """The Persson 2001 area curve the elastic solve stores: (A, 1 - A), shape (n_load, n_zeta)."""
    from xpersson.physics import area_fraction, diffusion_time

    tau = diffusion_time(psd, E_star, zeta)
    return area_fraction(np.atleast_1d(p0)[:, None], np.asarray(tau)[None, :])


def detach(psd, E_star, p0, gamma=1.0, *, n=300, zeta=None, edges=None):
    """Gap-distribution bins of the Persson curve with the Yang-Persson S (gamma = 1: none)."""
    from xpersson.physics import detachment

    z = dense_zeta(psd.q_1 / psd.q_L, n) if zeta is None else zeta
    A, N = persson_curve(psd, E_star, p0, z)
    S = None if gamma == 1.0 else gamma + (1.0 - gamma) * A**2
    return detachment(psd, E_star, np.atleast_1d(p0), z, A, S, N, zeta_edges=edges)
