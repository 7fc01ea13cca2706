"""Parameter sweeps: expand a scene's lists and ranges into points, solve them, stack them.

Any parameter declared ``sweepable`` (material, spectrum, coefficient, boundary and analysis
parameters) accepts a list or a range table ``{start, stop, num, spacing}`` as ``load.p0`` does.
``load.p0`` stays the engine's own load dimension; every other swept parameter becomes a
Dataset dimension with its unit.

Combination (the scene's ``[sweep]`` table)::

    [sweep]
    mode = "product"                          # default: outer product of all swept parameters
    zip = [["material.E", "material.nu"]]     # zipped groups: one dimension per group

With ``mode = "zip"`` all swept parameters form one zipped group. Dimensions are ordered as the
parameters appear in the scene, or as ``order = ["spectrum.H", "material.E"]`` lists them
(archives record the order, so a re-solved sweep has the same dimension order).

Dimension naming rule:

1. the ``dim`` a plugin declares for the parameter (``ParamSpec(dim="v")``);
2. otherwise the parameter's own name (``material.E`` -> ``E``, ``spectrum.H`` -> ``H``);
3. if that name is already used by the Dataset (a coordinate, a core variable or an output of
   a selected plugin) or by another swept parameter, the dotted path with ``_``
   (``spectrum.h_rms`` -> ``spectrum_h_rms``). ``material.E`` and ``material.nu`` keep ``E`` and
   ``nu``: the core's variables of that name *are* the parameter and become its coordinate;
4. a name still taken is refused with an error naming both parameters.

A zipped group is one dimension named after its first parameter; the others are coordinates
along it. Each point is solved by the ordinary one-scene pipeline with one scalar value per
parameter (plugins never see a sweep), so the result equals stacking individual solves.
Where every plugin declares contact similarity (``fast_paths.contact_similarity``), the points
of a block that differ only in ``material.E`` / ``material.nu`` are solved as one batch of
equivalent loads (:mod:`.batched`): equal to the individual solves to rounding (1e-13
relative); where every plugin declares stacked parameters (``fast_paths.stacked_params``) and
the points differ only in those, a block is one stacked run (:mod:`.fast`). Inside
:func:`plain_paths` every point is solved on its own (the reference the fast paths are
checked against).

Modules: :mod:`.plan` (expand a scene into a :class:`SweepPlan`), :mod:`.blocks` (cut the grid
into blocks, solve and stack a block's points), :mod:`.batched` (material sweeps as batches),
:mod:`.execute` (resolve every point, schedule the blocks: serial, threads, dask), :mod:`.combine`
(one Dataset from the blocks), :mod:`.parts` (the folder format: one netCDF part per block plus
an index) and :mod:`.folder` (a run into a folder as a transaction: lock, identity, resume).
"""

from importlib import import_module
from typing import TYPE_CHECKING, Any

from ..plugins import plain_paths

if TYPE_CHECKING:  # imported on first access (below): a scene without a sweep needs only .plan
    from .blocks import POINT_STATUS, Block, BlockResult, blocks_of, run_block, stack
    from .execute import check_size, resolve_points, solve_sweep
    from .folder import LOCK, Transaction, study_hash
    from .parts import INDEX, finalize, open_parts
    from .plan import SweepParam, SweepPlan, cf_units, expand

__all__ = [
    "plain_paths",
    "SweepParam",
    "SweepPlan",
    "expand",
    "cf_units",
    "solve_sweep",
    "resolve_points",
    "check_size",
    "blocks_of",
    "Block",
    "BlockResult",
    "run_block",
    "stack",
    "finalize",
    "open_parts",
    "INDEX",
    "LOCK",
    "Transaction",
    "study_hash",
    "POINT_STATUS",
]

#: The submodule of each public name: imported when the name is first accessed, so that
#: ``xpersson validate`` and a solve without a sweep import neither xarray nor the folder code.
_WHERE = {
    **dict.fromkeys(("POINT_STATUS", "Block", "BlockResult", "blocks_of", "run_block"), "blocks"),
    "stack": "blocks",
    **dict.fromkeys(("check_size", "resolve_points", "solve_sweep"), "execute"),
    **dict.fromkeys(("LOCK", "Transaction", "study_hash"), "folder"),
    **dict.fromkeys(("INDEX", "finalize", "open_parts"), "parts"),
    **dict.fromkeys(("SweepParam", "SweepPlan", "cf_units", "expand"), "plan"),
}


def __getattr__(name: str) -> Any:
    if name in _WHERE:
        return getattr(import_module(f"{__name__}.{_WHERE[name]}"), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(__all__)
