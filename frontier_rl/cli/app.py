"""The ``frontier-rl`` command line: each command in a module of its own, put together here."""

from __future__ import annotations

import typer

from frontier_rl.cli.experiments import demo, evaluate
from frontier_rl.cli.explore import explore
from frontier_rl.cli.maps import maps_command
from frontier_rl.cli.output import OneLineGroup
from frontier_rl.cli.protocols import benchmark_app
from frontier_rl.cli.ros2 import ros2_app
from frontier_rl.cli.train import train

app = typer.Typer(
    add_completion=False, no_args_is_help=True, help="Frontier exploration for search and rescue.", cls=OneLineGroup
)
app.command()(explore)
app.command()(demo)
app.command()(evaluate)
app.command()(train)
app.add_typer(benchmark_app, name="benchmark")
app.command("maps")(maps_command)
app.add_typer(ros2_app, name="ros2")
