"""What a sweep does when a declared fast path fails on a block.

The rule (issue 33): a fast path that raises, or gives variables unlike the plain path's,
does not end the sweep and is not hidden. The block is solved point by point, which isolates a
failing point and records it (``point_status``) as a sweep should. When that plain path then
solves every point of the block, the fast path failed where the plain one did not: a bug of
the plugin's declaration (:class:`xpersson.plugins.FastPaths`) or of the engine. The block
records it (:attr:`~xpersson.sweep.stacking.BlockResult.fast_path_failures`, kept in its part),
the sweep's Dataset carries every such record in the attribute ``xpersson_fast_path_failures``
and the sweep warns once (:class:`~xpersson.XperssonWarning`, from the calling thread after the
run) naming the plugins, the path and the exception.
"""

from __future__ import annotations

import json
import warnings
from collections.abc import Iterable
from typing import Any

from ..errors import XperssonWarning

__all__ = ["FastPathFailed", "declaring", "failed", "failure_attrs", "warn_failures"]

#: Global attribute of a sweep Dataset listing the fast paths that failed (JSON list of text).
FAILURES_ATTR = "xpersson_fast_path_failures"


class FastPathFailed(Exception):
    """A declared fast path failed on a block (raised to :func:`~.blocks.run_block`).

    Parameters
    ----------
    path : str
        The path: ``"stacked_params"`` or ``"contact_similarity"``.
    plugins : list of str
        The plugin classes of the block that declare it.
    reason : str
        What happened (the exception's type and text, or the variable that differs).
    """

    def __init__(self, path: str, plugins: list[str], reason: str) -> None:
        self.path, self.plugins, self.reason = path, plugins, reason
        super().__init__(
            f"fast path {path!r} declared by {', '.join(plugins) or 'the scene plugins'} "
            f"failed: {reason}"
        )


def declaring(rs: Any, path: str) -> list[str]:
    """The plugin classes of the resolved point ``rs`` that declare ``path``."""
    plugins = [rs.coefficient, rs.boundary, *(a for _, a in rs.analyses)]
    out = []
    for p in plugins:
        fp = type(p).fast_paths
        declared = fp.contact_similarity if path == "contact_similarity" else fp.stacked_params
        if declared is not None and declared is not False:
            out.append(f"{type(p).__module__}.{type(p).__qualname__}")
    return out


def failed(path: str, rs: Any, exc: BaseException) -> FastPathFailed:
    """The failure of ``path`` on a block whose first point is ``rs`` from an exception."""
    return FastPathFailed(path, declaring(rs, path), f"{type(exc).__name__}: {exc}")


def _all_failures(results: Iterable[Any]) -> list[str]:
    return [f"block {r.block.number}: {f}" for r in results for f in r.fast_path_failures]


def failure_attrs(results: Iterable[Any]) -> dict[str, str]:
    """The sweep Dataset's record of the failed fast paths (empty when none failed)."""
    found = _all_failures(results)
    return {FAILURES_ATTR: json.dumps(found)} if found else {}


def warn_failures(results: Iterable[Any], stacklevel: int = 3) -> None:
    """Warn once (from the calling thread) when a fast path failed on some block."""
    found = _all_failures(results)
    if found:
        warnings.warn(
            f"{len(found)} block(s) of this sweep were solved point by point because a declared "
            f"fast path failed where the plain path solved every point (a bug of the plugin's "
            f"FastPaths declaration or of xpersson; the results are the plain path's). "
            f"First: {found[0]}. All are listed in the attribute {FAILURES_ATTR!r}.",
            XperssonWarning,
            stacklevel=stacklevel,
        )
