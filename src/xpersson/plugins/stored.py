"""What an analysis reads of the solve besides the area curve: the spectrum and the modulus.

A public module of the plugin-author layer. The analyses compute from the solved Dataset, never
from the scene (docs/architecture.md): the spectrum the solve used is the Dataset's
``psd_C(q_psd)`` with its segment exponents ``psd_exponent(q_psd)``, and the contact modulus its
``E_star``. :func:`spectrum_of` rebuilds that spectrum so that every number derived from it is
the solving process's, bit for bit, whether the Dataset is the one the pipeline just assembled
or an archive reopened years later (``xpersson.open_dataset``, ``xarray.open_dataset``).

An archive written before ``psd_exponent`` was stored has only the table: its segments'
exponents are then the log-log slopes between the stored values (see
:class:`xpersson.physics.psd.StoredSpectrum`), the same spectrum up to round-off.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..errors import ArchiveError
from ..physics.psd import PowerSpectrum, StoredSpectrum

__all__ = ["SPECTRUM_VARIABLES", "spectrum_of", "contact_modulus"]

#: The Dataset's variables that define its spectrum (``psd_exponent`` optional: older archives).
SPECTRUM_VARIABLES = ("q_psd", "psd_C", "psd_exponent")


def _values(ds: Any, name: str, indexers: dict[str, int], why: str) -> np.ndarray:
    """``ds``'s variable ``name`` at ``indexers`` as a float array; an ArchiveError naming it
    and ``why`` it is needed when the Dataset lacks it."""
    var = ds.variables.get(name) if hasattr(ds, "variables") else None
    if var is None:
        have = [n for n in SPECTRUM_VARIABLES if n in getattr(ds, "variables", {})]
        raise ArchiveError(
            f"the Dataset has no variable {name!r} ({why}); analyses compute from the solved "
            f"Dataset's own spectrum and modulus (it has {', '.join(have) or 'none'} of "
            f"{', '.join(SPECTRUM_VARIABLES[:2])}, and E_star): keep them when selecting "
            "variables, or re-solve the archive's scene (xpersson reproduce)"
        )
    values = np.asarray(var.values, dtype=float)
    if any(d in var.dims for d in indexers):  # numpy indexing: no xarray isel per point
        values = values[tuple(indexers.get(d, slice(None)) for d in var.dims)]
    return values


def spectrum_of(ds: Any, **indexers: int) -> PowerSpectrum:
    """The power spectrum a Dataset was solved with, rebuilt from the Dataset alone.

    Parameters
    ----------
    ds : xarray.Dataset
        A solved Dataset (a point's; or a block's or sweep's with ``indexers`` selecting one
        point): ``q_psd`` [1/m], ``psd_C`` [m^4] and, where stored, ``psd_exponent`` [1].
    **indexers : int
        Positions along the Dataset's other dimensions of ``psd_C`` (e.g. ``point=k``, or a
        sweep's ``H=2``); nodes where a sweep's union of breakpoints leaves ``psd_C`` NaN are
        not the point's and are dropped.

    Returns
    -------
    PowerSpectrum
        A frozen :class:`~xpersson.physics.psd.StoredSpectrum`: ``C(q)`` [m^4], the moments and
        ``I3`` equal to the solving spectrum's bit for bit (with ``psd_exponent``; else up to
        round-off in the exponents). ``q_L`` and ``q_1`` are the first and last nodes.

    Raises
    ------
    ArchiveError
        The Dataset lacks ``q_psd`` or ``psd_C`` (the message names which), or ``psd_C`` has
        dimensions other than ``q_psd`` that ``indexers`` do not select.
    """
    why = "the wavevectors of the power spectrum's nodes, 1/m"
    q = _values(ds, "q_psd", indexers, why)
    C = _values(ds, "psd_C", indexers, "the power spectrum C(q) the solve used, m^4")
    e = None
    if "psd_exponent" in ds.variables:
        e = _values(ds, "psd_exponent", indexers, "")
    if C.ndim != 1 or q.shape != C.shape:
        extra = [d for d in ds.variables["psd_C"].dims if d != "q_psd" and d not in indexers]
        raise ArchiveError(
            f"psd_C has the dimensions {extra} besides q_psd: select one point "
            f"(spectrum_of(ds, {extra[0] if extra else 'dim'}=i) or ds.isel(...)) first"
        )
    keep = np.isfinite(C)  # a sweep's union of nodes: NaN where a node is another point's
    if e is not None:
        e = e[keep]
        if not np.all(np.isfinite(e[:-1])):  # a partial exponent table: not this spectrum's
            e = None
    try:
        return StoredSpectrum(q[keep], C[keep], e).freeze()
    except ValueError as exc:
        raise ArchiveError(f"the Dataset's spectrum (q_psd, psd_C) is malformed: {exc}") from None


def contact_modulus(ds: Any, **indexers: int) -> float:
    """The contact modulus ``E* = E / (1 - nu^2)`` [Pa] the Dataset was solved with
    (its ``E_star``; ``indexers`` select a point as in :func:`spectrum_of`).

    Raises
    ------
    ArchiveError
        The Dataset has no ``E_star`` or it is not one number.
    """
    E = _values(ds, "E_star", indexers, "the contact modulus E / (1 - nu^2), Pa")
    if E.size != 1:
        raise ArchiveError(f"E_star has {E.size} values: select one point first")
    return float(E.reshape(()))
