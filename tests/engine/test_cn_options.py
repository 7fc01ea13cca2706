"""The default ``cn`` options (:meth:`xpersson.engine._cn.CNOptions.read`, made once per
``atol``) are those of their fields."""

from __future__ import annotations

import pytest

from xpersson.engine._cn import _DEFAULTS, AIM, CNOptions
from xpersson.engine._problem import window_k


@pytest.mark.parametrize("atol", [1e-12, 1e-7, 3e-3])
def test_default_options_are_their_fields(atol):
    """The options of no options are the defaults with the window of ``atol``."""
    opts = CNOptions.read({}, atol)
    assert opts == CNOptions(**_DEFAULTS, window_k=window_k(atol), aim=AIM)
    assert CNOptions.read({"nodes": _DEFAULTS["nodes"]}, atol) == opts
