"""ACDD discovery attributes from the scene's ``[metadata]`` table (issue 26): stored as global
attributes, overriding xpersson's defaults, read back by the IOOS compliance-checker."""

from __future__ import annotations

import tomllib
import warnings
from pathlib import Path

import pytest

import xpersson

ROOT = Path(__file__).resolve().parents[1]
META = {
    "creator_name": "A. Engineer",
    "creator_email": "a.engineer@example.org",
    "institution": "Seal lab",
    "project": "gasket study",
    "keywords": "gasket, rubber, leakage",
    "license": "CC-BY-4.0",
}


def _scene(**extra):
    with open(ROOT / "examples" / "elastic.toml", "rb") as fh:
        scene = tomllib.load(fh)
    scene.update(extra)
    return scene


def _solve(scene):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", xpersson.XperssonWarning)
        return xpersson.solve(scene)


def test_metadata_become_global_attributes_and_survive_the_archive(tmp_path):
    ds = _solve(_scene(metadata=META))
    for key, value in META.items():
        assert ds.attrs[key] == value
    path = xpersson.to_netcdf(ds, tmp_path / "m.nc")
    back = xpersson.open_dataset(path)
    assert {k: back.attrs[k] for k in META} == META
    # without the table the defaults stay and nothing of the user's is invented
    plain = _solve(_scene())
    assert "creator_name" not in plain.attrs and plain.attrs["keywords"].startswith("contact")


def test_a_sweep_keeps_the_metadata():
    scene = _scene(metadata=META)
    scene["material"]["E"] = ["5 MPa", "10 MPa"]
    assert _solve(scene).attrs["institution"] == "Seal lab"


@pytest.mark.parametrize(
    ("meta", "match"),
    [
        ({"colour": "red"}, r"metadata\.colour: unknown key; allowed \(ACDD-1\.3\)"),
        ({"creator_name": 3}, r"metadata\.creator_name: must be a string"),
        ("creator", r"metadata: must be a table"),
    ],
)
def test_bad_metadata_is_refused_before_work(meta, match):
    with pytest.raises(xpersson.SceneError, match=match):
        _solve(_scene(metadata=meta))


def test_the_checker_sees_the_creator_and_institution(tmp_path):
    runner = pytest.importorskip("compliance_checker.runner")
    path = xpersson.to_netcdf(_solve(_scene(metadata=META)), tmp_path / "m.nc")
    suite = runner.CheckSuite()
    suite.load_all_available_checkers()
    groups = suite.run_all(suite.load_dataset(str(path)), ["acdd:1.3"], skip_checks=[])
    messages = {m for results, _ in groups.values() for r in results for m in r.msgs}
    assert "creator_name not present" in {
        m for results, _ in suite.run_all(
            suite.load_dataset(str(xpersson.to_netcdf(_solve(_scene()), tmp_path / "p.nc"))),
            ["acdd:1.3"], skip_checks=[],
        ).values() for r in results for m in r.msgs
    }  # fmt: skip
    for key in ("creator_name", "institution", "project", "license"):
        assert f"{key} not present" not in messages
