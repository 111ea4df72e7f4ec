"""Sphinx configuration of the symkf documentation (``python -m sphinx -W -b html docs OUT``).

Pages are MyST Markdown; ``tutorial.md`` is a MyST notebook executed at every build (myst-nb,
nbclient), so its LaTeX results and figures are those of the current code. The API reference
is autodoc with napoleon (numpydoc-style ``Parameters`` / ``Returns`` / ``Examples`` sections).
"""

import sys
from pathlib import Path

import symkf

sys.path.insert(0, str(Path(__file__).parent))   # docs/offline.py, the extension below

project = "symkf"
author = "The symkf developers"
copyright = "2026, The symkf developers"
release = version = symkf.__version__

# offline: MathJax served from the site itself, and the build fails if a page loads an asset
# from another host (docs/offline.py)
extensions = ["myst_nb", "sphinx.ext.autodoc", "sphinx.ext.napoleon", "sphinx.ext.mathjax", "offline"]
myst_enable_extensions = ["dollarmath", "amsmath"]
myst_heading_anchors = 3
exclude_patterns = ["_build", "jupyter_execute"]

nb_execution_mode = "force"
nb_execution_raise_on_error = True
nb_execution_timeout = 600
nb_execution_show_tb = True

autodoc_default_options = {"members": True, "undoc-members": False, "show-inheritance": True}
autodoc_member_order = "bysource"
autodoc_typehints = "description"
napoleon_numpy_docstring = True
napoleon_google_docstring = False
# pages link to the repository's files outside docs/ (proofs/, examples/); tests/test_docs.py
# checks every relative link resolves, so Sphinx need not report them as missing documents
suppress_warnings = ["myst.xref_missing"]

html_theme = "alabaster"
html_title = f"symkf {release}"
