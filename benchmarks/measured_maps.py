"""Measured maps keep their roughness (issue 35): the table's h_rms and rms slope against the
map's own, and A/A0 against the closed form at the map's own slope, on synthetic periodic maps
(with and without roll-off, band-limited or not, H = 0.5 and 0.8, 256^2 and 512^2), next to
what SurfaceTopography's binned power spectrum keeps.

    OPENBLAS_NUM_THREADS=1 python benchmarks/measured_maps.py
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import SurfaceTopography as ST

import xpersson
from xpersson.physics.elastic import area_fraction
from xpersson.physics.psd import Tabulated
from xpersson.testing.surfaces import rolled_off, synthetic_map

L = 1e-3
Q = 2 * math.pi / L
E_STAR = 10e6 / 0.75


def _slope(h: np.ndarray) -> float:
    k = 2 * np.pi * np.fft.fftfreq(h.shape[0], L / h.shape[0])
    gx = np.real(np.fft.ifft2(1j * k[:, None] * np.fft.fft2(h)))
    gy = np.real(np.fft.ifft2(1j * k[None, :] * np.fft.fft2(h)))
    return float(np.sqrt(np.mean(gx**2 + gy**2)))


def row(n: int, H: float, q_r: float, q_s: float | None) -> str:
    h = synthetic_map(n, L, rolled_off(H, Q, q_r * Q, q_s and q_s * Q), 1e-6, seed=7)
    topo = ST.Topography(h, (L, L), periodic=True, unit="m")
    slope = _slope(h)
    p0 = [f * E_STAR * slope for f in (0.04, 0.12, 0.25)]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ds = xpersson.solve({"spectrum": topo, "material": {"E": "10 MPa", "nu": 0.5},
                             "load": {"p0": [f"{p!r} Pa" for p in p0]}})  # fmt: skip
    closed = area_fraction(np.asarray(p0), E_STAR**2 * slope**2 / 8)[0]
    da = np.max(np.abs(ds.area_fraction.isel(zeta=-1).values / closed - 1))
    q, C = topo.power_spectrum_from_area(nb_points_per_decade=20)
    ok = np.isfinite(C) & (C > 1e-40 * np.nanmax(C))
    st = Tabulated(q[ok], C[ok], "surface_topography")
    return (
        f"{n:4d} {H:4.1f} {q_r:4.0f} {str(q_s):>5} | {float(ds.h_rms) / h.std() - 1:+.1e} "
        f"{float(ds.rms_slope) / slope - 1:+.1e} {da:.1e} | {st.h_rms() / h.std() - 1:+.3f} "
        f"{st.rms_slope() / slope - 1:+.3f}"
    )


def main() -> None:
    print("   n    H  q_r   q_s | xpersson: h_rms  slope  max|A/A0 / closed - 1| "
          "| ST binned: h_rms slope")  # fmt: skip
    for n in (256, 512):
        for H, q_r, q_s in ((0.8, 4, None), (0.8, 1, None), (0.5, 4, None), (0.5, 1, None),
                            (0.8, 4, n // 16), (0.5, 1, n // 16)):  # fmt: skip
            print(row(n, H, q_r, q_s))


if __name__ == "__main__":
    main()
