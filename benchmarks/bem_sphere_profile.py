"""Why the rough sphere's nominal radius exceeds the BEM's at larger alpha (issue 39).

Three checks on the rough sphere of ``benchmarks/bem_sphere.py`` (the same scene, closure
``yp08``), each a candidate cause of the radius being overestimated at Johnson's alpha >= 0.3:

1. **The asymptotic continuation** of ``u(p)`` below ``A/A0 = ASYMPTOTE``: the theory's radius
   holding 99 % of the force with the continuation starting at 1e-2, 1e-3 (the default) and
   1e-4 of the nominal area.
2. **The 99 %-force definition**: the radii holding 50 %, 90 % and 99 % of the force, theory
   against one BEM realisation (``--n`` points per side, the cell of ``bem_sphere.CELLS``). If
   only the tail were wrong, the 50 % and 90 % radii would agree.
3. **The interfacial spring itself**: the mean separation ``u(p)`` of a *flat* of the same
   spectrum (alpha = 3's rms height), BEM (three realisations on a 0.6 mm cell, 512 points per
   side, 9 points per shortest wavelength) against the theory's ``separation_of_pressure``, at
   the nominal pressures of that sphere's contact; the slope ``du/dln p`` is the spring's
   compliance, which sets how far the nominal contact spreads.

Run: ``python benchmarks/bem_sphere_profile.py [--n 1024]`` (tamaas installed; about a minute);
prints Markdown and writes ``benchmarks/results/bem_sphere_profile.md``.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse  # noqa: E402
import warnings  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402
from bem_sphere import A0, CELLS, E_STAR, FORCE, Q_1, Q_L, R, scene  # noqa: E402

import xpersson  # noqa: E402
import xpersson.pipeline.body as body  # noqa: E402
from xpersson import bem  # noqa: E402
from xpersson.bem.sphere import cap, force_radius  # noqa: E402
from xpersson.scene import Scene  # noqa: E402

HERE = Path(__file__).resolve().parent
ALPHAS = (0.3, 1.0, 3.0)
FRACTIONS = (0.5, 0.9, 0.99)
FLAT_P = np.array([30.0, 100.0, 300.0, 1000.0, 3000.0])  # [Pa]


def theory(h_rms: float) -> tuple[list[float], list[float]]:
    """Radius [m] holding 99 % of the force per continuation start, and radii [m] per fraction
    (the default continuation)."""
    by_start = []
    for start in (1e-2, 1e-3, 1e-4):
        body.ASYMPTOTE, default = start, body.ASYMPTOTE
        try:
            by_start.append(float(xpersson.solve(scene(h_rms, "yp08"))["nominal_contact_radius"]))
        finally:
            body.ASYMPTOTE = default
    ds = xpersson.solve(scene(h_rms, "yp08"))
    r, p = ds["r"].values, ds["nominal_pressure"].values
    cum = np.concatenate([[0.0], np.cumsum(0.5 * (p[1:] * r[1:] + p[:-1] * r[:-1]) * np.diff(r))])
    return by_start, [float(np.interp(f * cum[-1], cum, r)) for f in FRACTIONS]


def bem_radii(h_rms: float, L: float, n: int) -> list[float]:
    """Radii [m] holding each fraction of the force, one BEM realisation."""
    rs = Scene(scene(h_rms)).resolve()
    (h,) = bem.synthesise(rs.psd.C, L, n, seed=39, realisations=1, q_min=Q_L, q_max=Q_1)
    (st,) = bem.solve(h + cap(L, n, R), L, E_STAR, [FORCE / L**2], keep_fields=True)
    return [force_radius(st.pressure, L, f) for f in FRACTIONS]


def flat_separation(h_rms: float) -> tuple[np.ndarray, np.ndarray]:
    """``u(p)/h_rms`` at :data:`FLAT_P`: BEM (mean of three realisations) and theory."""
    rs = Scene(scene(h_rms)).resolve()
    maps = bem.synthesise(rs.psd.C, 0.6e-3, 512, seed=7, realisations=3, q_min=Q_L, q_max=Q_1)
    u_bem = np.mean([[s.mean_gap for s in bem.solve(m - m.mean(), 0.6e-3, E_STAR, FLAT_P)]
                     for m in maps], axis=0)  # fmt: skip
    ds = xpersson.solve(scene(h_rms, "yp08"))
    u_th = np.interp(np.log(FLAT_P), np.log(ds["p0"].values), ds["separation_of_pressure"].values)
    return u_bem / h_rms, u_th / h_rms


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=1024)
    args = ap.parse_args()
    warnings.simplefilter("ignore")
    um = [f"{f:g}" for f in FRACTIONS]
    lines = [
        f"Closure `yp08`; BEM one realisation, n = {args.n}. Radii in um.",
        "",
        "| alpha | r99, continuation at A/A0 = 1e-2, 1e-3, 1e-4 | "
        + " | ".join(f"r{f} theory / BEM" for f in um)
        + " |",
        "|---|---|" + "---|" * len(FRACTIONS),
    ]
    for alpha in ALPHAS:
        h = alpha * A0 * A0 / R
        by_start, th = theory(h)
        bm = bem_radii(h, CELLS[alpha], args.n)
        cells = " | ".join(
            f"{t * 1e6:.0f} / {b * 1e6:.0f} ({t / b - 1:+.0%})" for t, b in zip(th, bm, strict=True)
        )
        lines.append(f"| {alpha:g} | {', '.join(f'{r * 1e6:.0f}' for r in by_start)} | {cells} |")
    u_bem, u_th = flat_separation(3.0 * A0 * A0 / R)
    slope = lambda u: np.diff(u) / np.diff(np.log(FLAT_P))  # noqa: E731
    lines += [
        "",
        "Flat of alpha = 3's rms height: mean separation u/h_rms, and its slope du/dln p "
        "between neighbouring pressures.",
        "",
        "| p [Pa] | " + " | ".join(f"{p:g}" for p in FLAT_P) + " |",
        "|---|" + "---|" * FLAT_P.size,
        "| u/h_rms BEM | " + " | ".join(f"{u:.2f}" for u in u_bem) + " |",
        "| u/h_rms theory | " + " | ".join(f"{u:.2f}" for u in u_th) + " |",
        "| du/dln p / h_rms BEM | | " + " | ".join(f"{s:.2f}" for s in slope(u_bem)) + " |",
        "| du/dln p / h_rms theory | | " + " | ".join(f"{s:.2f}" for s in slope(u_th)) + " |",
    ]
    text = "\n".join(lines)
    print(text)
    out = HERE / "results" / "bem_sphere_profile.md"
    out.write_text(
        "# Rough sphere: nominal radius against BEM (benchmarks/bem_sphere_profile.py)\n\n"
        + text
        + "\n"
    )


if __name__ == "__main__":
    main()
