"""Other robots as one robot meets them: obstacles its path follower collides with and its LiDAR
cannot see through, discs its planner goes round, and passers-by its laser filter keeps out of its
map (they are moving, not walls)."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from frontier_rl.core.navigation.follower import obstacle_distance, stamp_discs
from frontier_rl.core.sensing.lidar import Lidar
from frontier_rl.core.world.grid import CellState, OccupancyGrid

TEAMMATE_FILTER_MARGIN_M = 0.1
"""The laser filter that keeps teammates out of a robot's map drops this much (m) around them too,
so that a noisy reading that ends just short of a teammate leaves no phantom wall."""


class Teammates:
    """The other robots around one robot, as of the last :meth:`place`.

    Args:
        grid: the world's ground truth.
        lidar: the robot's LiDAR; the teammates are stamped into its own blocked grid.
        robot_radius: this robot's radius (m), and the teammates' unless :meth:`place` says other.
    """

    def __init__(self, grid: OccupancyGrid, lidar: Lidar, robot_radius: float) -> None:
        self._grid = grid
        self._lidar = lidar
        self._robot_radius = robot_radius
        self._true_blocked = lidar.blocked_padded  # the LiDAR gets its own copy once a teammate shows up
        self.true_clearance = obstacle_distance(grid.data == CellState.OCCUPIED, grid.resolution)
        """Distance (m) from each cell to the nearest wall."""
        self.clearance = self.true_clearance
        """Distance (m) from each cell to the nearest wall or teammate: what the follower collides with."""
        self._boxes = np.zeros((0, 4), np.int64)  # the discs stamped into clearance
        self._stamped = 0
        self.positions = np.zeros((0, 2))
        """(k, 2) world points (m) of the other robots."""
        self.radius = robot_radius
        """The other robots' radius (m)."""

    def __len__(self) -> int:
        return int(self.positions.shape[0])

    def place(self, positions: NDArray[np.float64], radius: float, at: tuple[float, float]) -> None:
        """Other robots at ``positions`` ((k, 2) world points, m) of ``radius`` (m), seen from this
        robot at ``at`` (m): stamped into the follower's clearance and the LiDAR's blocked grid."""
        self.radius = radius
        self.positions = np.asarray(positions, dtype=np.float64).reshape(-1, 2)
        if len(self) == 0 and self._stamped == 0:
            return
        if self.clearance is self.true_clearance:
            self.clearance = self.true_clearance.copy()
            self._lidar.blocked_padded = self._true_blocked.copy()
        if len(self._boxes) < len(self):
            self._boxes = np.zeros((len(self), 4), np.int64)
        g = self._grid
        reach = int(math.ceil((radius + 2.0 * self._robot_radius) / g.resolution)) + 1
        # A teammate overlapping this robot (squeezing past) does not hide the world from it.
        apart = self.distances(at) > radius + g.resolution
        self._stamped = stamp_discs(
            self.clearance, self.true_clearance, self._lidar.blocked_padded, self._true_blocked, self._boxes,
            self._stamped, self.positions[:, 0], self.positions[:, 1], apart, radius, reach, g.origin[0],
            g.origin[1], g.resolution,
        )  # fmt: skip

    def distances(self, point: tuple[float, float]) -> NDArray[np.float64]:
        """Distance (m) from ``point`` to each teammate."""
        x, y = point
        return np.asarray(np.hypot(self.positions[:, 0] - x, self.positions[:, 1] - y), dtype=np.float64)

    def within(self, distance: float, *points: tuple[float, float]) -> bool:
        """Whether a teammate is within ``distance`` (m) of any of ``points``."""
        return len(self) > 0 and any(self.distances(point).min() <= distance for point in points)

    def touching(self, at: tuple[float, float]) -> bool:
        """Whether a teammate is (about) in contact with this robot at ``at``."""
        return self.within(self.radius + self._robot_radius + 2.0 * self._grid.resolution, at)

    def laser_filter(self) -> tuple[NDArray[np.float64], float] | None:
        """The discs (centres (k, 2) and radius, m) a scan's marks are dropped in; None if none."""
        return (self.positions, self.radius + TEAMMATE_FILTER_MARGIN_M) if len(self) else None
