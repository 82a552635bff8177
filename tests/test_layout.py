"""The layout rules of issue 16, checked: module and function sizes and no import cycle (the layers
themselves are import-linter contracts in pyproject.toml, run by ``make lint``)."""

from __future__ import annotations

import ast
from pathlib import Path

import grimp
import pytest

PACKAGE = Path(__file__).resolve().parent.parent / "frontier_rl"
MODULES = sorted(PACKAGE.rglob("*.py"))
MAX_MODULE_LINES = 400
MAX_FUNCTION_LINES = 60


def _name(path: Path) -> str:
    return path.relative_to(PACKAGE).as_posix()


@pytest.mark.parametrize("path", MODULES, ids=_name)
def test_no_module_is_over_400_lines(path: Path) -> None:
    lines = len(path.read_text().splitlines())
    assert lines <= MAX_MODULE_LINES, f"{_name(path)}: {lines} lines"


def _is_numba_kernel(node: ast.FunctionDef) -> bool:
    """Compiled kernels are written out on purpose (no calls into Python, few helpers)."""
    return any("njit" in ast.unparse(d) or "jit(" in ast.unparse(d) for d in node.decorator_list)


@pytest.mark.parametrize("path", MODULES, ids=_name)
def test_no_function_is_over_60_lines_outside_the_numba_kernels(path: Path) -> None:
    long = [
        f"{node.name} ({node.end_lineno - node.lineno + 1} lines)"  # type: ignore[operator]
        for node in ast.walk(ast.parse(path.read_text()))
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef)
        and not _is_numba_kernel(node)  # type: ignore[arg-type]
        and node.end_lineno - node.lineno + 1  # type: ignore[operator]
        > MAX_FUNCTION_LINES
    ]
    assert not long, f"{_name(path)}: {', '.join(long)}"


MAX_FORMAT_SKIPS = 20
"""``# fmt: skip`` lines allowed in the package: for a table or a kernel whose layout is the point,
not to squeeze code under the size bounds (there were 107 before ``ruff format`` laid them out)."""


def test_format_skips_are_few() -> None:
    skips = []
    for path in MODULES:
        lines = enumerate(path.read_text().splitlines(), 1)
        skips += [f"{_name(path)}:{n}" for n, line in lines if line.rstrip().endswith("# fmt: skip")]
    assert len(skips) <= MAX_FORMAT_SKIPS, f"{len(skips)} lines with fmt: skip: {', '.join(skips)}"


def test_no_import_cycle() -> None:
    graph = grimp.build_graph("frontier_rl", exclude_type_checking_imports=True)
    cycles = []
    for module in sorted(graph.modules):
        for imported in sorted(graph.find_modules_directly_imported_by(module)):
            back = graph.find_shortest_chain(importer=imported, imported=module)
            if back is not None:
                cycles.append(" -> ".join((module, *back)))
    assert not cycles, "import cycles:\n" + "\n".join(cycles)
