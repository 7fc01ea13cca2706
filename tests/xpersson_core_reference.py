"""Reference scenes and spectra shared by the core tests."""

import numpy as np

# physics.md §1.4 parameter set
REFERENCE_SCENE = {
    "spectrum": {
        "model": "self_affine",
        "H": 0.8,
        "q_L": "1e3 1/m",
        "q_r": "1e4 1/m",
        "q_1": "1e8 1/m",
        "h_rms": "1 um",
    },
    "material": {"E": "10 MPa", "nu": 0.5},
    "load": {"p0": ["1e4 Pa", "1e5 Pa", "1e6 Pa"]},
}


def random_spectrum(rng: np.random.Generator, table: bool):
    """A spectrum drawn from ``rng``: a table of 2-12 breakpoints over up to 5 decades with
    exponents of both signs (``table``), or a self-affine one with or without a roll-off."""
    from xpersson.physics._self_affine import SelfAffineRollOff
    from xpersson.physics._tabulated import Tabulated

    q_L = 10 ** rng.uniform(1, 4)
    if table:  # many segments, exponents of both signs
        q = np.sort(q_L * 10 ** rng.uniform(0, 5, rng.integers(1, 12)))
        q = np.unique(np.concatenate(([q_L], q)))
        return Tabulated(q, 10 ** rng.uniform(-40, -20, q.size))
    H = rng.uniform(0.1, 1.0)
    q_r = q_L * 10 ** rng.choice([0.0, rng.uniform(0, 1)])  # without a roll-off, or with
    return SelfAffineRollOff.from_h_rms(1e-6, H, q_L, q_r, q_r * 10 ** rng.uniform(1, 4))
