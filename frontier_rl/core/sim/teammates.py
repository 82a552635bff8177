"""Other robots as one robot meets them: discs its path follower collides with and its LiDAR
cannot see through, discs its planner goes round, and passers-by its laser filter keeps out of its
map (they are moving, not walls)."""

from __future__ import annotations

import math

import numba as nb
import numpy as np
from numpy.typing import NDArray
from scipy import ndimage

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
        self.wall_clearance = obstacle_distance(grid.data == CellState.OCCUPIED, grid.resolution)
        """Distance (m) from each cell to the nearest wall: what the follower collides with, besides
        the teammates' discs (:attr:`collision_gap`)."""
        self._boxes = np.zeros((0, 4), np.int64)  # the discs stamped into the LiDAR's grid
        self._stamped = 0
        self.positions = np.zeros((0, 2))
        """(k, 2) world points (m) of the other robots."""
        self._passing = np.zeros(0, np.bool_)  # those the laser filter keeps out of the map
        self.radius = robot_radius
        """The other robots' radius (m)."""

    def __len__(self) -> int:
        return int(self.positions.shape[0])

    def place(
        self,
        positions: NDArray[np.float64],
        radius: float,
        at: tuple[float, float],
        passing: NDArray[np.bool_] | None = None,
    ) -> None:
        """Other robots at ``positions`` ((k, 2) world points, m) of ``radius`` (m), seen from this
        robot at ``at`` (m): stamped into the LiDAR's blocked grid.
        The laser filter drops those ``passing`` (all by default): a robot that failed stays where
        it is, and its disc, mapped as a wall, closes the map there (filtered, it left a patch of
        unknown that no teammate could ever map, whose frontier ended the episode `unreachable`)."""
        self.radius = radius
        self.positions = np.asarray(positions, dtype=np.float64).reshape(-1, 2)
        self._passing = np.ones(len(self), np.bool_) if passing is None else np.asarray(passing, np.bool_)
        if len(self) == 0 and self._stamped == 0:
            return
        if self._lidar.blocked_padded is self._true_blocked:
            self._lidar.blocked_padded = self._true_blocked.copy()
        if len(self._boxes) < len(self):
            self._boxes = np.zeros((len(self), 4), np.int64)
        g = self._grid
        reach = int(math.ceil(radius / g.resolution)) + 1
        # A teammate overlapping this robot (placed on it) does not hide the world from it.
        apart = self.distances(at) > radius + g.resolution
        self._stamped = stamp_discs(
            self._lidar.blocked_padded,
            self._true_blocked,
            self._boxes,
            self._stamped,
            self.positions[:, 0],
            self.positions[:, 1],
            apart,
            radius,
            reach,
            g.origin[0],
            g.origin[1],
            g.resolution,
        )

    @property
    def collision_gap(self) -> float:
        """Centre distance (m) below which this robot and a teammate collide."""
        return self.radius + self._robot_radius

    def distances(self, point: tuple[float, float]) -> NDArray[np.float64]:
        """Distance (m) from ``point`` to each teammate."""
        x, y = point
        return np.asarray(np.hypot(self.positions[:, 0] - x, self.positions[:, 1] - y), dtype=np.float64)

    def within(self, distance: float, *points: tuple[float, float]) -> bool:
        """Whether a teammate is within ``distance`` (m) of any of ``points``."""
        return len(self) > 0 and any(self.distances(point).min() <= distance for point in points)

    @property
    def contact_distance(self) -> float:
        """Centre distance (m) within which a teammate is (about) in contact with this robot."""
        return self.radius + self._robot_radius + 2.0 * self._grid.resolution

    def in_contact(self, at: tuple[float, float]) -> NDArray[np.float64]:
        """The teammates in contact with this robot at ``at``: (k, 2) world points (m)."""
        return self.positions[self.distances(at) <= self.contact_distance]

    def laser_filter(self) -> tuple[NDArray[np.float64], float] | None:
        """The discs (centres (k, 2) and radius, m) a scan's marks are dropped in; None if none."""
        passing = self.positions[self._passing]
        return (passing, self.radius + TEAMMATE_FILTER_MARGIN_M) if len(passing) else None


def obstacle_distance(occupied: NDArray[np.bool_], resolution: float) -> NDArray[np.float64]:
    """Distance (m) from each cell centre to the nearest occupied cell centre (``inf`` if none)."""
    if not occupied.any():
        return np.full(occupied.shape, np.inf)
    return np.asarray(ndimage.distance_transform_edt(~occupied), dtype=np.float64) * resolution


@nb.njit(cache=True)
def stamp_discs(
    blocked_padded: NDArray[np.bool_],
    true_blocked_padded: NDArray[np.bool_],
    boxes: NDArray[np.int64],
    stamped: int,
    xs: NDArray[np.float64],
    ys: NDArray[np.float64],
    occlude: NDArray[np.bool_],
    radius: float,
    reach: int,
    origin_x: float,
    origin_y: float,
    resolution: float,
) -> int:
    """Take back the ``stamped`` discs of ``boxes`` (row0, row1, col0, col1 per disc) from the
    LiDAR's ``blocked_padded``, then stamp a disc of ``radius`` (m) at every point (xs, ys) (m)
    where ``occlude`` is set: the cells whose centre lies in it (within ``reach`` cells) stop
    beams. ``boxes`` is rewritten. Returns the number of discs stamped."""
    rows, cols = blocked_padded.shape[0] - 2, blocked_padded.shape[1] - 2
    for k in range(stamped):
        for r in range(boxes[k, 0], boxes[k, 1]):
            for c in range(boxes[k, 2], boxes[k, 3]):
                blocked_padded[r + 1, c + 1] = true_blocked_padded[r + 1, c + 1]
    for k in range(xs.shape[0]):
        row = int(math.floor((ys[k] - origin_y) / resolution))
        col = int(math.floor((xs[k] - origin_x) / resolution))
        r0, r1 = max(row - reach, 0), min(row + reach + 1, rows)
        c0, c1 = max(col - reach, 0), min(col + reach + 1, cols)
        boxes[k, 0], boxes[k, 1], boxes[k, 2], boxes[k, 3] = r0, max(r1, r0), c0, max(c1, c0)
        if not occlude[k]:
            continue
        for r in range(r0, r1):
            cy = origin_y + (r + 0.5) * resolution
            for c in range(c0, c1):
                cx = origin_x + (c + 0.5) * resolution
                if math.hypot(cx - xs[k], cy - ys[k]) <= radius:
                    blocked_padded[r + 1, c + 1] = True
    return int(xs.shape[0])
