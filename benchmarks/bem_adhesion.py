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
  SurfaceTopography/JJP ``C^iso`` divided by ``(2 pi)^2`` (physics.md §8.1). The white noise is
  drawn on a fixed 128^2 lattice from the seed and only the modes ``1 <= |k| <= 32`` are kept,
  so the same surface is sampled exactly on 128^2, 256^2 and 512^2 grids (grid-convergence
  check). Each realisation is scaled to the exact rms slope 0.1 (its discrete ``h_rms`` is
  stored).
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
APPROACH = (2.4, 1.4, 0.9, 0.6)
#: Strong adhesion (Tabor targets above 2): the mean stress at gap 0.6 h_rms is already tensile,
#: so the approach goes on in these steps until the compressive stress exceeds the largest
#: load (or the gap reaches its last step) [h_rms].
APPROACH_DEEP = (0.45, 0.3, 0.2, 0.12, 0.06)
STRONG = 2.0
#: Retraction: fine steps (the compressive loads change fast near the turning point at strong
#: adhesion), then coarse ones until the contact is lost [h_rms].
RETRACT_FINE = (0.03, 10)
RETRACT_STEP = 0.1
NOISE_GRID = 128


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
    """Gaussian self-affine surface on an n x n grid, cell side 1, rms 2-D slope SLOPE."""
    rng = np.random.default_rng(seed)
    white = np.fft.fft2(rng.standard_normal((NOISE_GRID, NOISE_GRID))) / NOISE_GRID
    k = np.fft.fftfreq(NOISE_GRID, d=1.0 / NOISE_GRID)
    kx, ky = np.meshgrid(k, k, indexing="ij")
    kk = np.hypot(kx, ky)
    keep = (kk >= 1) & (kk <= RATIO)
    amp = np.where(keep, np.where(kk > 0, kk, 1.0) ** (-(1.0 + H)), 0.0)
    spec = np.zeros((n, n), dtype=complex)
    idx = np.fft.fftfreq(n, d=1.0 / n).astype(int)
    sel = np.ix_(
        np.where(np.abs(idx) <= NOISE_GRID // 2 - 1)[0],
        np.where(np.abs(idx) <= NOISE_GRID // 2 - 1)[0],
    )
    src = idx[np.abs(idx) <= NOISE_GRID // 2 - 1] % NOISE_GRID
    spec[sel] = (white * amp)[np.ix_(src, src)]
    h = np.real(np.fft.ifft2(spec)) * n * n
    kn = np.fft.fftfreq(n, d=1.0 / n)
    kxn, kyn = np.meshgrid(kn, kn, indexing="ij")
    fh = np.fft.fft2(h)
    gx = np.real(np.fft.ifft2(2j * math.pi * kxn * fh))
    gy = np.real(np.fft.ifft2(2j * math.pi * kyn * fh))
    h *= SLOPE / math.sqrt(float(np.mean(gx**2 + gy**2)))
    return h - h.max()


def _solver(tm: Any, surf: np.ndarray, work: float, rho: float, control: str) -> tuple[Any, ...]:
    """Model, solver and adhesion term (keep all three alive: the solver holds raw pointers)."""
    tm.set_log_level(tm.LogLevel.error)
    n = surf.shape[0]
    model = tm.ModelFactory.createModel(tm.model_type.basic_2d, [1.0, 1.0], [n, n])
    model.E, model.nu = 1.0, 0.0  # E* = 1
    kind = tm.PolonskyKeerRey.gap if control == "gap" else tm.PolonskyKeerRey.pressure
    solver = tm.PolonskyKeerRey(model, surf, 1e-8, kind, kind)
    adh = None
    if work > 0:
        adh = tm.ExponentialAdhesionFunctional(surf)
        adh.parameters = {"rho": rho, "surface_energy": work}
        solver.addFunctionalTerm(adh)
    return model, solver, adh


def _state(model: Any, rho: float) -> dict[str, float]:
    gap = np.asarray(model["gap"])
    tr = np.asarray(model.traction)
    return {
        "gap": float(gap.mean()),
        "p": float(tr.mean()),
        "area": float(np.mean(gap <= 0.0)),
        "area_in_range": float(np.mean(gap < rho)),
        "p_contact": float(np.sum(np.where(gap <= 0.0, tr, 0.0)) / tr.size),
    }


def adhesive_path(
    surf: np.ndarray, work: float, rho: float, h_rms: float, deep: bool = False
) -> dict[str, list]:
    """Approach then retraction under displacement control (dimensionless units).

    ``deep``: approach on through :data:`APPROACH_DEEP` until the mean stress exceeds the
    largest load (strong adhesion).
    """
    import tamaas as tm

    model, solver, _keep = _solver(tm, surf, work, rho, "gap")
    approach = []
    g = APPROACH[0]
    for step in APPROACH + (APPROACH_DEEP if deep else ()):
        if step in APPROACH_DEEP and approach[-1]["p"] > max(LOADS) * SLOPE:
            break
        g = step
        solver.solve(g * h_rms)
        approach.append(_state(model, rho))
    retract = [approach[-1]]
    while True:
        fine = len(retract) <= RETRACT_FINE[1]
        g = round(g + (RETRACT_FINE[0] if fine else RETRACT_STEP), 10)
        solver.solve(g * h_rms)
        st = _state(model, rho)
        retract.append(st)
        if st["area"] == 0.0 or g > 4.0:
            break
    return {"approach": approach, "retract": retract}


def elastic_areas(surf: np.ndarray, loads: list[float]) -> list[float]:
    """Non-adhesive contact area at imposed mean pressures (dimensionless, E* = 1)."""
    import tamaas as tm

    model, solver, _keep = _solver(tm, surf, 0.0, 1.0, "pressure")
    out = []
    for p in loads:
        solver.solve(p)
        out.append(float(np.mean(np.asarray(model.traction) > 0.0)))
    return out


def branch_area(path: list[dict[str, float]], loads: np.ndarray) -> tuple[np.ndarray, float]:
    """A at the loads on the stable part of a retraction branch; and its pull-off [E*]."""
    p = np.array([s["p"] for s in path])
    a = np.array([s["area"] for s in path])
    pull = max(-float(p.min()), 0.0)
    # Load control follows the running minimum of p along the retraction (each new record
    # is a stable state; snap-off saw-teeth in between are skipped).
    keep = [0]
    for i in range(1, p.size):
        if p[i] < p[keep[-1]]:
            keep.append(i)
    ps, as_ = p[keep][::-1], a[keep][::-1]  # p increasing
    out = np.full(loads.shape, np.nan)
    ok = (loads >= ps[0]) & (loads <= ps[-1])
    out[ok] = np.interp(loads[ok], ps, as_)
    return out, pull


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
        if out["grid"] == n:
            _extend_elastic(name, out, n_surf, n, comp)
            _add_works(out, only or ())
            return _solve_paths(name, out, n_surf, n, rho, h_rms, loads, only)
    out = {"H": H, "grid": n, "seeds": list(range(n_surf)), "works": []}
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
    import tamaas as tm

    return {
        "tamaas_version": tm.__version__,
        "numpy_version": np.__version__,
        "python": platform.python_version(),
        "solver": "tamaas.PolonskyKeerRey(gap, gap), tol 1e-8; ExponentialAdhesionFunctional",
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
        "approach_gaps_over_h_rms": list(APPROACH),
        "approach_deep_gaps_over_h_rms": f"{list(APPROACH_DEEP)} for tabor > {STRONG:g}, until "
        "the mean stress exceeds the largest load",
        "retract_steps_over_h_rms": f"{RETRACT_FINE[1]} x {RETRACT_FINE[0]}, then {RETRACT_STEP}",
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
