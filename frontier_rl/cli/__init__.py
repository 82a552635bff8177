"""The ``frontier-rl`` command line (:data:`app`, a Typer application): one module per command, the
options they share in :mod:`frontier_rl.cli.options`, and how they talk to the user in
:mod:`frontier_rl.cli.output`."""

from frontier_rl.cli.app import app
from frontier_rl.cli.options import MAX_SEED, WORLD_HELP

__all__ = ["MAX_SEED", "WORLD_HELP", "app"]
