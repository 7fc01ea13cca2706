"""Text and tension table of ``docs/adhesion_bem.md`` (used by ``adhesion_bem_compare.py``)."""

from __future__ import annotations

import math
from typing import Any

#: Largest Tabor parameter of the verified (calibrated) range.
VERIFIED_MAX = 2.0


def tension_lines(bem: dict[str, Any], pred: dict[str, Any]) -> list[str]:
    """Per case: pull-off (BEM mean, per-surface range, adhesive, factor) and, per tensile load,
    how many BEM surfaces hold contact against whether ``adhesive`` does (its area)."""
    meta = bem["provenance"]
    loads = meta["loads_over_Estar_hprime"]
    tens = [i for i, x in enumerate(loads) if x < 0]
    scale = meta["E_star_Pa"] * meta["rms_slope"]
    lines = [
        "## Tension: pull-off and contact under tensile loads",
        "",
        "Pull-off: the BEM's mean over its surfaces (per-surface range in brackets) against",
        "`adhesive`'s, and their factor. Tensile loads (in Pa): BEM surfaces holding contact",
        "`k/n` / `adhesive`'s area (`-`: it lets go). A load counts as *held by most* when more",
        "than half of the BEM surfaces hold there.",
        "",
        "| spectrum | mu_T | pull-off BEM [Pa] | adhesive [Pa] | factor | "
        + " | ".join(f"{loads[i] * scale:g} Pa" for i in tens)
        + " |",
        "|" + "---|" * (5 + len(tens)),
    ]
    for name, sp in bem["spectra"].items():
        for k, entry in enumerate(sp["works"]):
            if entry["tabor"] > VERIFIED_MAX or not entry["paths"]:
                continue
            pulls = entry["pull_off_Pa"]
            mean = sum(pulls) / len(pulls)
            model = pred[name]["works"][k]["adhesive"]
            m_pull = model["pull_off_Pa"]
            f = max(m_pull / mean, mean / m_pull) if m_pull > 0 and mean > 0 else math.inf
            cells = []
            for i in tens:
                held = sum(1 for a in entry["area"] if a[i] is not None)
                am = model["area"][i]
                cells.append(f"{held}/{len(pulls)} / " + ("-" if am is None else f"{am:.2g}"))
            lines.append(
                f"| {name} | {entry['tabor']} | {mean:.3g} ({min(pulls):.3g}-{max(pulls):.3g}) "
                f"| {m_pull:.3g} | **{f:.2f}** | " + " | ".join(cells) + " |"
            )
    return lines + [""]


def held_by_most(bem: dict[str, Any], pred: dict[str, Any]) -> tuple[int, int]:
    """(tensile loads held by most BEM surfaces where adhesive holds too, all such loads)."""
    loads = bem["provenance"]["loads_over_Estar_hprime"]
    ok = total = 0
    for name, sp in bem["spectra"].items():
        for k, entry in enumerate(sp["works"]):
            if entry["tabor"] > VERIFIED_MAX or not entry["paths"]:
                continue
            n = len(entry["area"])
            for i, x in enumerate(loads):
                if x < 0 and 2 * sum(1 for a in entry["area"] if a[i] is not None) > n:
                    total += 1
                    ok += pred[name]["works"][k]["adhesive"]["area"][i] is not None
    return ok, total


def header(bem: dict[str, Any]) -> list[str]:
    meta = bem["provenance"]
    return [
        "# Adhesion: xpersson's models against a boundary-element referee",
        "",
        "Regenerate: `python benchmarks/bem_adhesion.py` (the referee, tamaas; about an hour on",
        "two cores) then `python benchmarks/adhesion_bem_compare.py` (this page).",
        "",
        f"Referee: tamaas {meta['tamaas_version']} `PolonskyKeerRey` with its exponential",
        "adhesion functional (energy `-w exp(-g/rho)` per area, `rho = 0.1 h_rms`), periodic",
        f"Gaussian self-affine surfaces on a {meta['grid']}^2 grid, `q_1/q_L = "
        f"{meta['q1_over_qL']}`, rms slope {meta['rms_slope']}, no roll-off, Persson's PSD",
        "convention; retraction branch under displacement control, read at imposed mean",
        "stresses (load control: stable states up to the most tensile stress), averaged over",
        "the surfaces (`benchmarks/results/bem_adhesion.md` has the referee alone and its",
        "provenance). xpersson solves the same scene (spectrum, `E* = 1 MPa`, work, range).",
        "",
        "Columns: loads `p0/(E* h'_rms)`. Cells: `A/A0` at the finest scale and, at compressive",
        "loads, the enhancement `A(w)/A(0)` (each method against its own non-adhesive area: the",
        "BEM's small cell has 1.2-1.9x Persson's non-adhesive area). `-`: no contact (beyond",
        "pull-off) or refused (`jkr` refuses tensile loads when `gamma_eff(1) = 0`); BEM cells at",
        "tensile loads average the surfaces that hold contact there; `n`: surfaces averaged;",
        "`+-`: standard error of the BEM's mean ratio over its surfaces.",
        "",
    ]


OPTIONS = """## Options evaluated (why `adhesive`)

* **Persson's wall, `jkr`** (`sigma_a = [c_a gamma_eff E* q]^(1/2)`, `gamma_eff` reduced by
  the full-contact elastic energy of the finer scales): on these scenes `gamma_eff(1) = 0`
  (Persson-Tosatti `w_eff < 0`), so the wall starts at `p = 0`, the enhancement is the same at
  every load (1.2-1.4x at mu_T = 0.6, 1.6-1.8x at 1.0; `c_a = 2`: +6 %) and tensile loads are
  refused. Rejected (table below).
* **Wall variants** (explored on one 128^2 surface, H = 0.8, not kept): the local balance
  without the `gamma_eff` reduction and capped at the cohesive strength `w/rho`
  (`sigma_a = (sigma_J^-2 + (w/rho)^-2)^(-1/2)`) puts a wall of several kPa at zeta = 1: a
  large area at zero load and a flat `A(p0)` (enhancement 25x falling to 2.8x at mu_T = 0.6
  with `c_a = 1/4`, against the BEM's 3.3x to 2.1x); a partial reduction (a fraction of the
  finer scales' energy) switches abruptly between the two behaviours. No single constant fits.
* **DMT mean field with the referee's own law** (`dmt`, exponential law): the attraction over
  the gap distribution of Persson's contact at `p_rep = p0 + p_att`. The right fall with load
  and the right pull-off at mu_T = 1, but near its stickiness threshold (mu_T = 1) it
  over-predicts the enhancement at the lightest loads (14-17x against the BEM's 6-7 +- 1.5x
  with six surfaces: beyond every single surface's ratio, so model error, not scatter).
* **Scaled mean field, kept as `adhesive`'s compressive branch**: the same mean field with its
  attraction scaled by `ATTRACTION_SCALE = 0.85` (one constant, chosen on the H = 0.8
  spectrum, where 0.8-0.9 keep every point within 1.8x; H = 0.5 is the check). Tabulated
  (fast), with pull-off, stickiness and regime. At mu_T = 1 it is just below its stickiness
  (`k0 = 0.94`): alone it holds no tension there.
* Other transforms of the attraction (not kept): `k -> k^0.5` keeps the stickiness threshold
  where it is (lightest loads at mu_T = 1 2.8x off); an area-dependent scale (1 at small area
  falling to 0.8) loses the tension as the constant does.

### The tensile branch (this pass; all on the stored BEM data)

`python benchmarks/bem_adhesion_tension.py` reprints the numbers below (no BEM solve);
`python benchmarks/bem_adhesion_clusters.py` re-solves one path and counts its contacts.

Reading the BEM's retraction paths as `k = p_att/p_rep` against the area (`p_rep` from each
surface's own non-adhesive `A(p)`, surface means), against the unscaled mean field at the
same Persson-equivalent area (`A/1.45`, the cell's non-adhesive area excess):

| BEM / mean field | A = 0.003 | 0.005 | 0.01 | 0.02 | 0.03 | 0.05 |
|---|---|---|---|---|---|---|
| H08 mu_T 0.6 | 1.11 / 0.51 | 0.93 / 0.51 | 0.76 / 0.51 | 0.64 / 0.51 | 0.58 / 0.50 | 0.53 / 0.48 |
| H08 mu_T 1.0 | 1.82 / 1.10 | 1.53 / 1.09 | 1.19 / 1.09 | 1.01 / 1.09 | 0.92 / 1.08 | 0.83 / 1.04 |
| H05 mu_T 1.0 | 1.29 / 1.06 | 1.13 / 1.06 | 1.03 / 1.06 | 0.92 / 1.05 | 0.87 / 1.04 | 0.83 / 1.01 |

The BEM's `k` rises at small area (about `A^-0.3`) where the mean field has its plateau: an
excess attraction of roughly constant size (50-130 Pa per cell at mu_T = 1), i.e. a force per
cell, not per contact area: a finite-size effect. Candidates tried for it (pull-off in Pa,
BEM means H08 28 / 111, H05 7.2 / 64 at mu_T 0.6 / 1.0):

* **Mean field on each surface's realised spectrum** (the cell's few long-wavelength modes
  binned into its own PSD; scaled 0.85): per-surface `k0` 0.69-1.09 at H08 mu_T = 1 (the least
  sticky surface is the BEM's least sticky in every case), but pull-offs 0-71 (mean 16) there
  and 0 at mu_T = 0.6: the cell's own spectrum does not make it sticky. Unscaled: mean 167 /
  114 at mu_T = 1 but 0 at 0.6 and 3-4x too high at 1.6. Not kept.
* **Rough bump, rigid (Derjaguin)**: the surface smoothed at `zeta_c q_L` as a sphere
  `R = 1/kappa(zeta_c)`, the finer band through the (scaled) mean field as an effective
  traction-gap law `p_rep(u) - p_att(u)` of the mean gap (Joe, Thouless and Barber's idea of
  a rough interface's effective law, evaluated in the mean field). Pull-off
  `2 pi R W_eff / L^2`: H08 7-9 / 24-39, H05 0-1.3 / 8-10 (zeta_c 8-16; zeta_c = 4 gives
  0 / 56 and 0 / 7). Not kept.
* **Rough bump, elastic (Hertz nominal pressure, local mean field inside)**: 0-2 Pa at
  mu_T <= 1 (the local pressures of a Hertz patch are too high for the band's attraction).
* **Cell-corrected mean field** (the BEM cell's non-adhesive area, 1.2-1.9x Persson's, as the
  elastic curve): the same as rescaling the attraction (`k -> 1.45 k`); not new.
* **Smooth bump with Persson-Tosatti's `gamma_eff`** (kept, `adhesive`'s floor): the bump at
  the scale that holds best, `max_zeta 2 pi gamma_eff(zeta) R(zeta)`, `gamma_eff` the work
  less the full-contact elastic energy of the finer roughness {cite:p}`persson2001adhesion`. Its
  `W_eff R` agrees with the rigid rough bump's (0.48 w against 0.42 w at zeta ~ 8, H08
  mu_T = 1): one bump holds 10 / 42 (H08) and 3.6 / 9.2 (H05) Pa, 2.6-7x below the BEM.
  Counting the BEM's contact clusters along two retraction paths (mu_T = 1, seed 0; spots
  merged within 3 um): H08 5-6 clusters at -50 to -98 Pa and a single one at the final
  pull-off (100 Pa, A = 0.004); H05 6 clusters at its pull-off (67 Pa, A = 0.011), a single
  one holding up to 36 Pa. So a single BEM cluster holds 2.4x (H08) and 4x (H05) the single
  bump's force, and several clusters share the load under tension.
  The scan keeps only bumps whose Derjaguin interaction zone `sqrt(2 R h_f)` (`h_f` the
  finer roughness' rms height) fits a quarter wavelength of their scale: unconstrained, the
  best scale sits at 0.88-0.97 of that bound in the fitted cases (it does not bind there),
  while on a rolled-off spectrum the plateau would send it to a 'bump' with `R >> L`.
  `adhesive` lets `BUMPS = 2.7` such bumps hold (both effects in one number), the one
  constant of the floor, fitted on H08 at mu_T 0.6 and 1.0 (the single bump's factors to the
  BEM there: 2.8 and 2.6) and checked on H05 (tension table above the factor table).
* **How the floor enters** (kept): first as a separate branch (the bumps' own DMT-Hertz area
  where larger than the mean field's): tensile areas 5-20x below the BEM's. Kept instead: the
  bumps' force per cell `P_f` is the excess attraction the `k(A)` table shows, so it is added
  to the mean field's attraction, `p_rep - 0.85 p_att(p_rep) = p0 + d` with
  `d = max(P_f - P_mf, 0)` (`P_mf` the mean field's own pull-off; no extra where the sticky
  mean field holds more, so the pull-off is `max(P_f, P_mf)`). One continuous `A(p0)`; at
  mu_T = 1 (H08) the tensile areas come within 1.4-8x of the BEM's, and the compressive
  worst factor improves from 1.64 to 1.54 (the light loads at mu_T = 0.6 gain, those at 1.0
  lose a little). No constant was refitted for it.

"""


LIMITS = """## Findings, limits and what is missing

* Compressive branch (the scaled mean field, at `p0 + d`): the enhancement within 1.54x of the
  BEM at every compressive point of the calibrated range, falling with load as the BEM's.
* Tension: the pull-off is the sticky mean field's (mu_T = 1.6: 2.2x above the BEM's) or the
  floor's, `BUMPS` bumps of the nominal area in DMT contact (mu_T <= 1): 1.02-1.04x on H08
  (fitted there) and 1.36x / 2.6x on H05 (the check), so it misses the check at H05 mu_T = 1
  (25 against 64 Pa; that case's BEM mean is carried by one surface at 195 Pa, its median is
  36 Pa) and lets go at -25 Pa there, where 5 of 6 BEM surfaces hold. Areas under tension
  (regime 4, `expected_factor` 0): 1.4-8x below the BEM's at mu_T = 1 (H08), far below near
  the pull-off (mu_T = 0.6, -25 Pa: 7e-5 against 0.0045); the pull-off and the fact of contact
  are modelled, the tensile area only roughly.
* The floor is a finite-size effect: its stress is `P_f = BUMPS F / L^2`, `L = nominal_size`
  (default the roughness' longest wavelength `2 pi/q_L`, the BEM's cell). For a real nominal
  area (`L >> 2 pi/q_L`) it vanishes as `L^-2`: `adhesive` then predicts tension only where
  the mean field is sticky (`small_load_ratio > 1`; on these spectra mu_T >~ 1.05).
  Whether the BEM's tension below that threshold survives on larger cells (more modes, a
  roll-off) is not checked: the referee has one cell size. `BUMPS` is a calibrated constant
  (H08, two works), not a derived one; per-surface BEM pull-offs scatter 6x.
* Surfaces: 3-6 per spectrum and work (each adhesive path at 256^2 takes 1-4 CPU minutes, the
  strong case 5); the cases with the largest scatter (mu_T = 1) have 6.
* Stronger adhesion (mu_T = 3, one surface): the row beyond the calibrated range in the factor
  table is `adhesive`'s regime-3 figure.
* Calibration: two constants fitted on the referee itself (`ATTRACTION_SCALE` on the H = 0.8
  areas, `BUMPS` on the H = 0.8 pull-offs), both checked on H = 0.5 only: a calibrated model,
  not a prediction from first principles. Deeper in the JKR regime (mu_T >> 1) the mean
  field's attraction must give way to Persson's detachment wall; `adhesive` flags regime 3.
* Absolute areas: the BEM's non-adhesive area on this small cell is 1.2-1.9x Persson's, so
  absolute adhesive areas differ by about that factor; the enhancement ratio is the measure.
* Literature: Derjaguin, Muller, Toporov, J. Colloid Interface Sci. 53, 314 (1975) (DMT
  sphere); Persson and Tosatti, J. Chem. Phys. 115, 5597 (2001) (`gamma_eff`, stickiness);
  Fuller and Tabor, Proc. R. Soc. A 345, 327 (1975) (rough contact as adhering asperities);
  Joe, Thouless and Barber, J. Mech. Phys. Solids 118, 365 (2018) (effective traction-gap law
  of a rough interface); Persson and Scaraggi, J. Chem. Phys. 141, 124701 (2014) (DMT mean
  field, scale-dependent Tabor parameter).

"""
