"""``pipeline.direct_dataset`` (issue 36): the Dataset ``xr.Dataset`` builds from aligned
variables, without its merge."""

from __future__ import annotations

import numpy as np
import xarray as xr

from xpersson.pipeline import direct_dataset


def test_direct_dataset_is_the_dataset_xarray_builds():
    rng = np.random.default_rng(1)
    data = {
        "a": xr.Variable(("H", "zeta"), rng.random((3, 4)), {"units": "1"}),
        "b": xr.Variable(("H",), rng.random(3), {"units": "Pa"}),
    }
    coords = {
        "zeta": xr.Variable(("zeta",), np.geomspace(1, 10, 4), {"units": "1"}),
        "H": xr.Variable(("H",), [0.3, 0.5, 0.7]),
        "q": xr.Variable(("zeta",), np.geomspace(1e3, 1e4, 4), {"units": "m^-1"}),
        "p0": xr.Variable((), 1e5, {"units": "Pa"}),
    }
    got = direct_dataset(data, coords, {"title": "t"})
    want = xr.Dataset(data, coords=coords, attrs={"title": "t"})
    assert got is not None
    assert got.identical(want)
    assert list(got.variables) == list(want.variables)
    assert list(got.xindexes) == list(want.xindexes) == ["zeta", "H"]
    assert dict(got.sizes) == dict(want.sizes)
