"""A map file's size in cells and metres, read cheaply: an image's header (Pillow reads no pixels
for it), a ``map_server`` YAML's resolution, a HouseExpo plan sized by the loader's own function
(its polygon read and checked, not rasterised). The sizes are those
:func:`~frontier_rl.io.load_map` gives the file with its default resolution (before a world
resamples cells finer than 0.04 m)."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from PIL import Image, UnidentifiedImageError

from frontier_rl.errors import MapError
from frontier_rl.io.houseexpo import HOUSEEXPO_RESOLUTION, read_houseexpo_plan
from frontier_rl.io.loaded_map import positive_metres
from frontier_rl.io.ros_map import ros_map_image
from frontier_rl.safe_yaml import load_yaml_file


@dataclass(frozen=True)
class MapSize:
    """A map's extent.

    Attributes:
        width_cells: cells along x (the image's columns).
        height_cells: cells along y (the image's rows).
        resolution_m: edge of one cell (m).
    """

    width_cells: int
    height_cells: int
    resolution_m: float

    @property
    def width_m(self) -> float:
        """Extent along x (m)."""
        return self.width_cells * self.resolution_m

    @property
    def height_m(self) -> float:
        """Extent along y (m)."""
        return self.height_cells * self.resolution_m


def image_size(path: Path, resolution: float) -> MapSize:
    """The size of the image at ``path`` read from its header, one cell per pixel of ``resolution`` (m).

    Raises:
        MapError: a missing file or one that is not an image.
    """
    try:
        with Image.open(path) as image:
            width, height = image.size
    except (OSError, UnidentifiedImageError) as exc:  # UnidentifiedImageError is an OSError; named for the reader
        raise MapError(f"{path}: cannot read the image's size: {exc}") from None
    return MapSize(width, height, positive_metres(resolution, "resolution", path))


def ros_map_size(yaml_path: Path) -> MapSize:
    """The size of a ``map_server`` map: its image's header and the YAML's ``resolution`` (m).

    Raises:
        MapError: a malformed YAML, a resolution that is not a positive number, a missing image.
    """
    doc = load_yaml_file(yaml_path, MapError, "map YAML")
    if not isinstance(doc, dict):
        raise MapError(f"{yaml_path}: a map YAML must be a mapping of fields, got {type(doc).__name__}")
    return image_size(ros_map_image(yaml_path), positive_metres(doc.get("resolution"), "resolution", yaml_path))


def houseexpo_size(json_path: Path, resolution: float = HOUSEEXPO_RESOLUTION) -> MapSize:
    """The grid :func:`~frontier_rl.io.houseexpo.load_houseexpo` makes of a HouseExpo file, sized
    as it sizes it (:func:`~frontier_rl.io.houseexpo.read_houseexpo_plan`: the polygon read and
    checked, its bounding box and a band of wall around it, in cells of ``resolution`` (m)),
    without rasterising it.

    Raises:
        MapError: as :func:`~frontier_rl.io.houseexpo.load_houseexpo`.
    """
    plan = read_houseexpo_plan(json_path, resolution)
    return MapSize(plan.cols, plan.rows, plan.resolution)
