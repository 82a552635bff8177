"""Sphinx configuration of the frontier_rl documentation site (``make docs``).

The site builds offline: no intersphinx, no theme assets from the network. Pages are Markdown (MyST);
the reference pages are generated from the code at build time (``_ext/generated_pages.py``).
"""

from __future__ import annotations

import sys
from pathlib import Path

DOCS = Path(__file__).resolve().parent
sys.path.insert(0, str(DOCS / "_ext"))
sys.path.insert(0, str(DOCS.parent))

import frontier_rl  # noqa: E402  (after the path set-up above)

project = "frontier_rl"
author = "frontier_rl developers"
copyright = "frontier_rl developers, MIT licence"
release = version = frontier_rl.__version__

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.napoleon",
    "attribute_docstrings",
    "generated_pages",
    "code_references",
    "api_members",
]

source_suffix = {".md": "markdown"}
root_doc = "index"
exclude_patterns = ["_build", "_generated", "_ext", "**/data/**"]
nitpicky = True
smartquotes = False  # options stay "--world", quotes stay straight: text a reader copies

# ----------------------------------------------------------------------------------------- MyST
myst_enable_extensions = ["colon_fence", "deflist", "attrs_block", "attrs_inline", "dollarmath"]
myst_heading_anchors = 3

# --------------------------------------------------------------------------------- autodoc
autodoc_member_order = "bysource"
autodoc_typehints = "description"
autodoc_typehints_description_target = "documented_params"
autodoc_typehints_format = "short"
autodoc_preserve_defaults = True
autodoc_class_signature = "mixed"
autodoc_default_options = {"members": True}
napoleon_google_docstring = True
napoleon_numpy_docstring = False
napoleon_use_rtype = False
napoleon_attr_annotations = True
napoleon_use_ivar = True  # a class's Attributes as one compact field list

# Types from libraries that have no documentation here to link to (the build is offline: no
# intersphinx), and names the docstrings use in their prose.
nitpick_ignore_regex = [
    (
        "py:.*",
        r"(numpy|np|numpy\.typing|npt|gymnasium|gym|torch|stable_baselines3|pettingzoo|scipy|PIL|click|typer)(\..*)?",
    ),
    ("py:.*", r"NDArray|ArrayLike|DTypeLike"),
    (
        "py:.*",
        r"(collections\.abc|typing|typing_extensions|pathlib|enum|dataclasses|os|io|random|concurrent\.futures)\..*",
    ),
    ("py:class", r"(Path|Any|Callable|Iterator|Iterable|Sequence|Mapping|Generator|TypeVar|Self)"),
    ("py:class", r"(int|float|str|bool|bytes|object|tuple|list|dict|set|frozenset|type|None|complex)"),
    ("py:class", r"(np\.)?(u?int\d+|float\d+|bool_|intp|uint8|int8|int64|float32|float64|floating|integer|generic)"),
    ("py:class", r"(StrEnum|IntEnum|Enum|Exception|ValueError|KeyError|TypeError|RuntimeError|OSError)"),
    ("py:.*", r".*\.(ObsT|ActT|T|T_co|K|V)"),
    ("py:class", r"(ObsT|ActT|T|T_co|K|V)"),
]

# ------------------------------------------------------------------------------------ HTML
html_theme = "furo"
html_title = f"frontier_rl {release}"
html_static_path = ["_static"]
html_css_files = ["site.css"]
html_last_updated_fmt = None
html_copy_source = False
html_show_sourcelink = False
html_theme_options = {
    "navigation_with_keys": True,
    "top_of_page_buttons": [],
}
