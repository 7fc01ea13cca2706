"""The model error of a sweep's block: the ancillary variables of :mod:`xpersson.pipeline.
model_error`, attached to the block's stacked Dataset on every path (point by point, batched,
stacked), so that the parts a sweep writes to a folder carry them too.

The features are computed once per distinct resolved scene (a :class:`~.batched.SweepPoints`
block: one per combination of its non-material values) and the bands evaluated as array
operations over the block's points: no per-point loop on the fast paths.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import xarray as xr

from ..pipeline import model_error
from .batched import SweepPoints
from .stacking import Block

__all__ = ["attach_block"]


def attach_block(ds: xr.Dataset, block: Block, points: Any) -> list[str]:
    """Add the model-error variables to a block's Dataset ``ds`` (in place); their names.

    ``points``: the block's resolved points in C order (a list or a :class:`SweepPoints`).
    """
    dims = tuple(d for d in block.dims if d in ds.dims)
    if dims != tuple(block.dims):  # a block without its sweep dims (never stacked so): skip
        return []
    if isinstance(points, SweepPoints):
        distinct, index = _distinct(points)
    else:
        distinct, index = list(points), None
    return model_error.attach(ds, distinct, dims, index=index)


def _distinct(points: SweepPoints) -> tuple[list[Any], np.ndarray]:
    """The block's distinct resolved scenes (one per non-material combination, in C order)
    and the entry of each point (an int array of the block's shape).

    The material values (E, nu) do not enter the model error's features.
    """
    distinct = list(points.subs.values())
    own = [n if not m else 1 for n, m in zip(points.shape, points.material, strict=True)]
    index = np.arange(len(distinct)).reshape(own)
    return distinct, np.broadcast_to(index, points.shape)
