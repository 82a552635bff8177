"""Whether the robot gets nearer to the goal under way, as explore_lite's ``progress_timeout`` asks:
a goal the robot has got no ``progress_distance`` nearer to for that long is given up. Nearer is
measured in a straight line and, once the straight line has made no progress for that long, along
the way the robot's costmap plans there: a way round a long wall first leads away from the goal (on
``ipa_plant`` a corridor beyond a long wall was given up six times, by distance alone)."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from frontier_rl.core.navigation.costmap import Costmap
from frontier_rl.core.navigation.thin_walls import Recovery
from frontier_rl.core.sim.leg import tail_lengths
from frontier_rl.core.world.grid import OccupancyGrid
from frontier_rl.core.world.robot import Pose
from frontier_rl.robot.explorer_decision import Goal
from frontier_rl.robot.explorer_params import ExplorerParams
from frontier_rl.robot.paths import path_to_point

ReachableOn = Callable[[OccupancyGrid, Pose, Recovery], tuple[Costmap, NDArray[np.bool_]]]
"""The costmap of a map at a level and the cells the robot reaches on it from a pose."""


@dataclass
class GoalProgress:
    """The robot's progress towards a goal.

    Attributes:
        best_distance_m: the goal's straight-line distance at its least (m).
        at_s: when the robot last made progress (s, the explorer's clock).
        pose: where it stood then.
    """

    best_distance_m: float
    at_s: float
    pose: Pose

    @classmethod
    def start(cls, goal: Goal, pose: Pose, now: float) -> GoalProgress:
        """The progress towards ``goal``, sent at ``now`` (s) with the robot at ``pose``."""
        return cls(math.hypot(goal.x - pose.x, goal.y - pose.y), now, pose)

    def stalled(
        self,
        goal: Goal,
        grid: OccupancyGrid,
        pose: Pose,
        now: float,
        params: ExplorerParams,
        robot_radius_m: float,
        reachable_on: ReachableOn,
    ) -> bool:
        """Whether the robot, at ``pose`` at ``now`` (s), has got no nearer to ``goal`` for
        ``progress_timeout``, neither in a straight line nor along the way ``reachable_on``'s
        costmap of ``grid`` plans there (at the goal's level); the way is asked for only when the
        straight line has made no progress for that long."""
        distance = math.hypot(goal.x - pose.x, goal.y - pose.y)
        if distance <= self.best_distance_m - params.progress_distance:
            self.best_distance_m, self.at_s, self.pose = distance, now, pose
        elif now - self.at_s > params.progress_timeout and self._nearer_along_the_way(
            goal, grid, pose, params, robot_radius_m, reachable_on
        ):
            self.at_s, self.pose = now, pose
        return now - self.at_s > params.progress_timeout

    def _nearer_along_the_way(
        self,
        goal: Goal,
        grid: OccupancyGrid,
        pose: Pose,
        params: ExplorerParams,
        robot_radius_m: float,
        reachable_on: ReachableOn,
    ) -> bool:
        """Whether the way to ``goal`` on ``grid`` (planned at its level) is ``progress_distance``
        shorter from ``pose`` than from where the robot stood at its last progress: both planned on
        the same map, to the same cell (a SLAM map's origin moves as it grows). A way to a frontier's
        goal that ends beyond the robot's reach of it (the reachable cell nearest a goal the map has
        since walled off, or the edge of an island the robot stands on) is none: nearer to its end
        is not nearer to the goal. Within that reach it is one (an inflation grown over the goal
        cell still lets the robot get there); a point goal's way ends where the point is nearest."""
        costmap, reachable = reachable_on(grid, pose, goal.recovery)
        now_way = path_to_point(grid, costmap, reachable, pose, goal.x, goal.y)
        reach = robot_radius_m + grid.resolution
        if now_way is None or (len(goal.frontier) and math.dist(now_way[-1], (goal.x, goal.y)) > reach):
            return False
        then_way = path_to_point(grid, costmap, reachable, self.pose, goal.x, goal.y)
        if then_way is None:
            return False
        return bool(tail_lengths(now_way)[0] <= tail_lengths(then_way)[0] - params.progress_distance)
