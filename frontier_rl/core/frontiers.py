"""Frontier detection: fringe cells, 8-connected clusters, size filter, centres, information gain.

A *fringe* cell is a FREE cell with an UNKNOWN 4-neighbour. Fringe cells are grouped into
8-connected clusters; clusters of ``min_cells`` or fewer are dropped (LiDAR noise specks), and only
clusters that touch the region the robot can reach through known free space are candidates.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property

import numba as nb
import numpy as np
from numpy.typing import NDArray

from frontier_rl.core.grid import CellState, OccupancyGrid
from frontier_rl.core.raycast import FASTMATH, ray_start
from frontier_rl.core.robot import Pose

_UNKNOWN = np.int8(CellState.UNKNOWN)
_FREE = np.int8(CellState.FREE)
_OCCUPIED = np.int8(CellState.OCCUPIED)

_NEIGHBOURS_8 = np.array([(-1, -1), (-1, 0), (-1, 1), (0, -1), (0, 1), (1, -1), (1, 0), (1, 1)], np.int64)


@nb.njit(cache=True, inline="always")
def _is_fringe(state: NDArray[np.int8], row: int, col: int) -> bool:
    rows, cols = state.shape
    if state[row, col] != _FREE:
        return False
    return bool(
        (row > 0 and state[row - 1, col] == _UNKNOWN)
        or (row + 1 < rows and state[row + 1, col] == _UNKNOWN)
        or (col > 0 and state[row, col - 1] == _UNKNOWN)
        or (col + 1 < cols and state[row, col + 1] == _UNKNOWN)
    )


@nb.njit(cache=True)
def fringe_mask(state: NDArray[np.int8]) -> NDArray[np.bool_]:
    """FREE cells with an UNKNOWN 4-neighbour (cells beyond the grid's edge are not unknown)."""
    rows, cols = state.shape
    padded = np.full((rows + 2, cols + 2), _FREE, np.int8)
    padded[1:-1, 1:-1] = state
    out = np.zeros((rows, cols), np.bool_)
    for r in range(rows):
        for c in range(cols):
            out[r, c] = padded[r + 1, c + 1] == _FREE and (
                (padded[r, c + 1] == _UNKNOWN)
                | (padded[r + 2, c + 1] == _UNKNOWN)
                | (padded[r + 1, c] == _UNKNOWN)
                | (padded[r + 1, c + 2] == _UNKNOWN)
            )
    return out


@nb.njit(cache=True)
def cluster_fringe(
    state: NDArray[np.int8],
    reachable: NDArray[np.bool_],
    robot_row: float,
    robot_col: float,
) -> tuple[NDArray[np.int64], NDArray[np.float64], NDArray[np.int64]]:
    """Find the 8-connected fringe clusters and gather their statistics in one pass.

    Args:
        state: grid of cell states.
        reachable: cells the robot can reach through known free space.
        robot_row, robot_col: robot position in continuous cell coordinates.

    Returns:
        counts: (n, 2) cells per cluster and how many of them are reachable.
        stats: (n, 3) sum of row indices, sum of column indices, min squared distance (cells²)
            from the robot to a cell centre.
        cells: flat indices of the fringe cells, grouped by cluster (cluster k owns
            ``cells[offsets[k]:offsets[k+1]]`` where offsets is the cumulative sum of counts).
    """
    rows, cols = state.shape
    todo = fringe_mask(state)  # fringe cells not yet in a cluster
    stack = np.empty(rows * cols, np.int64)
    cells = np.empty(rows * cols, np.int64)
    counts_list = []
    stats_list = []
    n_cells = 0
    n_clusters = 0
    for r0 in range(rows):
        for c0 in range(cols):
            if not todo[r0, c0]:
                continue
            n_clusters += 1
            todo[r0, c0] = False
            top = 0
            stack[top] = r0 * cols + c0
            top += 1
            size = 0
            n_reach = 0
            sum_r = 0.0
            sum_c = 0.0
            min_d2 = np.inf
            while top > 0:
                top -= 1
                flat = stack[top]
                r = flat // cols
                c = flat % cols
                cells[n_cells] = flat
                n_cells += 1
                size += 1
                if reachable[r, c]:
                    n_reach += 1
                sum_r += r
                sum_c += c
                d2 = (r + 0.5 - robot_row) ** 2 + (c + 0.5 - robot_col) ** 2
                min_d2 = min(min_d2, d2)
                for k in range(8):
                    rr = r + _NEIGHBOURS_8[k, 0]
                    cc = c + _NEIGHBOURS_8[k, 1]
                    if 0 <= rr < rows and 0 <= cc < cols and todo[rr, cc]:
                        todo[rr, cc] = False
                        stack[top] = rr * cols + cc
                        top += 1
            counts_list.append((size, n_reach))
            stats_list.append((sum_r, sum_c, min_d2))
    counts = np.zeros((n_clusters, 2), np.int64)
    stats = np.zeros((n_clusters, 3), np.float64)
    for k in range(n_clusters):
        counts[k, 0], counts[k, 1] = counts_list[k]
        stats[k, 0], stats[k, 1], stats[k, 2] = stats_list[k]
    return counts, stats, cells[:n_cells].copy()


@nb.njit(cache=True)
def count_fringe(state: NDArray[np.int8], rows_idx: NDArray[np.int64], cols_idx: NDArray[np.int64]) -> int:
    """How many of the given cells are still fringe cells."""
    n = 0
    for i in range(rows_idx.shape[0]):
        if _is_fringe(state, rows_idx[i], cols_idx[i]):
            n += 1
    return n


@nb.njit(cache=True, fastmath=FASTMATH)
def visible_unknown(
    state: NDArray[np.int8],
    stamp: NDArray[np.int32],
    stamp_id: int,
    cx: float,
    cy: float,
    n_rays: int,
    max_range: float,
) -> int:
    """Unknown cells a scan from (cx, cy) (cell units) would reveal: rays pass through free and
    unknown cells and stop at occupied ones or the grid's edge; each cell counts once."""
    rows, cols = state.shape
    total = 0
    for i in range(n_rays):
        a = 2.0 * math.pi * i / n_rays
        row, col, s_r, s_c, tm_r, tm_c, td_r, td_c = ray_start(cx, cy, math.cos(a), math.sin(a))
        t = 0.0
        while t <= max_range and 0 <= row < rows and 0 <= col < cols:
            value = state[row, col]
            if value == _OCCUPIED:
                break
            if value == _UNKNOWN and stamp[row, col] != stamp_id:
                stamp[row, col] = stamp_id
                total += 1
            if tm_c < tm_r:
                col += s_c
                t = tm_c
                tm_c += td_c
            else:
                row += s_r
                t = tm_r
                tm_r += td_r
    return total


@dataclass(frozen=True)
class Frontiers:
    """The candidate frontiers of one map, as parallel arrays (one entry per frontier).

    Attributes:
        grid: the map they were found on.
        centers: (n, 2) cluster centres, the mean of the cells' centres, world (x, y) in m.
        sizes: (n,) number of fringe cells.
        distances: (n,) straight-line distance from the robot to the centre (m).
        min_distances: (n,) straight-line distance from the robot to the nearest cell centre (m).
        flat_cells: flat indices into ``grid`` of the cells of all clusters, grouped by cluster.
        spans: (n, 2) start and end of each frontier's cells in ``flat_cells``.
    """

    grid: OccupancyGrid
    centers: NDArray[np.float64]
    sizes: NDArray[np.int64]
    distances: NDArray[np.float64]
    min_distances: NDArray[np.float64]
    flat_cells: NDArray[np.int64] = field(repr=False)
    spans: NDArray[np.int64] = field(repr=False)

    def __len__(self) -> int:
        return int(self.sizes.shape[0])

    def cells_of(self, index: int) -> NDArray[np.int64]:
        """(size, 2) row and column indices in ``grid`` of frontier ``index``'s cells."""
        start, end = self.spans[index]
        rows, cols = np.divmod(self.flat_cells[start:end], self.grid.width)
        return np.column_stack((rows, cols)).astype(np.int64)

    @cached_property
    def cells(self) -> tuple[NDArray[np.int64], ...]:
        """Per frontier, the (row, col) indices of its cells in ``grid``, shape (size, 2)."""
        return tuple(self.cells_of(i) for i in range(len(self)))

    def subset(self, keep: NDArray[np.bool_]) -> Frontiers:
        """The frontiers where ``keep`` is True, in the same order."""
        idx = np.flatnonzero(keep)
        return Frontiers(
            self.grid,
            self.centers[idx],
            self.sizes[idx],
            self.distances[idx],
            self.min_distances[idx],
            self.flat_cells,
            self.spans[idx],
        )

    def information_gain(self, sensor_range: float, n_rays: int = 180) -> NDArray[np.int64]:
        """Unknown cells a scan of range ``sensor_range`` (m) from each centre would reveal."""
        grid = self.grid
        stamp = np.zeros(grid.shape, np.int32)
        gains = np.zeros(len(self), np.int64)
        res = grid.resolution
        for i, (x, y) in enumerate(self.centers):
            gains[i] = visible_unknown(
                grid.data,
                stamp,
                i + 1,
                (x - grid.origin[0]) / res,
                (y - grid.origin[1]) / res,
                n_rays,
                sensor_range / res,
            )
        return gains


def detect_frontiers(
    grid: OccupancyGrid,
    robot: Pose,
    reachable: NDArray[np.bool_] | None = None,
    min_cells: int = 4,
) -> Frontiers:
    """Frontier clusters of ``grid`` larger than ``min_cells`` that touch ``reachable``.

    Args:
        grid: the robot's map.
        robot: robot pose (m); distances are measured from it.
        reachable: cells the robot can reach through known free space (same shape as the grid);
            ``None`` accepts every cluster.
        min_cells: clusters of this many cells or fewer are dropped (the thesis drops <= 4).
    """
    res = grid.resolution
    robot_col = (robot.x - grid.origin[0]) / res
    robot_row = (robot.y - grid.origin[1]) / res
    reach = np.ones(grid.shape, np.bool_) if reachable is None else reachable
    counts, stats, flat = cluster_fringe(grid.data, reach, robot_row, robot_col)
    centers, sizes, distances, min_distances, spans = _kept_clusters(
        counts, stats, min_cells, grid.origin[0], grid.origin[1], res, robot.x, robot.y
    )
    return Frontiers(grid, centers, sizes, distances, min_distances, flat, spans)


@nb.njit(cache=True)
def _kept_clusters(
    counts: NDArray[np.int64],
    stats: NDArray[np.float64],
    min_cells: int,
    origin_x: float,
    origin_y: float,
    resolution: float,
    robot_x: float,
    robot_y: float,
) -> tuple[NDArray[np.float64], NDArray[np.int64], NDArray[np.float64], NDArray[np.float64], NDArray[np.int64]]:
    """The clusters of :func:`cluster_fringe` larger than ``min_cells`` with a reachable cell:
    centres (m), sizes, distance from the robot to the centre and to the nearest cell (m), and
    their spans in the cluster-ordered cells."""
    n = 0
    for k in range(counts.shape[0]):
        n += counts[k, 0] > min_cells and counts[k, 1] > 0
    centers = np.empty((n, 2))
    sizes = np.empty(n, np.int64)
    distances = np.empty(n)
    min_distances = np.empty(n)
    spans = np.empty((n, 2), np.int64)
    start = 0
    i = 0
    for k in range(counts.shape[0]):
        size = counts[k, 0]
        if size > min_cells and counts[k, 1] > 0:
            x = origin_x + (stats[k, 1] / size + 0.5) * resolution
            y = origin_y + (stats[k, 0] / size + 0.5) * resolution
            centers[i, 0], centers[i, 1] = x, y
            sizes[i] = size
            distances[i] = math.hypot(x - robot_x, y - robot_y)
            min_distances[i] = math.sqrt(stats[k, 2]) * resolution
            spans[i, 0], spans[i, 1] = start, start + size
            i += 1
        start += size
    return centers, sizes, distances, min_distances, spans
