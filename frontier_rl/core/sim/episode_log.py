"""What an episode records as it goes (the decisions, the map updates, the poses), and the
:class:`~frontier_rl.core.sim.metrics.EpisodeResult` made from it."""

from __future__ import annotations

from collections import Counter
from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from frontier_rl.core.sim.config import UNSEEN_ROOM_M2
from frontier_rl.core.sim.leg_result import AbortCause, LegResult
from frontier_rl.core.sim.metrics import (
    DecisionRecord,
    EndReason,
    EpisodeResult,
    FrontierLeft,
    time_to_coverage,
    unseen_area_m2,
)
from frontier_rl.core.world.grid import OccupancyGrid
from frontier_rl.core.world.robot import Pose


def completion_reason(left: Sequence[FrontierLeft]) -> EndReason:
    """How an episode that ran out of candidates ended: ``UNREACHABLE`` when one of the frontiers
    left leaves real space unseen (:attr:`FrontierLeft.leaves_space
    <frontier_rl.core.sim.metrics.FrontierLeft.leaves_space>`: more unseen free cells beside it
    than a speck has, or more than :data:`UNSEEN_ROOM_M2` behind it); else ``EXPLORED``. A frontier
    whose unknown side is all wall (cells no beam reached, or range noise that marked cells inside
    a wall free) leaves nothing to explore."""
    return EndReason.UNREACHABLE if any(f.leaves_space for f in left) else EndReason.EXPLORED


def leaves_space(unseen_free_cells: int, unseen_behind_m2: float, speck_cells: int) -> bool:
    """Whether a frontier left with ``unseen_free_cells`` beside it and ``unseen_behind_m2`` (m²)
    behind it leaves space to explore: more than ``speck_cells`` cells
    (:meth:`SimConfig.speck_cells <frontier_rl.core.sim.config.SimConfig.speck_cells>`; fewer is a
    speck, as the thesis treats fringe clusters that small), or more than :data:`UNSEEN_ROOM_M2`."""
    return unseen_free_cells > speck_cells or unseen_behind_m2 > UNSEEN_ROOM_M2


class EpisodeLog:
    """An episode's record: every decision, every map update (the coverage curve) and every pose.

    Args:
        explorable_cells: the world's explorable cells, the coverage curve's denominator.
    """

    def __init__(self, explorable_cells: int) -> None:
        self._explorable = max(explorable_cells, 1)
        self.decisions: list[DecisionRecord] = []
        self.aborts_by_cause: Counter[AbortCause] = Counter()
        self._times: list[float] = []
        self._explored: list[int] = []
        self._paths: list[float] = []
        self._poses: list[tuple[float, float, float]] = []

    @property
    def aborts(self) -> int:
        """Goals given up so far."""
        return sum(self.aborts_by_cause.values())

    def abort(self, cause: AbortCause) -> None:
        """A goal was given up, for ``cause``."""
        self.aborts_by_cause[cause] += 1

    def pose(self, pose: Pose) -> None:
        """The robot is at ``pose`` (a LiDAR tick)."""
        self._poses.append((pose.x, pose.y, pose.theta))

    def map_update(self, time_s: float, explored_cells: int, path_m: float) -> None:
        """The map was updated at ``time_s`` (s), after the robot drove ``path_m`` (m) in all, and
        now has ``explored_cells`` explorable cells mapped."""
        self._times.append(time_s)
        self._explored.append(explored_cells)
        self._paths.append(path_m)

    def decision(self, leg: LegResult, weight: float | None) -> None:
        """A decision, taken with ranking weight ``weight`` (None for a policy without one), drove ``leg``."""
        (x, y), goal = leg.start_xy, leg.goal
        self.decisions.append(
            DecisionRecord(float(leg.start_s), float(x), float(y), float(goal[0]), float(goal[1]), weight, leg.outcome)
        )

    def poses_since(self, first: int) -> NDArray[np.float64]:
        """(n, 3) the poses from the ``first``-th logged one on (x, y, theta; m, rad)."""
        return np.asarray(self._poses[first:], dtype=np.float64).reshape(-1, 3)

    @property
    def pose_count(self) -> int:
        """How many poses are logged."""
        return len(self._poses)

    def trajectory(self) -> NDArray[np.float64]:
        """(n, 3) robot poses (x, y, theta) so far."""
        return np.asarray(self._poses, dtype=np.float64).reshape(-1, 3)

    def result(
        self,
        *,
        sim_time_s: float,
        path_length_m: float,
        coverage: float,
        truncated: bool,
        reason: EndReason | None,
        left: tuple[FrontierLeft, ...],
        free_coverage: float,
        final_map: OccupancyGrid,
        wall_time_s: float,
    ) -> EpisodeResult:
        """The episode's result from this log and the figures only the simulator knows."""
        times = np.asarray(self._times, dtype=np.float64)
        curve = np.asarray(self._explored, dtype=np.float64) / self._explorable
        return EpisodeResult(
            sim_time_s=sim_time_s,
            path_length_m=path_length_m,
            coverage=coverage,
            t90_s=time_to_coverage(times, curve, 0.90),
            t99_s=time_to_coverage(times, curve, 0.99),
            decisions=len(self.decisions),
            aborts=self.aborts,
            aborts_by_cause=aborts_by_cause([self.aborts_by_cause]),
            done=reason is EndReason.EXPLORED,
            truncated=truncated,
            wall_time_s=wall_time_s,
            end_reason=reason,
            free_coverage=free_coverage,
            unknown_left_m2=unseen_area_m2(left, final_map.resolution),
            explorable_m2=self._explorable * final_map.resolution**2,
            coverage_times_s=times,
            coverage_curve=curve,
            coverage_path_m=np.asarray(self._paths, dtype=np.float64),
            trajectory=self.trajectory(),
            decision_log=tuple(self.decisions),
            final_map=final_map,
            frontiers_left=left,
        )


def aborts_by_cause(counts: Sequence[Counter[AbortCause]]) -> dict[AbortCause, int]:
    """The goals given up per cause, summed over ``counts`` (a robot's, or a team's robots'), every
    cause named (0 where none), in :class:`~frontier_rl.core.sim.leg_result.AbortCause`'s order."""
    total: Counter[AbortCause] = sum(counts, Counter())
    return {cause: total[cause] for cause in AbortCause}
