"""BEM referee for adhesive rough contact: tamaas on the same spectrum as an xpersson scene.

What it solves
--------------
Periodic Gaussian self-affine surfaces (no roll-off, ``q_1/q_L = 32``, rms 2-D slope 0.1)
against an elastic half-space, with tamaas' boundary-element solver (``PolonskyKeerRey``,
gap primal and gap constraint, i.e. displacement control) and its exponential adhesion
functional ``E_adh = -w exp(-g/rho)`` per unit area (range ``rho = 0.1 h_rms``; maximum
traction ``w/rho``). Non-adhesive control: the same solver at imposed mean pressure.

* Spectra: ``H = 0.8`` (the issue's) and ``H = 0.5``; each with three works of adhesion chosen
  so that the plugin's Tabor parameter ``tabor_parameter(psd, E*, w, rho, zeta_1)`` is 0.6, 1.0
  and 1.6 at the finest scale, and a stronger case (3.0; ``--tabor 3.0``) beyond them.
* Surfaces: Gaussian random fields with Persson's isotropic PSD ``C_P(q)``. On a periodic cell
  of side ``L`` the Fourier amplitude of the mode ``q`` has variance ``C_P(q) (2 pi/L)^2``
  (``<h^2> = sum_q C_P (2 pi / L)^2 -> int d^2q C_P``); Persson's ``C_P`` is the
  SurfaceTopography/JJP ``C^iso`` divided by ``(2 pi)^2``. The maps come from
  :func:`xpersson.bem.synthesise` on a fixed 128^2 lattice (modes ``1 <= |k| <= 32``),
  Fourier-interpolated, so the same surface is sampled exactly on 128^2, 256^2 and 512^2
  grids (grid-convergence check). Each realisation is scaled to the exact rms slope 0.1 (its
  discrete ``h_rms`` is stored). The solves are :mod:`xpersson.bem`'s; every state records
  tamaas' convergence and a non-converged state never enters the reference (skipped on the
  retraction branch). Results written before this generator (part files without
  ``generator``) came from an in-script generator with other seeds and are not resumed.
* Path: approach from mean gap ``2.4 h_rms`` to ``0.6 h_rms`` (coarse steps, the warm start;
  for Tabor targets above 2 on to at most ``0.06 h_rms`` until the largest load is exceeded),
  then retract in steps of ``0.1 h_rms`` until the contact is lost. The retraction branch up to
  its most tensile mean stress (pull-off under load control) is the reference; ``A(p)`` is
  interpolated at common loads ``p0/(E* h'_rms)``.
* Contact area: the fraction of grid points with zero gap.

Units: the solver works with ``L = 1`` and ``E* = 1``; the stored scene is SI (``L = 100 um``,
``E = 0.75 MPa``, ``nu = 0.5``, so ``E* = 1 MPa``). Results scale with ``E* L`` for the work,
``E*`` for stresses and ``L`` for lengths.

Output: ``results/bem_adhesion.json`` (provenance: tamaas version, seeds, grid, parameters,
raw retraction/approach curves per surface, surface-averaged table) and
``results/bem_adhesion.md`` (the averaged table). ``--grid-check`` adds the 128^2 / 256^2 /
512^2 comparison on one case to ``results/bem_adhesion_grid.json``.

Optional bench dependency: ``pip install tamaas`` (never needed by the library).

Usage::

    OPENBLAS_NUM_THREADS=1 python benchmarks/bem_adhesion.py [--spectrum H08|H05] [--surfaces 4]
    OPENBLAS_NUM_THREADS=1 python benchmarks/bem_adhesion.py --grid-check
    python benchmarks/bem_adhesion.py --merge     # (re)writes the json/md from the parts
"""

from __future__ import annotations

import argparse
import json
import math
import platform
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

from xpersson import bem
from xpersson.bem import derived as D

HERE = Path(__file__).resolve().parent
RESULTS = HERE / "results"

#: Cell side [m], contact modulus [Pa]; the BEM runs in units L = 1, E* = 1.
L_CELL = 1e-4
E_STAR = 1e6
SLOPE = 0.1
RATIO = 32
RANGE_FRACTION = 0.1
TABOR_TARGETS = (0.6, 1.0, 1.6)
SPECTRA = {"H08": 0.8, "H05": 0.5}
#: Common loads p0 / (E* h'_rms) of the reference table.
LOADS = (-0.001, -0.0005, -0.00025, 0.0025, 0.005, 0.01, 0.02, 0.04)
#: Strong adhesion (Tabor targets above this): the mean stress at gap 0.6 h_rms is already
#: tensile, so the approach goes on (xpersson.bem.derived.APPROACH_DEEP) until the compressive
#: stress exceeds the largest load.
STRONG = 2.0
NOISE_GRID = 128
#: Surface generator of the part files: parts written by another one are not resumed.
GENERATOR = "xpersson.bem.synthesise [seed, 0] on NOISE_GRID^2, Fourier-interpolated"


def scene(H: float, work: float = 0.0) -> dict[str, Any]:
    """The xpersson scene (SI) with the BEM's spectrum, modulus, work [J/m^2] and range."""
    q_L = 2.0 * math.pi / L_CELL
    sc: dict[str, Any] = {
        "spectrum": {
            "model": "self_affine",
            "H": H,
            "q_L": f"{q_L!r} 1/m",
            "q_1": f"{RATIO * q_L!r} 1/m",
            "rms_slope": SLOPE,
        },
        "material": {"E": f"{0.75 * E_STAR!r} Pa", "nu": 0.5},
    }
    if work > 0:
        sc["boundary"] = {"work_of_adhesion": f"{work!r} J/m**2", "range": f"{range_of(H)!r} m"}
    return sc


def continuum_psd(H: float) -> Any:
    """Persson-convention PSD of the scene (xpersson public physics object), SI."""
    from xpersson.physics import SelfAffineRollOff

    q_L = 2.0 * math.pi / L_CELL
    return SelfAffineRollOff.from_rms_slope(SLOPE, H=H, q_L=q_L, q_r=q_L, q_1=RATIO * q_L)


def range_of(H: float) -> float:
    """Range of the exponential law [m]: 0.1 h_rms of the continuum spectrum."""
    return RANGE_FRACTION * float(continuum_psd(H).h_rms())


def works_of(H: float, targets: tuple[float, ...] = TABOR_TARGETS) -> list[float]:
    """Works of adhesion [J/m^2] giving the target Tabor parameters at zeta_1."""
    from xpersson_adhesion import tabor_parameter

    mu1 = float(tabor_parameter(continuum_psd(H), E_STAR, 1.0, range_of(H), [RATIO])[0])
    return [float((m / mu1) ** 1.5) for m in targets]  # mu ~ w^(2/3)


def _add_works(out: dict[str, Any], targets: tuple[float, ...]) -> None:
    """Append work entries for Tabor targets not yet in ``out`` (a stronger case on a resume)."""
    have = {e["tabor"] for e in out["works"]}
    new = tuple(m for m in targets if m not in have)
    for work_si, mu in zip(works_of(out["H"], new), new, strict=True):
        out["works"].append(
            {"tabor": mu, "work_J_m2": work_si, "paths": [], "area": [], "pull_off_Pa": []}
        )


def surface(H: float, seed: int, n: int) -> np.ndarray:
    """Gaussian self-affine surface on an n x n grid, cell side 1, rms 2-D slope SLOPE.

    Synthesised by :func:`xpersson.bem.synthesise` on the fixed NOISE_GRID^2 lattice (modes
    ``1 <= |k| <= RATIO``) and Fourier-interpolated to ``n`` (exact: the map is band-limited),
    so the same surface is sampled on every grid; scaled to the exact rms slope.
    """
    q_L = 2.0 * math.pi / L_CELL
    h0 = bem.synthesise(continuum_psd(H).C, L_CELL, NOISE_GRID, seed=seed, q_max=RATIO * q_L)
    spec = np.fft.fft2(h0[0] / L_CELL)
    idx = np.fft.fftfreq(NOISE_GRID, d=1.0 / NOISE_GRID).astype(int) % n
    big = np.zeros((n, n), dtype=complex)
    big[np.ix_(idx, idx)] = spec
    h = np.fft.ifft2(big).real * (n / NOISE_GRID) ** 2
    h *= SLOPE / bem.map_moments(h, 1.0)[1]
    return h - h.max()


def _as_dict(st: Any, rho: float) -> dict[str, Any]:
    """A BEM state as stored in the JSON paths (dimensionless: E* = 1, L = 1)."""
    if not st.converged:
        return {"converged": False, "error": st.error}
    return {
        "gap": st.mean_gap,
        "p": st.p0,
        "area": st.area_fraction,
        "area_in_range": float(np.mean(st.gap < rho)),
        "p_contact": float(np.sum(np.where(st.contact, st.pressure, 0.0)) / st.pressure.size),
        "converged": True,
        "error": st.error,
    }


def adhesive_path(
    surf: np.ndarray, work: float, rho: float, h_rms: float, deep: bool = False
) -> dict[str, list]:
    """Approach then retraction under displacement control (dimensionless units), by
    :func:`xpersson.bem.adhesive_path`; non-converged states are kept flagged (never used).

    ``deep``: approach on until the mean stress exceeds the largest load (strong adhesion).
    """
    p_max = max(LOADS) * SLOPE if deep else None
    path = bem.adhesive_path(surf, 1.0, 1.0, work, rho, p_max=p_max, strict=False,
                             h_rms=h_rms, keep_fields=True)  # fmt: skip
    return {k: [_as_dict(st, rho) for st in v] for k, v in path.items()}


def elastic_areas(surf: np.ndarray, loads: list[float]) -> list[float]:
    """Non-adhesive contact area at imposed mean pressures (dimensionless, E* = 1)."""
    return [st.area_fraction for st in bem.solve(surf, 1.0, 1.0, loads, tol=1e-8)]


def branch_area(path: list[dict[str, Any]], loads: np.ndarray) -> tuple[np.ndarray, float]:
    """A at the loads on the stable part of a retraction branch; and its pull-off [E*]
    (:func:`xpersson.bem.retraction_branch`; non-converged states are skipped)."""
    from types import SimpleNamespace

    states = [
        SimpleNamespace(p0=s["p"], area_fraction=s["area"])
        for s in path
        if s.get("converged", True)
    ]
    return bem.retraction_branch(states, loads)


def _extend_elastic(name: str, out: dict[str, Any], n_surf: int, n: int, comp: list) -> None:
    """Non-adhesive areas for the seeds not yet in ``out`` (more surfaces on a resume)."""
    H = out["H"]
    for seed in range(len(out["elastic_area"]), n_surf):
        surf = surface(H, seed, n)
        t0 = time.process_time()
        out["elastic_area"].append(elastic_areas(surf, comp))
        out["surface_h_rms_over_L"].append(float(surf.std()))
        print(f"{name} seed {seed} elastic {time.process_time() - t0:.1f} s", flush=True)
        (RESULTS / f"bem_adhesion_{name}.part.json").write_text(json.dumps(out))
    out["seeds"] = list(range(max(n_surf, len(out["elastic_area"]))))


def run_spectrum(
    name: str, n_surf: int, n: int, only: tuple[float, ...] | None = None
) -> dict[str, Any]:
    """Every work and surface of one spectrum; a JSON-ready dict (SI and reduced units).

    ``only``: solve the adhesive paths of these Tabor targets only (more surfaces for the
    cases whose surface scatter is large; the other works keep their surfaces).
    """
    H = SPECTRA[name]
    psd = continuum_psd(H)
    h_rms = float(psd.h_rms()) / L_CELL
    rho = RANGE_FRACTION * h_rms
    loads = np.array(LOADS) * SLOPE  # in E*
    comp = [float(x) for x in loads if x > 0]
    part = RESULTS / f"bem_adhesion_{name}.part.json"
    if part.exists():  # resume: keep every (surface, work) already solved
        out = json.loads(part.read_text())
        if out["grid"] == n and out.get("generator") == GENERATOR:
            _extend_elastic(name, out, n_surf, n, comp)
            _add_works(out, only or ())
            return _solve_paths(name, out, n_surf, n, rho, h_rms, loads, only)
    out = {"H": H, "grid": n, "seeds": list(range(n_surf)), "works": [], "generator": GENERATOR}
    elastic = []
    for seed in range(n_surf):
        surf = surface(H, seed, n)
        t0 = time.process_time()
        elastic.append(elastic_areas(surf, comp))
        print(f"{name} seed {seed} elastic {time.process_time() - t0:.1f} s", flush=True)
    out["elastic_area"] = elastic
    out["surface_h_rms_over_L"] = [float(surface(H, s, n).std()) for s in range(n_surf)]
    for work_si, mu in zip(works_of(H), TABOR_TARGETS, strict=True):
        entry: dict[str, Any] = {"tabor": mu, "work_J_m2": work_si, "paths": [], "area": []}
        entry["pull_off_Pa"] = []
        out["works"].append(entry)
    return _solve_paths(name, out, n_surf, n, rho, h_rms, loads, only)


def _solve_paths(
    name: str,
    out: dict[str, Any],
    n_surf: int,
    n: int,
    rho: float,
    h_rms: float,
    loads: Any,
    only: tuple[float, ...] | None = None,
) -> dict[str, Any]:
    """The adhesive paths not yet in ``out`` (seeds outer: a partial run has every work)."""
    H = out["H"]
    for seed in range(n_surf):
        surf = surface(H, seed, n)
        for entry in out["works"]:
            if len(entry["paths"]) != seed or (only and entry["tabor"] not in only):
                continue
            t0 = time.process_time()
            work = entry["work_J_m2"] / (E_STAR * L_CELL)
            path = adhesive_path(surf, work, rho, h_rms, deep=entry["tabor"] > STRONG)
            area, pull = branch_area(path["retract"], loads)
            entry["paths"].append(path)
            entry["area"].append([None if math.isnan(x) else float(x) for x in area])
            entry["pull_off_Pa"].append(pull * E_STAR)
            print(
                f"{name} mu={entry['tabor']} seed {seed}: {len(path['retract'])} retract steps, "
                f"pull-off {pull * E_STAR:.4g} Pa, {time.process_time() - t0:.1f} s",
                flush=True,
            )
            out["seeds_done"] = seed + 1
            (RESULTS / f"bem_adhesion_{name}.part.json").write_text(json.dumps(out))
    return out


def provenance(n: int) -> dict[str, Any]:
    """Versions, parameters and units of the run."""
    return {
        "tamaas_version": bem.tamaas_version(),
        "generator": GENERATOR,
        "numpy_version": np.__version__,
        "python": platform.python_version(),
        "solver": "xpersson.bem: tamaas.PolonskyKeerRey(gap, gap), tol 1e-8; "
        "ExponentialAdhesionFunctional; non-converged states flagged and skipped",
        "elastic_solver": "tamaas.PolonskyKeerRey(pressure, pressure), tol 1e-8",
        "grid": n,
        "cell_side_m": L_CELL,
        "E_star_Pa": E_STAR,
        "E_Pa": 0.75 * E_STAR,
        "nu": 0.5,
        "rms_slope": SLOPE,
        "q1_over_qL": RATIO,
        "range_over_h_rms": RANGE_FRACTION,
        "tabor_targets": list(TABOR_TARGETS),
        "loads_over_Estar_hprime": list(LOADS),
        "approach_gaps_over_h_rms": list(D.APPROACH),
        "approach_deep_gaps_over_h_rms": f"{list(D.APPROACH_DEEP)} for tabor > {STRONG:g}, "
        "until the mean stress exceeds the largest load",
        "retract_steps_over_h_rms": f"{D.RETRACT_FINE[1]} x {D.RETRACT_FINE[0]}, then "
        f"{D.RETRACT_STEP}",
        "contact": "gap == 0 (adhesive, gap control); traction > 0 (non-adhesive, load control)",
        "reference_branch": "retraction, stable part up to the most tensile mean stress",
        "command": "python benchmarks/bem_adhesion.py",
    }


def ratio_se(adh: np.ndarray, el: np.ndarray) -> np.ndarray:
    """Standard error of the ratio of means ``R = mean(adh)/mean(el)`` per load [1].

    ``adh``, ``el``: (n_surfaces, n_load) areas of the same surfaces with and without adhesion.
    Delta method for a ratio estimator: ``se^2 = var(adh - R el) / (n mean(el)^2)`` with the
    sample variance (n - 1), per load over the surfaces with a value there (the others are
    NaN: load not on their retraction branch); NaN with fewer than two.
    """
    out = np.full(adh.shape[1], np.nan)
    for j in range(adh.shape[1]):
        ok = np.isfinite(adh[:, j])
        n = int(ok.sum())
        if n >= 2:
            r = adh[ok, j].mean() / el[ok, j].mean()
            resid = adh[ok, j] - r * el[ok, j]
            out[j] = math.sqrt(resid.var(ddof=1) / n) / el[ok, j].mean()
    return out


def summarise(data: dict[str, Any]) -> dict[str, Any]:
    """Surface-averaged areas, ratios A(w)/A(0) and pull-off per spectrum and work."""
    table = {}
    for name, sp in data["spectra"].items():
        el_all = np.array(sp["elastic_area"], dtype=float)
        rows = []
        for entry in sp["works"]:
            if not entry["area"]:  # a partial run: this work not solved yet
                continue
            el = el_all[: len(entry["area"])]  # the surfaces solved with adhesion
            a = np.array([[np.nan if x is None else x for x in r] for r in entry["area"]])
            mean = np.nanmean(np.where(np.isnan(a), np.nan, a), axis=0)
            count = np.sum(~np.isnan(a), axis=0)
            comp = np.array(LOADS) > 0
            ratio = np.full(len(LOADS), np.nan)
            ratio[comp] = mean[comp] / el.mean(axis=0)
            se = np.full(len(LOADS), np.nan)
            se[comp] = ratio_se(a[:, comp], el)
            rows.append(
                {
                    "tabor": entry["tabor"],
                    "work_J_m2": entry["work_J_m2"],
                    "area": [None if math.isnan(x) else float(x) for x in mean],
                    "n_surfaces": [int(c) for c in count],
                    "ratio": [None if math.isnan(x) else float(x) for x in ratio],
                    "ratio_se": [None if math.isnan(x) else float(x) for x in se],
                    "pull_off_Pa": float(np.mean(entry["pull_off_Pa"])),
                }
            )
        table[name] = {
            "H": sp["H"],
            "elastic_area": [float(x) for x in el_all.mean(axis=0)],
            "works": rows,
        }
    return table


def write_md(data: dict[str, Any], path: Path) -> None:
    """The averaged table as markdown."""
    lines = [
        "# BEM referee: adhesive rough contact (tamaas)",
        "",
        f"`{data['provenance']['command']}` -- tamaas {data['provenance']['tamaas_version']}, "
        f"{data['provenance']['grid']}^2 grid, retraction branch; column n: surfaces averaged. "
        "Loads in units of E* h'_rms "
        f"(E* = {E_STAR:g} Pa, h'_rms = {SLOPE}).",
        "",
    ]
    for name, tab in data["table"].items():
        lines += [f"## {name} (H = {tab['H']})", ""]
        head = "| mu_T | n | w [J/m^2] | pull-off [Pa] | " + " | ".join(f"{x:g}" for x in LOADS)
        lines += [head + " |", "|" + "---|" * (4 + len(LOADS))]
        el = ["", "", ""] + ["" if x < 0 else "" for x in LOADS]
        j = 0
        for i, x in enumerate(LOADS):
            if x > 0:
                el[3 + i] = f"{tab['elastic_area'][j]:.4f}"
                j += 1
        lines.append("| 0 (A) | | 0 | 0 | " + " | ".join(el[3:]) + " |")
        for row in tab["works"]:
            cells = [
                "-" if a is None else f"{a:.4f}" + ("" if r is None else f" ({r:.2f}x)")
                for a, r in zip(row["area"], row["ratio"], strict=True)
            ]
            lines.append(
                f"| {row['tabor']} | {max(row['n_surfaces'])} | {row['work_J_m2']:.4g} | "
                f"{row['pull_off_Pa']:.4g} | " + " | ".join(cells) + " |"
            )
        lines.append("")
    lines.append(
        "Cells: surface-averaged A/A0 (ratio A(w)/A(0) at compressive loads); at tensile loads "
        "the mean over the surfaces that hold contact there (`-`: none). Pull-off: mean over "
        "the surfaces. Grid convergence: `bem_adhesion_grid.json`."
    )
    path.write_text("\n".join(lines) + "\n")


def grid_check(grids: tuple[int, ...] = (128, 256, 512)) -> None:
    """One case (H = 0.8, mu_T = 0.6, seed 0) on 128^2, 256^2 and 512^2 grids.

    The 256^2 result of the main run (same surface, same path) is reused when its part file
    holds it.
    """
    H = SPECTRA["H08"]
    h_rms = float(continuum_psd(H).h_rms()) / L_CELL
    rho = RANGE_FRACTION * h_rms
    work = works_of(H)[0] / (E_STAR * L_CELL)
    loads = np.array(LOADS) * SLOPE
    comp = [float(x) for x in loads if x > 0]
    out: dict[str, Any] = {"case": "H08, tabor 0.6, seed 0", "grids": {}}
    part = RESULTS / "bem_adhesion_H08.part.json"
    for n in grids:
        t0 = time.process_time()
        surf = surface(H, 0, n)
        main = json.loads(part.read_text()) if part.exists() else None
        if n == 256 and main is not None and main["works"][0]["paths"]:
            path = main["works"][0]["paths"][0]
            elastic = main["elastic_area"][0]
        else:
            path = adhesive_path(surf, work, rho, h_rms)
            elastic = elastic_areas(surf, comp)
        area, pull = branch_area(path["retract"], loads)
        out["grids"][str(n)] = {
            "area": [None if math.isnan(x) else float(x) for x in area],
            "elastic_area": elastic,
            "pull_off_Pa": pull * E_STAR,
            "cpu_s": time.process_time() - t0,
        }
        print(f"grid {n}: pull-off {pull * E_STAR:.4g} Pa, area {area}", flush=True)
        out["provenance"] = provenance(n) | {"grid": list(grids)}
        (RESULTS / "bem_adhesion_grid.json").write_text(json.dumps(out, indent=1))


def merge() -> None:
    """Combine the per-spectrum parts into bem_adhesion.json and .md."""
    spectra = {}
    for name in SPECTRA:
        part = RESULTS / f"bem_adhesion_{name}.part.json"
        if part.exists():
            spectra[name] = json.loads(part.read_text())
    if not spectra:
        sys.exit("no parts to merge")
    grid = next(iter(spectra.values()))["grid"]
    data = {"provenance": provenance(grid), "spectra": spectra}
    data["table"] = summarise(data)
    (RESULTS / "bem_adhesion.json").write_text(json.dumps(data, indent=1))
    write_md(data, RESULTS / "bem_adhesion.md")


def main(argv: list[str] | None = None) -> None:
    """Command line: one spectrum, the grid check, or the merge."""
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--spectrum", choices=sorted(SPECTRA), default=None)
    ap.add_argument("--surfaces", type=int, default=3)
    ap.add_argument("--grid", type=int, default=256)
    ap.add_argument("--grid-check", action="store_true")
    ap.add_argument("--merge", action="store_true")
    ap.add_argument(
        "--tabor", type=float, nargs="*", default=None, help="only these targets (new: added)"
    )
    args = ap.parse_args(argv)
    RESULTS.mkdir(exist_ok=True)
    if args.grid_check:
        grid_check()
        return
    if args.merge:
        merge()
        return
    for name in [args.spectrum] if args.spectrum else list(SPECTRA):
        only = tuple(args.tabor) if args.tabor else None
        part = run_spectrum(name, args.surfaces, args.grid, only)
        (RESULTS / f"bem_adhesion_{name}.part.json").write_text(json.dumps(part))
    merge()


if __name__ == "__main__":
    main()
