"""The robot's trail: the cells its centre has crossed, a way back it knows it fits through.

A robot that drove into clutter can find its own map closed behind it (walls grow a cell where the
LiDAR sees them), though it came in that way on the true map. The narrow-passage recovery keeps the
trail open (:func:`~frontier_rl.core.navigation.thin_walls.recovery_costmap`).
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np
from numpy.typing import NDArray

from frontier_rl.core.world.grid import CellState, OccupancyGrid


def mark_path(trail: NDArray[np.bool_], grid: OccupancyGrid, points: NDArray[np.float64]) -> None:
    """Set in ``trail`` (``grid``'s shape) the cells of the polyline through ``points`` ((n, 2) world
    points, m), 4-connected: where it steps diagonally from one cell to the next, both cells beside
    the two are set too (the planner never cuts a corner; a wall the robot touched closes the one it
    did not cross)."""
    xy = np.ascontiguousarray(points, dtype=np.float64)
    _mark_path(trail, grid.origin[0], grid.origin[1], grid.resolution, xy)


@nb.njit(cache=True)
def _mark_path(
    trail: NDArray[np.bool_], origin_x: float, origin_y: float, resolution: float, xy: NDArray[np.float64]
) -> None:
    """:func:`mark_path`, each segment sampled every quarter cell (the poses are a LiDAR tick apart)."""
    rows, cols = trail.shape
    last_row, last_col = -1, -1
    for i in range(xy.shape[0]):
        ax, ay = xy[max(i - 1, 0), 0], xy[max(i - 1, 0), 1]
        bx, by = xy[i, 0], xy[i, 1]
        steps = max(1, int(math.ceil(math.hypot(bx - ax, by - ay) / (0.25 * resolution))))
        for k in range(steps + 1):
            t = k / steps
            col = int(math.floor((ax + t * (bx - ax) - origin_x) / resolution))
            row = int(math.floor((ay + t * (by - ay) - origin_y) / resolution))
            if not (0 <= row < rows and 0 <= col < cols):
                continue
            trail[row, col] = True
            if last_row >= 0 and abs(row - last_row) == 1 and abs(col - last_col) == 1:
                trail[last_row, col] = True
                trail[row, last_col] = True
            last_row, last_col = row, col


def opened_on_trail(
    cells: NDArray[np.int64],
    trail: NDArray[np.bool_],
    state: NDArray[np.int8],
    felt: NDArray[np.bool_],
    keep_out: NDArray[np.bool_],
) -> NDArray[np.bool_]:
    """Which of ``cells`` ((n, 2) map cells) the narrow-passage recovery's costmap opens along the
    robot's ``trail``: those the trail crossed that the map ``state`` has free, with no wall the robot
    touched (``felt``) within the ``keep_out`` disc
    (:func:`~frontier_rl.core.navigation.costmap.felt_keep_out`) of them. A check of a path
    planned on that costmap that ignored the trail would find the path it was given walled."""
    rows, cols = cells[:, 0], cells[:, 1]
    opened: NDArray[np.bool_] = trail[rows, cols] & (state[rows, cols] == CellState.FREE)
    if not opened.any():
        return opened
    n = keep_out.shape[0] // 2
    offsets = np.argwhere(keep_out) - n
    near_r = rows[opened, None] + offsets[None, :, 0]
    near_c = cols[opened, None] + offsets[None, :, 1]
    inside = (near_r >= 0) & (near_r < state.shape[0]) & (near_c >= 0) & (near_c < state.shape[1])
    touched = inside & felt[np.where(inside, near_r, 0), np.where(inside, near_c, 0)]
    opened[opened] = ~touched.any(axis=1)
    return opened
