"""Reading the package's docstrings for generated pages: the fields of a Google-style "Attributes:"
section, and Sphinx roles rewritten as MyST roles with their targets made absolute."""

from __future__ import annotations

import functools
import importlib
import inspect
import re
from typing import Any

_ROLE = re.compile(r":(?P<role>func|class|data|meth|mod|attr|obj|exc|const):`(?P<target>[^`]+)`")
_LITERAL = re.compile(r"``(?P<text>[^`]+)``")
_ENTRY = re.compile(r"^(?P<names>[A-Za-z_][\w, ]*?):(?:\s+(?P<text>.*))?$")


class DocstringError(ValueError):
    """A docstring that cannot document what it should (a field without a description)."""


def attributes_section(obj: Any) -> dict[str, str]:
    """The entries of ``obj``'s "Attributes:" section: name -> description (one line, the
    continuation lines joined). An entry naming several fields ("a, b, c: ...") gives each the text."""
    doc = inspect.cleandoc(obj.__doc__ or "")
    lines = doc.splitlines()
    try:
        start = next(i for i, line in enumerate(lines) if line.strip() == "Attributes:")
    except StopIteration:
        return {}
    header_indent = _indent(lines[start])
    entries: dict[str, list[str]] = {}
    names: list[str] = []
    entry_indent: int | None = None
    for line in lines[start + 1 :]:
        if not line.strip():
            continue
        indent = _indent(line)
        if indent <= header_indent:
            break  # the next section
        if entry_indent is None:
            entry_indent = indent
        match = _ENTRY.match(line.strip()) if indent == entry_indent else None
        if match:
            names = [n.strip() for n in match["names"].split(",")]
            for name in names:
                entries[name] = [match["text"] or ""]
        elif names:
            for name in names:
                entries[name].append(line.strip())
    return {name: " ".join(part for part in parts if part) for name, parts in entries.items()}


def _indent(line: str) -> int:
    return len(line) - len(line.lstrip())


def to_myst(text: str, context: Any) -> str:
    """``text`` (reStructuredText prose) as MyST Markdown: ``:role:`target``` becomes
    ``{role}`target``` with a target relative to ``context`` (a class or module) made absolute, and
    double-backquoted literals single-backquoted."""

    def role(match: re.Match[str]) -> str:
        return f"{{{match['role']}}}`{absolute_target(match['target'], context)}`"

    return _LITERAL.sub(lambda m: f"`{m['text']}`", _ROLE.sub(role, text))


def absolute_target(target: str, context: Any) -> str:
    """A role target (``drop_cells``, ``~.lidar.LidarConfig``, ``Title <name>``) made absolute
    where ``context`` (a class or module) names it; kept as it is otherwise."""
    explicit = re.fullmatch(r"(?P<title>.*?)\s*<(?P<name>[^>]+)>", target)
    if explicit:
        return f"{explicit['title']} <{absolute_target(explicit['name'], context)}>"
    short = target.startswith("~")
    name = target.lstrip("~").lstrip(".")
    if exists(name):
        return target
    for scope in _scopes(context):
        path = f"{scope}.{name}"
        if exists(path):
            return f"~{path}" if short or "." not in name else path
    return target


def _scopes(context: Any) -> list[str]:
    """Where a relative name in ``context``'s docstring may live: the class, then its module."""
    if inspect.ismodule(context):
        return [context.__name__]
    module = getattr(context, "__module__", "")
    return [f"{module}.{context.__qualname__}", module]


_MISSING = object()


def exists(path: str) -> bool:
    """Whether dotted ``path`` names a module of frontier_rl, or an attribute of one."""
    return find_object(path, _MISSING) is not _MISSING


def find_object(path: str, default: Any = None) -> Any:
    """The module of frontier_rl, or attribute of one, that dotted ``path`` names; ``default`` if none."""
    found = _lookup(path)
    return default if found is _MISSING else found


@functools.cache
def _lookup(path: str) -> Any:
    parts = path.split(".")
    if parts[0] != "frontier_rl":
        return _MISSING
    for split in range(len(parts), 0, -1):
        try:
            obj: Any = importlib.import_module(".".join(parts[:split]))
        except ImportError:
            continue
        try:
            for attribute in parts[split:]:
                obj = _attribute(obj, attribute)
        except AttributeError:
            return _MISSING
        return obj
    return _MISSING


def _attribute(obj: Any, name: str) -> Any:
    """``obj.name``, where a dataclass field without a default (no class attribute) counts too."""
    fields = getattr(obj, "__dataclass_fields__", {})
    if name in fields and not hasattr(obj, name):
        return fields[name]
    return getattr(obj, name)
