"""Write the measured-surface examples: synthetic scans of one self-affine surface (H = 0.8,
roll-off at 25 um wavelength), in the formats users have. Run from this folder:

    python make_maps.py

map.txt   AFM-style plain matrix: 64 x 64 heights in nm, 20 um x 20 um (no metadata)
map.nc    netCDF written by SurfaceTopography: 64 x 64, 1 mm x 1 mm, unit um, periodic
fine.nc   a 100 um x 100 um scan of the same surface (64 x 64, unit um, periodic)
line.txt  stylus-style line scan: 1024 heights in um over 2 mm (one column)
"""

from __future__ import annotations

import math

import numpy as np
import SurfaceTopography as ST

from xpersson.testing.surfaces import rolled_off, synthetic_map

Q_R = 2 * math.pi / 25e-6  # roll-off [1/m]
SHAPE = rolled_off(0.8, 1.0, Q_R, None)  # the surface's PSD up to a factor [m^4]
SCALE = 1.5e-24  # C_r [m^4]: h_rms ~ 0.5 um


def psd(q: np.ndarray) -> np.ndarray:
    return SCALE * SHAPE(q)


def main() -> None:
    h = synthetic_map(64, 20e-6, psd, seed=1)
    np.savetxt("map.txt", h * 1e9, fmt="%.3f")  # nm, no header
    for name, size, seed in (("map.nc", 1e-3, 2), ("fine.nc", 1e-4, 3)):
        h = synthetic_map(64, size, psd, seed=seed)
        ST.Topography(h * 1e6, (size * 1e6, size * 1e6), periodic=True, unit="um").to_netcdf(name)
    rows = synthetic_map(1024, 2e-3, psd, seed=4)
    np.savetxt("line.txt", rows[0] * 1e6, fmt="%.5f")  # um


if __name__ == "__main__":
    main()
