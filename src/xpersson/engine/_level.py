"""What one grid level of the ``cn`` method is made of and gives: its nodes and system rows
(memoised per grid in :mod:`xpersson.cache`), its outputs, their combination over levels
(Richardson) and their projection onto admissible probabilities.  The march itself is in
:mod:`._moving`; the scheme is described in :mod:`._cn`.

Units: diffusion time ``tau`` in Pa^2, pressures ``p`` in Pa; the unknown ``R = W P`` (mass
per unit of the mapped coordinate ``x`` in [0, 1]) is dimensionless.
"""

from __future__ import annotations

import sys
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import NDArray

from ..cache import Cache
from ._cn_plan import Window, _faces
from ._grid import clustered

__all__ = [
    "Level",
    "LevelInputs",
    "LevelNodes",
    "Outputs",
    "SystemRows",
    "combine",
    "face_basis",
    "level_nodes",
    "system_rows",
    "weighted",
]

Array = NDArray[np.float64]


class LevelNodes(NamedTuple):
    """The nodes of a level on the unit interval (read-only arrays)."""

    x: Array
    """Nodes ``x_j``, ``j = 0 .. n`` in [0, 1], clustered at both ends (:func:`.clustered`)."""
    xf: Array
    """Face midpoints ``x_{j+1/2} = (x_j + x_{j+1}) / 2``, ``(n,)``."""
    dxf: Array
    """Node spacings ``x_{j+1} - x_j``, ``(n,)``."""
    w: Array
    """Control volumes (trapezoid weights; half cells at the ends), ``(n + 1,)``."""


class SystemRows(NamedTuple):
    """Rows of the system of ``loads`` loads concatenated (``loads x nodes`` rows, read-only)."""

    near: Array
    """The two rows at each wall of every load: first, second, second-to-last, last node
    (four groups of ``loads``)."""
    last: Array
    """The last row of every load (the upper wall)."""
    walls: Array
    """The identity rows: the first and last row of every load."""
    volumes: Array
    """The control volumes of every row, 0 on the identity rows."""


_NODES = Cache("engine.level_nodes", scope="process", maxsize=32, doc="nodes of a cn grid level")
_ROWS = Cache("engine.system_rows", scope="process", maxsize=32, doc="rows of a cn level system")
_BASIS = Cache("engine.face_basis", scope="process", maxsize=32, doc="face functions of a level")
_GRID = Cache(
    "engine.level_grid", scope="process", maxsize=32, doc="nodes, rows and face functions"
)


def level_nodes(n: int, stretch: float) -> LevelNodes:
    """The nodes of a level of ``n`` intervals clustered by ``stretch`` (see
    :class:`LevelNodes`); the levels of every solve reuse a few, hence the cache."""

    def compute() -> LevelNodes:
        x = clustered(n, stretch)
        return LevelNodes(x, *_faces(x))

    return _NODES.get((n, stretch), compute)


class LevelGrid(NamedTuple):
    """What a level of ``loads`` loads on ``n`` intervals marches on, from one look-up."""

    nodes: LevelNodes
    """:func:`level_nodes`."""
    rows: SystemRows
    """:func:`system_rows`."""
    basis: Array
    """:func:`face_basis`."""
    xw: Array
    """``nodes.x * nodes.w``: the weights of the load's moment ``int x R dx`` (read-only)."""


class LevelInputs(NamedTuple):
    """What one grid level marches on (also what the tests' reference solver is given)."""

    taus: Array
    """Times ``tau_0 .. tau_M`` [Pa^2] of the ``M`` steps."""
    theta: Array
    """Implicitness per step, ``(M,)``: 1/2 (Crank-Nicolson) or 1 (implicit Euler)."""
    out_at: Array
    """For every numerical output, the number of steps after which it is taken."""
    nodes: LevelNodes
    """The nodes on [0, 1]."""
    window: Window
    """The window's edges per load and step."""
    p0: Array
    """Loads ``(loads, 1)`` [Pa]."""
    k: float
    """Half-width of the window in units of ``sqrt(2 tau)`` (the start's window mass is
    ``erf(k / sqrt 2)``)."""
    yield_wall: bool
    """Whether the upper wall is a (moving) yield wall: its closure rows replace the
    absorbing wall."""
    image: float | None = None
    """The resting absorbing lower wall [Pa] of a one-wall start (the start state is the
    image solution), or None (the free Gaussian)."""
    grid: LevelGrid | None = None
    """The level's nodes, rows and face functions (:func:`._level.level_grid`), or None
    (looked up where needed)."""


def level_grid(loads: int, n: int, stretch: float) -> LevelGrid:
    """:func:`level_nodes`, :func:`system_rows` and :func:`face_basis` of a level in one
    cache look-up (a look-up costs ~3 us: three of them were ~10 % of a small level's
    set-up on the compiled path)."""
    return _GRID.get(
        f"{loads} {n} {stretch!r}",  # (a string key: ~0.5 us less than a tuple's content key)
        lambda: _level_grid(loads, n, stretch),
    )


def _level_grid(loads: int, n: int, stretch: float) -> LevelGrid:
    """:func:`level_grid` computed (the moment's weights ``x w`` once per grid, not per level:
    the same products)."""
    nodes = level_nodes(n, stretch)
    rows, basis = system_rows(loads, n, stretch), face_basis(n, stretch)
    return LevelGrid(nodes, rows, basis, nodes.x * nodes.w)


def system_rows(loads: int, n: int, stretch: float) -> SystemRows:
    """The rows of ``loads`` systems on the nodes of :func:`level_nodes` (see
    :class:`SystemRows`).  The wall fluxes use both rows at each wall: the solve leaves
    round-off ~ eps on the wall rows, which the fluxes must include for the probability
    balance to hold to round-off."""

    def compute() -> SystemRows:
        w = level_nodes(n, stretch).w
        nn = w.size
        first = np.arange(loads) * nn  # first row of each load in the concatenated system
        near = np.concatenate([first, first + 1, first + nn - 2, first + nn - 1])
        last = first + nn - 1
        walls = np.concatenate([first, last])
        volumes = np.tile(w, loads)
        volumes[walls] = 0.0
        return SystemRows(near, last, walls, volumes)

    return _ROWS.get((loads, n, stretch), compute)


def face_basis(n: int, stretch: float) -> Array:
    """The face functions ``1, x_f, 1/dx_f`` (3, nodes) of :func:`level_nodes` (the last
    slot, where there is no face, is 0): every face coefficient of the scheme is a
    combination of them."""

    def compute() -> Array:
        nodes = level_nodes(n, stretch)
        nf = nodes.xf.size
        basis = np.zeros((3, nf + 1))
        basis[0, :nf] = 1.0
        basis[1, :nf] = nodes.xf
        basis[2, :nf] = 1.0 / nodes.dxf
        return basis

    return _BASIS.get((n, stretch), compute)


class Outputs(NamedTuple):
    """Per-load outputs of a level (or of a combination of levels) at the numerical output
    times: arrays ``(loads, outputs)`` (``P``: ``(loads, outputs, len(p_out))``); immutable
    (a named tuple: ~0.3 us to make, a frozen dataclass ~1.5 us)."""

    area: Array
    """``int R dx``: the probability still in the window [1]."""
    absorbed_lower: Array
    """Probability absorbed by the real lower wall [1]."""
    absorbed_upper: Array
    """Probability absorbed by the real upper wall, or the plastic area ``A_pl`` [1]."""
    load: Array
    """``int p R dx`` [Pa]."""
    moment_lower: Array
    """``int p_l d(absorbed_lower)``, the lower wall's term of the load identity [Pa]."""
    moment_upper: Array
    """The upper wall's term of the load identity [Pa]."""
    P: Array | None
    """Density at ``p_out`` [1/Pa], or None."""


_FIELDS = Outputs._fields
_SCALARS = 6  # the fields (loads, outputs) before the densities P


class Level(NamedTuple):
    """What the march of one grid level gives (:func:`._moving._march`)."""

    outputs: Outputs | None
    """The outputs; None when the level failed."""
    nsteps: int
    """Time steps marched."""
    n_nodes: int
    """Nodes per load."""
    failure: str = ""
    """Why the level failed (the walls swept the window; a singular system), or ``""``."""

    @property
    def ok(self) -> bool:
        """Whether the level completed (its outputs are usable)."""
        return not self.failure


def _kernel(name: str) -> Any:
    """The compiled kernels ``name`` of :mod:`._compiled` (``fields``), or None
    (the option is off, or the process has not loaded the compiled march: it is looked up,
    not imported, so that this module stays below it)."""
    compiled = sys.modules.get(f"{__package__}._compiled")
    return None if compiled is None else compiled.built(name)


def combine(fine: Outputs, coarse: Outputs, extrapolate: bool) -> Outputs:
    """The finer level, or its Richardson combination with the coarser (linear in the levels:
    the probability balance is kept)."""
    if not extrapolate:
        return fine  # (immutable: the same outputs)
    fast = _kernel("fields") if fine.P is None and fine.area.ndim == 2 else None
    if fast is not None:  # (one compiled pass, the same operations)
        out = np.empty((_SCALARS, *fine.area.shape))
        if fast[0](*fine[:_SCALARS], *coarse[:_SCALARS], out):
            return Outputs(*out, None)
    # the six (loads, outputs) fields at once, ``a + (a - b) / 3`` element by element
    a = np.array(fine[:_SCALARS])
    d = np.subtract(a, np.array(coarse[:_SCALARS]))
    d /= 3.0
    np.add(a, d, out=d)
    P = None if fine.P is None else fine.P + (fine.P - coarse.P) / 3.0
    return Outputs(*d, P)


def weighted(levels: list[Outputs], weights: Array) -> Outputs:
    """The combination ``sum_i weights[i] levels[i]`` of every output (weights summing to 1,
    e.g. Richardson's: the probability balance, linear in the levels, is kept)."""
    one = levels[0]
    fast = _kernel("fields") if len(levels) == 3 and one.P is None and one.area.ndim == 2 else None
    if fast is not None:  # (one compiled pass, the same operations)
        out = np.empty((_SCALARS, *levels[0].area.shape))
        w3 = np.asarray(weights, dtype=float)
        if w3.shape == (3,) and fast[1](w3, *levels[0][:_SCALARS], *levels[1][:_SCALARS],
                                        *levels[2][:_SCALARS], out):  # fmt: skip
            return Outputs(*out, None)
    ws = [float(c) for c in weights]
    # the six (loads, outputs) fields at once, then the densities (the same operations,
    # element by element, as ``sum`` of each field: 0 + w_0 v_0 + w_1 v_1 + ...)
    out = [_weighted(np.array([lv[:_SCALARS] for lv in levels]), ws)]
    if levels[0].P is not None:
        out.append(_weighted(np.array([lv.P for lv in levels]), ws))
    return Outputs(*out[0], out[1] if len(out) > 1 else None)


def _weighted(v: Array, ws: list[float]) -> Array:
    """``0 + w_0 v[0] + w_1 v[1] + ...`` (``v`` this function's own copy: scaled in place)."""
    acc = v[0] * ws[0]  # (0 + w_0 v_0: the sum's first term, -0 made +0 by adding 0)
    acc += 0.0
    for c, row in zip(ws[1:], v[1:], strict=True):
        row *= c
        acc += row
    return acc
