"""Sweep folders as transactions (issue 24): identity, lock, resume, verification on open.

The fast subset of ``benchmarks/faults.py``: a resumed study equals an uninterrupted one bit for
bit (after a removed part, a damaged part and a SIGKILL mid-run); of two runs into one folder
exactly one proceeds; a different study is refused; hostile indexes and foreign parts are
refused with an error naming the index or the part.
"""

from __future__ import annotations

import json
import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

import pytest

import xpersson
from xpersson.archive import file_digest
from xpersson.cli import main
from xpersson.errors import ArchiveError, FolderBusyError
from xpersson.sweep import INDEX, LOCK, Transaction, expand
from xpersson.sweep.parts import seal_index

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "sweep"))
from xpersson_sweep_testlib import scene  # noqa: E402

E = ["5 MPa", "10 MPa", "20 MPa"]


def _scene(e: list[str] = E) -> dict:
    return scene(material={"E": list(e)}, output={"zeta_per_decade": 2})


TIMES = ("date_created", "history")
"""Attributes that record when a run happened (they differ between any two runs)."""


def _same(a: Any, b: Any) -> None:
    """Bit-for-bit equal data, coordinates and attributes but the solver's wall time."""
    a, b = a.load(), b.load().copy()
    sa, sb = json.loads(a.attrs["xpersson_solver"]), json.loads(b.attrs["xpersson_solver"])
    sa["work"].pop("wall_time_s"), sb["work"].pop("wall_time_s")
    assert sa == sb
    b.attrs["xpersson_solver"] = a.attrs["xpersson_solver"]
    for key in TIMES:
        assert key in b.attrs
        b.attrs[key] = a.attrs[key]
    assert a.identical(b), [k for k in a.attrs if a.attrs[k] != b.attrs.get(k)]


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    folder = tmp_path_factory.mktemp("ref") / "sweep"
    return xpersson.solve(_scene(), output=folder, chunk=1).load(), folder


def test_resume_recomputes_missing_and_damaged_parts_only(reference, tmp_path):
    ref, ref_folder = reference
    folder = tmp_path / "s"
    shutil.copytree(ref_folder, folder)
    (folder / "part-00001.nc").unlink()
    with pytest.raises(ArchiveError, match="part-00001.nc: part missing"):
        xpersson.open_dataset(folder)
    damaged = folder / "part-00002.nc"
    data = bytearray(damaged.read_bytes())
    # overwrite the last 4 KiB (variable data and metadata): zeroing the middle of the file hit
    # HDF5 free space once a variable was added (already zeros: no damage at all)
    data[-4096:] = b"\xa5" * 4096
    damaged.write_bytes(data)
    kept = (folder / "part-00000.nc").stat().st_mtime_ns
    shutil.copy(ref_folder / "part-00001.nc", folder / "part-00001.nc")
    with pytest.raises(ArchiveError, match="part-00002.nc"):
        xpersson.open_dataset(folder)
    (folder / "part-00001.nc").unlink()
    with pytest.raises(ArchiveError, match="part-00001.nc"):
        xpersson.open_dataset(folder)
    with pytest.warns(xpersson.XperssonWarning, match=r"1 damaged part.*part-00002.nc"):
        resumed = xpersson.solve(_scene(), output=folder, chunk=1)
    _same(resumed, ref)
    assert (folder / "part-00000.nc").stat().st_mtime_ns == kept  # reused, not rewritten
    _same(xpersson.open_dataset(folder), ref)


@pytest.mark.parametrize("where", [0.25, 0.5, 0.75])
def test_resume_never_reuses_a_part_whose_bytes_changed(reference, tmp_path, where):
    """Any changed byte (data, attributes or HDF5 free space) sends the part to be solved again.

    Per-variable fletcher32 does not cover attributes or free space; the digest the complete
    index recorded does, and a resume checks it before reusing a part (and keeps it across
    a resume that is itself interrupted).
    """
    ref, ref_folder = reference
    folder = tmp_path / "s"
    shutil.copytree(ref_folder, folder)
    part = folder / "part-00001.nc"
    data = bytearray(part.read_bytes())
    k = int(where * len(data))
    data[k] ^= 0x01
    part.write_bytes(data)
    before = json.loads((folder / INDEX).read_text())
    with pytest.warns(xpersson.XperssonWarning, match=r"1 damaged part.*part-00001.nc"):
        resumed = xpersson.solve(_scene(), output=folder, chunk=1)
    _same(resumed, ref)
    after = {e["number"]: e["sha256"] for e in json.loads((folder / INDEX).read_text())["parts"]}
    kept = {e["number"]: e["sha256"] for e in before["parts"] if e["number"] != 1}
    assert {n: d for n, d in after.items() if n != 1} == kept  # the others reused
    assert file_digest(part) == after[1]  # solved again, not the flipped file re-sealed
    _same(xpersson.open_dataset(folder), ref)


def test_resume_after_sigkill_equals_an_uninterrupted_run(reference, tmp_path):
    ref, _ = reference
    folder = tmp_path / "killed"
    code = (
        "import sys, json, xpersson\n"
        f"sys.path.insert(0, {str(Path(__file__).resolve().parents[1] / 'sweep')!r})\n"
        "import time\n"
        "from xpersson.sweep import blocks\n"
        "run = blocks.run\n"
        "def slow(*a, **k):\n    time.sleep(0.4)\n    return run(*a, **k)\n"
        "blocks.run = slow\n"
        f"xpersson.solve(json.loads({json.dumps(json.dumps(_scene()))}), output={str(folder)!r},"
        " chunk=1)\n"
    )
    proc = subprocess.Popen([sys.executable, "-c", code])
    deadline = time.monotonic() + 120
    while not (folder / "part-00000.nc").exists() and time.monotonic() < deadline:
        time.sleep(0.02)
    os.kill(proc.pid, signal.SIGKILL)
    proc.wait()
    assert not (folder / "part-00002.nc").exists()
    with pytest.raises(ArchiveError, match="incomplete"):
        xpersson.open_dataset(folder)
    _same(xpersson.solve(_scene(), output=folder, chunk=1), ref)


def test_exactly_one_of_two_runs_proceeds(tmp_path, capsys):
    folder = tmp_path / "busy"
    plan = expand(xpersson.Scene(_scene()))
    txn = Transaction.begin(folder, plan, {"points_per_block": 1, "multiple": 1})
    try:
        with pytest.raises(FolderBusyError, match="another run"):
            xpersson.solve(_scene(), output=folder)
        scene_file = tmp_path / "s.toml"
        scene_file.write_text(_toml(_scene()), encoding="utf-8")
        assert main(["run", str(scene_file), "-o", f"{folder}/"]) == 2
        assert "another run is writing" in capsys.readouterr().err
    finally:
        txn.release()
    assert xpersson.solve(_scene(), output=folder).attrs["status"] == "success"
    assert (folder / LOCK).exists()


def _toml(data: dict) -> str:
    lines = []
    for section, table in data.items():
        lines.append(f"[{section}]")
        lines += [f"{k} = {json.dumps(v)}" for k, v in table.items()]
    return "\n".join(lines) + "\n"


def test_a_different_study_is_refused_unless_overwrite(reference, tmp_path, capsys):
    ref, ref_folder = reference
    folder = tmp_path / "other"
    shutil.copytree(ref_folder, folder)
    other = _scene(["5 MPa", "11 MPa", "20 MPa"])
    with pytest.raises(ArchiveError, match="different study"):
        xpersson.solve(other, output=folder)
    _same(xpersson.open_dataset(folder), ref)  # untouched
    with pytest.raises(ArchiveError, match="holds this study already"):
        xpersson.solve(_scene(), output=folder, resume=False)
    ds = xpersson.solve(other, output=folder, overwrite=True)
    assert ds["E"].values.tolist() == [5e6, 11e6, 20e6]
    with pytest.raises(ArchiveError, match="nothing to resume"):
        xpersson.solve(_scene(), output=tmp_path / "empty", resume=True)
    (tmp_path / "foreign").mkdir()
    (tmp_path / "foreign" / "notes.txt").write_text("mine", encoding="utf-8")
    with pytest.raises(ArchiveError, match="not empty"):
        xpersson.solve(_scene(), output=tmp_path / "foreign")
    assert (tmp_path / "foreign" / "notes.txt").read_text(encoding="utf-8") == "mine"


def _edit_index(folder: Path, edit, reseal: bool = True) -> None:
    """Edit the index; ``reseal`` recomputes its checksum (a crafted index, not a damaged one)."""
    index = json.loads((folder / INDEX).read_text(encoding="utf-8"))
    edit(index)
    if reseal:
        index = seal_index(index)
    (folder / INDEX).write_text(json.dumps(index), encoding="utf-8")


HOSTILE = {
    "traversal": (lambda ix: ix["parts"][0].update(name="../../../etc/passwd"), "not allowed"),
    "absolute": (lambda ix: ix["parts"][0].update(name="/etc/passwd"), "not allowed"),
    "huge grid": (lambda ix: ix["parts"][0].update(grid_index=[10**12]), "tile"),
    "huge shape": (lambda ix: ix.update(shape=[10**15]), "malformed"),
    "swapped parts": (
        lambda ix: (
            ix["parts"][0].update(name="part-00001.nc"),
            ix["parts"][1].update(name="part-00000.nc"),
        ),
        "part-0000[01].nc",
    ),
    "not json": (None, "not a readable sweep index"),
    "foreign format": (lambda ix: ix.update(format="other"), "format"),
    "interrupted": (lambda ix: ix.update(state="running"), "incomplete"),
    "scene changed": (lambda ix: ix["attrs"].update(xpersson_scene="{}"), "scene"),
    "coordinate changed": (lambda ix: ix["coords"]["E"][1].__setitem__(0, 6e6), "'E'"),
    "run changed": (lambda ix: ix["parts"][0].update(run="0" * 32), "part-00000.nc"),
    "constant malformed": (lambda ix: ix["constant"].update(area_fraction=7), "constant"),
    "attrs malformed": (lambda ix: ix.update(attrs=1.5), "attrs"),
}


@pytest.mark.parametrize("case", ["attrs", "constant", "status"])
def test_an_edited_index_fails_its_checksum(reference, tmp_path, case):
    _, ref_folder = reference
    folder = tmp_path / "e"
    shutil.copytree(ref_folder, folder)
    edits = {
        "attrs": lambda ix: ix["attrs"].update(title="changed"),
        "constant": lambda ix: ix["constant"].clear(),
        "status": lambda ix: ix["attrs"].update(status="failed"),
    }
    _edit_index(folder, edits[case], reseal=False)
    with pytest.raises(ArchiveError, match="index fails its checksum"):
        xpersson.open_dataset(folder)


@pytest.mark.parametrize("case", list(HOSTILE))
def test_hostile_indexes_are_refused_naming_what(reference, tmp_path, case):
    _, ref_folder = reference
    folder = tmp_path / "h"
    shutil.copytree(ref_folder, folder)
    edit, match = HOSTILE[case]
    if edit is None:
        (folder / INDEX).write_text("{not json", encoding="utf-8")
    else:
        _edit_index(folder, edit)
    with pytest.raises(ArchiveError, match=match):
        xpersson.open_dataset(folder)


def test_a_part_of_another_study_is_refused(reference, tmp_path):
    _, ref_folder = reference
    other = tmp_path / "o"
    xpersson.solve(_scene(["5 MPa", "11 MPa", "20 MPa"]), output=other, chunk=1)
    folder = tmp_path / "mix"
    shutil.copytree(ref_folder, folder)
    shutil.copy(other / "part-00001.nc", folder / "part-00001.nc")
    with pytest.raises(ArchiveError, match="part-00001.nc"):
        xpersson.open_dataset(folder)
    # with the checksum in the index matched too, the part's identity still gives it away
    digest = file_digest(folder / "part-00001.nc")
    _edit_index(folder, lambda ix: ix["parts"][1].update(sha256=digest))
    with pytest.raises(ArchiveError, match="part-00001.nc: part does not belong"):
        xpersson.open_dataset(folder)
