"""Map files: ROS ``map_server`` YAML + PGM/PNG (read and write), DungeonMaps PNG, HouseExpo JSON.

:func:`load_map` picks the reader from the file:

* ``.yaml`` / ``.yml``: a ROS ``map_server`` map (no start);
* ``.png`` / ``.pgm`` with a ``map_server`` YAML of the same name beside it that uses it: that map;
* ``.png`` in the DungeonMaps palette with a start marker: a DungeonMaps map (with a start);
* any other ``.png`` / ``.pgm``: a plain bitmap (black wall, white free) read as ``map_server``
  reads it with the default thresholds and the origin at (0, 0);
* ``.json``: a HouseExpo floor plan (no start).

Map files may come from strangers: a YAML is read by :mod:`frontier_rl.safe_yaml` (at most 1 MiB,
no anchors or aliases, YAML-1.2 numbers), an image may have at most :data:`MAX_MAP_PIXELS` pixels,
and a PGM's header must match its pixel data exactly; anything else is a one-line :class:`MapError`.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

from frontier_rl.core.world.grid import CellState
from frontier_rl.errors import MapError, short_repr
from frontier_rl.io._image import MAX_MAP_PIXELS
from frontier_rl.io.dungeon import DUNGEON_RESOLUTION, is_dungeon_image, load_dungeon_map
from frontier_rl.io.houseexpo import HOUSEEXPO_RESOLUTION, load_houseexpo
from frontier_rl.io.loaded_map import LoadedMap, positive_metres
from frontier_rl.io.ros_map import (
    MapImageParams,
    MapMode,
    load_map_image,
    load_ros_map,
    ros_map_image,
    ros_map_shades,
    save_ros_map,
)

__all__ = [
    "BITMAP_RESOLUTION",
    "MAX_MAP_PIXELS",
    "LoadedMap",
    "MapImageParams",
    "MapMode",
    "load_dungeon_map",
    "load_houseexpo",
    "load_map",
    "load_map_image",
    "load_ros_map",
    "ros_map_image",
    "ros_map_shades",
    "save_ros_map",
]

#: Default cell size (m) of a plain bitmap without a YAML.
BITMAP_RESOLUTION = 0.05
_YAML_SUFFIXES = (".yaml", ".yml")
_IMAGE_SUFFIXES = (".png", ".pgm")


def _sibling_yaml(image_path: Path) -> Path | None:
    """The ``map_server`` YAML named like ``image_path`` (``cave.yaml`` for ``cave.png``) that uses it."""
    for suffix in _YAML_SUFFIXES:
        candidate = image_path.with_suffix(suffix)
        if not candidate.is_file():
            continue
        image = ros_map_image(candidate)
        try:
            same = image.resolve() == image_path.resolve()
        except (OSError, ValueError, RuntimeError) as exc:  # a NUL byte, a lone surrogate, a symlink loop
            raise MapError(f"{candidate}: its image {short_repr(str(image))} cannot be resolved: {exc}") from None
        if same:
            return candidate
    return None


def _load(path: Path, resolution: float | None) -> LoadedMap:
    suffix = path.suffix.lower()
    if suffix == ".json":
        return load_houseexpo(path, HOUSEEXPO_RESOLUTION if resolution is None else resolution)
    yaml_path = path if suffix in _YAML_SUFFIXES else None
    if suffix in _IMAGE_SUFFIXES:
        yaml_path = _sibling_yaml(path)
    if yaml_path is not None:
        grid = load_ros_map(yaml_path)
        if resolution is not None:
            grid = replace(grid, resolution=positive_metres(resolution, "resolution", path))
        return LoadedMap(grid=grid, start=None, source=path)
    if suffix == ".png" and is_dungeon_image(path):
        return load_dungeon_map(path, DUNGEON_RESOLUTION if resolution is None else resolution)
    if suffix in _IMAGE_SUFFIXES:
        res = positive_metres(BITMAP_RESOLUTION if resolution is None else resolution, "resolution", path)
        return LoadedMap(grid=load_map_image(path, res, params=MapImageParams()), start=None, source=path)
    raise MapError(f"unsupported map file type {short_repr(path.suffix)}: {path} (use .yaml, .png, .pgm or .json)")


def load_map(path: str | Path, resolution: float | None = None) -> LoadedMap:
    """Load any supported map file, choosing the reader by suffix and content (see the module doc).

    Args:
        path: the map file.
        resolution: cell size (m). None keeps the file's own (ROS YAML) or the format's default
            (DungeonMaps 0.04375, HouseExpo 0.05, plain bitmap 0.05); a value overrides a YAML's.

    Raises:
        MapError: a missing, unsupported or malformed file, or a map without a single free cell.
    """
    source = Path(path)
    if source.is_dir():
        raise MapError(f"{source} is a folder, not a map file: name one of the maps in it")
    if not source.is_file():
        raise MapError(f"map file not found: {source}")
    loaded = _load(source, resolution)
    if loaded.grid.count(CellState.FREE) == 0:
        raise MapError(f"{source}: the map has no free cell")
    return loaded
