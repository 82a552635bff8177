"""The ``frontier-rl`` command line: each command in a module of its own, put together here."""

from __future__ import annotations

import typer

from frontier_rl.cli.experiments import demo, evaluate
from frontier_rl.cli.explore import explore
from frontier_rl.cli.maps import maps_command
from frontier_rl.cli.protocols import benchmark_app
from frontier_rl.cli.ros2 import ros2_app
from frontier_rl.cli.subcommands import LazyGroup, Subcommand
from frontier_rl.cli.train import train


class FrontierRLGroup(LazyGroup):
    """The program's commands, in the order its help lists them."""

    subcommands = (
        Subcommand("explore", explore),
        Subcommand("demo", demo),
        Subcommand("evaluate", evaluate),
        Subcommand("train", train),
        Subcommand("maps", maps_command),
        Subcommand("benchmark", benchmark_app),
        Subcommand("ros2", ros2_app),
    )


# Help laid out by click as plain text: typer's rich layout imports rich's Markdown, syntax and
# traceback modules (0.1 s of every `--help`) and breaks a command's summary where its docstring does.
app = typer.Typer(
    add_completion=False,
    no_args_is_help=True,
    help="Frontier exploration for search and rescue.",
    cls=FrontierRLGroup,
    rich_markup_mode=None,
)


@app.callback()
def _program() -> None:
    """The program's own options (only ``--help``); Typer runs this before the command."""
