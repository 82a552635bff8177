"""The robot's body on the simulated clock: when its next scan is due, and what its bumper feels."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from frontier_rl.core.mapping.mapper import LogOddsMapper
from frontier_rl.core.sim.config import SimConfig
from frontier_rl.core.world.grid import CellState, OccupancyGrid
from frontier_rl.core.world.robot import Pose


def until_next_scan(
    mapper: LogOddsMapper, config: SimConfig, pose: Pose, sim_time: float, max_sim_time: float
) -> tuple[float, NDArray[np.float64]]:
    """How long (s) a robot at ``pose`` at ``sim_time`` (s) may drive before the mapper's time
    trigger, in whole LiDAR ticks (at most to ``max_sim_time``), and the ``gate`` of
    :func:`~frontier_rl.core.navigation.follower.follow_path` for the mapper's motion triggers."""
    period = config.lidar.period
    mapper_cfg = config.mapper
    left = max_sim_time - sim_time
    last = mapper.last_update
    if last is None:
        return min(period, left), np.array([period, pose.x, pose.y, pose.theta, 0.0, 0.0])
    last_pose, last_time = last
    if mapper_cfg.temporal_update > 0:
        wait = min(mapper_cfg.temporal_update - 1e-9 - (sim_time - last_time), left)  # no tick count of 1e308 s
        ticks = max(1, math.ceil(wait / period))
        duration = min(ticks * period, left)
    else:
        duration = left
    gate = np.array(
        [period, last_pose.x, last_pose.y, last_pose.theta, mapper_cfg.linear_update, mapper_cfg.angular_update]
    )
    return duration, gate


def touched_walls(grid: OccupancyGrid, pose: Pose, radius: float) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """The rows and columns of the wall cells of ``grid`` (the world) that a robot of ``radius``
    (m) at ``pose`` touches, within one and a half cells: what a bumper would feel."""
    reach = radius + 1.5 * grid.resolution
    row, col = grid.world_to_cell(pose.x, pose.y)
    n = int(math.ceil(reach / grid.resolution))
    r0, c0 = max(row - n, 0), max(col - n, 0)
    window = grid.data[r0 : row + n + 1, c0 : col + n + 1] == CellState.OCCUPIED
    rows, cols = np.nonzero(window)
    centres_x = grid.origin[0] + (cols + c0 + 0.5) * grid.resolution
    centres_y = grid.origin[1] + (rows + r0 + 0.5) * grid.resolution
    near = np.hypot(centres_x - pose.x, centres_y - pose.y) <= reach
    return rows[near] + r0, cols[near] + c0
