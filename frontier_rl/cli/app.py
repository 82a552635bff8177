"""The ``frontier-rl`` command line: each command in a module of its own, put together here."""

from __future__ import annotations

from typing import Annotated

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
    context_settings={"help_option_names": ["-h", "--help"]},  # the commands' contexts inherit it
)


def _print_version(asked: bool) -> None:
    if asked:
        from frontier_rl import __version__

        print(f"frontier-rl {__version__}")
        raise typer.Exit


@app.callback()
def _program(
    version: Annotated[
        bool, typer.Option("--version", help="Print the version and exit.", is_eager=True, callback=_print_version)
    ] = False,
) -> None:
    """The program's own options (``--help``, ``--version``); Typer runs this before the command."""
