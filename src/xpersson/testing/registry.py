"""Registry injection: make plugin classes available by name without installing them."""

from __future__ import annotations

import contextlib
from collections.abc import Iterator, Mapping

from ..plugins import Registry, normalize_group, using_registry

__all__ = ["registry_with"]


@contextlib.contextmanager
def registry_with(autoload: bool | None = None, **groups: Mapping[str, type]) -> Iterator[Registry]:
    """Make plugins available by name without installing them.

    Builds a :class:`~xpersson.plugins.Registry` with ``extra=groups`` (installed entry points
    stay visible unless ``autoload=False``) and installs it as the default registry for the
    duration of the ``with`` block (also usable as a decorator).

    Parameters
    ----------
    autoload : bool, optional
        Passed to :class:`~xpersson.plugins.Registry` (``False``: built-ins only).
    **groups
        ``spectra=``, ``coefficients=``, ``boundaries=``, ``analyses=`` (singular forms are
        accepted): mappings name -> plugin class.

    Examples
    --------
    >>> with registry_with(boundaries={"mywall": MyWall}) as reg:  # doctest: +SKIP
    ...     ds = xpersson.solve(scene_using_mywall)
    """
    extra = {normalize_group(g): dict(v) for g, v in groups.items()}
    with using_registry(Registry(autoload=autoload, extra=extra)) as reg:
        yield reg
