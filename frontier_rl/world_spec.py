"""World arguments: a generator name, a map file or a catalogue map turned into a :class:`World`,
and world lists ("office,rooms=2,maps/,dungeon/easy") parsed into families of worlds with sampling
weights and train / validation splits.

A world is looked up in this order: a generator's name, then an existing file or folder, then a
name of the map catalogue (:mod:`frontier_rl.io.catalogue`; ``frontier-rl maps`` lists it). A
catalogue collection stands where a folder would, its members by their catalogue names, so a
results folder names them as given, wherever the package is installed."""

from __future__ import annotations

import contextlib
import hashlib
import math
from dataclasses import dataclass, field, replace
from functools import lru_cache
from pathlib import Path

import numpy as np

from frontier_rl.core.world.catalog import WORLD_GENERATORS, generate_world
from frontier_rl.core.world.robot import Pose, checked_pose
from frontier_rl.core.world.scale import MAPPING_CELL_M, RESAMPLE_BELOW_M, checked_resolution, resolution_bounds
from frontier_rl.core.world.worlds import World, make_world
from frontier_rl.errors import ConfigError, MapError, UnknownNameError, short_repr
from frontier_rl.io import LoadedMap, load_map
from frontier_rl.io.catalogue import CatalogueEntry, CatalogueMap, MapCollection, catalogue
from frontier_rl.io.ros_map import ros_map_image
from frontier_rl.map_fingerprint import MapFingerprint


def _unknown_world(spec: str) -> UnknownNameError:
    return UnknownNameError(
        f"unknown world {short_repr(spec)}: not one of {', '.join(sorted(WORLD_GENERATORS))}, no such file or "
        "folder, and no catalogue map of that name (`frontier-rl maps` lists them)"
    )


def _catalogued(spec: str, base_dir: str | Path | None) -> CatalogueEntry | None:
    """The catalogue entry ``spec`` names, or None for a generator or an existing path (which come first).

    Raises:
        UnknownNameError: none of the three.
    """
    if spec in WORLD_GENERATORS or _exists(str(Path(base_dir or ".", spec))):
        return None
    entry = catalogue().find(spec)
    if entry is None:
        raise _unknown_world(spec)
    return entry


def _located(spec: str, base_dir: str | Path | None) -> tuple[Path | None, CatalogueEntry | None]:
    """What :func:`world_path` gives, and the catalogue entry it was found as (None for a generator
    or an existing path): the catalogue is looked up once."""
    if spec in WORLD_GENERATORS:
        return None, None
    if not spec.strip():  # else the current folder
        raise _unknown_world(spec)
    entry = _catalogued(spec, base_dir)
    if entry is None:
        return (Path(spec) if base_dir is None else Path(base_dir, spec)), None
    if isinstance(entry, MapCollection):
        return entry.folder, entry
    if not entry.installed:
        raise MapError(entry.not_installed())
    return entry.path, entry


def world_path(spec: str, base_dir: str | Path | None = None) -> Path | None:
    """The file or folder the world ``spec`` names: None for a generator, an existing path (a
    relative one against ``base_dir``, default the current directory), else a catalogue map's file
    or a collection's folder.

    Raises:
        UnknownNameError: none of these.
        MapError: a catalogue map that is not installed (the message says where to get it).
    """
    return _located(spec, base_dir)[0]


def _map_located(spec: str, base_dir: str | Path | None) -> tuple[Path, CatalogueMap | None]:
    """What :func:`map_file` gives, and the catalogue map it was found as (None for a path)."""
    path, entry = _located(spec, base_dir)
    if path is None:
        raise ConfigError(f"world {short_repr(spec)} is a generator, not a map file")
    if isinstance(entry, MapCollection):
        raise ConfigError(f"world {short_repr(spec)} is a collection of maps; `frontier-rl maps {spec}` lists them")
    return path, entry


def map_file(spec: str, base_dir: str | Path | None = None) -> Path:
    """The map file the world ``spec`` names (:func:`world_path`), given a path or a catalogue map.

    Raises:
        ConfigError: a generator or a catalogue collection (they name no one file).
        UnknownNameError, MapError: as :func:`world_path`.
    """
    return _map_located(spec, base_dir)[0]


def world_name(spec: str, base_dir: str | Path | None = None) -> str:
    """The name of the world ``spec`` names, as :func:`resolve_world` gives it, without reading a
    map: a generator's or catalogue map's own name, a map file's stem.

    Raises:
        UnknownNameError, ConfigError, MapError: as :func:`resolve_world`.
    """
    if spec in WORLD_GENERATORS:
        return spec
    path, entry = _map_located(spec, base_dir)
    return _map_name(spec, path, entry)


def _map_name(spec: str, path: Path, entry: CatalogueMap | None) -> str:
    return spec if entry is not None else path.stem


def resolve_world(
    spec: str,
    seed: int,
    start: Pose | None = None,
    resolution: float | None = None,
    *,
    stored_start: bool = True,
    base_dir: str | Path | None = None,
) -> World:
    """The world named by ``spec``: a procedural generator ("office", "rooms", "cluttered", ...)
    drawn with ``seed``, or a map file (ROS YAML, DungeonMaps PNG, HouseExpo JSON, bitmap) or a
    catalogue map read once per process and version of the file (:func:`read_map`). The one
    resolver of the CLI, the evaluation's episodes and the environments' worlds. A catalogue
    map's world is called by its catalogue name, a file's by its stem.

    Args:
        spec: generator name, path or catalogue name.
        seed: seeds the generator, or the random start on a map file without one.
        start: a start pose that replaces the generated / stored one.
        resolution: cell size (m) for map files that carry none (bitmaps, HouseExpo); checked
            (:func:`checked_resolution`) before the file is read, whatever the world.
        stored_start: keep a start stored in the map file; False draws one with ``seed`` all the
            same (training starts every episode at a random free cell).
        base_dir: the folder a relative path is found in (default: the current directory).

    Raises:
        UnknownNameError: neither a generator, an existing file nor a catalogue name.
        ConfigError: a resolution or start no world can use; a catalogue collection.
        MapError: a map file that cannot be used, a catalogue map that is not installed.
    """
    resolution = checked_resolution(resolution, "resolution")
    if start is not None:
        start = checked_pose(start, "start pose")
    if spec in WORLD_GENERATORS:
        world = generate_world(spec, seed)
        return world if start is None else make_world(world.grid, world.name, start=start)
    path, entry = _map_located(spec, base_dir)
    loaded = read_map(str(path), resolution)
    start = start or (loaded.start if stored_start else None)
    name = _map_name(spec, path, entry)
    try:
        return make_world(loaded.grid, name, start=start, rng=np.random.default_rng(seed))
    except MapError as error:  # the map read, but no robot fits on it: name the file
        raise MapError(f"{spec}: {error}") from None


def read_map(path: str, resolution: float | None = None) -> LoadedMap:
    """The map file or catalogue map ``path`` (:func:`~frontier_rl.io.load_map`) as the robot maps it: a grid on
    cells finer than ``RESAMPLE_BELOW_M`` (0.04 m) is resampled to ``MAPPING_CELL_M`` (0.05 m;
    :meth:`~frontier_rl.core.world.grid.OccupancyGrid.resampled`), as a robot's SLAM maps a
    finely drawn building on its own cells. Read once per process and version
    of the file (its resolved path, size and modification time; for a ROS map, the YAML's: an
    image rewritten without its YAML is not noticed), the last 128 kept: reading can take longer
    than an episode. Errors name a file ``path`` as given."""
    file = map_file(path)
    given = path if file == Path(path) else str(file)
    resolved = file.resolve()
    stat = resolved.stat()
    return _read_map_version(_MapVersion(str(resolved), resolution, stat.st_size, stat.st_mtime_ns, given))


def world_fingerprint(world: str, resolution: float | None) -> str:
    """A generator's name, or a map file's path or catalogue name as given with a hash of the grid
    it loads as (the same for a catalogue map wherever the package is installed)."""
    if world in WORLD_GENERATORS:
        return world
    return str(MapFingerprint(world, map_digest(read_map(world, resolution))))


def map_digest(loaded: LoadedMap) -> str:
    """A hash of a loaded map's grid, cells, origin and start (16 hex digits)."""
    digest = hashlib.sha256(loaded.grid.data.tobytes())
    digest.update(repr((loaded.grid.shape, loaded.grid.resolution, loaded.grid.origin, loaded.start)).encode())
    return digest.hexdigest()[:16]


@dataclass(frozen=True)
class _MapVersion:
    """A map file's cache key; ``given`` (the path as the caller wrote it) is not part of it."""

    resolved: str
    resolution: float | None
    size: int
    mtime_ns: int
    given: str = field(compare=False, hash=False)


@lru_cache(maxsize=128)
def _read_map_version(version: _MapVersion) -> LoadedMap:
    loaded = load_map(version.given, resolution=version.resolution)
    if not resolution_bounds()[0] <= loaded.grid.resolution < RESAMPLE_BELOW_M:
        return loaded  # as drawn, or a cell no world accepts, which make_world names as the file has it
    return replace(loaded, grid=loaded.grid.resampled(MAPPING_CELL_M))


MAP_SUFFIXES = (".yaml", ".yml", ".png", ".pgm", ".json")
"""The file endings read as maps when a folder is given as a world."""

SPLITS = ("train", "validation")
"""The parts of a world family: a folder's validation files are never trained on."""

VALIDATION_SHARE = 10
"""About one file in this many (those whose name hashes to 0 modulo it, and at least one) of a
folder of at least as many map files is a validation file; folders with fewer files are used whole
by both splits (their validation episodes differ in start pose only)."""

MAX_WEIGHT = 1e6


@dataclass(frozen=True)
class WorldFamily:
    """One entry of a world list: a generator, a map file or a folder of map files, drawn with
    probability ``weight`` over the sum of the weights of the list.

    Attributes:
        spec: the entry as given, without its weight.
        members: the generator name, or the map files (a folder's, sorted).
        weight: the sampling weight (> 0).
    """

    spec: str
    members: tuple[str, ...]
    weight: float = 1.0

    def split(self, part: str) -> tuple[str, ...]:
        """The members of the ``train`` or ``validation`` part (see :data:`VALIDATION_SHARE`)."""
        if part not in SPLITS:
            raise ConfigError(f"unknown split {short_repr(part)}; choose one of {', '.join(SPLITS)}")
        if len(self.members) < VALIDATION_SHARE:
            return self.members
        held_out = tuple(m for m in self.members if _name_hash(m) % VALIDATION_SHARE == 0)
        if not held_out:  # no name drew a validation hash: the least hash, so that neither part is empty
            held_out = (min(self.members, key=_name_hash),)
        if len(held_out) == len(self.members):
            return self.members
        return held_out if part == "validation" else tuple(m for m in self.members if m not in held_out)


def _name_hash(member: str) -> int:
    """A hash of the member's file name: a catalogue map's is its file's, so that a collection
    splits as its folder does."""
    entry = _catalogued(member, None)
    name = entry.path.name if isinstance(entry, CatalogueMap) else Path(member).name
    digest = hashlib.sha256(name.encode("utf-8", "surrogateescape")).digest()
    return int.from_bytes(digest[:8], "big")


def _weighted(item: str) -> tuple[str, float | None]:
    """``item`` split into its spec and its weight ("rooms=2" -> ("rooms", 2.0)); no weight when
    it has no "=" or names an existing file or folder as it is."""
    spec, sep, text = item.rpartition("=")
    if not sep or item in WORLD_GENERATORS or _exists(item) or catalogue().find(item):
        return item, None
    if not spec.strip():
        raise ConfigError(f"world {short_repr(item)} names no world before its weight")
    try:
        weight = float(text)
    except ValueError:
        weight = math.nan
    if not (math.isfinite(weight) and 0 < weight <= MAX_WEIGHT):
        raise ConfigError(
            f"world weight must be a number in (0, {MAX_WEIGHT:g}], got {short_repr(text)} in {short_repr(item)}"
        )
    return spec.strip(), weight


def _exists(item: str) -> bool:
    try:
        return Path(item).exists()
    except OSError as exc:  # a name too long for the file system, ...
        raise ConfigError(f"world {short_repr(item)}: {exc.strerror or exc}") from None


def _members(item: str) -> tuple[str, ...]:
    """The generator name, the map file or catalogue map, a folder's map files (:func:`_folder_maps`),
    or a catalogue collection's maps (by their catalogue names)."""
    entry = _catalogued(item, None)
    if isinstance(entry, MapCollection):
        if not entry.members:
            raise ConfigError(f"catalogue collection {short_repr(item)} has no maps installed ({entry.folder})")
        return entry.members
    if entry is not None:
        return (item,)
    path = Path(item)
    if item not in WORLD_GENERATORS and path.is_dir():
        files = _folder_maps(path)
        if not files:
            raise ConfigError(f"world folder {short_repr(item)} holds no map files ({', '.join(MAP_SUFFIXES)})")
        return files
    if item in WORLD_GENERATORS or path.is_file():
        return (item,)
    raise _unknown_world(item)


def _folder_maps(folder: Path) -> tuple[str, ...]:
    """The map files of ``folder``, sorted: each map once, so a ROS map's image, read through its
    YAML, is not also a bitmap of its own (the image a YAML names, or one of the YAML's stem)."""
    files = sorted(p for p in folder.iterdir() if p.suffix.lower() in MAP_SUFFIXES)
    yamls = [p for p in files if p.suffix.lower() in (".yaml", ".yml")]
    stems = {p.with_suffix("") for p in yamls}
    images = set()
    for yaml_file in yamls:
        with contextlib.suppress(MapError):  # a broken YAML is refused where its map is loaded, named
            images.add(_resolved(ros_map_image(yaml_file)))
    return tuple(str(p) for p in files if p in yamls or not (p.with_suffix("") in stems or _resolved(p) in images))


def _resolved(path: Path) -> Path:
    """``path`` resolved; a symbolic link that loops is refused, naming it (Python 3.11 raises a
    RuntimeError, a traceback at the command line)."""
    try:
        return path.resolve()
    except (RuntimeError, OSError) as error:
        raise MapError(f"{path}: cannot be resolved ({error})") from None


def parse_world_mix(text: str) -> tuple[WorldFamily, ...]:
    """A comma-separated world list ("office=2,rooms,maps/=0.5,dungeon/easy") as families of
    worlds: each entry a generator name, a map file or a folder of map files, or a catalogue map
    or collection, with an optional sampling weight after "=" (default 1; a folder's or a
    collection's weight is shared by its files).

    Raises:
        UnknownNameError: an entry that is neither a generator, an existing file or folder nor a
            catalogue name.
        ConfigError: no entries, a weight that is not a number in (0, 10⁶], a folder without map files.
    """
    families = tuple(world_family(item) for item in world_entries(text))
    if not families:
        raise ConfigError(f"no worlds given in {short_repr(text)}")
    return families


def world_entries(text: str) -> tuple[str, ...]:
    """The entries of a comma-separated world list, stripped, empty ones dropped."""
    return tuple(item for item in (part.strip() for part in text.split(",")) if item)


def world_family(item: str) -> WorldFamily:
    """One entry of a world list ("rooms=2", "maps/", a file name that may hold commas) as a
    family (see :func:`parse_world_mix`)."""
    spec, weight = _weighted(item.strip())
    return WorldFamily(spec, _members(spec), 1.0 if weight is None else weight)


def parse_world_list(text: str) -> tuple[str, ...]:
    """The worlds of a comma-separated list ("office,rooms,maps/,dungeon/easy"), folders expanded
    into the map files they hold and catalogue collections into their maps' names: what an
    evaluation runs its episodes on, each world alike.

    Raises:
        ConfigError: an entry with a weight ("rooms=2": weights are for training mixes), and the
            errors of :func:`parse_world_mix`.
    """
    families = parse_world_mix(text)
    weighted = [item for family, item in zip(families, world_entries(text), strict=True) if item != family.spec]
    if weighted:
        raise ConfigError(
            f"world {short_repr(weighted[0])} has a weight: weights (NAME=W) set how often training "
            "draws a world; here every world runs the same number of episodes"
        )
    return tuple(m for f in families for m in f.members)
