"""Each object of the API reference documented once: a name the package exports at its top level
(``frontier_rl.Ranking``) is documented there, under the name a user imports, and left out of the
modules that also list it (``frontier_rl.policies``, ``frontier_rl.swarm``, ...). Sphinx knows it by its
defining module's name too (autodoc's canonical name), so a reference to either links to it."""

from __future__ import annotations

from typing import Any

from sphinx.application import Sphinx

import frontier_rl

TOP_LEVEL = "frontier_rl"


def _exported_ids() -> set[int]:
    return {id(getattr(frontier_rl, name)) for name in frontier_rl.__all__ if not name.startswith("__")}


def skip_exported(app: Sphinx, what: str, name: str, obj: Any, skip: bool, options: Any) -> bool | None:
    """Skip a module member that the top level exports, unless the top level is what is documented
    (numbers and strings, which are shared by value, are never skipped)."""
    if what != "module" or app.env.temp_data.get("autodoc:module") == TOP_LEVEL:
        return None
    if not isinstance(obj, int | float | str | bytes | None) and id(obj) in _exported_ids():
        return True
    return None


def setup(app: Sphinx) -> dict[str, Any]:
    app.connect("autodoc-skip-member", skip_exported)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
