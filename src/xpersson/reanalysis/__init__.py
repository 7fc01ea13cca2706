"""Analyses of a solved Dataset after the fact: :func:`analyse` (``xpersson.analyse``).

An archive reopened years later (``xpersson.open_dataset``, ``xarray.open_dataset``) carries
what the analyses compute from: the solved area curves, the spectrum the solve used
(``psd_C``, ``psd_exponent`` on ``q_psd``: :func:`xpersson.plugins.stored.spectrum_of`), the
contact modulus ``E_star``, and the resolved scene (attribute ``xpersson_scene``), which names
the coefficient and the boundary whose declarations the analyses read. :func:`analyse` runs an
analysis on that Dataset as the solving process ran it: the same context, and the same
``ctx.solve_at`` (the scene's solve at denser magnifications where the output grid is too
coarse for the integrals over zeta), with the spectrum taken from the Dataset, never from a
file or a spectrum plugin. The numbers equal those of the analysis run inside the solve.
"""

from __future__ import annotations

from typing import Any

import xarray as xr

from ._body import analyse_body, is_body
from ._point import analyse_point
from ._sweep import analyse_sweep, is_sweep

__all__ = ["analyse"]


def analyse(ds: xr.Dataset, name: str, /, **params: Any) -> xr.Dataset:
    """Run the analysis ``name`` on a solved Dataset and return a new Dataset with its outputs.

    Parameters
    ----------
    ds : xarray.Dataset
        A solved scene, sweep or finite body: the Dataset :func:`xpersson.solve` returned, or
        an archive reopened with :func:`xpersson.open_dataset` or :func:`xarray.open_dataset`.
        A sweep's every point is analysed with its own swept values (the sweep's coordinates),
        as the sweep's point-by-point path analyses it (:mod:`._sweep`); a finite body's flat
        is analysed and the body computed again from it (:mod:`._body`). A subset along a
        sweep's dimensions is the sweep of its values, a subset of the loads the scene of
        those loads (the analyses treat a Dataset's loads together: equal to the full solve's
        to round-off).
    name : str
        An installed analysis (``xpersson plugins list analyses``), e.g. ``"gap_pdf"``,
        ``"leakage"``, ``"elastic_energy"``, ``"thermal_contact"``.
    **params
        The analysis's parameters, as in a scene's ``[analyses.NAME]`` table (numbers in SI,
        or strings with units: ``u_max="2 um"``). In a sweep the same for every point.

    Returns
    -------
    xarray.Dataset
        ``ds`` (not modified) with the analysis's variables (and those of the analyses it
        requires that ``ds`` lacks) added; variables of the same names are replaced. A sweep's
        outputs have the layout the sweep gives them: its dimensions in front, dropped where
        the output does not change along them, NaN at points that failed.

    Raises
    ------
    ArchiveError
        ``ds`` lacks what the analyses compute from (the spectrum ``psd_C``/``q_psd``,
        ``E_star``, the scene attribute ``xpersson_scene``, a sweep's coordinate: the message
        names it), or is cut along ``zeta`` or a finite body's ``force``.
    SceneError
        An unknown analysis or parameter (as in a scene).
    """
    if is_sweep(ds):
        return analyse_sweep(ds, name, params)
    if is_body(ds):
        return analyse_body(ds, name, params)
    return analyse_point(ds, name, params)
