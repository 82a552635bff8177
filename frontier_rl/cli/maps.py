"""``frontier-rl maps [NAME]``: the maps that ship with frontier_rl, by the names ``--world`` takes
(:mod:`frontier_rl.io.catalogue`), as a table or as JSON."""

from __future__ import annotations

import json
from typing import Annotated, Any

import typer
from rich import box
from rich.table import Table

from frontier_rl.cli.output import friendly_errors, stdout_console
from frontier_rl.io.catalogue import Catalogue, CatalogueMap, MapCollection, catalogue
from frontier_rl.io.map_size import MapSize

COLUMNS = ("name", "family", "cells", "size (m)", "res. (m)", "licence", "installed", "source")
"""The table's columns (``installed`` only where a map is not; ``--json`` gives the same and more:
the description, the full source address)."""


def _size(entry: CatalogueMap | MapCollection, maps: Catalogue) -> MapSize | None:
    """A map's size; a collection's where its members share one (its first member's), else None."""
    if isinstance(entry, CatalogueMap):
        return entry.size()
    members = maps.members(entry)
    return members[0].size() if entry.uniform_size and members else None


def _installed(entry: CatalogueMap | MapCollection, maps: Catalogue) -> str:
    """Whether it is installed: yes, no, or (a collection missing some members) partly."""
    if isinstance(entry, CatalogueMap):
        return "yes" if entry.installed else "no"
    present = [m.installed for m in maps.members(entry)]
    return "yes" if present and all(present) else ("partly" if any(present) else "no")


def entry_record(entry: CatalogueMap | MapCollection, maps: Catalogue) -> dict[str, Any]:
    """One map or collection as plain values (what ``--json`` prints): sizes in cells and m, or
    None where unknown (not installed, or a collection whose members differ)."""
    size = _size(entry, maps)
    record: dict[str, Any] = {
        "name": entry.name,
        "kind": "map" if isinstance(entry, CatalogueMap) else "collection",
        "family": str(entry.family),
        "description": entry.description,
        "width_cells": None if size is None else size.width_cells,
        "height_cells": None if size is None else size.height_cells,
        "width_m": None if size is None else round(size.width_m, 4),
        "height_m": None if size is None else round(size.height_m, 4),
        "resolution_m": None if size is None else size.resolution_m,
        "source": entry.source,
        "licence": entry.licence,
        "installed": _installed(entry, maps),
    }
    if isinstance(entry, MapCollection):
        record["count"] = len(entry.members)
    return record


def _row(record: dict[str, Any]) -> tuple[str, ...]:
    varies = "varies" if record["kind"] == "collection" else "—"
    known = record["width_cells"] is not None
    name = f"{record['name']} ({record['count']} maps)" if record["kind"] == "collection" else record["name"]
    return (
        name,
        record["family"],
        f"{record['width_cells']} × {record['height_cells']}" if known else varies,
        f"{record['width_m']:.1f} × {record['height_m']:.1f}" if known else varies,
        f"{record['resolution_m']:g}" if known else varies,
        record["licence"],
        record["installed"],
        _repository(record["source"]),
    )


def _repository(url: str) -> str:
    """A source address as the table shows it: a GitHub repository's owner/name (the full address is in --json)."""
    path = url.removeprefix("https://").removeprefix("github.com/")
    return "/".join(path.split("/")[:2]) if path != url.removeprefix("https://") else path


def _entries(name: str | None, maps: Catalogue) -> tuple[CatalogueMap | MapCollection, ...]:
    """What to list: the catalogue (maps in no collection, then the collections), a collection's
    members, or the one map ``name``."""
    if name is None:
        return maps.listed()
    entry = maps.get(name)
    return maps.members(entry) if isinstance(entry, MapCollection) else (entry,)


@friendly_errors
def maps_command(
    name: Annotated[
        str | None, typer.Argument(help="A collection to list the maps of (e.g. dungeon/easy), or one map.")
    ] = None,
    as_json: Annotated[bool, typer.Option("--json", help="Print a JSON list instead of a table.")] = False,
) -> None:
    """The maps that ship with frontier_rl: pass a name as --world, or a collection in a world list."""
    maps = catalogue()
    records = [entry_record(entry, maps) for entry in _entries(name, maps)]
    console = stdout_console()
    if as_json:
        console.out(json.dumps(records, indent=2), highlight=False)
        return
    title = f"{name}: {len(records)} maps" if name and len(records) > 1 else "Maps that ship with frontier_rl"
    table = Table(title=title, box=box.SIMPLE_HEAD)
    everything_here = all(record["installed"] == "yes" for record in records)
    columns = [c for c in COLUMNS if c != "installed" or not everything_here]
    for column in columns:
        left = column in ("name", "family", "source", "licence")
        table.add_column(column, justify="left" if left else "right", no_wrap=column == "name", overflow="fold")
    for record in records:
        table.add_row(*(cell for column, cell in zip(COLUMNS, _row(record), strict=True) if column in columns))
    console.print(table)
    for record in records:
        if record["installed"] != "yes":
            console.print(f"{record['name']}: not installed here; get it from {record['source']} and pass the path.")
    if name is None:
        console.print("A collection lists its maps with `frontier-rl maps NAME`, e.g. `frontier-rl maps dungeon/easy`.")
