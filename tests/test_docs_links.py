"""The docs build's offline link check (docs/_ext/offline_links.py, issue 38): a broken internal
link, a missing anchor and a "physics.md" citation are each reported; good links are not."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def links():
    pytest.importorskip("sphinx")
    spec = importlib.util.spec_from_file_location(
        "offline_links", ROOT / "docs" / "_ext" / "offline_links.py"
    )
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_broken_links_anchors_and_physics_md_are_reported(tmp_path, links):
    (tmp_path / "sub").mkdir()
    (tmp_path / "index.html").write_text(
        '<a href="sub/page.html#here">ok</a> <a href="sub/page.html#gone">x</a>'
        '<a href="missing.html">y</a> <a href="https://example.org/x">external</a>'
        '<a href="#top" id="top">self</a>'
    )
    (tmp_path / "sub" / "page.html").write_text('<h1 id="here">see physics.md §1.2</h1>')
    found = links.check(tmp_path)
    assert found == [
        "index.html: broken anchor 'sub/page.html#gone'",
        "index.html: broken link 'missing.html' (no file missing.html)",
        "sub/page.html:1: cites 'physics.md' (cite the bibliography instead)",
    ]
