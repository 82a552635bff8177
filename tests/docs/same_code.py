"""Whether a block that is not run does what a block that runs does (``<!-- not run: same as PAGE -->``).

Two blocks are compared as code, not text: the marked block's imports must be among the other's,
so must the attributes it reads (a result's fields, in its print lines too), and its other
statements must appear in the other block in the same order, nested the same way, with the same
names, calls, arguments and keywords. What may differ: the literal values (another world, a
shorter run: the same type of value), what the lines that print show, and whatever more the block
that runs does. So an API a page shows can only change in both blocks at once, and the block that
runs shows that the other's calls work.
"""

from __future__ import annotations

import ast
import copy
from pathlib import Path

PLAIN_TYPES = (dict, list, tuple, str, int, float, Path)
"""Types whose attributes a block may read without the block that runs reading them too
(``summary.methods.items()``, ``model_file.name``)."""
_BODIES = ("body", "orelse", "finalbody", "handlers")
"""The fields of a compound statement that hold statements."""


def covers(run: str, marked: str) -> list[str]:
    """What of ``marked``'s code the code ``run`` does not do, as ``line N: CODE`` of ``marked``
    (empty: it does it all)."""
    run_imports, run_attributes, run_code = _code(run)
    marked_imports, marked_attributes, marked_code = _code(marked)
    lines = marked.splitlines()
    missing = [f"import {name}" for name in sorted(marked_imports - run_imports)]
    missing += [f".{name} (never read there)" for name in sorted(marked_attributes - run_attributes)]
    return missing + [f"line {s.lineno}: {lines[s.lineno - 1].strip()}" for s in _not_matched(marked_code, run_code)]


def _code(source: str) -> tuple[set[str], set[str], list[ast.stmt]]:
    """A block's imported names (``module:name as alias``), the attributes it reads (but those of
    :data:`PLAIN_TYPES`), and its other statements with literal values masked and the statements
    that only print left out."""
    tree = _MaskLiterals().visit(ast.parse(source))
    imports = set()
    attributes = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            imports |= {f"{alias.name} as {alias.asname or alias.name}" for alias in node.names}
        elif isinstance(node, ast.ImportFrom):
            imports |= {f"{node.module}:{alias.name} as {alias.asname or alias.name}" for alias in node.names}
        elif isinstance(node, ast.Attribute) and not any(hasattr(kind, node.attr) for kind in PLAIN_TYPES):
            attributes.add(node.attr)
    return imports, attributes, _statements(tree.body)


def _statements(body: list[ast.stmt]) -> list[ast.stmt]:
    """``body`` without imports and output: a ``print(...)`` line, or a loop or condition that only prints."""
    kept = []
    for statement in body:
        if isinstance(statement, ast.Import | ast.ImportFrom) or _prints(statement):
            continue
        statement = copy.copy(statement)
        for field in _BODIES:
            if isinstance(getattr(statement, field, None), list):
                setattr(statement, field, _statements(getattr(statement, field)))
        if isinstance(statement, ast.For | ast.While | ast.If) and not statement.body and not statement.orelse:
            continue
        kept.append(statement)
    return kept


def _prints(statement: ast.stmt) -> bool:
    call = statement.value if isinstance(statement, ast.Expr) else None
    return isinstance(call, ast.Call) and isinstance(call.func, ast.Name) and call.func.id == "print"


def _not_matched(marked: list[ast.stmt], run: list[ast.stmt]) -> list[ast.stmt]:
    """The statements of ``marked`` that ``run`` lacks, each looked for after the last one found; of a
    compound statement that ``run`` has with less in it, the statements it lacks inside."""
    missing = []
    position = 0
    for statement in marked:
        found = next((i for i in range(position, len(run)) if _same(statement, run[i])), None)
        if found is not None:
            position = found + 1
            continue
        like = next((other for other in run[position:] if _header(other) == _header(statement)), None)
        inner = [_not_matched(_body(statement, f), _body(like, f)) for f in _BODIES] if like is not None else []
        missing += [s for part in inner for s in part] or [statement]
    return missing


def _same(marked: ast.stmt, run: ast.stmt) -> bool:
    """Whether ``run`` does what ``marked`` does: the same statement, its bodies covering ``marked``'s."""
    if _header(marked) != _header(run):
        return False
    return not any(_not_matched(_body(marked, f), _body(run, f)) for f in _BODIES)


def _body(statement: ast.stmt, field: str) -> list[ast.stmt]:
    value = getattr(statement, field, None)
    return value if isinstance(value, list) else []


def _header(statement: ast.stmt) -> str:
    """The statement without the statements it holds."""
    bare = copy.copy(statement)
    for field in _BODIES:
        if isinstance(getattr(bare, field, None), list):
            setattr(bare, field, [])
    return ast.dump(bare)


class _MaskLiterals(ast.NodeTransformer):
    """Every literal value replaced by its type's name."""

    def visit_Constant(self, node: ast.Constant) -> ast.Constant:
        return ast.copy_location(ast.Constant(value=f"<{type(node.value).__name__}>"), node)
