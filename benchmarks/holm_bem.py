"""Holm's spot picture of xpersson-transport against boundary-element contact sets (tamaas).

On the contact sets of ``transport_bem.py`` (same spectrum, solver and direct conduction
solve) this compares three conductances per nominal area:

* ``g direct``: the conduction problem solved on the BEM contact set (``transport_bem``);
* ``g Holm (clusters)``: Holm's non-interacting spots on the *actual* contact set: each
  connected cluster (4-connectivity, periodic) of area ``A_i`` is a disc of radius
  ``a_i = sqrt(A_i / pi)`` conducting ``4 a_i / (rho_1 + rho_2)`` (Holm 1967), summed over the
  clusters without interaction (Greenwood 1966 adds the interaction, which lowers it);
* ``g Holm (plugin)``: ``holm_conductance`` of the ``electrical_contact`` analysis at the BEM's
  finest magnification ``zeta_1 = q2/q0`` (spots of radius ``c_r/q_1`` covering Persson's
  ``A(zeta_1)``), and the same formula with the BEM's own contact area.

Run from the checkout (tamaas installed)::

    python benchmarks/holm_bem.py [--n 256] [--seeds 2]

Writes ``benchmarks/results/holm_bem.md`` (read by ``verify_transport.py``).
"""

from __future__ import annotations

import os

os.environ["OPENBLAS_NUM_THREADS"] = "1"

import argparse  # noqa: E402
import math  # noqa: E402
import sys  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402
from scipy import ndimage  # noqa: E402

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import transport_bem as tb  # noqa: E402

C_R = math.pi / 2  # the plugin's default spot_radius_factor


def periodic_clusters(contact: np.ndarray) -> np.ndarray:
    """Pixel counts of the connected clusters of a periodic boolean map (4-connectivity)."""
    lab, n = ndimage.label(contact)
    parent = np.arange(n + 1)

    def find(i: int) -> int:
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    for a, b in ((lab[0, :], lab[-1, :]), (lab[:, 0], lab[:, -1])):
        for x, y in zip(a, b, strict=True):
            if x and y:
                rx, ry = find(int(x)), find(int(y))
                if rx != ry:
                    parent[rx] = ry
    roots = np.array([find(i) for i in range(n + 1)])
    counts = np.bincount(roots[lab.ravel()], minlength=n + 1)
    counts[0] = 0
    return counts[counts > 0]


def holm_clusters(contact: np.ndarray) -> tuple[float, int]:
    """Non-interacting Holm sum over the clusters [S m-2] (L = 1 m) and the cluster count."""
    n = contact.shape[0]
    areas = periodic_clusters(contact) / n**2
    a = np.sqrt(areas / math.pi)
    return float(np.sum(4.0 * a / tb.RHO_SUM)), int(areas.size)


def bem_run(n: int, seed: int) -> dict[str, np.ndarray]:
    """Per load: contact fraction, direct conductance, Holm cluster sum, cluster count."""
    out: dict[str, list] = {"A": [], "g": [], "holm": [], "spots": []}
    for st in tb.bem_states(n, seed):
        g_h, k = holm_clusters(st.contact)
        out["A"].append(st.area_fraction)
        out["g"].append(tb.conduction(st.contact))
        out["holm"].append(g_h)
        out["spots"].append(k)
    return {k: np.array(v, dtype=float) for k, v in out.items()}


def plugin_holm() -> dict[str, np.ndarray]:
    """The plugin's Holm outputs on the continuum spectrum (Persson 2007, S = 1)."""
    import xpersson

    two_pi = 2.0 * math.pi
    scene = {
        "spectrum": {"model": "self_affine", "H": tb.HURST, "q_L": f"{two_pi * tb.Q0!r} 1/m",
                     "q_r": f"{two_pi * tb.Q1!r} 1/m", "q_1": f"{two_pi * tb.Q2!r} 1/m",
                     "h_rms": f"{tb.H_RMS!r} m"},
        "material": {"E": "1 Pa", "nu": 0.0},
        "load": {"p0": [f"{float(p)!r} Pa" for p in tb.LOADS]},
        "analyses": {"electrical_contact": {"resistivity_1": "1.7e-8 ohm*m",
                                            "resistivity_2": "1.7e-8 ohm*m"}},
    }  # fmt: skip
    ds = xpersson.solve(scene)
    return {
        "g_holm_z1": ds["holm_conductance"].isel(zeta=-1).values,
        "g_barber": ds["electrical_constriction_conductance"].values,
        "z_h": ds["holm_magnification"].values,
        "A": ds["area_fraction"].isel(zeta=-1).values,
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=256)
    ap.add_argument("--seeds", type=int, default=2)
    args = ap.parse_args()
    runs = [bem_run(args.n, s) for s in range(1, args.seeds + 1)]
    m = {k: np.mean([r[k] for r in runs], axis=0) for k in runs[0]}
    th = plugin_holm()
    q1 = 2 * math.pi * tb.Q2
    own = 4.0 * m["A"] * q1 / (math.pi * C_R * tb.RHO_SUM)  # spots c_r/q_1 on the BEM's area
    lines = [
        "# Holm's spot picture vs BEM contact sets (tamaas PKR)",
        "",
        f"`python benchmarks/holm_bem.py --n {args.n} --seeds {args.seeds}`: the spectrum and "
        f"loads of transport_bem.py (q0, q1, q2 = {tb.Q0}, {tb.Q1}, {tb.Q2} x 2 pi/L, "
        f"H = {tb.HURST}), {args.seeds} seeds averaged, grid {args.n}^2.",
        "",
        "| p0/E* | A BEM | spots | g Holm clusters / g direct | g Holm plugin(zeta_1) / g direct"
        " | spots c_r/q_1 on A BEM / g direct | Barber (plugin) / g direct | holm_magnification |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for i, p in enumerate(tb.LOADS):
        lines.append(
            f"| {p:.3g} | {m['A'][i]:.4f} | {m['spots'][i]:.0f} | {m['holm'][i] / m['g'][i]:.3f}"
            f" | {th['g_holm_z1'][i] / m['g'][i]:.3f} | {own[i] / m['g'][i]:.3f} | "
            f"{th['g_barber'][i] / m['g'][i]:.3f} | {th['z_h'][i]:.3g} |"
        )
    r_cl = m["holm"] / m["g"]
    r_pl = th["g_holm_z1"] / m["g"]
    lines += [
        "",
        f"Holm clusters / g direct: {r_cl.min():.3f} ... {r_cl.max():.3f}.",
        f"Holm plugin at zeta_1 / g direct: {r_pl.min():.3f} ... {r_pl.max():.3f}.",
    ]
    out = HERE / "results" / "holm_bem.md"
    out.write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
