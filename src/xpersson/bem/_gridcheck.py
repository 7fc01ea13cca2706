"""The grid check of a cross-check: the BEM outputs on a grid twice as fine, as ratios.

Every realisation is solved a second time on a ``2n x 2n`` grid: the same surface (it is
band-limited, so its Fourier interpolation is exact), the same band ``q_L..q_max``, 16 points
on the shortest wavelength instead of 8. The ratio fine/coarse of each BEM output, of the
means over the realisations where both solves converged, measures the BEM's discretisation
error at the cross-check's grid (1 where the coarse grid has converged in resolution).
"""

from __future__ import annotations

import numpy as np
import xarray as xr

__all__ = ["add_grid_ratios"]


def _paired_means(coarse: np.ndarray, fine: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Means over the realisations (axis 0) of the points where both grids have a value."""
    both = np.isfinite(coarse) & np.isfinite(fine)
    n = both.sum(axis=0)
    with np.errstate(invalid="ignore", divide="ignore"):
        c = np.where(n > 0, np.where(both, coarse, 0).sum(axis=0) / np.maximum(n, 1), np.nan)
        f = np.where(n > 0, np.where(both, fine, 0).sum(axis=0) / np.maximum(n, 1), np.nan)
    return c, f


def _link(ds: xr.Dataset, name: str, extra: str) -> None:
    own = ds[name].attrs.get("ancillary_variables", "")
    ds[name].attrs["ancillary_variables"] = f"{own} {extra}".strip()


def add_grid_ratios(
    ds: xr.Dataset,
    coarse: dict[str, np.ndarray],
    fine: dict[str, np.ndarray],
    pairs: list[tuple[str, str]],
    fine_grid: int,
    du: np.ndarray | None,
) -> None:
    """Add ``X_grid_ratio`` (fine/coarse BEM mean) for every compared output ``X`` in ``ds``,
    ``gap_pdf_grid_l1`` (the L1 distance of the two grids' gap distributions) and
    ``bem_converged_fine``.

    Parameters
    ----------
    ds
        The cross-check's Dataset (its ``X`` variables already present).
    coarse, fine
        Per-realisation BEM values on the two grids, under the BEM names (realisation first).
    pairs
        ``(BEM name, theory name)`` of the compared outputs.
    fine_grid
        Points per side of the fine grid [1].
    du
        Widths of the gap pdf's bins [m] (``None``: no gap pdf).
    """
    text = (
        f"BEM on a {fine_grid}^2 grid (16 points on the shortest wavelength) / BEM on the "
        f"cross-check's grid (8), same surfaces and band, means over the realisations where "
        f"both converged"
    )
    for bem_name, name in pairs:
        if name not in ds or bem_name not in fine:
            continue
        c, f = _paired_means(coarse[bem_name], fine[bem_name])
        with np.errstate(invalid="ignore", divide="ignore"):
            ratio = np.where(np.isfinite(c) & (c != 0), f / c, np.nan)
        ds[f"{name}_grid_ratio"] = (
            ds[name].dims,
            ratio,
            {"units": "1", "long_name": f"{text}: {name}"},
        )
        _link(ds, name, f"{name}_grid_ratio")
    if du is not None and "gap_pdf" in fine and "gap_pdf" in ds:
        c, f = _paired_means(coarse["gap_pdf"], fine["gap_pdf"])
        wc, wf = _paired_means(coarse["area_fraction"], fine["area_fraction"])
        ds["gap_pdf_grid_l1"] = (
            ("p0",),
            np.sum(np.abs(f - c) * du, axis=-1) + np.abs(wf - wc),
            {
                "units": "1",
                "long_name": f"L1 distance of the BEM's gap distributions (pdf and contact "
                f"weight) on the {fine_grid}^2 and the cross-check's grid",
            },
        )
        _link(ds, "gap_pdf", "gap_pdf_grid_l1")
