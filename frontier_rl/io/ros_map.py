"""ROS ``map_server`` maps: a YAML file plus a PGM/PNG image, read and written.

Reading follows ROS 1 ``map_server`` (``image_loader.cpp``): a pixel's brightness is the mean of its
colour channels, ``p = (255 - brightness) / 255`` (``brightness / 255`` with ``negate``), and

* ``trinary`` (default): ``p > occupied_thresh`` is occupied, ``p < free_thresh`` free, else unknown;
* ``scale``: as trinary, but values in between become ``1 + floor(98 * ratio)`` (1..99);
* ``raw``: the (negated) brightness is the cell value; values above 100 become unknown (as Nav2).

A fully transparent pixel is unknown in trinary and scale mode. The image's top row is the map's
highest y, so rows are flipped: row 0 of the grid is the lower-left corner (the grid convention).
One departure, with a warning: where the thresholds read ``map_saver``'s grey unknown (205) as free
and that grey is more than :data:`GREY_AS_FREE_SHARE` of the free cells, it is read as unknown
(:func:`load_ros_map`).
Writing follows ``map_saver``: free 254, occupied 0, unknown 205, thresholds 0.65 / 0.196.

The YAML is read by :mod:`frontier_rl.safe_yaml` (at most 1 MiB, no anchors or aliases, YAML-1.2
numbers as ``yaml-cpp`` reads them: ``6e2`` is 600.0); the image by :func:`~frontier_rl.io._image.read_image`
(at most :data:`~frontier_rl.io._image.MAX_MAP_PIXELS` pixels, a PGM's header must match its data).
"""

from __future__ import annotations

import difflib
import io
import json
import math
import numbers
import warnings
from dataclasses import dataclass
from enum import StrEnum
from pathlib import Path
from typing import Any

import numpy as np
import yaml
from numpy.typing import NDArray
from PIL import Image

from frontier_rl.atomic_write import write_bytes_atomic, write_text_atomic
from frontier_rl.core.world.grid import CellState, OccupancyGrid
from frontier_rl.errors import MapError, MapWarning, short_repr
from frontier_rl.io._image import read_image
from frontier_rl.io.loaded_map import MAX_COORDINATE_M
from frontier_rl.safe_yaml import load_yaml_file, parse_yaml

#: Pixel values that ``map_saver`` writes for each cell state.
FREE_PIXEL = 254
OCCUPIED_PIXEL = 0
UNKNOWN_PIXEL = 205
#: ``map_saver`` thresholds on cell values (occupancy %): <= 25 is saved free, >= 65 occupied.
SAVE_FREE_MAX = 25
SAVE_OCCUPIED_MIN = 65
OCCUPIED_THRESH = 0.65
"""map_server's default occupancy probability above which a cell is occupied (0..1): what a YAML
without ``occupied_thresh`` means, what ``map_saver`` writes, and (as 65 %) how an
``OccupancyGrid`` message's values are read (:class:`~frontier_rl.robot.map_message.MapThresholds`)."""
FREE_THRESH = 0.196
"""map_server's default occupancy probability below which a cell is free (0..1), likewise."""
GREY_AS_FREE_SHARE = 0.1
"""The share of a map's free cells that may be grey :data:`UNKNOWN_PIXEL` read as free before the
grey is read as unknown instead, with a :class:`~frontier_rl.errors.MapWarning`. ``map_saver``
writes unknown as 205, which is free for a ``free_thresh`` above 0.196 (p = 50 / 255 = 0.19608), as
Nav2's default of 0.25 that its ``map_saver`` writes into the YAML: so read (as Nav2's map server
reads it), a SLAM map's whole unknown surround is floor, the building a room in a plain, and the
robot starts and explores outside it. Nav2's depot sample reads 5 % of its free cells so (grey spots
among the shelves), and keeps them free."""
MAP_YAML_FIELDS = ("image", "resolution", "origin", "negate", "occupied_thresh", "free_thresh", "mode")
"""The fields ``map_server`` reads from a map YAML; it ignores any other, and so does this reader,
with a :class:`~frontier_rl.errors.MapWarning` (``mod: raw`` would otherwise read as trinary
without a word)."""

_IMAGE_FORMATS = {"pgm": "PPM", "png": "PNG"}
_MAX_PIXEL = 255.0
_SCALE_SPAN = 98  # scale mode maps the in-between ratio onto 1 .. 1 + 98


class MapMode(StrEnum):
    """How ``map_server`` turns a pixel into a cell value."""

    TRINARY = "trinary"
    SCALE = "scale"
    RAW = "raw"


@dataclass(frozen=True)
class MapImageParams:
    """The pixel-interpretation fields of a ``map_server`` YAML.

    Attributes:
        occupied_thresh: occupancy probability above which a cell is occupied (0..1).
        free_thresh: occupancy probability below which a cell is free (0..1).
        negate: whether white means occupied and black free.
        mode: trinary, scale or raw.
    """

    occupied_thresh: float = OCCUPIED_THRESH
    free_thresh: float = FREE_THRESH
    negate: bool = False
    mode: MapMode = MapMode.TRINARY

    def __post_init__(self) -> None:
        for name in ("occupied_thresh", "free_thresh"):
            value = getattr(self, name)
            if not 0.0 <= value <= 1.0:
                raise MapError(f"{name} must lie in [0, 1], got {short_repr(value)}")
        if self.free_thresh > self.occupied_thresh:
            raise MapError(f"free_thresh {self.free_thresh!r} must not exceed occupied_thresh {self.occupied_thresh!r}")


def pixels_to_cells(
    shade: NDArray[np.float64], transparent: NDArray[np.bool_], params: MapImageParams
) -> NDArray[np.int8]:
    """Cell values (image row order) of pixels with brightness ``shade`` (0..255), as ``map_server``."""
    value = _MAX_PIXEL - shade if params.negate else shade
    if params.mode is MapMode.RAW:
        raw = np.trunc(value)
        return np.where(raw <= CellState.OCCUPIED, raw, CellState.UNKNOWN).astype(np.int8)
    occ = (_MAX_PIXEL - value) / _MAX_PIXEL
    cells = np.full(shade.shape, CellState.UNKNOWN, dtype=np.int8)
    if params.mode is MapMode.SCALE:
        span = max(params.occupied_thresh - params.free_thresh, np.finfo(np.float64).tiny)
        ratio = np.clip((occ - params.free_thresh) / span, 0.0, 1.0)
        cells[:] = 1 + np.floor(_SCALE_SPAN * ratio)
    cells[occ > params.occupied_thresh] = CellState.OCCUPIED
    cells[occ < params.free_thresh] = CellState.FREE
    cells[transparent] = CellState.UNKNOWN
    return cells


def load_map_image(
    image_path: str | Path,
    resolution: float,
    origin: tuple[float, float] = (0.0, 0.0),
    params: MapImageParams | None = None,
) -> OccupancyGrid:
    """An image read as ``map_server`` would with the given fields (resolution m/cell, origin m)."""
    image = read_image(Path(image_path))
    return _grid_of(pixels_to_cells(image.shade, image.transparent, params or MapImageParams()), resolution, origin)


def _grid_of(cells: NDArray[np.int8], resolution: float, origin: tuple[float, float]) -> OccupancyGrid:
    """The grid of cell values in image row order (the image's top row is the map's highest y)."""
    return OccupancyGrid(np.ascontiguousarray(np.flipud(cells)), resolution, origin)


def _read_yaml(path: Path) -> dict[str, Any]:
    """The fields of a map YAML, read by :func:`frontier_rl.safe_yaml.load_yaml_file` (bounded, no aliases)."""
    if not path.is_file():
        raise MapError(f"map file not found: {path}")
    doc = load_yaml_file(path, MapError, "map YAML")
    if not isinstance(doc, dict):
        raise MapError(f"{path}: a map YAML must be a mapping of fields, got {type(doc).__name__}")
    return doc


def _field(doc: dict[str, Any], key: str, path: Path) -> Any:
    if key not in doc:
        raise MapError(f"{path}: missing field '{key}'")
    return doc[key]


def _number(value: Any, key: str, path: Path) -> float:
    """A finite number; numeric strings are accepted as yaml-cpp does."""
    number: float | None = None
    if isinstance(value, numbers.Real) and not isinstance(value, bool):
        number = float(value)
    elif isinstance(value, str):
        try:
            number = float(value)
        except ValueError:
            number = None
    if number is None or not math.isfinite(number):
        raise MapError(f"{path}: field '{key}' must be a finite number, got {short_repr(value)}")
    return number


def _resolution(doc: dict[str, Any], path: Path) -> float:
    resolution = _number(_field(doc, "resolution", path), "resolution", path)
    if resolution <= 0:
        raise MapError(f"{path}: field 'resolution' must be positive (m/cell), got {short_repr(resolution)}")
    return resolution


def _params(doc: dict[str, Any], path: Path) -> MapImageParams:
    negate = _field(doc, "negate", path)
    if negate not in (0, 1) or not isinstance(negate, int):
        raise MapError(f"{path}: field 'negate' must be 0 or 1, got {short_repr(negate)}")
    mode_name = doc.get("mode", MapMode.TRINARY.value)
    if not isinstance(mode_name, str) or mode_name.lower() not in {m.value for m in MapMode}:
        raise MapError(f"{path}: field 'mode' must be trinary, scale or raw, got {short_repr(mode_name)}")
    try:
        return MapImageParams(
            occupied_thresh=_number(_field(doc, "occupied_thresh", path), "occupied_thresh", path),
            free_thresh=_number(_field(doc, "free_thresh", path), "free_thresh", path),
            negate=bool(negate),
            mode=MapMode(mode_name.lower()),
        )
    except MapError as exc:
        raise MapError(f"{path}: {exc}") from exc


def _image_path(doc: dict[str, Any], path: Path) -> Path:
    image = _field(doc, "image", path)
    if not isinstance(image, str) or not image.strip():
        raise MapError(f"{path}: field 'image' must be a file name, got {short_repr(image)}")
    image_path = Path(image)
    return image_path if image_path.is_absolute() else path.parent / image_path


def ros_map_image(yaml_path: str | Path) -> Path:
    """The image file that a ``map_server`` YAML refers to (resolved against the YAML's folder)."""
    path = Path(yaml_path)
    return _image_path(_read_yaml(path), path)


def ros_map_shades(yaml_path: str | Path) -> tuple[NDArray[np.float64], float]:
    """The brightness (0..255, image order) of every pixel of a ``map_server`` map's image, before
    its thresholds, and the map's resolution (m/pixel): what tools that read the raw image see
    (Explore-Bench's ground truth is its pixels that are not grey 205)."""
    path = Path(yaml_path)
    doc = _read_yaml(path)
    return read_image(_image_path(doc, path)).shade, _resolution(doc, path)


def load_ros_map(yaml_path: str | Path) -> OccupancyGrid:
    """Read a ``map_server`` map (YAML + image) into an :class:`OccupancyGrid`: as ``map_server``
    reads it, but for ``map_saver``'s grey unknown where the YAML's thresholds make it more than
    :data:`GREY_AS_FREE_SHARE` of the free cells (read as unknown, with a
    :class:`~frontier_rl.errors.MapWarning`).

    Args:
        yaml_path: the YAML file; its ``image`` is resolved relative to the YAML's folder.

    Raises:
        MapError: a missing or malformed file or field, a rotated origin (yaw != 0) or a bad image.
    """
    path = Path(yaml_path)
    doc = _read_yaml(path)
    image_path = _image_path(doc, path)
    resolution = _resolution(doc, path)
    origin = _field(doc, "origin", path)
    if not isinstance(origin, list | tuple) or len(origin) != 3:
        raise MapError(f"{path}: field 'origin' must be [x, y, yaw], got {short_repr(origin)}")
    x, y, yaw = (_number(v, "origin", path) for v in origin)
    if max(abs(x), abs(y)) > MAX_COORDINATE_M:
        raise MapError(f"{path}: field 'origin' must lie within +-{MAX_COORDINATE_M:g} m, got {short_repr(origin)}")
    if yaw != 0.0:
        raise MapError(f"{path}: rotated maps are not supported, origin yaw is {short_repr(yaw)} rad")
    params = _params(doc, path)
    _warn_of_unknown_fields(doc, path)
    if not image_path.is_file():
        raise MapError(f"{path}: image file not found: {image_path}")
    image = read_image(image_path)
    cells = pixels_to_cells(image.shade, image.transparent, params)
    _grey_as_unknown(path, params, image.shade, cells)
    return _grid_of(cells, resolution, (x, y))


def _warn_of_unknown_fields(doc: dict[str, Any], path: Path) -> None:
    """A :class:`~frontier_rl.errors.MapWarning` naming the fields of ``doc`` that ``map_server``
    does not read (at most five, each with the field it may be a slip for)."""
    unknown = [str(key) for key in doc if key not in MAP_YAML_FIELDS]
    if not unknown:
        return
    named = []
    for key in unknown[:5]:
        close = difflib.get_close_matches(key, MAP_YAML_FIELDS, n=1)
        named.append(short_repr(key) + (f" (did you mean {close[0]}?)" if close else ""))
    more = f" and {len(unknown) - 5} more" if len(unknown) > 5 else ""
    warnings.warn(
        f"{path}: field{'s' if len(unknown) > 1 else ''} {', '.join(named)}{more} ignored: map_server reads "
        f"only {', '.join(MAP_YAML_FIELDS)}",
        MapWarning,
        stacklevel=3,
    )


def _grey_as_unknown(path: Path, params: MapImageParams, shade: NDArray[np.float64], cells: NDArray[np.int8]) -> None:
    """Mark unknown, in ``cells`` (in place), the free cells that are pixels of map_saver's grey
    unknown (:data:`UNKNOWN_PIXEL`, by their ``shade``), with a :class:`~frontier_rl.errors.MapWarning`,
    where they are more than :data:`GREY_AS_FREE_SHARE` of the free cells; nothing to count where
    the thresholds do not read that grey as free (most maps)."""
    one_grey = pixels_to_cells(np.full((1, 1), float(UNKNOWN_PIXEL)), np.zeros((1, 1), np.bool_), params)
    if one_grey[0, 0] != CellState.FREE:
        return
    free = cells == CellState.FREE
    grey_free = (np.rint(shade) == UNKNOWN_PIXEL) & free
    count = int(np.count_nonzero(grey_free))
    share = count / max(int(np.count_nonzero(free)), 1)
    if share > GREY_AS_FREE_SHARE:
        cells[grey_free] = CellState.UNKNOWN
        warnings.warn(
            f"{path}: {count:,} pixel{'s' if count > 1 else ''} of grey {UNKNOWN_PIXEL} (map_saver's unknown, "
            f"{share:.0%} of the free cells) read as unknown, not as free space as free_thresh "
            f"{params.free_thresh:g} would have them; set free_thresh: {FREE_THRESH} in the YAML to say so",
            MapWarning,
            stacklevel=3,
        )


def _yaml_string(text: str) -> str:
    """``text`` as a YAML scalar: bare like ``map_saver`` writes it, quoted where YAML (as
    :func:`~frontier_rl.safe_yaml.parse_yaml` reads it) would misread it."""
    try:
        bare_ok = parse_yaml(text) == text
    except (yaml.YAMLError, ValueError):
        bare_ok = False
    return text if bare_ok else json.dumps(text)


def save_ros_map(grid: OccupancyGrid, yaml_path: str | Path, image_format: str = "pgm") -> Path:
    """Write ``grid`` as ``map_saver`` does: a trinary image beside a YAML; returns the YAML's path.

    The image takes the YAML's name with the suffix ``image_format`` ("pgm" or "png"). Cell values
    0..25 are saved free, 65..100 occupied, anything else unknown, so a grid of :class:`CellState`
    values reads back exactly: ``load_ros_map(save_ros_map(g, p)) == g``.
    """
    path = Path(yaml_path)
    if path.suffix.lower() not in (".yaml", ".yml"):
        raise MapError(f"map YAML path must end in .yaml or .yml, got {path}")
    fmt = image_format.lower().lstrip(".")
    if fmt not in _IMAGE_FORMATS:
        raise MapError(f"image_format must be 'pgm' or 'png', got {short_repr(image_format)}")
    image_path = path.with_suffix(f".{fmt}")
    data = grid.data
    pixels = np.full(grid.shape, UNKNOWN_PIXEL, dtype=np.uint8)
    pixels[(data >= CellState.FREE) & (data <= SAVE_FREE_MAX)] = FREE_PIXEL
    pixels[data >= SAVE_OCCUPIED_MIN] = OCCUPIED_PIXEL
    text = (
        f"image: {_yaml_string(image_path.name)}\n"
        f"mode: {MapMode.TRINARY.value}\n"
        f"resolution: {float(grid.resolution)!r}\n"
        f"origin: [{float(grid.origin[0])!r}, {float(grid.origin[1])!r}, 0.0]\n"
        f"negate: 0\n"
        f"occupied_thresh: {OCCUPIED_THRESH}\n"
        f"free_thresh: {FREE_THRESH}\n"
    )
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        encoded = io.BytesIO()
        Image.fromarray(np.ascontiguousarray(np.flipud(pixels))).save(encoded, format=_IMAGE_FORMATS[fmt])
        write_bytes_atomic(image_path, encoded.getvalue())
        write_text_atomic(path, text)
    except OSError as exc:
        raise MapError(f"cannot write map {path}: {exc}") from exc
    return path
