"""DungeonMaps (Chen et al. 2019, as shipped by ARiADNE): 640 x 480 PNG floor plans with a start.

Colours: (127, 127, 127) obstacle or outside, (195, 195, 194) free, and a 16 x 16 yellow square
(255, 216, 0) that marks the robot's start. Read as greyscale with the Rec. 709 luma weights that
the published planners use (``skimage.color.rgb2gray``), free is > 150 and the start square is 208.
The maps have no metric scale: the default 0.04375 m/px turns the planners' 80 px sensor range into
the LDS-01's 3.5 m, so a map is 28 m x 21 m.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from frontier_rl.core.world.grid import CellState, OccupancyGrid
from frontier_rl.core.world.robot import Pose
from frontier_rl.errors import MapError
from frontier_rl.io._image import RasterImage, read_image
from frontier_rl.io.loaded_map import LoadedMap, positive_metres

#: Default scale (m per pixel): 80 px of sensor range = 3.5 m.
DUNGEON_RESOLUTION = 0.04375
#: Greyscale above which a pixel is free (the start square included).
FREE_GREY_MIN = 150.0
#: Greyscale of the start square, and how far (0..255) a pixel may stray from it or its colour.
START_GREY = 208.0
START_RGB = (255.0, 216.0, 0.0)
START_TOLERANCE = 3.0
#: Colours of a DungeonMaps PNG (obstacle, free, start) in RGB and as greyscale, for detection.
PALETTE_RGB = np.array([(127.0, 127.0, 127.0), (195.0, 195.0, 194.0), START_RGB])
PALETTE_GREY = np.array([127.0, 195.0, START_GREY])
#: Share of pixels that must be palette colours for :func:`is_dungeon_image` to accept an image.
PALETTE_MIN_SHARE = 0.99
_LUMA_709 = np.array([0.2125, 0.7154, 0.0721])


def _near(colour: NDArray[np.float64], entry: NDArray[np.float64]) -> NDArray[np.bool_]:
    """Mask of the pixels whose every channel is within the tolerance of ``entry``'s."""
    near = np.ones(colour.shape[:2], dtype=np.bool_)
    for channel, value in enumerate(entry):  # per channel: a reduction over a 3-long axis is slow
        near &= np.abs(colour[:, :, channel] - value) <= START_TOLERANCE
    return near


def _grey_and_start(image: RasterImage) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
    """Greyscale (0..255) and the start-marker mask of an image, in image row order."""
    colour = image.colour
    if colour.shape[2] == 1:
        grey = colour[:, :, 0]
        return grey, np.asarray(np.abs(grey - START_GREY) <= START_TOLERANCE)
    grey = _LUMA_709[0] * colour[:, :, 0] + _LUMA_709[1] * colour[:, :, 1] + _LUMA_709[2] * colour[:, :, 2]
    yellow = _near(colour, np.array(START_RGB))
    return grey, np.asarray(yellow | (np.abs(grey - START_GREY) <= START_TOLERANCE))


def is_dungeon_image(path: str | Path) -> bool:
    """Whether the image at ``path`` uses the DungeonMaps palette and has a start marker.

    Raises:
        MapError: the file is missing or not a readable image.
    """
    image = read_image(Path(path))
    _, start = _grey_and_start(image)
    if not start.any():
        return False
    colour = image.colour
    palette = PALETTE_GREY[:, np.newaxis] if colour.shape[2] == 1 else PALETTE_RGB
    in_palette = np.zeros(image.shape, dtype=np.bool_)
    for entry in palette:
        in_palette |= _near(colour, entry)
    return bool(np.mean(in_palette) >= PALETTE_MIN_SHARE)


def load_dungeon_map(png_path: str | Path, resolution: float = DUNGEON_RESOLUTION) -> LoadedMap:
    """Read a DungeonMaps PNG: free where greyscale > 150, occupied elsewhere, start at the marker.

    Args:
        png_path: the PNG file.
        resolution: edge of one pixel (m); the origin is (0, 0).

    Returns:
        The grid (one cell per pixel, row 0 at the bottom) and the start: the centre (m) of the
        start-marker pixels, heading 0 rad.

    Raises:
        MapError: an unreadable image, a bad resolution or an image without a start marker.
    """
    path = Path(png_path)
    res = positive_metres(resolution, "resolution", path)
    image = read_image(path)
    grey, start = _grey_and_start(image)
    if not start.any():
        raise MapError(f"{path}: no start marker (greyscale {START_GREY:g} or RGB {START_RGB}) in the image")
    free = np.flipud((grey > FREE_GREY_MIN) | start)
    data = np.where(free, CellState.FREE, CellState.OCCUPIED).astype(np.int8)
    grid = OccupancyGrid(np.ascontiguousarray(data), res, (0.0, 0.0))
    rows, cols = np.nonzero(np.flipud(start))
    x, y = grid.cell_to_world(float(rows.mean()), float(cols.mean()))
    return LoadedMap(grid=grid, start=Pose(float(x), float(y), 0.0), source=path)


def marker_pixels(png_path: str | Path) -> NDArray[np.int64]:
    """The start marker's pixels of a DungeonMaps PNG as (row, col) in image order (row 0 at the
    top), row-major: as ``np.nonzero`` lists them for the published planners' start.

    Raises:
        MapError: an unreadable image or one without a start marker.
    """
    path = Path(png_path)
    _, start = _grey_and_start(read_image(path))
    if not start.any():
        raise MapError(f"{path}: no start marker (greyscale {START_GREY:g} or RGB {START_RGB}) in the image")
    return np.argwhere(start).astype(np.int64)
