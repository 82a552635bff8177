"""The architecture page's tables, generated from what the build checks: the layers of the package and
the stages of the engine as the import-linter contracts of ``pyproject.toml`` state them, each
package described by the first paragraph of its docstring. A layer added to the contracts, or a
package's docstring changed, shows here at the next build.
"""

from __future__ import annotations

import importlib
import inspect
import tomllib
from pathlib import Path

from docstrings import to_myst

ROOT = Path(__file__).resolve().parents[2]
CONTRACTS = {
    "layers.md": "Packages import only the layers below them",
    "stages.md": "The engine's stages import only the stages before them",
}
"""Each table's file and the name of the contract it shows."""


def generate(out_dir: Path) -> None:
    """Write one table per contract of :data:`CONTRACTS` into ``out_dir``."""
    contracts = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["importlinter"]["contracts"]
    by_name = {contract["name"]: contract for contract in contracts}
    for file, name in CONTRACTS.items():
        if name not in by_name:
            raise ValueError(f"pyproject.toml has no import-linter contract named {name!r}")
        (out_dir / file).write_text(layer_table(by_name[name]["layers"]))


def layer_table(layers: list[str]) -> str:
    """A Markdown table of ``layers`` (the contract's order: the top layer first), a row per module."""
    rows = ["| layer | module | what it is |", "|---:|---|---|"]
    for depth, layer in enumerate(layers):
        for module in (m.strip() for m in layer.split("|")):
            rows.append(f"| {len(layers) - depth} | `{module}` | {summary(module)} |")
    return "\n".join(rows) + "\n"


def summary(name: str) -> str:
    """The first paragraph of module ``name``'s docstring, on one line."""
    module = importlib.import_module(name)
    if not module.__doc__:
        raise ValueError(f"{name} has no docstring to describe it with")
    first = inspect.cleandoc(module.__doc__).split("\n\n")[0]
    return to_myst(" ".join(first.split()), module).replace("|", "\\|")
