"""Issue 37: the reader, the disk and the forger (the fast subset of ``benchmarks/faults.py``).

One section per class of failure; every test failed on the code before the issue.
"""

from __future__ import annotations

import sys
from pathlib import Path

import pytest
import xarray as xr

import xpersson
from xpersson.errors import ArchiveError
from xpersson.sweep import parts

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "sweep"))
from xpersson_sweep_testlib import scene  # noqa: E402


def _scene(e3: str = "20 MPa") -> dict:
    return scene(material={"E": ["5 MPa", "10 MPa", e3]}, output={"zeta_per_decade": 2})


@pytest.fixture(scope="module")
def study(tmp_path_factory):
    folder = tmp_path_factory.mktemp("snap") / "s"
    xpersson.solve(_scene(), output=folder, chunk=1)
    return folder, xpersson.open_dataset(folder).load()


# -- 1. snapshot reads ------------------------------------------------------------------------
@pytest.mark.parametrize("kept", [True, False])
def test_a_folder_overwritten_after_opening_is_never_read_as_the_other_study(
    study, tmp_path, monkeypatch, kept
):
    import shutil

    src, ref = study
    folder = tmp_path / "s"
    shutil.copytree(src, folder)
    if not kept:  # every part re-read (and re-verified) when loaded
        monkeypatch.setattr(parts, "SNAPSHOT_BYTES", -1)
    with xr.set_options(file_cache_maxsize=1):  # as with more parts than xarray keeps open
        ds = xpersson.open_dataset(folder)
        xpersson.solve(_scene("21 MPa"), output=folder, chunk=1, overwrite=True)
        if kept:
            assert ds.load().identical(ref)  # what was opened, not what is there now
        else:
            with pytest.raises(ArchiveError, match=r"part-0000\d\.nc: part changed after"):
                ds.load()
