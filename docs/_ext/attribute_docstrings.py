"""Napoleon, fitted to how this package writes attributes.

* Napoleon reads the first line of an attribute's, property's or constant's docstring as
  ``TYPE: DESCRIPTION`` and turns everything before the first colon into a type ("The range (m)
  within which a scan updates the map: the LiDAR's..." became a type of seven words). Those
  docstrings are prose here, their types come from the annotations, so they are left as they are.
* An "Attributes:" entry may describe several fields at once (``t90_s, t99_s: ...``); napoleon
  would make the first name a type. Such an entry is given to each field.
"""

from __future__ import annotations

import re
from typing import Any

from sphinx.application import Sphinx
from sphinx.ext import napoleon

PROSE = frozenset({"attribute", "property", "data"})
"""The kinds of object whose docstring napoleon leaves alone here."""

_SHARED_ENTRY = re.compile(r"^(?P<indent>\s+)(?P<names>[A-Za-z_]\w*(?:,\s*[A-Za-z_]\w*)+):(?P<text>.*)$")


def split_shared_entries(lines: list[str]) -> list[str]:
    """``lines`` of a docstring with each "Attributes:" entry that names several fields repeated
    once per field, its continuation lines with it."""
    out: list[str] = []
    in_section, index = False, 0
    while index < len(lines):
        line = lines[index]
        if line.strip().endswith(":") and not line.startswith((" ", "\t")):
            in_section = line.strip() == "Attributes:"
        match = _SHARED_ENTRY.match(line) if in_section else None
        if not match:
            out.append(line)
            index += 1
            continue
        indent = len(match["indent"])
        end = index + 1
        while end < len(lines) and lines[end].strip() and len(lines[end]) - len(lines[end].lstrip()) > indent:
            end += 1
        for name in match["names"].split(","):
            out += [f"{match['indent']}{name.strip()}:{match['text']}", *lines[index + 1 : end]]
        index = end
    return out


def napoleon_fitted(app: Sphinx, what: str, name: str, obj: Any, options: Any, lines: list[str]) -> None:
    """Napoleon's docstring processing, skipped for :data:`PROSE` objects, after
    :func:`split_shared_entries`."""
    if what in PROSE:
        return
    lines[:] = split_shared_entries(lines)
    napoleon._process_docstring(app, what, name, obj, options, lines)  # type: ignore[arg-type]


def setup(app: Sphinx) -> dict[str, Any]:
    app.setup_extension("sphinx.ext.napoleon")
    for listener in list(app.events.listeners["autodoc-process-docstring"]):
        if listener.handler is napoleon._process_docstring:
            app.disconnect(listener.id)
    app.connect("autodoc-process-docstring", napoleon_fitted)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
