"""Napoleon for the docstrings of modules, classes and functions only.

Napoleon reads the first line of an attribute's, property's or constant's docstring as
``TYPE: DESCRIPTION`` and turns everything before the first colon into a type
("The range (m) within which a scan updates the map: the LiDAR's..." became a type of seven
words). This package writes those docstrings as prose, their types come from the annotations, so
they are left to Sphinx as they are.
"""

from __future__ import annotations

from typing import Any

from sphinx.application import Sphinx
from sphinx.ext import napoleon

PROSE = frozenset({"attribute", "property", "data"})
"""The kinds of object whose docstring napoleon leaves alone here."""


def napoleon_outside_attributes(app: Sphinx, what: str, name: str, obj: Any, options: Any, lines: list[str]) -> None:
    """Napoleon's docstring processing, skipped for :data:`PROSE` objects."""
    if what not in PROSE:
        napoleon._process_docstring(app, what, name, obj, options, lines)  # type: ignore[arg-type]


def setup(app: Sphinx) -> dict[str, Any]:
    app.setup_extension("sphinx.ext.napoleon")
    for listener in list(app.events.listeners["autodoc-process-docstring"]):
        if listener.handler is napoleon._process_docstring:
            app.disconnect(listener.id)
    app.connect("autodoc-process-docstring", napoleon_outside_attributes)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
