"""The way back to where the robot started, once exploration is over (``return_to_init``).

explore_lite sends the start as a point goal. A robot that explored beyond a doorway its SLAM map
draws too narrow for the normal costmap has no way back there, so the way home is the path planned
on the first narrow-passage recovery level that has one, sent to the controller as the explorer's
goals found there are; a node sends it again, planned afresh from where the robot stands, when the
navigation stack gives it up.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import replace

import numpy as np
from numpy.typing import NDArray

from frontier_rl.core.navigation.costmap import Costmap
from frontier_rl.core.navigation.thin_walls import Recovery
from frontier_rl.core.world.grid import OccupancyGrid
from frontier_rl.core.world.robot import Pose
from frontier_rl.robot.explorer_decision import Goal
from frontier_rl.robot.paths import path_to_point

HOME_REACH_M = 0.5
"""How near the start (m) a way back must end to be the way home: a dock, or a person, drawn on
the start keeps the normal costmap's way from its very cell (the radius a robot standing on a
wall cell of its map sets out within)."""

HOME_TRIES = 3
"""How many times a node sends the way home, each planned afresh from where the robot stands,
before the navigation stack aborting or rejecting it ends the run (someone in a doorway, a
controller that gave a path up)."""

Reach = Callable[[Recovery], tuple[Costmap, NDArray[np.bool_]]]
"""The costmap at a level and the cells the robot reaches on it."""


def way_home(start: tuple[float, float], grid: OccupancyGrid, pose: Pose, reach: Reach, recovery_paths: bool) -> Goal:
    """The way from ``pose`` back to ``start`` (m, map frame) on ``grid``: a point goal, or (with
    ``recovery_paths``) the path planned on the first narrow-passage recovery level with a way
    there (``reach``) when the normal costmap has none; a way there ends within
    :data:`HOME_REACH_M` of the start."""
    x, y = start
    home = Goal(x, y, np.zeros((0, 2)))
    levels = (Recovery.NONE, Recovery.HALF_CELL, Recovery.WHOLE_CELL) if recovery_paths else ()
    for level in levels:
        costmap, reachable = reach(level)
        path = path_to_point(grid, costmap, reachable, pose, x, y)
        if path is not None and math.dist(path[-1], start) <= HOME_REACH_M:
            return home if level is Recovery.NONE else replace(home, recovery=level, path=path)
    return home
