"""Sphinx configuration of the murus documentation site (``make docs``).

The build is offline: intersphinx reads only the inventories shipped under ``_intersphinx/``
(``_intersphinx/make_inventories.py`` writes and refreshes them), the theme bundles its assets,
the API reference is generated from the installed package by ``_ext/apigen.py`` and the
gallery scripts run locally.
"""

from __future__ import annotations

import os
import sys
import warnings
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(HERE / "_ext"))

# gallery scripts and autodoc must not open windows or use the numba threads others need
os.environ.setdefault("MPLBACKEND", "Agg")

import murus  # noqa: E402

# myst-parser uses an attribute Sphinx 9 deprecates: a Python warning of the theme's
# dependencies, not a warning of this documentation
warnings.filterwarnings("ignore", message=r".*\.app' is deprecated", module=r"myst_parser\..*")

project = "murus"
author = "the murus contributors"
copyright = "the murus contributors, BSD-3-Clause"
release = murus.__version__
version = release

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.intersphinx",
    "sphinx.ext.mathjax",
    "sphinx-mathjax-offline",  # MathJax served from _static: the pages work offline
    "sphinx.ext.viewcode",
    "numpydoc",
    "myst_parser",
    "sphinx_gallery.gen_gallery",
    "apigen",
    "docstrings",
    "repofiles",
]

source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
root_doc = "index"
exclude_patterns = [
    "_build", "_intersphinx", "_ext", "_generated", "**.ipynb_checkpoints",
    # pages of the repository included into site pages, not pages of their own
    "retaining_backfills.md", "limit_analysis.md", "mechanisms.md",
    "gallery/*.py", "gallery/*.ipynb", "gallery/*.md5", "gallery/*.zip", "gallery/*.json",
]

# --- MyST --------------------------------------------------------------------------------------
myst_enable_extensions = ["dollarmath", "amsmath", "colon_fence", "deflist"]
myst_heading_anchors = 3

# --- autodoc / numpydoc ------------------------------------------------------------------------
autodoc_default_options = {"member-order": "bysource"}
autodoc_inherit_docstrings = False
autodoc_typehints = "none"          # numpydoc's Parameters sections carry the types
autodoc_mock_imports: list[str] = []
autosummary_generate = False
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_validation_checks: set[str] = set()
numpydoc_xref_param_type = True    # types in Parameters/Returns link to numpy, xarray, ...
numpydoc_xref_aliases = {
    "ndarray": "numpy.ndarray",
    "Generator": "numpy.random.Generator",
    "Dataset": "xarray.Dataset",
    "DataArray": "xarray.DataArray",
    "Axes": "matplotlib.axes.Axes",
    "Figure": "matplotlib.figure.Figure",
    "Path": "pathlib.Path",
    "Executor": "concurrent.futures.Executor",
}
# words of type descriptions that are not objects (unresolved names render as plain code: nitpicky
# is off)
numpydoc_xref_ignore = {"of", "or", "and", "optional", "default", "shape", "the", "a", "an",
                        "with", "in", "to", "for", "each", "per", "if", "one", "two", "n",
                        "same", "as", "like", "any", "keyword", "only", "length", "pair", "list-like"}
nitpicky = False
suppress_warnings: list[str] = []   # none needed: every warning is an error (-W)

# --- intersphinx: local inventories only, never the network -----------------------------------
_INV = HERE / "_intersphinx"
_TARGETS = {
    "python": "https://docs.python.org/3/",
    "numpy": "https://numpy.org/doc/stable/",
    "scipy": "https://docs.scipy.org/doc/scipy/",
    "xarray": "https://docs.xarray.dev/en/stable/",
    "matplotlib": "https://matplotlib.org/stable/",
}
intersphinx_mapping = {
    name: (url, str(_INV / f"{name}.inv"))
    for name, url in _TARGETS.items() if (_INV / f"{name}.inv").is_file()
}
intersphinx_timeout = 1
intersphinx_cache_limit = -1

# --- gallery: examples/gallery/plot_*.py, executed at build time ----------------------------------
sphinx_gallery_conf = {
    "examples_dirs": str(ROOT / "examples" / "gallery"),
    "gallery_dirs": "gallery",
    "filename_pattern": r"/plot_",
    "within_subsection_order": "FileNameSortKey",
    "download_all_examples": False,
    "remove_config_comments": True,
    "abort_on_example_error": True,
    "reference_url": {"murus": None},      # links to the API reference of this site
    "doc_module": ("murus",),
    "backreferences_dir": None,
    "matplotlib_animations": False,
    "image_scrapers": ("matplotlib",),
    "show_memory": False,
    "min_reported_time": 1,
}

# --- HTML --------------------------------------------------------------------------------------
html_theme = "pydata_sphinx_theme"
html_title = f"murus {release}"
html_theme_options = {
    "navigation_with_keys": False,
    "show_toc_level": 2,
    "header_links_before_dropdown": 7,
    "navbar_end": ["theme-switcher", "navbar-icon-links"],
}
html_static_path: list[str] = []
html_show_sourcelink = False
