"""An offline link check of the built HTML, run at the end of every HTML build (no network).

Warns (so ``sphinx -W`` fails) on
- an internal link (``href`` without a scheme) to a file that the build did not write, or to an
  anchor (``#id``) that the target page does not define;
- the text "physics.md" anywhere in a page: the docs cite their own theory pages and the
  bibliography (``references.bib``), not a file users do not have.

Bibliography keys are checked by sphinxcontrib-bibtex itself (an unknown key is a warning).
Pages written by viewcode (``_modules/``) and sphinx-gallery downloads are checked like any other.
"""

from __future__ import annotations

from html.parser import HTMLParser
from pathlib import Path
from typing import Any
from urllib.parse import unquote, urlsplit

from sphinx.util import logging

logger = logging.getLogger(__name__)

FORBIDDEN = "physics.md"


class _Page(HTMLParser):
    """The ids and the internal hrefs of one HTML page."""

    def __init__(self) -> None:
        super().__init__(convert_charrefs=True)
        self.ids: set[str] = set()
        self.hrefs: list[str] = []

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        for name, value in attrs:
            if value is None:
                continue
            if name in ("id", "name"):
                self.ids.add(value)
            elif name in ("href", "src") and not urlsplit(value).scheme:
                if not value.startswith(("//", "mailto:", "javascript:")):
                    self.hrefs.append(value)


def _parse(path: Path, cache: dict[Path, _Page]) -> _Page:
    if path not in cache:
        page = _Page()
        page.feed(path.read_text(encoding="utf-8", errors="replace"))
        cache[path] = page
    return cache[path]


def check(outdir: Path) -> list[str]:
    """The problems of the HTML tree under ``outdir`` (one line each)."""
    problems: list[str] = []
    cache: dict[Path, _Page] = {}
    for html in sorted(outdir.rglob("*.html")):
        text = html.read_text(encoding="utf-8", errors="replace")
        rel = html.relative_to(outdir)
        if FORBIDDEN in text:
            line = text[: text.index(FORBIDDEN)].count("\n") + 1
            problems.append(f"{rel}:{line}: cites {FORBIDDEN!r} (cite the bibliography instead)")
        for href in _parse(html, cache).hrefs:
            parts = urlsplit(href)
            target = html if not parts.path else (html.parent / unquote(parts.path)).resolve()
            if target.is_dir():
                target = target / "index.html"
            if not target.exists():
                problems.append(f"{rel}: broken link {href!r} (no file {target.name})")
            elif parts.fragment and target.suffix == ".html" and rel.parts[0] != "_modules":
                # (viewcode's back-links from _modules/ point at the object's documented name,
                # which for a re-exported object, e.g. xpersson.sweep.plain_paths, is not the
                # anchor of its defining module: Sphinx's quirk, the page itself exists)
                if unquote(parts.fragment) not in _parse(target, cache).ids:  # noqa: SIM102
                    problems.append(f"{rel}: broken anchor {href!r}")
    return problems


def _finished(app: Any, exception: Exception | None) -> None:
    if exception is not None or app.builder.format != "html":
        return
    for problem in check(Path(app.outdir)):
        logger.warning(problem, type="offline_links")


def setup(app: Any) -> dict[str, Any]:
    app.connect("build-finished", _finished)
    return {"parallel_read_safe": True, "parallel_write_safe": True}


if __name__ == "__main__":  # python docs/_ext/offline_links.py BUILD_DIR
    import sys

    found = check(Path(sys.argv[1]))
    print("\n".join(found) or "no broken internal link, no physics.md")
    sys.exit(1 if found else 0)
