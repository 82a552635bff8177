"""Cell states and the occupancy grid with its world <-> cell transforms.

Conventions follow ``nav_msgs/OccupancyGrid``: ``int8`` data, row-major, cell ``(0, 0)`` at the
map origin (the lower-left corner), ``x`` grows with the column and ``y`` with the row.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import IntEnum

import numpy as np
from numpy.typing import NDArray

from frontier_rl.errors import MapError


class CellState(IntEnum):
    """The three cell values of a ``nav_msgs/OccupancyGrid``."""

    UNKNOWN = -1
    FREE = 0
    OCCUPIED = 100


# The cell values as int8 scalars, the grid's dtype: what compiled kernels compare cells with and
# write (numba freezes a global it reads as a constant of its type).
UNKNOWN_I8 = np.int8(CellState.UNKNOWN)
FREE_I8 = np.int8(CellState.FREE)
OCCUPIED_I8 = np.int8(CellState.OCCUPIED)


@dataclass(frozen=True)
class OccupancyGrid:
    """A 2D grid of :class:`CellState` values placed in the world.

    Attributes:
        data: ``int8`` array of shape (rows, cols) holding :class:`CellState` values.
        resolution: cell edge length (m).
        origin: world coordinates (m) of the lower-left corner of cell (0, 0).
    """

    data: NDArray[np.int8]
    resolution: float
    origin: tuple[float, float] = (0.0, 0.0)

    def __post_init__(self) -> None:
        if not (np.isfinite(self.resolution) and self.resolution > 0):
            raise MapError(f"resolution must be a positive number of metres, got {self.resolution!r}")
        if self.data.ndim != 2 or self.data.shape[0] == 0 or self.data.shape[1] == 0:
            raise MapError(f"grid data must be a non-empty 2D array, got shape {self.data.shape}")
        if self.data.dtype != np.int8:
            raise MapError(f"grid data must be int8, got {self.data.dtype}")

    @property
    def shape(self) -> tuple[int, int]:
        """(rows, cols) of the grid."""
        return (int(self.data.shape[0]), int(self.data.shape[1]))

    @property
    def height(self) -> int:
        """Number of rows."""
        return int(self.data.shape[0])

    @property
    def width(self) -> int:
        """Number of columns."""
        return int(self.data.shape[1])

    @property
    def size_m(self) -> tuple[float, float]:
        """(width, height) of the grid in metres."""
        return (self.width * self.resolution, self.height * self.resolution)

    def world_to_cell(self, x: float, y: float) -> tuple[int, int]:
        """(row, col) of the cell holding world point (x, y) in metres; may lie outside the grid."""
        col = int(np.floor((x - self.origin[0]) / self.resolution))
        row = int(np.floor((y - self.origin[1]) / self.resolution))
        return row, col

    def cell_to_world(self, row: float, col: float) -> tuple[float, float]:
        """World coordinates (m) of the centre of cell (row, col)."""
        return (
            self.origin[0] + (col + 0.5) * self.resolution,
            self.origin[1] + (row + 0.5) * self.resolution,
        )

    def centres_near(
        self, x: float, y: float, radius: float
    ) -> tuple[slice, slice, NDArray[np.float64], NDArray[np.float64]]:
        """The rows and columns (slices, clipped to the grid, maybe empty) of every cell whose
        centre may lie within ``radius`` (m) of world point (x, y) (m), and the x of those columns'
        centres and the y of those rows' (m)."""
        reach = int(np.ceil(radius / self.resolution))
        row, col = self.world_to_cell(x, y)
        r0 = max(row - reach, 0)
        r1 = max(min(row + reach + 1, self.height), r0)  # a negative end would count from the far edge
        c0 = max(col - reach, 0)
        c1 = max(min(col + reach + 1, self.width), c0)
        cx = np.asarray(self.origin[0] + (np.arange(c0, c1) + 0.5) * self.resolution, np.float64)
        cy = np.asarray(self.origin[1] + (np.arange(r0, r1) + 0.5) * self.resolution, np.float64)
        return slice(r0, r1), slice(c0, c1), cx, cy

    def cells_to_world(self, cells: NDArray[np.int64]) -> NDArray[np.float64]:
        """World coordinates (m), shape (n, 2) as (x, y), of the centres of (n, 2) (row, col) cells."""
        cells = np.asarray(cells).reshape(-1, 2)
        return np.column_stack(
            (
                self.origin[0] + (cells[:, 1] + 0.5) * self.resolution,
                self.origin[1] + (cells[:, 0] + 0.5) * self.resolution,
            )
        )

    def world_to_cells(self, xy: NDArray[np.float64]) -> NDArray[np.int64]:
        """(row, col) cells, shape (n, 2), holding the (n, 2) world points (x, y) in metres."""
        xy = np.asarray(xy, dtype=np.float64).reshape(-1, 2)
        cols = np.floor((xy[:, 0] - self.origin[0]) / self.resolution).astype(np.int64)
        rows = np.floor((xy[:, 1] - self.origin[1]) / self.resolution).astype(np.int64)
        return np.column_stack((rows, cols))

    def offset_in(self, outer: OccupancyGrid) -> tuple[int, int]:
        """(row, col) of this grid's cell (0, 0) in ``outer``, a grid of the same cells (a crop
        of it, or one it was cropped from: then negative)."""
        return (
            round((self.origin[1] - outer.origin[1]) / outer.resolution),
            round((self.origin[0] - outer.origin[0]) / outer.resolution),
        )

    def in_bounds(self, row: int, col: int) -> bool:
        """Whether (row, col) is a cell of the grid."""
        return 0 <= row < self.height and 0 <= col < self.width

    def mask(self, state: CellState) -> NDArray[np.bool_]:
        """Boolean mask of the cells in ``state``."""
        return np.asarray(self.data == state.value)

    def count(self, state: CellState) -> int:
        """Number of cells in ``state``."""
        return int(np.count_nonzero(self.data == state.value))

    def resampled(self, cell: float) -> OccupancyGrid:
        """This grid on cells of ``cell`` m (at least this grid's), the origin kept: a new cell is
        occupied if any cell it overlaps is, free if every cell it overlaps is free and it lies
        within the grid, unknown otherwise (it sees walls as a robot's SLAM on coarser cells does)."""
        if not cell >= self.resolution:
            raise MapError(f"a grid of {self.resolution:g} m cells cannot be resampled to {cell!r} m cells")
        ratio = cell / self.resolution
        rows, cols = (math.ceil(n / ratio - 1e-9) for n in self.shape)

        def spans(count: int, limit: int) -> tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.bool_]]:
            edges = np.arange(count + 1) * ratio
            first = np.floor(edges[:-1] + 1e-9).astype(np.int64)
            end = np.ceil(edges[1:] - 1e-9).astype(np.int64)
            return first, np.minimum(end, limit), end <= limit

        (r0, r1, r_in), (c0, c1, c_in) = spans(rows, self.height), spans(cols, self.width)

        def overlaps(cells: NDArray[np.bool_]) -> NDArray[np.int32]:
            table = np.zeros((self.height + 1, self.width + 1), dtype=np.int32)  # at most MAX_MAP_PIXELS
            table[1:, 1:] = cells.cumsum(axis=0, dtype=np.int32).cumsum(axis=1, dtype=np.int32)
            return np.asarray(
                table[np.ix_(r1, c1)] - table[np.ix_(r0, c1)] - table[np.ix_(r1, c0)] + table[np.ix_(r0, c0)]
            )

        area = np.outer(r1 - r0, c1 - c0)
        all_free = (overlaps(self.mask(CellState.FREE)) == area) & np.outer(r_in, c_in)
        data = np.full((rows, cols), CellState.UNKNOWN.value, dtype=np.int8)
        data[all_free] = CellState.FREE.value
        data[overlaps(self.mask(CellState.OCCUPIED)) > 0] = CellState.OCCUPIED.value
        return OccupancyGrid(data=data, resolution=cell, origin=self.origin)
