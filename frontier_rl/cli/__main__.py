"""``python -m frontier_rl.cli``: the command line, as the ``frontier-rl`` script runs it."""

from frontier_rl.cli import app

app()
