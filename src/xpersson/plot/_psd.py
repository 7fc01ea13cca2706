"""The ``psd`` kind: the power spectrum a solve used, with a self-affine fit and the bands the
measured scans cover (``xpersson psd --plot`` draws the same figure from the maps)."""

from __future__ import annotations

import json
from typing import Any

import numpy as np
import xarray as xr

from ..physics.psd import SelfAffineFit, fit_self_affine
from ._figure import new_axes

__all__ = ["draw_psd", "psd", "bands_of"]


def bands_of(ds: xr.Dataset) -> list[tuple[float, float, str]]:
    """The measured scans' bands ``(q_lo, q_hi, label)`` [1/m] recorded in an archive's scene
    (``spectrum.parts``; empty for a spectrum that is not a measured map)."""
    try:
        spectrum = json.loads(ds.attrs.get("xpersson_scene", "{}")).get("spectrum", {})
        parts = json.loads(spectrum.get("parts") or "[]")
    except (TypeError, ValueError):
        return []
    out = []
    for part in parts:
        band = part.get("band_1_per_m")
        if band:
            name = str(part.get("file") or part.get("object") or "scan").rsplit("/", 1)[-1]
            size = max(part.get("physical_sizes_m") or [0.0])
            out.append((float(band[0]), float(band[1]), f"{name}, L = {size:.3g} m"))
    return out


def draw_psd(
    q: np.ndarray,
    C: np.ndarray,
    fit: SelfAffineFit | None = None,
    bands: list[tuple[float, float, str]] | None = None,
    ax: Any = None,
) -> Any:
    """Draw ``C(q)`` [m^4] against ``q`` [1/m] (log-log), the fit (dashed) and the bands
    (shaded, one colour each); returns the Axes."""
    ax = new_axes(ax)
    for i, (lo, hi, label) in enumerate(bands or []):
        ax.axvspan(lo, hi, color=f"C{i + 2}", alpha=0.12, lw=0, label=label)
    ax.loglog(q, C, "o-", ms=3, color="C0", label="table (Persson convention)")
    if fit is not None:
        qq = np.geomspace(q[0], q[-1], 200)
        ax.loglog(qq, fit.C(qq), "--", color="C1",
                  label=f"fit: H = {fit.H:.3f} ± {fit.H_err:.3f}, q_r = {fit.q_r:.3g} 1/m, "
                        f"h_rms = {fit.h_rms:.3g} ± {fit.h_rms_err:.2g} m")  # fmt: skip
    ax.set_xlabel("q (1/m)")
    ax.set_ylabel("C(q) (m⁴)")
    ax.legend(fontsize="small", loc="lower left")
    return ax


def psd(ds: xr.Dataset, ax: Any = None, max_curves: int = 12) -> Any:
    """The solved archive's PSD (``psd_C`` on ``q_psd``; the first point of a sweep), its
    self-affine fit and the measured bands."""
    del max_curves  # one spectrum per point; a sweep draws its first
    da = ds["psd_C"]
    for dim in [d for d in da.dims if d != "q_psd"]:
        da = da.isel({dim: 0})
    q = np.asarray(da["q_psd"].values if "q_psd" in da.coords else ds["q_psd"].values, float)
    C = np.asarray(da.values, float)
    ok = np.isfinite(C) & (C > 0)
    fit = fit_self_affine(q[ok], C[ok]) if ok.sum() >= 4 else None
    ax = draw_psd(q[ok], C[ok], fit, bands_of(ds), ax)
    ax.set_title("power spectrum used by the solve", fontsize="medium")
    return ax
