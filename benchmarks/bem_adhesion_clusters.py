"""Contact clusters along one BEM retraction path (evidence for ``adhesive``'s floor).

Re-solves one surface of ``bem_adhesion.py`` (same surface, work, range, approach and
retraction steps) and prints, per retraction step, the mean stress, the contact area, the
number of contact spots (connected zero-gap regions) and of clusters (spots merged within
``--merge`` grid points). Quoted in ``docs/adhesion_bem.md``: how many separate contacts hold
the cell under tension. Needs tamaas (optional bench dependency); 2-5 CPU minutes.

Usage::

    OPENBLAS_NUM_THREADS=1 python benchmarks/bem_adhesion_clusters.py --H 0.8 --seed 0 --tabor 1.0
"""

from __future__ import annotations

import argparse

import bem_adhesion as B
import numpy as np


def clusters(contact: np.ndarray, merge: int) -> tuple[int, int]:
    """(spots, clusters) of a boolean contact map; clusters merge spots within ``merge`` px."""
    from scipy import ndimage

    _, spots = ndimage.label(contact)
    _, merged = ndimage.label(ndimage.binary_dilation(contact, iterations=merge))
    return int(spots), int(merged)


def main(argv: list[str] | None = None) -> None:
    """Command line."""
    from xpersson import bem
    from xpersson.bem import derived as D

    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--H", type=float, default=0.8)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--tabor", type=float, default=1.0, choices=B.TABOR_TARGETS)
    ap.add_argument("--grid", type=int, default=256)
    ap.add_argument("--merge", type=int, default=8, help="merge distance [grid points]")
    args = ap.parse_args(argv)
    n = args.grid
    surf = B.surface(args.H, args.seed, n)
    h_rms = float(B.continuum_psd(args.H).h_rms()) / B.L_CELL
    works = dict(zip(B.TABOR_TARGETS, B.works_of(args.H), strict=True))
    work = works[args.tabor] / (B.E_STAR * B.L_CELL)
    rho = B.RANGE_FRACTION * h_rms
    solver = bem.GapSolver(surf, 1.0, 1.0, work=work, rho=rho, strict=False, keep_fields=True)
    g = D.APPROACH[0]
    for g in D.APPROACH:
        solver.at(g * h_rms)
    step = 0
    while True:
        step += 1
        fine = step <= D.RETRACT_FINE[1]
        g = round(g + (D.RETRACT_FINE[0] if fine else D.RETRACT_STEP), 10)
        st = solver.at(g * h_rms)
        if not st.converged:
            print(f"gap {g:.2f} h_rms  not converged (error {st.error:.3g}): skipped", flush=True)
            continue
        contact = st.contact
        if not contact.any() or g > 4.0:
            break
        spots, merged = clusters(contact, args.merge)
        print(
            f"gap {g:.2f} h_rms  p {st.p0 * B.E_STAR:9.1f} Pa  A {contact.mean():.4f}  "
            f"spots {spots}  clusters {merged}",
            flush=True,
        )


if __name__ == "__main__":
    main()
