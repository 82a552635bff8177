"""Start poses of a team: side by side around the world's start, as robots set down together."""

from __future__ import annotations

from collections import deque

import numpy as np

from frontier_rl.core.sim.teammates import obstacle_distance
from frontier_rl.core.world.grid import CellState
from frontier_rl.core.world.robot import Pose
from frontier_rl.core.world.scale import START_MARGIN_M
from frontier_rl.core.world.worlds import World
from frontier_rl.errors import ConfigError


def team_starts(world: World, robots: int, radius: float, spacing: float) -> list[Pose]:
    """``robots`` start poses: robot 0 on the world's start, the others on the nearest free cells
    (breadth-first over cells the robot fits on) at least ``spacing`` (m) from every earlier one,
    all facing the world start's heading. Raises ConfigError when there is no room for them."""
    grid = world.grid
    if spacing < 2.0 * radius:
        raise ConfigError(f"start spacing {spacing!r} m is less than a robot's diameter {2.0 * radius!r} m")
    fits = obstacle_distance(grid.data == CellState.OCCUPIED, grid.resolution) >= radius + START_MARGIN_M
    start = world.start
    origin = grid.world_to_cell(start.x, start.y)
    poses = [start]
    chosen = [(start.x, start.y)]
    seen = np.zeros(grid.shape, np.bool_)
    seen[origin] = True
    queue = deque([origin])
    while queue and len(poses) < robots:
        row, col = queue.popleft()
        x, y = grid.cell_to_world(row, col)
        if fits[row, col] and all(np.hypot(x - cx, y - cy) >= spacing for cx, cy in chosen):
            poses.append(Pose(x, y, start.theta))
            chosen.append((x, y))
        for dr, dc in ((1, 0), (-1, 0), (0, 1), (0, -1)):
            r, c = row + dr, col + dc
            if grid.in_bounds(r, c) and not seen[r, c] and fits[r, c]:
                seen[r, c] = True
                queue.append((r, c))
    if len(poses) < robots:
        raise ConfigError(
            f"world {world.name!r} has room for only {len(poses)} robot(s) {spacing:g} m apart "
            f"around its start, got robots={robots}"
        )
    return poses
