"""The user's metadata file (issue 38): ACDD attributes from ``XPERSSON_METADATA`` (or
``~/.config/xpersson/metadata.toml``) under the scene's ``[metadata]``; the archive names its
scene file by its name only; CF standard names only from the CF table."""

from __future__ import annotations

import tomllib
import warnings
from pathlib import Path

import pytest

import xpersson
from xpersson import provenance
from xpersson.schema import CORE_VARIABLES, STANDARD_NAME_VOCABULARY

ROOT = Path(__file__).resolve().parents[1]


def _solve(scene):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", xpersson.XperssonWarning)
        return xpersson.solve(scene)


def _scene(**extra):
    with open(ROOT / "examples" / "elastic.toml", "rb") as fh:
        scene = tomllib.load(fh)
    scene["output"] = {"zeta_per_decade": 2}
    scene.update(extra)
    return scene


def test_the_users_file_sets_attributes_and_the_scene_wins(tmp_path, monkeypatch):
    path = tmp_path / "metadata.toml"
    path.write_text('creator_name = "A. User"\ninstitution = "Lab"\nlicense = "CC0-1.0"\n')
    monkeypatch.setenv("XPERSSON_METADATA", str(path))
    ds = _solve(_scene(metadata={"institution": "Scene lab"}))
    assert ds.attrs["creator_name"] == "A. User" and ds.attrs["license"] == "CC0-1.0"
    assert ds.attrs["institution"] == "Scene lab"  # the scene's [metadata] wins
    path.write_text('[metadata]\ncreator_name = "B. User"\n')  # read again when it changes
    assert provenance.user_metadata() == {"creator_name": "B. User"}


def test_the_default_file_lives_in_the_xdg_config_home(tmp_path, monkeypatch):
    monkeypatch.delenv("XPERSSON_METADATA", raising=False)
    monkeypatch.setenv("XDG_CONFIG_HOME", str(tmp_path))
    assert provenance.user_metadata() == {}
    (tmp_path / "xpersson").mkdir()
    (tmp_path / "xpersson" / "metadata.toml").write_text('project = "P"\n')
    assert provenance.user_metadata_path() == tmp_path / "xpersson" / "metadata.toml"
    assert provenance.user_metadata() == {"project": "P"}
    monkeypatch.setenv("XPERSSON_METADATA", "")  # empty: no file at all
    assert provenance.user_metadata() == {}


@pytest.mark.parametrize(
    ("text", "match"),
    [
        ('colour = "red"\n', r"colour: unknown key; allowed \(ACDD-1\.3\)"),
        ("creator_name = 3\n", r"creator_name: must be a string, got int"),
        ("creator_name = \n", r"metadata file .*metadata\.toml"),
    ],
)
def test_a_bad_users_file_is_one_error_naming_it(tmp_path, monkeypatch, text, match):
    path = tmp_path / "metadata.toml"
    path.write_text(text)
    monkeypatch.setenv("XPERSSON_METADATA", str(path))
    with pytest.raises(xpersson.SceneError, match=match):
        provenance.user_metadata()
    monkeypatch.setenv("XPERSSON_METADATA", str(tmp_path / "missing.toml"))
    with pytest.raises(xpersson.SceneError, match="XPERSSON_METADATA: .*missing.toml does not"):
        provenance.user_metadata()


def test_the_archive_stores_the_scene_files_name_not_its_path(monkeypatch):
    monkeypatch.setenv("XPERSSON_METADATA", "")
    ds = _solve(ROOT / "examples" / "elastic.toml")
    assert ds.attrs["xpersson_scene_source"] == "elastic.toml"
    assert str(ROOT) not in "".join(str(v) for v in ds.attrs.values())
    assert ds.attrs["standard_name_vocabulary"] == STANDARD_NAME_VOCABULARY


def test_standard_names_come_from_the_cf_table():
    table = pytest.importorskip("compliance_checker.cf.util").StandardNameTable()
    names = {s.standard_name for s in CORE_VARIABLES.values() if s.standard_name}
    assert names == {"area_fraction", "status_flag"}
    assert all(n in table for n in names)


def test_cf_xarray_finds_the_standard_names_of_an_archive(tmp_path, monkeypatch):
    cf_xarray = pytest.importorskip("cf_xarray")  # noqa: F841 - registers ds.cf
    monkeypatch.setenv("XPERSSON_METADATA", "")
    path = xpersson.to_netcdf(_solve(_scene()), tmp_path / "e.nc")
    import xarray as xr

    with xr.open_dataset(path) as ds:
        assert ds.cf.standard_names == {
            "area_fraction": ["area_fraction"],
            "status_flag": ["solver_status"],
        }


def test_the_default_path_is_made_once_per_home_and_follows_the_environment(tmp_path, monkeypatch):
    from pathlib import Path

    calls = []
    home = Path.home
    monkeypatch.setattr(Path, "home", classmethod(lambda cls: calls.append(1) or home()))
    monkeypatch.delenv("XPERSSON_METADATA", raising=False)
    monkeypatch.delenv("XDG_CONFIG_HOME", raising=False)
    for name in ("a", "b"):  # a new $HOME: its ~/.config, found at once
        (tmp_path / name / ".config" / "xpersson").mkdir(parents=True)
        (tmp_path / name / ".config" / "xpersson" / "metadata.toml").write_text(
            f'project = "{name}"\n'
        )
        monkeypatch.setenv("HOME", str(tmp_path / name))
        with xpersson.set_options(cache=True):  # also in CI's run with XPERSSON_CACHE=off
            for _ in range(3):
                assert provenance.user_metadata() == {"project": name}
    assert len(calls) <= 2  # once per $HOME, not once per solve
    named = tmp_path / "named.toml"
    named.write_text('project = "named"\n')
    monkeypatch.setenv("XPERSSON_METADATA", str(named))  # set after the calls: honoured
    assert provenance.user_metadata() == {"project": "named"}
    monkeypatch.delenv("XPERSSON_METADATA")
    assert provenance.user_metadata() == {"project": "b"}
