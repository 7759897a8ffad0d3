"""Sphinx configuration: ``sphinx-build -W docs docs/_build/html`` (the ``docs`` extra installs what it needs).

The Markdown pages go through MyST, the API reference through autodoc with numpydoc, and the gallery
(``examples/``) through sphinx-gallery, which runs every script on each build.
"""

import os
import sys
import warnings
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
os.environ.setdefault("MPLBACKEND", "Agg")

import faultslip  # noqa: E402

# sphinx-gallery's back-references try each name a gallery script uses at every level of its module path
# (faultslip.critical for faultslip.models.critical): the previous release's flat names answer with a FutureWarning
warnings.filterwarnings("ignore", message=r"faultslip\.\w+ is faultslip\.", category=FutureWarning)

project = "faultslip"
author = "the faultslip developers"
release = version = faultslip.__version__
# sphinx-mathjax-offline serves MathJax from the built site: math renders with no network (no CDN)
extensions = ["myst_parser", "sphinx.ext.autodoc", "sphinx.ext.mathjax", "sphinx-mathjax-offline", "numpydoc",
              "sphinx_gallery.gen_gallery"]
source_suffix = {".md": "markdown", ".rst": "restructuredtext"}
exclude_patterns = ["_build", "figures/*.md", "auto_examples/*.ipynb", "auto_examples/*.py", "auto_examples/*.zip"]
myst_heading_anchors = 3
# $...$ and $$...$$ render as mathematics (MathJax, served offline above)
myst_enable_extensions = ["dollarmath"]
html_theme = "pydata_sphinx_theme"
html_title = "faultslip"
html_theme_options = {"navigation_with_keys": False, "show_toc_level": 2}
autodoc_member_order = "bysource"
autodoc_typehints = "none"
numpydoc_show_class_members = False
numpydoc_validation_checks = set()
sphinx_gallery_conf = {
    "examples_dirs": str(ROOT / "examples"),
    "gallery_dirs": "auto_examples",
    "filename_pattern": r"plot_",
    "download_all_examples": False,
    "remove_config_comments": True,
    "plot_gallery": "True",
    # its execution-times page loads a style sheet from a CDN: the site stays offline without it
    "write_computation_times": False,
    # the test run re-executes every example even where a cached result exists (FAULTSLIP_DOCS_RERUN=1)
    "run_stale_examples": os.environ.get("FAULTSLIP_DOCS_RERUN") == "1",
}
