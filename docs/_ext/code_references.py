"""Cross-references to frontier_rl code, resolved the way a reader of the docstring means them.

The docstrings name objects relative to the module that defines them (``:func:`drop_cells_at```),
while the API reference may document the object under another name (``frontier_rl.SimConfig``, the
name a user imports); and they link freely to the package's internals, which the reference does not
document. A reference that Sphinx cannot resolve is tried again here: relative to the defining
module and class of the object whose docstring holds it, then as the unique documented name that
ends with it. One that names existing code without a page is shown as code without a link; one
that names nothing (a typo, a function since renamed) still fails the build under ``-n -W``.
"""

from __future__ import annotations

from typing import Any

from docstrings import exists, find_object
from docutils import nodes
from sphinx.application import Sphinx
from sphinx.environment import BuildEnvironment


def candidates(target: str, module: str, cls: str, source: str = "") -> list[str]:
    """The absolute names ``target`` may stand for in a docstring of ``module``.``cls`` (documented
    there), whose ``source`` is ``"FILE:docstring of DEFINED.NAME"``, autodoc's note of where the
    docstring comes from."""
    names = [target]
    scopes = [f"{module}.{cls}", module] if cls else [module]
    _, marker, defined = source.partition("docstring of ")
    if marker:
        parts = defined.split(".")
        scopes += [".".join(parts[:end]) for end in range(len(parts), 1, -1)]
    documented = find_object(f"{module}.{cls}") if cls else None
    defined_in = getattr(documented, "__module__", None)
    if isinstance(defined_in, str):
        scopes += [f"{defined_in}.{getattr(documented, '__qualname__', cls)}", defined_in]
    names += [f"{scope}.{target}" for scope in scopes if scope]
    return list(dict.fromkeys(names))


def resolve_internal(app: Sphinx, env: BuildEnvironment, node: Any, contnode: nodes.Element) -> nodes.Element | None:
    """A link (or ``contnode`` unlinked) for a Python reference Sphinx could not resolve, when it
    names frontier_rl code; None (a missing reference) otherwise."""
    if node.get("refdomain") != "py":
        return None
    domain = env.get_domain("py")
    target = str(node.get("reftarget", "")).lstrip("~.")
    names = candidates(target, node.get("py:module") or "", node.get("py:class") or "", str(node.source or ""))
    names += _documented_ending_with(domain, target)
    for name in names:
        resolved = domain.resolve_xref(env, node["refdoc"], app.builder, node["reftype"], name, node, contnode)
        if resolved is not None:
            return resolved
    if any(exists(name) for name in names):
        return contnode
    return None


_NOTHING = object()


def _documented_ending_with(domain: Any, target: str) -> list[str]:
    """The one documented object whose name ends with ``target``'s last two parts (a member of a
    class documented under another name: ``frontier_rl.SimConfig.time_cap`` for
    ``frontier_rl.core.sim.config.SimConfig.time_cap``), or, for a bare name, with ``.target``; none
    if several do. A dotted target must name the same object as the match."""
    suffix = "." + ".".join(target.split(".")[-2:])
    matches = {(e.docname, e.node_id): name for name, e in domain.objects.items() if name.endswith(suffix)}
    if len(matches) != 1:
        return []
    (name,) = matches.values()
    if "." in target:
        meant = find_object(target, _NOTHING)
        if meant is _NOTHING or meant is not find_object(name, _NOTHING):
            return []
    return [name]


def setup(app: Sphinx) -> dict[str, Any]:
    app.connect("missing-reference", resolve_internal, priority=900)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
