"""The command-line reference, generated from the ``frontier-rl`` Typer app by Typer's own
documentation generator (what ``typer frontier_rl.cli utils docs`` prints): every command and
sub-command with its usage, arguments, options and defaults.

sphinx-click cannot render it: Typer carries its own copy of Click, whose command objects are not
``click.Command`` instances.
"""

from __future__ import annotations

from pathlib import Path

import typer
import typer.main
from typer.cli import get_docs_for_click

from frontier_rl.cli import app

PROGRAM = "frontier-rl"


def generate(out_dir: Path) -> None:
    """Write ``commands.md``: a section per command (headings from level 2)."""
    command = typer.main.get_command(app)
    text = get_docs_for_click(obj=command, ctx=typer.Context(command), name=PROGRAM, indent=1)
    (out_dir / "commands.md").write_text(text)
