"""The explorer's decisions on a real robot's map, without ROS: which frontier to send the
navigation stack to next, when to give a goal up, and when the building is done.

What explore_lite's users report (exploration that stops with unknown space left, goals that
oscillate or never progress, a blacklist that leaves parts unexplored) is answered by the engine's
own pieces: the candidates of :func:`~frontier_rl.core.sim.candidates.find_candidates` (a blacklist
that forgets, retries and the audit before giving up, goals on cells that see their frontier),
the narrow-passage recovery's levels when the normal costmap leaves none (open along the robot's
trail, :mod:`~frontier_rl.robot.trail`), then the last looks the simulated robot takes
(:mod:`frontier_rl.core.sim.looks`: through windows and gaps too small to be frontiers, into the
unknown a frontier left opens onto, and at frontiers given up, from elsewhere), any policy's
ranking, and an end reason that says what was left. The robot's navigation stack plans and drives;
the node that owns a :class:`FrontierExplorer` tells it what happened to each goal.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
from numpy.typing import NDArray

from frontier_rl.core.frontiers.blacklist import Blacklist
from frontier_rl.core.frontiers.fringe import count_fringe
from frontier_rl.core.navigation.costmap import Costmap
from frontier_rl.core.navigation.inflation import InflationMemory
from frontier_rl.core.navigation.thin_walls import Recovery
from frontier_rl.core.sim.candidates import Candidates, Look, find_candidates, reachable_cells
from frontier_rl.core.sim.config import DROP_CELL_M, SimConfig
from frontier_rl.core.sim.episode import DecisionContext, EpisodeAwarePolicy, ExplorationPolicy, checked_ranking
from frontier_rl.core.sim.episode_log import completion_reason
from frontier_rl.core.sim.frontiers_left import frontiers_left
from frontier_rl.core.sim.look_state import LookState
from frontier_rl.core.sim.looks import LOOK_PAYOFF_M2
from frontier_rl.core.sim.metrics import EndReason
from frontier_rl.core.world.grid import FREE_I8, CellState, OccupancyGrid
from frontier_rl.core.world.robot import Pose
from frontier_rl.errors import ConfigError, short_repr
from frontier_rl.robot.explorer_decision import Finished, Goal, Renewal
from frontier_rl.robot.explorer_params import ExplorerParams
from frontier_rl.robot.goal_progress import GoalProgress
from frontier_rl.robot.paths import path_to_point
from frontier_rl.robot.trail import Trail
from frontier_rl.robot.way_home import way_home


def check_robot_policy(policy: ExplorationPolicy, spec: str) -> None:
    """Raise :class:`ConfigError` if ``policy`` (made from ``spec``) plans on the true world (an
    :class:`~frontier_rl.core.sim.episode.EpisodeAwarePolicy`, the oracle), which a robot does not have."""
    if isinstance(policy, EpisodeAwarePolicy):
        raise ConfigError(f"policy {short_repr(spec)} plans on the true map, which a robot does not have")


class FrontierExplorer:
    """One robot's exploration, decided on the maps it is given.

    Args:
        policy: ranks the frontiers (any :class:`~frontier_rl.core.sim.episode.ExplorationPolicy`
            that needs no true map); a point policy's goal is sent as it is.
        params: the explorer's settings.
        config: the robot, sensor and navigation settings the frontiers are found with.
        rng: the policy's randomness.
    """

    def __init__(
        self,
        policy: ExplorationPolicy,
        params: ExplorerParams | None = None,
        config: SimConfig | None = None,
        rng: np.random.Generator | None = None,
    ) -> None:
        self.config = config or SimConfig()
        self.params = params or ExplorerParams()
        self.policy = policy
        self._rng = rng if rng is not None else np.random.default_rng(0)
        self._memory = InflationMemory()
        self._blacklist: Blacklist | None = None
        self._looks = LookState()
        self._sent_on: OccupancyGrid | None = None  # the map a look under way was sent on
        self.goal: Goal | None = None
        self.candidate_goals: NDArray[np.float64] = np.zeros((0, 2))  # of the last decision (m, map frame)
        self._arrived = False  # the navigation stack reached the goal under way
        self._aborted = False  # the navigation stack ended the goal under way short of it
        self.finished: Finished | None = None
        self.start: tuple[float, float] | None = None
        self.decisions = 0
        self.goals_given_up = 0
        self._progress: GoalProgress | None = None  # towards the goal under way
        self._trail = Trail()

    @property
    def params(self) -> ExplorerParams:
        """The explorer's settings; set them between decisions to change how it goes on (a ROS
        parameter set at run time): the frontiers then drop at the new ``min_frontier_size``."""
        return self._params

    @params.setter
    def params(self, params: ExplorerParams) -> None:
        self._params = params
        self.config = replace(self.config, min_frontier_cells=int(round(params.min_frontier_size / DROP_CELL_M)))

    # ------------------------------------------------------------ what the node asks

    def tick(self, grid: OccupancyGrid, pose: Pose, now: float) -> Goal | Renewal | Finished | None:
        """A planner tick at time ``now`` (s) with the robot's map and pose (map frame): a new goal
        to send (cancelling the one under way), the end of exploration, or None to carry on. The
        goal under way is kept while its frontier is not yet seen and the robot gets nearer to it
        within ``progress_timeout`` (a goal with a path comes back with its path planned afresh, a
        :class:`~frontier_rl.robot.explorer_decision.Renewal`); otherwise it is dropped (seen) or
        given up (blacklisted)."""
        if self.start is None:
            self.start = (pose.x, pose.y)
        self.passed(pose)
        if self.finished is not None:
            return None
        if now >= self.params.time_cap:
            return self.time_up(grid, pose)
        if self.goal is not None:
            if not self._frontier_open(grid):
                self.goal = None  # seen (on the way to a goal that then aborted too): the next one
            elif self._arrived:
                self.goal_failed(grid, reached=True)  # there, and still not seen: it cannot be seen from there
            elif self._aborted or self._stalled(self.goal, grid, pose, now):
                self.goal_failed(grid)
            else:
                return self._path_renewed(grid, pose)
        return self._decide(grid, pose, now)

    def passed(self, pose: Pose) -> None:
        """The robot is at ``pose`` (map frame): a point of its trail, the way back that the
        narrow-passage recovery keeps open (:mod:`~frontier_rl.robot.trail`). Each tick adds its
        pose; a node that reads the pose more often than it ticks passes each one it reads."""
        self._trail.add(pose.x, pose.y)

    def _path_renewed(self, grid: OccupancyGrid, pose: Pose) -> Renewal | None:
        """The goal under way with its path planned afresh (:meth:`renewed`), kept as the goal."""
        if self.goal is None or (renewal := self.renewed(self.goal, grid, pose)) is None:
            return None
        self.goal = renewal.goal
        return renewal

    def renewed(self, goal: Goal, grid: OccupancyGrid, pose: Pose) -> Renewal | None:
        """``goal`` with its path planned afresh from ``pose`` on ``grid`` (at its level), as Nav2's
        behaviour tree replans a ``navigate_to_pose`` goal every second: the map under a path goes
        on changing while the robot follows it; None for a goal without a path, or when no path to
        the same end is left (the navigation stack ends the goal)."""
        if goal.path is None:
            return None
        costmap, reachable = self._reachable(grid, pose, goal.recovery)
        path = path_to_point(grid, costmap, reachable, pose, goal.x, goal.y)
        # a way elsewhere is none (within a cell: a SLAM map's origin moves as it grows)
        if path is None or math.dist(path[-1], goal.path[-1]) >= grid.resolution:
            return None
        return Renewal(replace(goal, path=path))

    def time_up(self, grid: OccupancyGrid, pose: Pose) -> Finished:
        """End exploration at the time cap, with what is left of ``grid`` (a goal aborted and not
        judged yet given up on it first)."""
        self.judge_abort(grid)
        cand = self._levels(grid, pose)[0]
        none = replace(cand, frontiers=cand.frontiers.subset(np.zeros(0, np.int64)))  # every frontier is left
        return self._finish(EndReason.TIME_CAP, grid, pose, none)

    def goal_failed(self, grid: OccupancyGrid, *, reached: bool = False) -> None:
        """The navigation stack rejected or aborted the goal under way (or it made no progress; or,
        ``reached``, got there and its frontier is still not seen): its frontier is blacklisted, to
        be tried again once the map around it changes (a goal reached twice in vain: never). A last
        look is a visit of its cluster either way, and what it mapped on ``grid`` says whether the
        looks go on."""
        goal = self.goal
        if goal is not None and goal.look is not Look.NONE:
            self._looked(grid, goal, viewed=reached)
            if not reached:
                self.goals_given_up += 1
        elif goal is not None and len(goal.frontier):
            blacklist = self._blacklist_for(grid)
            blacklist.fail(goal.x, goal.y, grid.data, reached=reached, frontier=goal.frontier)
            self.goals_given_up += 1
        self.goal = None
        self._arrived = self._aborted = False

    def _looked(self, grid: OccupancyGrid, goal: Goal, *, viewed: bool) -> None:
        """The last look ``goal`` ended (``viewed``: the robot got there): a visit of its cluster,
        as the simulated robot records one, and for the looks' state the floor it mapped: the cells
        within the LiDAR's range of its viewpoint that ``grid`` has free and the map it was sent on
        did not (a teammate's floor elsewhere on a merged map, or a SLAM map that grew or lost free
        cells elsewhere, is not the look's). A look the navigation stack gave up (Nav2 plans on its
        own costmap, where a look found on the narrow-passage recovery's may have no path) counts
        only if it paid: it ends no look."""
        self._blacklist_for(grid).fail(goal.x, goal.y, grid.data, reached=True, frontier=goal.frontier, viewed=viewed)
        if goal.look in (Look.SMALL, Look.BLIND) and self._sent_on is not None:
            revealed = _newly_free_near(self._sent_on, grid, goal.x, goal.y, self.config.lidar.max_range)
            revealed_m2 = revealed * grid.resolution**2
            if viewed or revealed_m2 >= LOOK_PAYOFF_M2:
                self._looks.looked(revealed_m2, blind=goal.look is Look.BLIND)
        self._sent_on = None

    def goal_lost(self) -> None:
        """The navigation stack went away with the goal under way (it restarted, or a pause
        cancelled it): the next tick decides again, and the goal is not held against its frontier.
        A goal already ended is kept, to be judged by the next tick as any goal ended is (it
        ended before it could be lost)."""
        if not (self._arrived or self._aborted):
            self.goal = None

    def judged_on(self, grid: OccupancyGrid) -> bool:
        """Whether the goal under way, ended now, would be judged on ``grid``: a last look (what it
        mapped is counted on the map), or a frontier that ``grid`` still shows (more than its drop
        size: on that map it would be given up, reached or not)."""
        goal = self.goal
        if goal is None or len(goal.frontier) == 0 or goal.look is Look.GIVEN_UP:  # the last: a visit, whatever it maps
            return False
        return goal.look is not Look.NONE or self._frontier_open(grid)

    def goal_reached(self) -> None:
        """The navigation stack reached the goal under way: the next tick decides again, and
        blacklists the goal if its frontier is still not seen on that tick's map (seen edge-on, or
        through a slit: otherwise it would be chosen again and again)."""
        self._arrived = True

    def judge_abort(self, grid: OccupancyGrid) -> None:
        """Give up on ``grid`` now a goal the navigation stack aborted that no tick has judged yet
        (the run ends before the next tick would: the time cap, a stop), as that tick would: a
        frontier ``grid`` shows seen is dropped."""
        if self.goal is None or not self._aborted:
            return
        if self._frontier_open(grid):
            self.goal_failed(grid)
        else:
            self.goal = None

    def goal_aborted(self) -> None:
        """The navigation stack aborted the goal under way (or another node cancelled it; one it
        rejected, never driven, :meth:`goal_failed` gives up at once): the next tick gives it up as
        :meth:`goal_failed` does (or drops it, its frontier seen), on that tick's map, which a node
        whose maps lag the robot takes from after the goal's end (a last look counts the floor it
        mapped before the abort, and the blacklist remembers the map round it as it is then)."""
        self._aborted = True

    # ------------------------------------------------------------------- inside
    def _decide(self, grid: OccupancyGrid, pose: Pose, now: float) -> Goal | Finished:
        cand = self._candidates(grid, pose)
        if len(cand.frontiers) == 0:
            return self._finish(EndReason.EXPLORED, grid, pose, cand)
        context = DecisionContext(
            grid,
            cand.frontiers,
            pose,
            now,
            self.config.lidar.max_range,
            cand.costmap,
            robot_radius=self.config.robot.radius,
        )
        ranking = checked_ranking(self.policy.rank(context, self._rng), len(cand.frontiers), self.policy)
        self.candidate_goals = cand.frontiers.goals
        if ranking.goal is not None and cand.looks is Look.NONE:
            goal = Goal(float(ranking.goal[0]), float(ranking.goal[1]), np.zeros((0, 2)), ranking.weight, cand.recovery)
        else:  # a point policy among looks takes the look nearest its point: a point goal is no look, and
            # the same looks would come back at every decision
            index = int(ranking.order[0]) if ranking.goal is None else _nearest(cand.frontiers.goals, ranking.goal)
            row, col = (int(v) for v in cand.frontiers.goal_cells[index])
            x, y = grid.cell_to_world(row, col)
            cells = grid.cells_to_world(cand.frontiers.cells_of(index))
            goal = Goal(x, y, cells, ranking.weight, cand.recovery, cand.looks)
        if cand.recovery is not Recovery.NONE and self.params.recovery_paths:
            goal = replace(goal, path=path_to_point(cand.grid, cand.costmap, cand.reachable, pose, goal.x, goal.y))
        self.goal, self._arrived, self._aborted = goal, False, False
        self._sent_on = grid if goal.look is not Look.NONE else None
        self.decisions += 1
        self._progress = GoalProgress.start(goal, pose, now)
        return goal

    def _candidates(self, grid: OccupancyGrid, pose: Pose) -> Candidates:
        """The frontiers to choose from: on the normal costmap, else on the narrow-passage
        recovery's levels in turn, else the last looks (as the simulated robot's navigator does);
        the normal costmap's, with no frontier, when there is none of these."""
        levels = self._levels(grid, pose)
        if len(levels[-1].frontiers):
            return levels[-1]
        return self._looks.looks(levels, pose, self.config, self._blacklist_for(grid))

    def _levels(self, grid: OccupancyGrid, pose: Pose) -> list[Candidates]:
        """The candidates on the normal costmap and then on each narrow-passage recovery level in
        turn, up to the first that has a frontier."""
        blacklist = self._blacklist_for(grid)
        levels = [find_candidates(grid, pose, self.config, blacklist, grid.data, memory=self._memory)]
        for level in (Recovery.HALF_CELL, Recovery.WHOLE_CELL):
            if len(levels[-1].frontiers):
                break
            trail = self._trail.on(grid)
            levels.append(find_candidates(grid, pose, self.config, blacklist, grid.data, recovery=level, trail=trail))
        return levels

    def _reachable(self, grid: OccupancyGrid, pose: Pose, level: Recovery) -> tuple[Costmap, NDArray[np.bool_]]:
        """The costmap of ``grid`` at ``level`` (the normal one with the inflation kept from map to
        map, a recovery level's open along the robot's trail) and the cells the robot reaches on it."""
        trail = None if level is Recovery.NONE else self._trail.on(grid)
        return reachable_cells(grid, pose, self.config, recovery=level, memory=self._memory, trail=trail)

    def _blacklist_for(self, grid: OccupancyGrid) -> Blacklist:
        """The blacklist, in ``grid``'s frame: a SLAM map grows, and its origin moves with it."""
        nav = self.config.navigation
        if self._blacklist is None:
            self._blacklist = Blacklist(nav.blacklist_radius, nav.max_goal_failures, grid.resolution, grid.origin)
        self._blacklist.reframe(grid.resolution, grid.origin)
        return self._blacklist

    def _frontier_open(self, grid: OccupancyGrid) -> bool:
        """Whether more than the drop size of the goal's frontier cells are still frontier on ``grid``."""
        assert self.goal is not None
        if len(self.goal.frontier) == 0 or self.goal.look is not Look.NONE:
            return True  # a point goal, and a look, last until the navigation stack ends them
        cells = grid.world_to_cells(self.goal.frontier)
        inside = (cells[:, 0] >= 0) & (cells[:, 0] < grid.height) & (cells[:, 1] >= 0) & (cells[:, 1] < grid.width)
        cells = cells[inside]
        return count_fringe(grid.data, cells[:, 0], cells[:, 1]) > self.config.drop_cells(grid.resolution)

    def _stalled(self, goal: Goal, grid: OccupancyGrid, pose: Pose, now: float) -> bool:
        """Whether the robot has got no nearer to ``goal`` for ``progress_timeout``
        (:class:`~frontier_rl.robot.goal_progress.GoalProgress`)."""
        assert self._progress is not None
        return self._progress.stalled(goal, grid, pose, now, self.params, self.config.robot.radius, self._reachable)

    def _finish(self, reason: EndReason, grid: OccupancyGrid, pose: Pose, cand: Candidates) -> Finished:
        """The end: what is left of ``grid`` beside ``cand``'s frontiers, every unknown cell taken
        as possibly free (a robot has no true map to ask)."""
        maybe_free = OccupancyGrid(
            np.where(grid.data == CellState.UNKNOWN, FREE_I8, grid.data), grid.resolution, grid.origin
        )
        felt = np.zeros(grid.shape, np.bool_)
        blacklist, trail = self._blacklist_for(grid), self._trail.on(grid)
        left = frontiers_left(cand, maybe_free, pose, self.config, blacklist, grid.data, felt, trail)
        speck = self.config.speck_cells(grid.resolution)
        real = tuple(f for f in left if f.cells > speck)  # a speck is a speck, whatever unknown lies behind it
        if reason is EndReason.EXPLORED:
            reason = completion_reason(real)
        self.goal, self._arrived, self._aborted = None, False, False
        self.finished = Finished(reason, real, len(left) - len(real))
        return self.finished

    def home(self, grid: OccupancyGrid, pose: Pose) -> Goal | None:
        """The way back from ``pose`` to where the robot started (``return_to_init``) on ``grid``,
        once exploration is over (:func:`~frontier_rl.robot.way_home.way_home`); None before the
        first tick."""
        if self.start is None:
            return None
        return way_home(
            self.start, grid, pose, lambda level: self._reachable(grid, pose, level), self.params.recovery_paths
        )


def _newly_free_near(before: OccupancyGrid, now: OccupancyGrid, x: float, y: float, radius: float) -> int:
    """How many cells within ``radius`` (m) of (x, y) (m) ``now`` has free that ``before`` did not
    (unknown, occupied, or outside it), the two maps aligned by their world coordinates."""
    rows, cols, cx, cy = now.centres_near(x, y, radius)
    near = np.hypot(cx[None, :] - x, cy[:, None] - y) <= radius
    free = near & (now.data[rows, cols] == CellState.FREE)
    yy, xx = np.nonzero(free)
    if len(yy) == 0:
        return 0
    was = before.world_to_cells(np.column_stack((cx[xx], cy[yy])))
    inside = (was[:, 0] >= 0) & (was[:, 0] < before.height) & (was[:, 1] >= 0) & (was[:, 1] < before.width)
    was_free = np.zeros(len(yy), np.bool_)
    was_free[inside] = before.data[was[inside, 0], was[inside, 1]] == CellState.FREE
    return int(np.count_nonzero(~was_free))


def _nearest(points: NDArray[np.float64], point: tuple[float, float]) -> int:
    """The index of the row of ``points`` ((n, 2), m) nearest to ``point`` (m)."""
    return int(np.argmin(np.hypot(points[:, 0] - point[0], points[:, 1] - point[1])))
