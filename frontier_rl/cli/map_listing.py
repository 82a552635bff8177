"""What ``frontier-rl maps [NAME]`` prints: the maps that ship with frontier_rl, by the names ``--world``
takes (:mod:`frontier_rl.io.catalogue`), as a table that fits the terminal or as JSON.

The catalogue decides what a map or a collection is, its size and whether it is installed; this
module only lays that out."""

from __future__ import annotations

import json
from collections.abc import Callable, Sequence
from dataclasses import dataclass

from rich import box
from rich.console import Console
from rich.table import Table

from frontier_rl.cli.output import stdout_console, whole_width
from frontier_rl.io.catalogue import CatalogueEntry, CatalogueMap, MapCollection, catalogue

JsonValue = str | int | float | bool | None


def entry_record(entry: CatalogueEntry) -> dict[str, JsonValue]:
    """One map or collection as ``--json`` prints it, every field always present (None where unknown):

    - ``name``: the catalogue name (``--world`` takes it); ``kind``: ``"map"`` or ``"collection"``;
    - ``family``: ``ros``, ``stage``, ``dungeon`` or ``houseexpo`` (the file format);
    - ``description``: what it is, in a few words;
    - ``width_cells``, ``height_cells`` (int), ``width_m``, ``height_m``, ``resolution_m`` (float, m):
      the grid the map loads as; None for a map that is not installed or a collection whose maps
      differ in size;
    - ``licence``: an SPDX identifier where the origin names one, otherwise the origin's own words;
    - ``source``: the full upstream address (where to get a map that is not installed);
    - ``in_wheel``: whether the wheel carries it;
    - ``installed`` (bool): the map's files are here; a collection's: it has maps and all are here;
    - ``count``, ``installed_count`` (int): a collection's maps, and how many are installed; None for a map.
    """
    size = entry.size()
    collection = entry if isinstance(entry, MapCollection) else None
    return {
        "name": entry.name,
        "kind": "map" if collection is None else "collection",
        "family": str(entry.family),
        "description": entry.description,
        "width_cells": None if size is None else size.width_cells,
        "height_cells": None if size is None else size.height_cells,
        "width_m": None if size is None else _metres_value(size.width_m),
        "height_m": None if size is None else _metres_value(size.height_m),
        "resolution_m": None if size is None else size.resolution_m,
        "licence": entry.licence,
        "source": entry.source,
        "in_wheel": entry.in_wheel,
        "installed": entry.installed,
        "count": None if collection is None else len(collection.maps),
        "installed_count": None if collection is None else collection.installed_count,
    }


def _metres_value(metres: float) -> float:
    """A length (m) as listed: to 0.1 mm, so that 307 cells of 0.05 m read 15.35, not 15.350000000000001."""
    return round(metres, 4)


@dataclass(frozen=True)
class _Column:
    """A column of the table: its header, its cell for an entry, and its alignment."""

    header: str
    cell: Callable[[CatalogueEntry], str]
    right: bool = False


def _varies(entry: CatalogueEntry) -> str:
    """What a size cell says where there is no size: a collection's maps differ, or nothing is installed."""
    return "varies" if isinstance(entry, MapCollection) and not entry.uniform_size else "—"


def _cells(entry: CatalogueEntry) -> str:
    size = entry.size()
    return _varies(entry) if size is None else f"{size.width_cells} × {size.height_cells}"


def _metres(entry: CatalogueEntry) -> str:
    size = entry.size()
    return _varies(entry) if size is None else f"{_metres_value(size.width_m):.1f} × {_metres_value(size.height_m):.1f}"


def _resolution(entry: CatalogueEntry) -> str:
    size = entry.size()
    return _varies(entry) if size is None else f"{size.resolution_m:g}"


def _installed(entry: CatalogueEntry) -> str:
    """yes, no, or how many of a collection's maps are installed where some are."""
    if entry.installed:
        return "yes"
    if isinstance(entry, MapCollection) and entry.installed_count:
        return f"{entry.installed_count} of {len(entry.maps)}"
    return "no"


def _repository(entry: CatalogueEntry) -> str:
    """The source as the table shows it: a GitHub repository's owner/name (the full address is in
    ``maps NAME`` and ``--json``)."""
    path = entry.source.removeprefix("https://")
    return "/".join(path.removeprefix("github.com/").split("/")[:2]) if path.startswith("github.com/") else path


NAME = _Column("name", lambda e: e.name)
MAPS = _Column("maps", lambda e: str(len(e.maps)) if isinstance(e, MapCollection) else "", right=True)
FAMILY = _Column("family", lambda e: str(e.family))
CELLS = _Column("cells", _cells, right=True)
METRES = _Column("size (m)", _metres, right=True)
RESOLUTION = _Column("res (m)", _resolution, right=True)
LICENCE = _Column("licence", lambda e: e.licence)
INSTALLED = _Column("installed", _installed)
SOURCE = _Column("source", _repository)
LEFT_OUT_FIRST = (SOURCE, CELLS, MAPS, FAMILY, METRES, LICENCE, RESOLUTION)
"""The columns a narrow terminal loses, in this order, until the table fits: at 80 columns only the
source and the size in cells (the size in metres over the resolution; ``maps NAME`` and ``--json``
give every field), so that a collection still shows how many maps it holds; the name folds only on
a terminal narrower still."""


def _table(columns: Sequence[_Column], entries: Sequence[CatalogueEntry], title: str | None) -> Table:
    table = Table(title=title, box=box.SIMPLE_HEAD, show_edge=False, pad_edge=False, collapse_padding=True)
    for column in columns:
        fold = column is NAME  # the one column that may wrap, and only where nothing else fits
        table.add_column(column.header, justify="right" if column.right else "left", no_wrap=not fold, overflow="fold")
    for entry in entries:
        table.add_row(*(column.cell(entry) for column in columns))
    return table


def _fitted_table(
    columns: Sequence[_Column], entries: Sequence[CatalogueEntry], console: Console, title: str | None = None
) -> Table:
    """The table of ``entries`` with as many of ``columns`` as fit the console's width, the
    columns of :data:`LEFT_OUT_FIRST` left out first."""
    shown = list(columns)
    for column in (None, *LEFT_OUT_FIRST):
        shown = [c for c in shown if c is not column]
        table = _table(shown, entries, title)
        if whole_width(console, table) <= console.width:
            return table
    return table


def _details(entry: CatalogueEntry) -> list[tuple[str, str]]:
    """A map's or a collection's fields, whole, as (label, text) lines."""
    size = entry.size()
    lines = [("", entry.description), ("family", str(entry.family))]
    if isinstance(entry, CatalogueMap):
        lines.append(("file", str(entry.path)))
    if size is not None:
        shape = f"{size.width_cells} × {size.height_cells} cells of {size.resolution_m:g} m"
        lines.append(("size", f"{size.width_m:.2f} m × {size.height_m:.2f} m ({shape})"))
    lines += [("licence", entry.licence), ("installed", _installed(entry)), ("source", entry.source)]
    return lines


def _print_details(entry: CatalogueEntry, console: Console) -> None:
    """The heading of ``maps NAME``: every field, the source whole on its own line (soft-wrapped,
    so that it copies as one address)."""
    count = f" ({len(entry.maps)} maps)" if isinstance(entry, MapCollection) else ""
    console.print(f"{entry.name}{count}", style="bold", soft_wrap=True)
    for label, text in _details(entry):
        console.print(f"  {label:<10} {text}" if label else f"  {text}", soft_wrap=True)


def _not_installed(entries: Sequence[CatalogueEntry], console: Console) -> None:
    for entry in entries:
        if not entry.installed:
            console.print(entry.not_installed())


def _installed_column(entries: Sequence[CatalogueEntry]) -> list[_Column]:
    """The installed column, where something is not (a wheel leaves Stage's bitmaps out)."""
    return [] if all(e.installed for e in entries) else [INSTALLED]


def _print_listing(entries: Sequence[CatalogueEntry], console: Console) -> None:
    columns = [NAME, MAPS, FAMILY, CELLS, METRES, RESOLUTION, LICENCE, *_installed_column(entries), SOURCE]
    console.print(_fitted_table(columns, entries, console, "Maps that ship with frontier_rl"))
    console.print()
    _not_installed(entries, console)
    console.print(
        "`frontier-rl maps NAME` describes a map or lists a collection's maps (e.g. dungeon/easy); "
        "--json gives every field."
    )


def _print_collection(collection: MapCollection, console: Console) -> None:
    """Its fields, then its maps without what they all share with it."""
    _print_details(collection, console)
    console.print()
    maps = collection.maps
    licences = [LICENCE] if any(m.licence != collection.licence for m in maps) else []
    console.print(_fitted_table([NAME, CELLS, METRES, RESOLUTION, *licences, *_installed_column(maps)], maps, console))
    if not collection.installed:
        console.print()
        _not_installed([collection], console)


def show_maps(name: str | None, as_json: bool) -> None:
    """Print the catalogue (``name`` None), a collection's maps or one map, as a table or as JSON."""
    maps = catalogue()
    entry = None if name is None else maps.get(name)
    entries = maps.listed() if entry is None else entry.maps if isinstance(entry, MapCollection) else (entry,)
    console = stdout_console()
    if as_json:
        console.out(json.dumps([entry_record(e) for e in entries], indent=2), highlight=False)
    elif entry is None:
        _print_listing(entries, console)
    elif isinstance(entry, MapCollection):
        _print_collection(entry, console)
    else:
        _print_details(entry, console)
        _not_installed([entry], console)
