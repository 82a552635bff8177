"""Observation encoders: the robot's map as a fixed-size image, and per-frontier features.

The map image follows the thesis (§3.9): occupied → −1, unknown → 0, free → 1, padded with unknown
to a fixed square. It is stored as ``uint8`` (occupied 0, unknown 128, free 255), an affine image of
the thesis's values, so that Stable-Baselines3's ``CnnPolicy`` (which divides by 255) takes it as is.
Optional channels mark the candidate frontiers' cells and the robot's position (thesis models 1 and 3).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TypeVar

import numba as nb
import numpy as np
from numpy.typing import NDArray

from frontier_rl.core.frontiers.detection import Frontiers
from frontier_rl.core.world.grid import FREE_I8, OCCUPIED_I8, UNKNOWN_I8, CellState, OccupancyGrid
from frontier_rl.core.world.robot import Pose
from frontier_rl.errors import ConfigError

ScalarT = TypeVar("ScalarT", bound=np.generic)

THESIS_INPUT_CELLS = 250
"""Edge of the thesis's model input (cells): 12.5 m at 0.05 m, the whole office maze."""

MAP_OCCUPIED, MAP_UNKNOWN, MAP_FREE = 0, 128, 255
"""The uint8 pixel values of the map channel: the thesis's −1 / 0 / 1 mapped onto 0..255."""

MARK = 255
"""Pixel value of a frontier cell or the robot in the frontier and pose channels."""

POSE_RADIUS_M = 0.2
"""Radius (m) of the disc that marks the robot in the pose channel (visible after downsampling)."""

FRONTIER_FEATURES = ("distance", "path_cost", "size", "information_gain", "dx", "dy")
"""Per-frontier features of the frontier-choice observation, in column order."""


@dataclass(frozen=True)
class MapEncoder:
    """Encodes a map (plus frontiers and pose) as a ``(channels, size, size)`` uint8 image.

    Attributes:
        size: edge of the output image (pixels). 250 is the thesis's input; 64 the downsampled
            input of Niroui et al. The map window always spans at least 250 cells: ``size × factor``
            cells with ``factor = ceil(250 / size)``, so 64 shows a 256-cell window at 4 cells a pixel.
        frontier_channel: add a channel marking the candidate frontiers' cells.
        pose_channel: add a channel marking the robot.
    """

    size: int = THESIS_INPUT_CELLS
    frontier_channel: bool = False
    pose_channel: bool = False

    def __post_init__(self) -> None:
        if not 8 <= self.size <= 1024:
            raise ConfigError(f"observation size must be between 8 and 1024 pixels, got {self.size!r}")

    @property
    def factor(self) -> int:
        """Cells per pixel along each axis."""
        return math.ceil(THESIS_INPUT_CELLS / self.size)

    @property
    def window(self) -> int:
        """Edge of the map window (cells)."""
        return self.size * self.factor

    @property
    def channels(self) -> int:
        """Number of image channels."""
        return 1 + int(self.frontier_channel) + int(self.pose_channel)

    @property
    def shape(self) -> tuple[int, int, int]:
        """The observation's shape, channels first."""
        return (self.channels, self.size, self.size)

    def window_origin(self, grid: OccupancyGrid, pose: Pose) -> tuple[int, int]:
        """(row, col) of ``grid`` at the window's first pixel: the window is centred on the map and
        shifted, if needed, so that it contains the robot."""
        half = self.window // 2
        row0 = grid.height // 2 - half
        col0 = grid.width // 2 - half
        r, c = grid.world_to_cell(pose.x, pose.y)
        margin = min(half, max(2 * self.factor, 4))
        row0 = min(max(row0, r + margin - self.window + 1), r - margin)
        col0 = min(max(col0, c + margin - self.window + 1), c - margin)
        return row0, col0

    def pixel_to_world(self, grid: OccupancyGrid, pose: Pose, row: int, col: int) -> tuple[float, float]:
        """World (x, y) (m) of the centre of pixel (``row``, ``col``) of an image encoded from
        ``grid`` with the robot at ``pose``."""
        row0, col0 = self.window_origin(grid, pose)
        f = self.factor
        cell_r = row0 + (row + 0.5) * f
        cell_c = col0 + (col + 0.5) * f
        return (grid.origin[0] + cell_c * grid.resolution, grid.origin[1] + cell_r * grid.resolution)

    def encode(self, grid: OccupancyGrid, pose: Pose, frontiers: Frontiers | None = None) -> NDArray[np.uint8]:
        """The observation image of ``grid`` with the robot at ``pose``; ``frontiers`` is needed
        when the encoder has a frontier channel."""
        row0, col0 = self.window_origin(grid, pose)
        window = _crop(grid.data, row0, col0, self.window, CellState.UNKNOWN)
        out = np.empty(self.shape, np.uint8)
        state = downsample(window, self.factor) if self.factor > 1 else window
        out[0] = MAP_UNKNOWN
        out[0][state == CellState.OCCUPIED] = MAP_OCCUPIED
        out[0][state == CellState.FREE] = MAP_FREE
        channel = 1
        if self.frontier_channel:
            if frontiers is None:
                raise ConfigError("this encoder has a frontier channel: pass the frontiers")
            out[channel] = self._frontier_marks(grid, frontiers, row0, col0)
            channel += 1
        if self.pose_channel:
            out[channel] = self._pose_marks(grid, pose, row0, col0)
        return out

    def share_image(
        self, grid: OccupancyGrid, pose: Pose, mask: NDArray[np.bool_], offset: tuple[int, int]
    ) -> NDArray[np.uint8]:
        """A ``(1, size, size)`` image over the window :meth:`encode` shows of ``grid``: the share
        of each pixel's cells that ``mask`` holds, 0 (none) to :data:`MARK` (all). ``mask`` covers
        a larger grid of the same cells, in which ``grid``'s cell (0, 0) is (row, col) ``offset``."""
        row0, col0 = self.window_origin(grid, pose)
        window = _crop(mask, row0 + offset[0], col0 + offset[1], self.window, False)
        f = self.factor
        share: NDArray[np.float64] = window.reshape(self.size, f, self.size, f).mean(axis=(1, 3))
        return np.rint(share * MARK).astype(np.uint8)[None]

    def _frontier_marks(self, grid: OccupancyGrid, frontiers: Frontiers, row0: int, col0: int) -> NDArray[np.uint8]:
        """The frontier channel: :data:`MARK` on each pixel whose cells hold a frontier cell (only
        the frontiers' cells are visited, not the map)."""
        cells, _ = frontier_cells(frontiers)
        rows, cols = np.divmod(cells, grid.width)
        rows, cols = rows - row0, cols - col0
        inside = (rows >= 0) & (rows < self.window) & (cols >= 0) & (cols < self.window)
        channel = np.zeros((self.size, self.size), np.uint8)
        channel[rows[inside] // self.factor, cols[inside] // self.factor] = MARK
        return channel

    def _pose_marks(self, grid: OccupancyGrid, pose: Pose, row0: int, col0: int) -> NDArray[np.uint8]:
        """The pose channel: :data:`MARK` on each pixel whose cells hold a cell centre within
        :data:`POSE_RADIUS_M` of the robot (only the disc's bounding box is visited, not the window)."""
        radius = max(POSE_RADIUS_M / grid.resolution, 1.0)
        r = (pose.y - grid.origin[1]) / grid.resolution
        c = (pose.x - grid.origin[0]) / grid.resolution
        top, bottom = max(math.floor(r - radius) - row0 - 1, 0), min(math.ceil(r + radius) - row0 + 1, self.window)
        left, right = max(math.floor(c - radius) - col0 - 1, 0), min(math.ceil(c + radius) - col0 + 1, self.window)
        channel = np.zeros((self.size, self.size), np.uint8)
        if top < bottom and left < right:
            rows = np.arange(top, bottom)[:, None] + row0 + 0.5  # as the cells' centres over the window
            cols = np.arange(left, right)[None, :] + col0 + 0.5
            inside_r, inside_c = np.nonzero((rows - r) ** 2 + (cols - c) ** 2 <= radius * radius)
            channel[(inside_r + top) // self.factor, (inside_c + left) // self.factor] = MARK
        return channel


def frontier_cells(frontiers: Frontiers) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """The cells of all ``frontiers`` (flat indices into their grid), each frontier's together,
    and the frontier of each."""
    lengths = frontiers.spans[:, 1] - frontiers.spans[:, 0]
    cells = [frontiers.flat_cells[a:b] for a, b in frontiers.spans]
    return np.concatenate(cells or [np.zeros(0, np.int64)]), np.repeat(np.arange(len(frontiers)), lengths)


def _crop(data: NDArray[ScalarT], row0: int, col0: int, size: int, fill: object) -> NDArray[ScalarT]:
    """The ``size`` × ``size`` window of ``data`` starting at (row0, col0), ``fill`` outside."""
    out = np.full((size, size), fill, dtype=data.dtype)
    r0, c0 = max(row0, 0), max(col0, 0)
    r1, c1 = min(row0 + size, data.shape[0]), min(col0 + size, data.shape[1])
    if r1 > r0 and c1 > c0:
        out[r0 - row0 : r1 - row0, c0 - col0 : c1 - col0] = data[r0:r1, c0:c1]
    return out


def frontier_features(
    frontiers: Frontiers, pose: Pose, path_costs: NDArray[np.float64], sensor_range: float
) -> NDArray[np.float32]:
    """(n, 6) features of each frontier, scaled to about [−1, 1] (see :data:`FRONTIER_FEATURES`):
    straight-line distance and path cost to the centre over 10 m, size over 100 cells, information
    gain as a share of a full scan's disc, and the centre's offset from the robot over 10 m."""
    res = frontiers.grid.resolution
    disc_cells = math.pi * (sensor_range / res) ** 2
    gains = frontiers.information_gain(sensor_range)
    feats = np.column_stack(
        (
            frontiers.distances / 10.0,
            np.minimum(path_costs, 100.0) / 10.0,
            np.minimum(frontiers.sizes, 1000) / 100.0,
            gains / disc_cells,
            (frontiers.centers[:, 0] - pose.x) / 10.0,
            (frontiers.centers[:, 1] - pose.y) / 10.0,
        )
    )
    return feats.astype(np.float32).reshape(-1, len(FRONTIER_FEATURES))


def downsample(data: NDArray[np.int8], factor: int) -> NDArray[np.int8]:
    """Shrink a grid by an integer ``factor`` (the shape must divide).

    A block is OCCUPIED if any of its cells is, else FREE if at least half its cells are known
    free, else UNKNOWN: walls never vanish, and half-seen blocks stay unexplored.
    """
    rows, cols = data.shape
    if factor < 1 or rows % factor or cols % factor:
        raise ConfigError(f"downsample factor {factor!r} must be >= 1 and divide the shape {data.shape}")
    return _downsample(np.ascontiguousarray(data, np.int8), factor)


@nb.njit(cache=True)
def _downsample(data: NDArray[np.int8], factor: int) -> NDArray[np.int8]:
    """:func:`downsample` in one pass over the cells."""
    rows, cols = data.shape[0] // factor, data.shape[1] // factor
    out = np.empty((rows, cols), np.int8)
    half = factor * factor
    for br in range(rows):
        for bc in range(cols):
            occupied, free = False, 0
            for r in range(br * factor, br * factor + factor):
                for c in range(bc * factor, bc * factor + factor):
                    value = data[r, c]
                    occupied |= value == OCCUPIED_I8
                    free += value == FREE_I8
            out[br, bc] = OCCUPIED_I8 if occupied else FREE_I8 if 2 * free >= half else UNKNOWN_I8
    return out
