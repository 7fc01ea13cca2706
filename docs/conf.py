"""Sphinx configuration of the xpersson documentation (build: see docs/README.md)."""

from __future__ import annotations

import os
import sys
import warnings
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(ROOT / "src"))
sys.path.insert(0, str(HERE / "_ext"))
os.environ.setdefault("MPLBACKEND", "Agg")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

project = "xpersson"
author = "xpersson developers"
copyright = "xpersson developers, BSD-3-Clause"
try:
    from xpersson.provenance import version as _version

    release = _version()
except Exception:  # pragma: no cover - the docs build needs the package installed
    release = "0.1.0"
version = release

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "sphinx-mathjax-offline",  # MathJax 3 copied into _static: equations render offline, no CDN
    "sphinxcontrib.bibtex",
    "sphinx.ext.viewcode",
    "numpydoc",
    "myst_parser",
    "sphinx_gallery.gen_gallery",
    "matplotlib.sphinxext.plot_directive",
    "offline_links",  # docs/_ext: internal links and anchors of the built HTML, no physics.md
]

source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
exclude_patterns = [
    "_build",
    "_ext",
    "README.md",
    "examples/*",
    "auto_examples/*.ipynb",
    "auto_examples/*.py",
    "auto_examples/*.zip",
    "sg_execution_times.rst",
]
root_doc = "index"

# -- autodoc / numpydoc ---------------------------------------------------------------------------
autosummary_generate = True
autodoc_typehints = "none"  # numpydoc docstrings state types and units themselves
autodoc_member_order = "bysource"
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False
numpydoc_validation_checks: set[str] = set()
# numpydoc reports malformed docstrings as Python warnings, which sphinx -W does not see
warnings.filterwarnings("error", module="numpydoc")

# -- bibliography (docs/references.bib, cited with :cite:p:`key`) ---------------------------------
bibtex_bibfiles = ["references.bib"]
bibtex_default_style = "unsrt"
bibtex_reference_style = "author_year"

# -- MyST ------------------------------------------------------------------------------------------
myst_enable_extensions = ["dollarmath", "colon_fence"]
myst_heading_anchors = 3
# the Markdown pages shared with the repository (writing_a_plugin.md, contracts.md) link to
# repository files (examples/, plugins/) that are not documents of this site
suppress_warnings = ["myst.xref_missing"]

# -- figures computed at build time --------------------------------------------------------------
plot_include_source = True
plot_html_show_source_link = False
plot_html_show_formats = False
plot_formats = [("png", 110)]
plot_rcparams = {"figure.figsize": (7.0, 3.6), "figure.dpi": 110}

sphinx_gallery_conf = {
    "examples_dirs": ["examples"],
    "gallery_dirs": ["auto_examples"],
    "filename_pattern": r"/plot_",
    "abort_on_example_error": True,
    "only_warn_on_example_error": False,
    "remove_config_comments": True,
    "download_all_examples": False,
    "within_subsection_order": "FileNameSortKey",
    "write_computation_times": False,
}

html_theme = "furo"
html_title = f"xpersson {release}"
html_static_path: list[str] = []
