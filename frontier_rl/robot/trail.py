"""The way a real robot has come, drawn on whichever map it is asked of.

The simulated robot's trail (:mod:`frontier_rl.core.sim.trail`) is kept on the world's fixed grid. A
SLAM map grows and its origin moves, so the explorer keeps the robot's centre as points in the map
frame and draws them on each map's cells when the narrow-passage recovery asks: the way it came is
a way back, though its map may since have drawn a wall across it (on ``willow_2010`` a robot sent
into a pocket along a thinned-wall path found the pocket closed round it, and every level of the
recovery reached fewer than 60 cells).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from frontier_rl.core.sim.trail import mark_path
from frontier_rl.core.world.grid import OccupancyGrid

TRAIL_SPACING_M = 0.01
"""A pose this near (m) the trail's last point adds none."""

TRAIL_JUMP_M = 1.0
"""A pose farther (m) than this from the trail's last point starts a new stretch: the pose jumped
(a relocalisation), and a straight line across the jump is no way the robot drove. slam_toolbox
publishes its pose each time it adds a scan, after the robot has moved 0.5 m (its
``minimum_travel_distance``): such poses are points of one stretch, and a jump shorter than this
is drawn as a line (only the cells the map has free are opened)."""


class Trail:
    """The robot's centre over time (map frame, m), and the cells of a map it crossed."""

    def __init__(self) -> None:
        self._points = np.zeros((1024, 2))
        self._count = 0
        self._stretch_starts: list[int] = []  # the first point of each stretch
        self._drawn: NDArray[np.bool_] | None = None
        self._drawn_frame: tuple[tuple[int, int], tuple[float, float], float] | None = None
        self._drawn_count = 0  # the points drawn on ``_drawn``

    def __len__(self) -> int:
        return self._count

    def add(self, x: float, y: float) -> None:
        """The robot's centre is at (x, y) (m, map frame); a point not finite is ignored."""
        if not (math.isfinite(x) and math.isfinite(y)):
            return
        if self._count:
            last_x, last_y = self._points[self._count - 1]
            step = math.hypot(x - last_x, y - last_y)
            if step < TRAIL_SPACING_M:
                return
            if step > TRAIL_JUMP_M:
                self._stretch_starts.append(self._count)
        else:
            self._stretch_starts.append(0)
        if self._count == len(self._points):
            self._points = np.concatenate((self._points, np.zeros_like(self._points)))
        self._points[self._count] = (x, y)
        self._count += 1

    def on(self, grid: OccupancyGrid) -> NDArray[np.bool_]:
        """The cells of ``grid`` the robot's centre crossed (``grid``'s shape, 4-connected:
        :func:`~frontier_rl.core.sim.trail.mark_path`); read only, kept for the next map of the
        same frame, on which only the points added since are drawn."""
        frame = (grid.shape, (float(grid.origin[0]), float(grid.origin[1])), float(grid.resolution))
        if self._drawn is None or frame != self._drawn_frame:
            self._drawn, self._drawn_frame, self._drawn_count = np.zeros(grid.shape, np.bool_), frame, 0
        if self._count > self._drawn_count:
            self._draw(grid, self._drawn, self._drawn_count)
            self._drawn_count = self._count
        return self._drawn

    def _draw(self, grid: OccupancyGrid, cells: NDArray[np.bool_], since: int) -> None:
        """Draw on ``cells`` the points from ``since`` on, each stretch as a polyline (the one under
        way from the last point drawn, so that the line is not broken where drawing stopped)."""
        ends = [*self._stretch_starts[1:], self._count]
        for start, end in zip(self._stretch_starts, ends, strict=True):
            if end <= since:
                continue
            mark_path(cells, grid, self._points[max(start, since - 1) : end])
