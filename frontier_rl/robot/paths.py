"""The robot's ways to a point, planned on a costmap of its map: a goal's path to follow, the way
to a goal whose progress is checked, the way home."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from frontier_rl.core.navigation.costmap import Costmap
from frontier_rl.core.sim.paths import point_goal_cell
from frontier_rl.core.world.grid import OccupancyGrid
from frontier_rl.core.world.robot import Pose


def path_to_point(
    grid: OccupancyGrid, costmap: Costmap, reachable: NDArray[np.bool_], pose: Pose, x: float, y: float
) -> NDArray[np.float64] | None:
    """The way ((n, 2), m) from ``pose`` to the ``reachable`` cell of ``grid`` nearest to (x, y)
    (m), planned on ``costmap``, ending at that cell's centre; None if there is none."""
    goal_cell = point_goal_cell(grid, reachable, x, y)
    if goal_cell is None:
        return None
    cells = costmap.plan(grid.world_to_cell(pose.x, pose.y), goal_cell)
    if len(cells) == 0:
        return None
    path = grid.cells_to_world(cells)
    path[-1] = grid.cell_to_world(*goal_cell)
    return path
