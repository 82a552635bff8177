"""What the explorer decides at a planner tick (:class:`~frontier_rl.robot.explorer.FrontierExplorer`):
a goal for the navigation stack, the goal under way with its path planned afresh, or the end of
exploration with what was left."""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum

import numpy as np
from numpy.typing import NDArray

from frontier_rl.core.navigation.thin_walls import Recovery
from frontier_rl.core.sim.candidates import Look
from frontier_rl.core.sim.metrics import EndReason, FrontierLeft


class GoalStatus(Enum):
    """How the navigation stack ended a goal, in the words of ROS 2 actions (the simulated robot
    rejects and cancels none)."""

    SUCCEEDED = "succeeded"
    ABORTED = "aborted"
    REJECTED = "rejected"
    CANCELED = "canceled"
    """Cancelled by another node (an operator's cancel in RViz): the explorer's own cancels end no goal."""


@dataclass(frozen=True)
class Goal:
    """A goal for the navigation stack.

    Attributes:
        x, y: where to drive (m, map frame).
        frontier: the cells (m, map frame, (k, 2)) of the frontier it is for; empty for a point
            goal (a point policy's, or the way back to the start).
        weight: the ranking weight the policy used, if any.
        recovery: the costmap it was found on (the narrow-passage recovery's, where the normal one had none).
        look: a last look (:mod:`frontier_rl.core.sim.looks`) at ``frontier``'s cluster: it lasts
            until the navigation stack ends it, and is a visit of the cluster whatever it shows.
        path: for a goal found on a ``recovery`` level (with ``recovery_paths``), the way there
            ((n, 2), m, map frame, from the robot to the goal) planned on that level's costmap: a
            navigation stack that plans on its own costmap, where the map's doorway is too narrow,
            finds none, and is given this path to follow instead.
    """

    x: float
    y: float
    frontier: NDArray[np.float64]
    weight: float | None = None
    recovery: Recovery = Recovery.NONE
    look: Look = Look.NONE
    path: NDArray[np.float64] | None = None


@dataclass(frozen=True)
class Renewal:
    """The goal under way (a goal with a path) with its path planned afresh from where the robot
    stands (:meth:`FrontierExplorer.renewed <frontier_rl.robot.explorer.FrontierExplorer.renewed>`):
    for a navigation stack that follows the path it is given (Nav2's ``follow_path``). One that
    plans its own way there (``navigate_to_pose``) replans the goal it has by itself and is sent
    nothing: the goal sent again would restart its behaviour tree, recoveries and all (a goal on
    ``follow_path`` whose server went away goes to ``navigate_to_pose`` once)."""

    goal: Goal


@dataclass(frozen=True)
class Finished:
    """Exploration is over.

    Attributes:
        reason: ``explored``, ``unreachable`` (frontiers left, larger than a speck, with unknown
            space beside or behind them) or ``time_cap``.
        left: those frontiers, judged on the map alone: every unknown cell could be free
            (``unseen_free_cells`` counts the unknown cells beside one, ``unseen_behind_m2`` the
            unknown region it opens onto, within the map's bounds; ``has_path``, the audit).
        specks: frontiers left no larger than a speck (scan artefacts, gaps in walls).
    """

    reason: EndReason
    left: tuple[FrontierLeft, ...]
    specks: int

    @property
    def unknown_beside_m2(self) -> float:
        """The unknown area (m²) beside the frontiers left."""
        return float(sum(f.unknown_m2 for f in self.left))

    @property
    def with_a_path(self) -> int:
        """How many frontiers left the map still has a path to (the audit), not counting the
        unrevealable ones (:attr:`unrevealable`)."""
        return sum(f.has_path and not f.unrevealable for f in self.left)

    @property
    def unrevealable(self) -> int:
        """How many frontiers left are unrevealable: reached twice without their frontier going away,
        or with no more than a speck of their unknown in sight of any cell the robot can reach."""
        return sum(f.unrevealable for f in self.left)
