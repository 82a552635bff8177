"""The way home under way (``return_to_init``), as a node drives it: the goal sent, how often it
was sent, and its path kept to the map while the robot follows it.

The way home is planned once exploration is over (:func:`~frontier_rl.robot.way_home.way_home`).
Nav2 replans a ``navigate_to_pose`` goal itself; a path found on a narrow-passage recovery level
goes to ``follow_path``, whose controller follows the path it was given, so it is planned afresh
at each planner tick on the map then, as the explorer's own path goals are
(:meth:`FrontierExplorer.renewed <frontier_rl.robot.explorer.FrontierExplorer.renewed>`): where
the SLAM map is redrawn under the robot (a wall drawn across the old path), the path goes round
it, rather than leaving the controller to abort (after which the way is planned again from
scratch, :data:`HOME_TRIES` times in all).
"""

from __future__ import annotations

from frontier_rl.core.world.grid import OccupancyGrid
from frontier_rl.core.world.robot import Pose
from frontier_rl.robot.explorer import FrontierExplorer
from frontier_rl.robot.explorer_decision import Goal, Renewal
from frontier_rl.robot.way_home import HOME_TRIES


class HomeTrip:
    """The way home of ``explorer``'s run: :meth:`send` it, :meth:`renew` its path while it is
    driven, :meth:`end` it (arrived, given up or stopped)."""

    def __init__(self, explorer: FrontierExplorer) -> None:
        self._explorer = explorer
        self.goal: Goal | None = None  # the way home sent last, while the robot is on it
        self.tries = 0  # the ways home sent that count towards HOME_TRIES

    @property
    def under_way(self) -> bool:
        """Whether the robot is on its way home."""
        return self.goal is not None

    @property
    def tries_left(self) -> bool:
        """Whether the way home may be planned again after Nav2 gave it up."""
        return self.tries < HOME_TRIES

    def send(self, grid: OccupancyGrid, pose: Pose, *, counted: bool = True) -> Goal | None:
        """The way home from ``pose`` on ``grid``, to send (``counted`` among the tries: not when a
        pause cancelled the last); None when there is none (the explorer never ticked)."""
        home = self._explorer.home(grid, pose)
        if home is None:
            return None
        self.goal = home
        self.tries += counted
        return home

    def renew(self, grid: OccupancyGrid, pose: Pose) -> Renewal | None:
        """The way home's path planned afresh from ``pose`` on ``grid``; None for a way home without
        a path (Nav2 replans it), or with no path to the same end left (the controller gives it up,
        and it is planned again from scratch)."""
        if self.goal is None or (renewal := self._explorer.renewed(self.goal, grid, pose)) is None:
            return None
        self.goal = renewal.goal
        return renewal

    def end(self) -> None:
        """The robot is no longer on its way home."""
        self.goal = None
