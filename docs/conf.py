"""Sphinx configuration of the harness's documentation site (`make docs`).

The tables a reader should trust are generated here, at build time, from the code that owns
them (issue 52): the registered cases and methods from the registries, the columns of
results.csv, rates.csv and efficiency.csv from the modules that write them, the command line
from its argparse parser (sphinx-argparse). They are written to ``docs/_generated/`` (not
committed) and included by the pages.
"""
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
sys.path.insert(0, str(HERE / "_ext"))

from generate import write_generated  # noqa: E402

import harness  # noqa: E402

project = "signorini-harness"
author = "the signorini-harness authors"
copyright = "2026, " + author
release = version = harness.__version__

extensions = ["myst_parser", "sphinxarg.ext", "sphinx_gallery.gen_gallery", "sphinx.ext.autodoc"]
autodoc_member_order = "bysource"
autodoc_typehints = "none"        # the signatures say the names; the docstrings say the types
myst_enable_extensions = ["dollarmath", "colon_fence", "deflist"]
myst_heading_anchors = 3
source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
# the tutorials: scripts executed at every build (sphinx-gallery), a failing one fails the build
sphinx_gallery_conf = {
    "examples_dirs": "tutorials", "gallery_dirs": "tutorials_generated", "filename_pattern": r"plot_",
    "abort_on_example_error": True, "download_all_examples": False, "show_memory": False,
    "remove_config_comments": True, "within_subsection_order": "FileNameSortKey",
}
exclude_patterns = ["_build", "_generated", "tutorials/*"]
html_theme = "furo"
html_title = f"signorini-harness {release}"
# the pages link to the repository's files (examples, cases) by relative paths
suppress_warnings = ["myst.xref_missing"]

write_generated(HERE / "_generated")
