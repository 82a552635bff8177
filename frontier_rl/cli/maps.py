"""``frontier-rl maps [NAME]``: the maps that ship with frontier_rl (laid out by
:mod:`frontier_rl.cli.map_listing`, loaded only when the command runs)."""

from __future__ import annotations

from typing import Annotated

import typer

from frontier_rl.cli.output import friendly_errors


@friendly_errors
def maps_command(
    name: Annotated[
        str | None, typer.Argument(help="A collection to list the maps of (e.g. dungeon/easy), or a map to describe.")
    ] = None,
    as_json: Annotated[
        bool, typer.Option("--json", help="Print a JSON list (every field, the source whole) instead of a table.")
    ] = False,
) -> None:
    """The maps that ship with frontier_rl.

    Pass a map's name as --world, or a collection's in a world list."""
    from frontier_rl.cli.map_listing import show_maps

    show_maps(name, as_json)
