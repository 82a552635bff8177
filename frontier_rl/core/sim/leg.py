"""A leg: one drive toward a chosen goal, from the decision to the moment the robot gets there, the
goal's frontier is seen, or the goal is given up.

The leg follows its path in map updates (the follower drives until the mapper wants the next
scan), watches its progress, replans when a wall turns up on the path, turns on the spot to
recover when no path is left, marks walls it bumps into, and in a team waits for a teammate in the
way, then goes round it or gives way. It reaches the simulator only through :class:`LegPort`.
"""

from __future__ import annotations

import math
from collections.abc import Generator
from typing import Protocol, TypeVar

import numpy as np
from numpy.typing import NDArray

from frontier_rl.core.navigation.follower import FollowerParams, FollowStatus, careful_flags, follow_path
from frontier_rl.core.navigation.thin_walls import Recovery
from frontier_rl.core.sim.config import SimConfig
from frontier_rl.core.sim.leg_result import AbortCause, LegOutcome
from frontier_rl.core.sim.paths import cells_beyond
from frontier_rl.core.sim.teammates import Teammates
from frontier_rl.core.world.robot import Pose
from frontier_rl.core.world.worlds import World

_BLOCKED = (FollowStatus.BLOCKED, FollowStatus.BLOCKED_BY_ROBOT)


class LegNavigation(Protocol):
    """What a leg needs of the robot's navigation (:class:`~frontier_rl.core.sim.navigator.Navigator`)."""

    def replan(self, goal: tuple[float, float], recovery: Recovery, pose: Pose) -> NDArray[np.float64] | None:
        """A new path (n, 2) (m) from ``pose`` to ``goal`` on the current map, or None."""

    def replan_round_teammates(
        self, goal: tuple[float, float], recovery: Recovery, pose: Pose
    ) -> NDArray[np.float64] | None:
        """:meth:`replan`'s path, but one that keeps out of the teammates in contact, or None."""

    def give_way(self, goal: tuple[float, float]) -> None:
        """End the leg to ``goal`` for the teammates in contact: the next decision sees them as walls."""

    def path_blocked(self, path_cells: NDArray[np.int64], first: int, recovery: Recovery) -> bool:
        """Whether the map puts a wall on the path (world cells) from index ``first`` on."""

    def frontier_alive(self, cells: NDArray[np.int64]) -> bool:
        """Whether a frontier's cells (world cells) are still a frontier."""

    def blacklist_goal(
        self, goal: tuple[float, float], frontier_cells: NDArray[np.int64] | None, *, reached: bool = False
    ) -> None:
        """Record a failed attempt at ``goal`` (m) for the frontier of ``frontier_cells`` (world
        cells, None for a point goal); ``reached``: the robot got there and its frontier stayed."""


class LegPort(Protocol):
    """What a leg needs from the simulator: its clock and body, and where it can go on its map."""

    @property
    def config(self) -> SimConfig: ...
    @property
    def world(self) -> World: ...
    @property
    def pose(self) -> Pose: ...
    @property
    def sim_time(self) -> float: ...
    @property
    def truncated(self) -> bool: ...
    @property
    def nearby_robots(self) -> Teammates: ...
    @property
    def follow_params(self) -> FollowerParams: ...
    @property
    def navigator(self) -> LegNavigation: ...

    def advance(self, pose: Pose, driven: float, duration: float) -> tuple[int, int] | None:
        """Move the clock on by ``duration`` (s), the robot to ``pose`` having driven ``driven`` (m),
        and take a LiDAR tick: the cells first mapped free and occupied, or None (no map update)."""

    def until_next_scan(self) -> tuple[float, NDArray[np.float64]]:
        """How long (s) to drive before the mapper's next scan, and the follower's scan gate."""

    def wait_steps(self) -> Generator[None, None, None]:
        """Stand still until the next map update."""

    def rotate_steps(self) -> Generator[None, None, tuple[int, int]]:
        """A recovery rotation: the cells it first mapped free and occupied."""

    def bump(self) -> None:
        """Mark the walls the robot touches as occupied (its bumper)."""


class ProgressWatchdog:
    """move_base's progress check: a leg progresses while the way left gets shorter by
    ``progress_distance`` or the robot gets ``oscillation_distance`` away from where it last
    progressed (a replanned detour can make the way longer while the robot is doing fine)."""

    def __init__(self, time_s: float, xy: tuple[float, float], progress_distance: float, oscillation: float) -> None:
        self._best = math.inf
        self._since = time_s
        self._at = xy
        self._step = progress_distance
        self._oscillation = oscillation

    def stalled_for(self, remaining: float, xy: tuple[float, float], time_s: float) -> float:
        """Record the way ``remaining`` (m) from ``xy`` (m) at ``time_s`` (s); how long (s) the leg
        has gone without progress (0 when it just made some)."""
        moved = math.hypot(xy[0] - self._at[0], xy[1] - self._at[1]) >= self._oscillation
        if remaining < self._best - self._step or moved:
            self._best = min(self._best, remaining)
            self._since = time_s
            self._at = xy
            return 0.0
        return time_s - self._since


LOCAL_COSTMAP_REACH_M = 1.5
"""How far along a path given to follow (m) a wall on the map ends it: half the side of Nav2's
default local costmap (3 m), the window its controller checks."""


class Leg:
    """One drive along ``path`` (n, 2) (m) to ``goal`` (m): :meth:`run` it to its end.

    Args:
        port: the simulator.
        path: the planned path, its last point the goal.
        goal: the goal (m).
        frontier_cells: the world cells of the goal's frontier, None for a point goal.
        recovery: the costmap the path was planned on (the normal one, or a level of the
            narrow-passage recovery's), which replanning keeps to.
        given_path: a path given to follow, as Nav2's controller follows one: walls on the map are
            looked for only within :data:`LOCAL_COSTMAP_REACH_M` along it, and one there (or one
            the robot touched) is driven round on the same costmap, with no recovery rotations;
            where there is no way round, the leg is given up (``no_path``).
    """

    def __init__(
        self,
        port: LegPort,
        path: NDArray[np.float64],
        goal: tuple[float, float],
        frontier_cells: NDArray[np.int64] | None,
        recovery: Recovery,
        *,
        given_path: bool = False,
    ) -> None:
        self._port = port
        self._given_path = given_path
        self.goal = goal
        self._frontier_cells = frontier_cells
        self._recovery = recovery
        self._params = port.follow_params
        self._closing_in = False
        self._blocked_by_robot_since: float | None = None
        nav = port.config.navigation
        self._watchdog = ProgressWatchdog(
            port.sim_time, (port.pose.x, port.pose.y), nav.progress_distance, nav.oscillation_distance
        )
        self._next_frontier_check = port.sim_time + nav.frontier_check_period
        self._recoveries = 0
        self.abort_cause: AbortCause | None = None
        """Why the leg gave its goal up, once it has."""
        self._driven = 0.0  # m
        self.new_free = 0
        self.new_occupied = 0
        self._set_path(path)
        self._detour_limit = nav.detour_limit(float(self._tail[0]), recovery is not Recovery.NONE)  # m

    def _set_path(self, path: NDArray[np.float64]) -> None:
        self._path = path
        self._path_cells = self._port.world.grid.world_to_cells(path)
        self._tail = tail_lengths(path)
        self._careful = careful_flags()  # the follower's waypoint-by-waypoint modes, per path
        self._index = 0

    @property
    def given_path(self) -> bool:
        """Whether the leg follows a path it was given (:meth:`take_path`)."""
        return self._given_path

    def take_path(self, path: NDArray[np.float64]) -> None:
        """Follow ``path`` ((n, 2), m, from the robot to the leg's goal) from now on, as a
        controller takes the next path of the goal it drives to: the leg's progress, detour and
        costmap are kept."""
        self._set_path(path)

    def run(self) -> Generator[None, None, LegOutcome]:
        """Drive until the leg ends, yielding after every map update (or LiDAR tick of a turn)."""
        outcome = yield from self._drive()
        yield from self._settle(outcome)
        return outcome

    def _drive(self) -> Generator[None, None, LegOutcome]:
        port, given_path = self._port, self._given_path
        while not port.truncated:
            status, seen = self._follow()
            yield
            self._count(seen)
            if status == FollowStatus.REACHED:
                if self._closing_in or not self._frontier_alive():
                    return LegOutcome.REACHED
                self._close_in()
                continue
            if port.truncated:
                break
            if self._frontier_explored():
                return LegOutcome.EXPLORED
            self.abort_cause = self._giving_up()
            if self.abort_cause is not None:
                return LegOutcome.ABORTED
            if status == FollowStatus.BLOCKED_BY_ROBOT:
                ended = yield from self._wait_or_give_way()
                if ended is not None:
                    return ended
                continue
            self._blocked_by_robot_since = None
            if status == FollowStatus.BLOCKED:
                port.bump()
            # only a map update can put a new obstacle on the path
            if status == FollowStatus.BLOCKED or (seen is not None and self._path_blocked()):
                path = (yield from self._replan_or_recover()) if not given_path else self._round_the_wall()
                if path is None:
                    return self._lost_way()
                self._set_path(path)
        return LegOutcome.TIMEOUT

    def _path_blocked(self) -> bool:
        """Whether the map puts a wall on the path from the robot's waypoint on; for a path given
        to follow, only within :data:`LOCAL_COSTMAP_REACH_M` along it (a controller sees its local
        costmap only, and whoever gave it the path replans farther on) and beyond the planner's
        escape radius of the robot (:func:`~frontier_rl.core.sim.paths.cells_beyond`)."""
        navigator, index = self._port.navigator, self._index
        if not self._given_path:
            return navigator.path_blocked(self._path_cells, index, self._recovery)
        end = index + int(np.count_nonzero(self._tail[index:] >= self._tail[index] - LOCAL_COSTMAP_REACH_M))
        cells = cells_beyond(self._path[index:end], self._path_cells[index:end], self._port.pose)
        return len(cells) > 0 and navigator.path_blocked(cells, 0, self._recovery)

    def _round_the_wall(self) -> NDArray[np.float64] | None:
        """A path given to follow, blocked near the robot: a new way to the goal on its costmap (as a
        controller steers round what its local costmap shows), without the recovery rotations."""
        return self._port.navigator.replan(self.goal, self._recovery, self._port.pose)

    def _lost_way(self) -> LegOutcome:
        """No path is left after the recovery rotations: the time cap ended the leg, or it gives up."""
        if self._port.truncated:
            return LegOutcome.TIMEOUT
        self.abort_cause = AbortCause.NO_PATH
        return LegOutcome.ABORTED

    def _giving_up(self) -> AbortCause | None:
        """Why the leg gives up now: it has gone ``progress_timeout`` without progress, or driven
        farther than its detour limit (``detour_factor`` times its first plan and ``detour_slack``
        more, or the recovery's tighter limit on a narrow-passage recovery's costmap); None while
        it goes on."""
        port = self._port
        here = (port.pose.x, port.pose.y)
        stalled = self._watchdog.stalled_for(self._remaining(), here, port.sim_time)
        if stalled > port.config.navigation.progress_timeout:
            return AbortCause.NO_PROGRESS
        return AbortCause.DETOUR if self._driven > self._detour_limit else None

    def _follow(self) -> tuple[int, tuple[int, int] | None]:
        """Drive tick by tick until the mapper wants the next scan (nothing else changes before),
        then scan: the follower's status (reached when closing in and blocked) and the scan's new
        cells."""
        port = self._port
        truth = port.world.grid
        mates = port.nearby_robots
        pose = port.pose
        duration, gate = port.until_next_scan()
        x, y, theta, self._index, driven, used, status = follow_path(
            self._path[:, 0],
            self._path[:, 1],
            self._index,
            pose.x,
            pose.y,
            pose.theta,
            duration,
            self._params,
            mates.wall_clearance,
            mates.positions,
            mates.collision_gap,
            truth.origin[0],
            truth.origin[1],
            truth.resolution,
            gate,
            self._careful,
        )
        self._driven += driven
        if status in _BLOCKED and self._closing_in:
            status = FollowStatus.REACHED  # closing in and a wall or robot is in the way: as close as it gets
        return status, port.advance(Pose(x, y, theta), driven, used)

    def _count(self, seen: tuple[int, int] | None) -> None:
        if seen is not None:
            self.new_free += seen[0]
            self.new_occupied += seen[1]

    def _frontier_alive(self) -> bool:
        return self._frontier_cells is not None and self._port.navigator.frontier_alive(self._frontier_cells)

    def _close_in(self) -> None:
        """Within the goal tolerance and the frontier is still there: close in on the goal cell
        itself (a frontier seen through a gap needs the exact viewpoint)."""
        self._params = self._params._replace(goal_tolerance=self._port.world.grid.resolution)
        self._closing_in = True

    def _frontier_explored(self) -> bool:
        """Whether the periodic check finds the goal's frontier seen (never for a point goal)."""
        port = self._port
        if self._frontier_cells is None or port.sim_time < self._next_frontier_check:
            return False
        self._next_frontier_check = port.sim_time + port.config.navigation.frontier_check_period
        return not port.navigator.frontier_alive(self._frontier_cells)

    def _remaining(self) -> float:
        """The way (m) left along the path from the robot."""
        pose, i = self._port.pose, self._index
        return float(math.hypot(self._path[i, 0] - pose.x, self._path[i, 1] - pose.y) + self._tail[i])

    def _wait_or_give_way(self) -> Generator[None, None, LegOutcome | None]:
        """Give a teammate in the way ``teammate_patience`` to move on. Then, when the robot or a
        teammate in contact stands within a robot's width and the goal tolerance of the goal, the
        robot is as close as it gets (REACHED: teammates crowding round one goal had given way to
        each other for ever); else it takes a way round if there is one (None: the leg goes on), or
        gives way (GAVE_WAY: the robot chooses again with the teammate as an obstacle). Robots
        never drive through each other."""
        port = self._port
        if self._blocked_by_robot_since is None:
            self._blocked_by_robot_since = port.sim_time
        if port.sim_time - self._blocked_by_robot_since < port.config.navigation.teammate_patience:
            yield from port.wait_steps()
            return None
        self._blocked_by_robot_since = None
        here = (port.pose.x, port.pose.y)
        mates = port.nearby_robots
        near = mates.collision_gap + port.config.navigation.goal_tolerance
        if any(math.dist(xy, self.goal) <= near for xy in (here, *mates.in_contact(here))):
            return LegOutcome.REACHED
        path = port.navigator.replan_round_teammates(self.goal, self._recovery, port.pose)
        if path is None:
            port.navigator.give_way(self.goal)
            return LegOutcome.GAVE_WAY
        self._set_path(path)
        return None

    def _replan_or_recover(self) -> Generator[None, None, NDArray[np.float64] | None]:
        """A new path to the goal; while there is none, up to ``max_recoveries`` recovery
        rotations, each followed by another try."""
        port = self._port
        path = port.navigator.replan(self.goal, self._recovery, port.pose)
        while path is None and self._recoveries < port.config.navigation.max_recoveries and not port.truncated:
            self._recoveries += 1
            self._count((yield from port.rotate_steps()))
            path = port.navigator.replan(self.goal, self._recovery, port.pose)
        return path

    def _settle(self, outcome: LegOutcome) -> Generator[None, None, None]:
        """Blacklist a goal the leg gave up. At the goal the frontier may still be there (seen
        edge-on, or hidden in the LiDAR's blind zone): wait for the next map update, and if it is
        still there the robot cannot resolve it from here, so it is blacklisted too; otherwise the
        same frontier would be chosen again and again, at no cost in time, for ever."""
        if outcome is LegOutcome.REACHED and self._frontier_alive():
            yield from self._port.wait_steps()
            if self._frontier_alive():
                self._port.navigator.blacklist_goal(self.goal, self._frontier_cells, reached=True)
        if outcome is LegOutcome.ABORTED:
            self._port.navigator.blacklist_goal(self.goal, self._frontier_cells)


def tail_lengths(path: NDArray[np.float64]) -> NDArray[np.float64]:
    """For each waypoint, the length (m) of the path from it to the end."""
    seg = np.hypot(*np.diff(path, axis=0).T)
    return np.concatenate((np.cumsum(seg[::-1])[::-1], [0.0]))


_T = TypeVar("_T")


def run_leg(steps: Generator[None, None, _T]) -> _T:
    """Run a stepwise leg (:meth:`ExplorationSimulator.execute_steps`, ...) to its end; its result."""
    while True:
        try:
            next(steps)
        except StopIteration as stop:
            return stop.value  # type: ignore[no-any-return]
