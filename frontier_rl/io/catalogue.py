"""The catalogue of the maps frontier_rl ships (``frontier_rl/data/maps``), by name.

Every map has a name (``nav2_depot``, ``stage/cave``, ``houseexpo/<file stem>``,
``dungeon/<level>/<file stem>``), a family, its file, where it comes from and its licence; a
collection (``stage``, ``houseexpo``, ``dungeon/train``, ``dungeon/easy``, ...) names a folder of
them and can stand where a folder of maps does. The descriptions live in one file,
``data/maps/catalogue.yaml``, checked when it is read; a folder collection's members are its
files, listed (not read). A map whose licence keeps it out of the wheel (Stage's GPL-2.0
bitmaps) is still listed, as not installed, with where to get it.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from enum import StrEnum
from functools import lru_cache
from pathlib import Path
from types import MappingProxyType
from typing import Any

from frontier_rl.core.world.catalog import WORLD_GENERATORS
from frontier_rl.errors import MapError, UnknownNameError, short_repr
from frontier_rl.io.dungeon import DUNGEON_RESOLUTION
from frontier_rl.io.map_size import MapSize, houseexpo_size, image_size, ros_map_size
from frontier_rl.io.ros_map import ros_map_image
from frontier_rl.safe_yaml import load_yaml_file

#: The folder of the shipped maps, and the file that describes them.
MAPS_DIR = Path(__file__).resolve().parent.parent / "data" / "maps"
CATALOGUE_FILE = MAPS_DIR / "catalogue.yaml"


class MapFamily(StrEnum):
    """Where a map comes from, which says its format."""

    ROS = "ros"
    """A ROS ``map_server`` map (YAML + PGM) of a real or simulated building."""
    STAGE = "stage"
    """A Stage simulator bitmap, read through a ``map_server`` YAML of this project."""
    DUNGEON = "dungeon"
    """A DungeonMaps PNG (no scale: the loader's 0.04375 m per pixel), with a start."""
    HOUSEEXPO = "houseexpo"
    """A HouseExpo floor plan (JSON polygon in metres, rasterised at 0.05 m)."""


@dataclass(frozen=True)
class CatalogueMap:
    """One map of the catalogue.

    Attributes:
        name: its catalogue name (``--world`` takes it).
        family: where it comes from, and so its format.
        path: the file a world is loaded from (a ROS or Stage map's YAML).
        description: what it is, in a few words.
        source: the upstream address of the file (where to get it when it is not installed).
        licence: its licence as its origin states it: an SPDX identifier where the origin names one
            (``Apache-2.0``), otherwise the origin's own words (``BSD``: a package.xml's ``<license>``
            that names no variant); the SOURCE.md beside the file says more.
        in_wheel: whether the wheel carries it (False where the licence does not fit the package's).
    """

    name: str
    family: MapFamily
    path: Path
    description: str
    source: str
    licence: str
    in_wheel: bool = True

    @property
    def installed(self) -> bool:
        """Whether its file (and a YAML's image) is present."""
        if not self.path.is_file():
            return False
        if self.family in (MapFamily.ROS, MapFamily.STAGE):
            return ros_map_image(self.path).is_file()
        return True

    def size(self) -> MapSize | None:
        """Its size as loaded with the format's default resolution (from the file's header and
        YAML, not its pixels), or None when it is not installed."""
        if not self.installed:
            return None
        if self.family is MapFamily.DUNGEON:
            return image_size(self.path, DUNGEON_RESOLUTION)
        if self.family is MapFamily.HOUSEEXPO:
            return houseexpo_size(self.path)
        return ros_map_size(self.path)

    def not_installed(self) -> str:
        """Why it cannot be loaded and where to get it (one line), for a map that is not installed."""
        why = "its licence keeps it out of the wheel" if not self.in_wheel else "its file is missing"
        return (
            f"catalogue map {self.name!r} is not installed ({why}; {self.licence}): "
            f"get it from {self.source} and pass the file's path as the world"
        )


@dataclass(frozen=True)
class MapCollection:
    """A folder of maps of one family, usable where a folder of maps is.

    Attributes:
        name: its catalogue name.
        family: the family of its maps.
        folder: the folder of its files.
        maps: its maps, in the order of their file names (as a folder's files are): the files
            present, so a missing folder has none.
        description: what it is, in a few words.
        source: the upstream address of the folder.
        licence: its maps' licence, as :attr:`CatalogueMap.licence`.
        uniform_size: every map has the same size (so one stands for all).
        in_wheel: whether the wheel carries its maps.
    """

    name: str
    family: MapFamily
    folder: Path
    maps: tuple[CatalogueMap, ...]
    description: str
    source: str
    licence: str
    uniform_size: bool = False
    in_wheel: bool = True

    @property
    def members(self) -> tuple[str, ...]:
        """Its maps' names (what a world list expands it into)."""
        return tuple(m.name for m in self.maps)

    @property
    def installed_count(self) -> int:
        """How many of its maps are installed."""
        return sum(m.installed for m in self.maps)

    @property
    def installed(self) -> bool:
        """Whether it has maps and every one of them is installed."""
        return bool(self.maps) and all(m.installed for m in self.maps)

    def size(self) -> MapSize | None:
        """The size its maps share (an installed one's), or None: sizes that differ (not
        ``uniform_size``) or no map installed."""
        if not self.uniform_size:
            return None
        return next((m.size() for m in self.maps if m.installed), None)

    def not_installed(self) -> str:
        """Which of its maps are missing and where to get them (one line), for a collection that is
        not wholly installed."""
        why = "its licence keeps its maps out of the wheel" if not self.in_wheel else "its files are missing"
        return (
            f"catalogue collection {self.name!r} has {self.installed_count} of its {len(self.maps)} maps installed "
            f"({why}; {self.licence}): get them from {self.source} and pass their folder as the world"
        )


CatalogueEntry = CatalogueMap | MapCollection
"""A name of the catalogue: one map or a collection."""


@dataclass(frozen=True)
class Catalogue:
    """Every map (collections' members included) and every collection, by name.

    Attributes:
        maps: the maps, in the catalogue file's order, each collection's members after the maps
            the file lists.
        collections: the collections, in the file's order.
    """

    maps: tuple[CatalogueMap, ...]
    collections: tuple[MapCollection, ...]
    _by_name: Mapping[str, CatalogueEntry] = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        by_name: dict[str, CatalogueEntry] = {}
        entries: tuple[CatalogueEntry, ...] = (*self.maps, *self.collections)
        for entry in entries:
            if entry.name in by_name or entry.name in WORLD_GENERATORS:
                raise MapError(f"the map catalogue names {entry.name!r} twice (or as a world generator)")
            by_name[entry.name] = entry
        object.__setattr__(self, "_by_name", MappingProxyType(by_name))

    def find(self, name: str) -> CatalogueEntry | None:
        """The map or collection called ``name``, or None."""
        return self._by_name.get(name)

    def get(self, name: str) -> CatalogueEntry:
        """The map or collection called ``name``.

        Raises:
            UnknownNameError: no such name (the message says ``frontier-rl maps`` lists them).
        """
        entry = self.find(name)
        if entry is None:
            raise UnknownNameError(f"no map {short_repr(name)} in the catalogue; `frontier-rl maps` lists them")
        return entry

    def listed(self) -> tuple[CatalogueEntry, ...]:
        """What a listing shows: the maps that belong to no collection, then the collections."""
        members = {name for collection in self.collections for name in collection.members}
        return (*(m for m in self.maps if m.name not in members), *self.collections)


@lru_cache(maxsize=1)
def catalogue() -> Catalogue:
    """The catalogue of the shipped maps (read once per process)."""
    return load_catalogue(CATALOGUE_FILE)


def load_catalogue(path: Path, maps_dir: Path | None = None) -> Catalogue:
    """Read and check a catalogue file; its files are relative to ``maps_dir`` (default: its folder).

    Raises:
        MapError: a malformed file: a missing or mistyped field, an unknown family, a name used
            twice, a collection member that is no map.
    """
    root = path.parent if maps_dir is None else maps_dir
    doc = load_yaml_file(path, MapError, "map catalogue")
    if not isinstance(doc, dict) or set(doc) != {"maps", "collections"}:
        raise MapError(f"{path}: a map catalogue is a mapping of 'maps' and 'collections'")
    listed = [_map(name, fields, root, path) for name, fields in _section(doc, "maps", path).items()]
    maps = {m.name: m for m in listed}
    collections = []
    for name, fields in _section(doc, "collections", path).items():
        collection = _collection(name, fields, root, path, maps)
        collections.append(collection)
        maps.update((m.name, m) for m in collection.maps if m.name not in maps)
    return Catalogue(tuple(maps.values()), tuple(collections))


def _section(doc: dict[str, Any], key: str, path: Path) -> dict[str, Any]:
    section = doc[key]
    if not isinstance(section, dict) or not all(isinstance(name, str) and name for name in section):
        raise MapError(f"{path}: '{key}' must map names to their fields")
    return section


def _text(fields: dict[str, Any], key: str, where: str) -> str:
    value = fields.get(key)
    if not isinstance(value, str) or not value.strip():
        raise MapError(f"{where}: field '{key}' must be a non-empty string, got {short_repr(value)}")
    return value


def _flag(fields: dict[str, Any], key: str, default: bool, where: str) -> bool:
    value = fields.get(key, default)
    if not isinstance(value, bool):
        raise MapError(f"{where}: field '{key}' must be true or false, got {short_repr(value)}")
    return value


def _family(fields: dict[str, Any], where: str) -> MapFamily:
    text = _text(fields, "family", where)
    try:
        return MapFamily(text)
    except ValueError:
        raise MapError(f"{where}: unknown family {text!r}; one of {', '.join(MapFamily)}") from None


def _checked(fields: Any, allowed: set[str], where: str) -> dict[str, Any]:
    if not isinstance(fields, dict):
        raise MapError(f"{where}: its fields must be a mapping, got {short_repr(fields)}")
    unknown = sorted(str(k) for k in set(fields) - allowed)
    if unknown:
        raise MapError(f"{where}: unknown field(s) {', '.join(unknown)}")
    return fields


def _map(name: str, raw: Any, root: Path, path: Path) -> CatalogueMap:
    where = f"{path}: map {name!r}"
    fields = _checked(raw, {"family", "file", "description", "source", "licence", "wheel"}, where)
    return CatalogueMap(
        name=name,
        family=_family(fields, where),
        path=root / _text(fields, "file", where),
        description=_text(fields, "description", where),
        source=_text(fields, "source", where),
        licence=_text(fields, "licence", where),
        in_wheel=_flag(fields, "wheel", True, where),
    )


def _collection(name: str, raw: Any, root: Path, path: Path, maps: dict[str, CatalogueMap]) -> MapCollection:
    """A collection, its maps each file of its folder with its suffix, named ``NAME/STEM``,
    described by the map of that name where ``maps`` has one (it must be the same file), otherwise
    by the collection."""
    where = f"{path}: collection {name!r}"
    allowed = {"family", "folder", "suffix", "description", "source", "licence", "uniform_size", "wheel"}
    fields = _checked(raw, allowed, where)
    family, folder, suffix = (
        _family(fields, where),
        root / _text(fields, "folder", where),
        _text(fields, "suffix", where),
    )
    source, licence, description = (_text(fields, key, where) for key in ("source", "licence", "description"))
    in_wheel = _flag(fields, "wheel", True, where)
    files = sorted((p for p in folder.iterdir() if p.suffix.lower() == suffix), key=str) if folder.is_dir() else []
    members = []
    for file in files:
        member = maps.get(f"{name}/{file.stem}")
        if member is None:
            member = CatalogueMap(f"{name}/{file.stem}", family, file, description, source, licence, in_wheel)
        elif member.path != file or member.family is not family:
            raise MapError(f"{where}: map {member.name!r} is not its file {file.name} of family {family}")
        members.append(member)
    uniform = _flag(fields, "uniform_size", False, where)
    return MapCollection(name, family, folder, tuple(members), description, source, licence, uniform, in_wheel)
