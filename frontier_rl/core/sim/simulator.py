"""The exploration episode: decide -> drive -> sense -> map, on a simulated clock.

:class:`ExplorationSimulator` is a state machine with one entry point per decision, so that an
episode runner and a Gymnasium env drive it the same way: :meth:`candidates` gives the current
frontiers, :meth:`execute` drives to the first of a ranked list that can be planned to (or
:meth:`go_to` to any point), simulating LiDAR, mapping and navigation until the leg ends.
"""

from __future__ import annotations

import math
from collections.abc import Generator, Sequence
from dataclasses import dataclass, field
from enum import Enum
from typing import TypeVar

import numpy as np
from numpy.typing import NDArray

from frontier_rl.core.frontiers.blacklist import Blacklist
from frontier_rl.core.frontiers.detection import Frontiers, count_fringe, detect_frontiers, unknown_beside
from frontier_rl.core.mapping.mapper import LogOddsMapper, MapperConfig
from frontier_rl.core.navigation.astar import SearchScratch
from frontier_rl.core.navigation.costmap import Costmap, nearest_cell
from frontier_rl.core.navigation.follower import (
    NavigationConfig,
    follow_path,
    footprint_offsets,
    path_blocked,
)
from frontier_rl.core.navigation.thin_walls import thin_walls
from frontier_rl.core.sensing.lidar import Lidar, LidarConfig
from frontier_rl.core.sim.metrics import DecisionRecord, EpisodeResult, FrontierLeft, time_to_coverage
from frontier_rl.core.sim.teammates import Teammates
from frontier_rl.core.world.grid import CellState, OccupancyGrid
from frontier_rl.core.world.robot import Pose, RobotConfig
from frontier_rl.core.world.worlds import World, make_world
from frontier_rl.errors import ConfigError


@dataclass(frozen=True)
class SimConfig:
    """Everything that defines a simulated episode besides the world and the seed.

    Attributes:
        robot: robot footprint and speed limits.
        lidar: the range sensor.
        mapper: the log-odds map update.
        navigation: costmap, planner and controller.
        min_frontier_cells: frontier clusters of this many cells or fewer are dropped.
        max_sim_time: sim-time cap of an episode (s); the episode is truncated there. ``None``
            (the default) scales it with the world: see :meth:`time_cap`.
        sensor_noise: whether LiDAR ranges get noise.
        time_per_area: the default cap allows this much sim time per m² of explorable space (s/m²).
        min_time_cap: ... and never less than this (s).
        frontier_segment_length: frontier clusters longer than this (m) are split into segments,
            each a candidate with its own goal (about the mapping range: one view resolves one).
        frontier_goal_reach: a frontier's goal is a reachable cell that sees it from at most this
            far (m); a frontier with none is not a candidate.
    """

    robot: RobotConfig = field(default_factory=RobotConfig)
    lidar: LidarConfig = field(default_factory=LidarConfig)
    mapper: MapperConfig = field(default_factory=MapperConfig)
    navigation: NavigationConfig = field(default_factory=NavigationConfig)
    min_frontier_cells: int = 4
    max_sim_time: float | None = None
    sensor_noise: bool = True
    time_per_area: float = 10.0
    min_time_cap: float = 3600.0
    frontier_segment_length: float = 3.0
    frontier_goal_reach: float = 3.0

    def __post_init__(self) -> None:
        if self.min_frontier_cells < 0:
            raise ConfigError(f"min_frontier_cells must be >= 0, got {self.min_frontier_cells!r}")
        if self.max_sim_time is not None and not (self.max_sim_time > 0 and math.isfinite(self.max_sim_time)):
            raise ConfigError(f"max_sim_time must be a positive number of seconds, got {self.max_sim_time!r}")
        for name in ("time_per_area", "min_time_cap", "frontier_segment_length", "frontier_goal_reach"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0):
                raise ConfigError(f"{name} must be a positive number, got {value!r}")

    @property
    def mapping_range(self) -> float:
        """The range (m) within which a scan updates the map: the LiDAR's, cropped at the mapper's."""
        return min(self.lidar.max_range, self.mapper.usable_range)

    def fit_world(self, world: World) -> World:
        """``world`` with its explorable space computed for this robot's radius and mapping range
        (the same world when it already is)."""
        if (world.robot_radius, world.sensor_range) == (self.robot.radius, self.mapping_range):
            return world
        return make_world(
            world.grid, world.name, start=world.start, robot_radius=self.robot.radius, sensor_range=self.mapping_range
        )

    def time_cap(self, world: World) -> float:
        """The sim-time cap (s) of an episode on ``world``: ``max_sim_time`` when set, else
        ``time_per_area`` s per m² of its explorable space, at least ``min_time_cap`` (an office
        of 12.5 m x 12.5 m gets 3,600 s; a 60 m x 50 m floor about 20,000 s)."""
        if self.max_sim_time is not None:
            return self.max_sim_time
        area = world.explorable_count * world.grid.resolution**2
        return max(self.min_time_cap, self.time_per_area * area)


class LegOutcome(Enum):
    """How a drive toward a goal ended."""

    REACHED = "reached"
    EXPLORED = "explored"  # the goal's frontier was seen before the robot got there
    ABORTED = "aborted"  # no progress, no path, or stuck: the goal is blacklisted
    TIMEOUT = "timeout"  # the episode's sim-time cap
    NONE = "none"  # no candidate could be planned to


class EndReason(Enum):
    """Why an episode ended."""

    EXPLORED = "explored"  # no frontier left with free space behind it
    UNREACHABLE = "unreachable"  # frontiers left with free space behind: every attempt failed, or no reachable view
    TIME_CAP = "time_cap"  # the sim-time cap


@dataclass(frozen=True)
class LegResult:
    """One decision's drive.

    Attributes:
        outcome: how it ended.
        frontier: index of the frontier driven to (in the candidates), -1 for a point goal or none.
        goal: the goal (m).
        duration_s: sim time the leg took (s).
        distance_m: distance driven (m).
        new_free, new_occupied: cells first mapped free / occupied during the leg.
    """

    outcome: LegOutcome
    frontier: int
    goal: tuple[float, float]
    duration_s: float
    distance_m: float
    new_free: int
    new_occupied: int


@dataclass
class _Candidates:
    grid: OccupancyGrid
    costmap: Costmap
    reachable: NDArray[np.bool_]
    frontiers: Frontiers
    tight: bool = False  # the costmap of the narrow-passage recovery (core/navigation/thin_walls.py)


class ExplorationSimulator:
    """One robot exploring one world.

    Args:
        world: the ground truth and start pose.
        config: simulation settings.
        rng: the only source of randomness (sensor noise); the same seed gives the same episode.
        teammates: other robots' positions (k, 2) (m) at the start, for the first scan.
    """

    def __init__(
        self,
        world: World,
        config: SimConfig | None = None,
        rng: np.random.Generator | None = None,
        teammates: NDArray[np.float64] | None = None,
    ) -> None:
        self.config = config or SimConfig()
        self.world = world = self.config.fit_world(world)
        self.rng = rng if rng is not None else np.random.default_rng(0)
        self.max_sim_time = self.config.time_cap(world)
        grid = world.grid
        self._lidar = Lidar(grid, self.config.lidar)
        self._teammates = Teammates(grid, self._lidar, self.config.robot.radius)
        self._footprint = footprint_offsets(self.config.robot.radius, grid.resolution)
        # the planner's, reused by every costmap of the episode: they are crops of the world, padded
        self._scratch = SearchScratch((grid.height + 2) * (grid.width + 2))
        r = self.config.robot
        n = self.config.navigation
        self._follow_params = np.array(
            [r.max_linear_speed, r.max_angular_speed, r.turn_in_place_angle, n.heading_gain, n.lookahead,
             n.goal_tolerance, n.control_dt, r.radius],
            dtype=np.float64,
        )  # fmt: skip
        self.reset(teammates)

    # ------------------------------------------------------------------ state
    def reset(self, teammates: NDArray[np.float64] | None = None) -> None:
        """Put the robot back at the start with an empty map and take the first scan (with other
        robots standing at ``teammates``, (k, 2) m, see :meth:`set_teammates`)."""
        self.pose = self.world.start
        self.mapper = LogOddsMapper(self.world.grid, self.config.mapper, self.world.explorable)
        self.sim_time = 0.0
        self.path_length = 0.0
        self.aborts = 0
        nav = self.config.navigation
        grid = self.world.grid
        self.blacklist = Blacklist(nav.blacklist_radius, nav.max_goal_failures, grid.resolution, grid.origin)
        self.decisions: list[DecisionRecord] = []
        self._times: list[float] = []
        self._explored: list[int] = []
        self._poses: list[tuple[float, float, float]] = []
        self._candidates: _Candidates | None = None
        self.target: tuple[float, float] | None = None  # the frontier centre or point of the leg under way
        self.set_teammates(np.zeros((0, 2)) if teammates is None else teammates)
        self._scan()

    def refresh(self) -> None:
        """The map was changed from outside (merged with a teammate's): forget the cached candidates."""
        self._candidates = None

    @property
    def coverage(self) -> float:
        """Fraction of the explorable region mapped so far."""
        return self.mapper.explored_cells / max(self.world.explorable_count, 1)

    @property
    def truncated(self) -> bool:
        """Whether the sim-time cap has been reached."""
        return self.sim_time >= self.max_sim_time - 1e-9

    @property
    def finished(self) -> bool:
        """Whether exploration has ended by itself: no candidate frontier is left (every one
        explored, or failed all its attempts, or out of reach); :meth:`end_reason` says which."""
        return len(self.candidates().frontiers) == 0

    def end_reason(self) -> EndReason | None:
        """Why the episode ended, None while it goes on."""
        if self.truncated:
            return EndReason.TIME_CAP
        if not self.finished:
            return None
        return self._reason_from(self.frontiers_left())

    def _reason_from(self, left: tuple[FrontierLeft, ...]) -> EndReason:
        """The end reason of a finished episode that leaves the frontiers ``left``."""
        return EndReason.UNREACHABLE if unresolved(left, self.config) else EndReason.EXPLORED

    def frontiers_left(self) -> tuple[FrontierLeft, ...]:
        """The frontiers of the current map that are not candidates (blacklisted after failed
        attempts, or with no reachable cell that sees them), with the unknown area beside each."""
        cand = self.candidates()
        every = detect_frontiers(
            cand.grid, self.pose, None, self.config.min_frontier_cells, self.config.frontier_segment_length
        )
        res = cand.grid.resolution
        top, left_col = self.world.grid.world_to_cell(*cand.grid.cell_to_world(0, 0))
        truth = self.world.grid.data[top : top + cand.grid.height, left_col : left_col + cand.grid.width]
        candidate_cells = np.zeros(cand.grid.shape[0] * cand.grid.shape[1], np.bool_)
        for start, end in cand.frontiers.spans:
            candidate_cells[cand.frontiers.flat_cells[start:end]] = True
        left = []
        for i in range(len(every)):
            cells = every.cells_of(i)
            if candidate_cells[cells[:, 0] * cand.grid.width + cells[:, 1]].any():
                continue
            x, y = (float(v) for v in every.centers[i])
            failures = max((self.blacklist.failures_near(*g) for g in cand.grid.cells_to_world(cells)), default=0)
            unknown, unseen = unknown_beside(cand.grid.data, cells[:, 0], cells[:, 1], truth)
            left.append(FrontierLeft(x, y, int(every.sizes[i]), unknown, unseen, unseen * res * res, failures))
        return tuple(left)

    def trajectory(self) -> NDArray[np.float64]:
        """(n, 3) robot poses (x, y, theta) so far: after every drive step, at least at every map update."""
        return np.asarray(self._poses, dtype=np.float64).reshape(-1, 3)

    def map(self) -> OccupancyGrid:
        """The robot's current map (grown to the seen area)."""
        return self.candidates().grid

    def set_teammates(self, positions: NDArray[np.float64], radius: float | None = None) -> None:
        """Other robots at ``positions`` ((k, 2) world points, m) of ``radius`` (m; this robot's own
        by default), until the next call: the follower collides with them, the planner plans around
        them and the LiDAR's beams stop at them. The map leaves them out (a laser filter drops the
        scan's marks on and around them: they are passing, not walls)."""
        own_radius = self.config.robot.radius
        self._teammates.place(positions, own_radius if radius is None else radius, (self.pose.x, self.pose.y))

    @property
    def teammates(self) -> NDArray[np.float64]:
        """The other robots' positions, (k, 2) world points (m), as of :meth:`set_teammates`."""
        return self._teammates.positions

    # ---------------------------------------------------------------- sensing
    def _scan(self) -> tuple[int, int] | None:
        """A LiDAR tick: the mapper folds the scan in when Gmapping would process it. Returns the
        cells first seen free and occupied, or None when the map did not change."""
        self._poses.append((self.pose.x, self.pose.y, self.pose.theta))
        if not self.mapper.wants_scan(self.pose, self.sim_time):
            return None
        noise = self.rng if self.config.sensor_noise else None
        filtered = self._teammates.laser_filter()
        update = self.mapper.integrate_simulated(self._lidar, self.pose, noise, self.sim_time, filtered)
        self._times.append(self.sim_time)
        self._explored.append(self.mapper.explored_cells)
        self._candidates = None
        return update.new_free, update.new_occupied

    # -------------------------------------------------------------- decisions
    def candidates(self) -> _Candidates:
        """The current map, its costmap and the reachable, non-blacklisted frontiers (cached).

        When the blacklist would leave none, the goals that may be retried are lifted once, so
        that the episode never ends with a frontier it gave up on after a single failure. When the
        normal costmap leaves none, those of the narrow-passage recovery (``tight``: the map with
        its walls a cell thinner, core/navigation/thin_walls.py) are the candidates if there are any."""
        if self._candidates is None:
            grid = self.mapper.occupancy_grid(margin=2)
            cand = self._candidates_on(grid, tight=False)
            if len(cand.frontiers) == 0:
                # The narrow-passage recovery (core/navigation/thin_walls.py): before giving up, plan on the
                # map with its walls a cell thinner, as range noise made them a cell thicker.
                tight = self._candidates_on(grid, tight=True)
                if len(tight.frontiers):
                    cand = tight
            self._candidates = cand
        return self._candidates

    def _candidates_on(self, grid: OccupancyGrid, tight: bool) -> _Candidates:
        """The candidates on ``grid`` with the normal or the tight costmap."""
        felt = None
        if tight:
            top, left = self.world.grid.world_to_cell(*grid.cell_to_world(0, 0))
            felt = self.mapper.felt[top : top + grid.height, left : left + grid.width]
        costmap, reachable, frontiers = reachable_frontiers(grid, self.pose, self.config, scratch=self._scratch,
                                                            thin_except=felt)  # fmt: skip
        if self.blacklist.entries and len(frontiers):
            self.blacklist.refresh(self.mapper.state)
            goals = frontiers.goals
            kept = frontiers.subset(~self.blacklist.blocked(goals))
            if len(kept) == 0:
                self.blacklist.retry()
                kept = frontiers.subset(~self.blacklist.blocked(goals))
            frontiers = kept
        return _Candidates(grid, costmap, reachable, frontiers, tight)

    def frontiers(self) -> Frontiers:
        """The current candidate frontiers."""
        return self.candidates().frontiers

    def execute(self, order: Sequence[int] | NDArray[np.int64], weight: float | None = None) -> LegResult:
        """Drive to the first frontier of ``order`` (indices into :meth:`frontiers`) that a path
        can be planned to; frontiers that cannot be planned to are blacklisted on the way."""
        return run_leg(self.execute_steps(order, weight))

    def execute_steps(
        self, order: Sequence[int] | NDArray[np.int64], weight: float | None = None
    ) -> Generator[None, None, LegResult]:
        """:meth:`execute` step by step: the leg yields each time its clock has moved on (a drive up
        to the next map update, about 0.5 s of sim time, or one LiDAR tick of a turn) and returns
        its result, so that several robots can share one clock."""
        cand = self.candidates()
        start_time, start_len = self.sim_time, self.path_length
        for index in order:
            index = int(index)
            if not 0 <= index < len(cand.frontiers):
                raise IndexError(f"frontier index {index} out of range 0..{len(cand.frontiers) - 1}")
            row, col = (int(v) for v in cand.frontiers.goal_cells[index])
            goal = cand.grid.cell_to_world(row, col)
            path = self._plan(cand, (row, col))
            if path is None:
                self.blacklist.fail(*goal, self.mapper.state)
                self.aborts += 1
                continue
            frontier_xy = cand.grid.cells_to_world(cand.frontiers.cells_of(index))
            self.target = goal
            try:
                return (yield from self._drive(path, goal, frontier_xy, index, weight, cand.tight))
            finally:
                self.target = None
        self._candidates = None  # the blacklist changed
        self._log(weight, (math.nan, math.nan), LegOutcome.NONE)
        return LegResult(LegOutcome.NONE, -1, (math.nan, math.nan), self.sim_time - start_time,
                         self.path_length - start_len, 0, 0)  # fmt: skip

    def go_to(self, x: float, y: float, weight: float | None = None) -> LegResult:
        """Drive to the reachable cell nearest to world point (x, y) (m): the point-goal action. A
        point no path leads to costs a recovery rotation and is given up; a point where the robot
        already is costs one turn on the spot. Every call takes simulated time."""
        return run_leg(self.go_to_steps(x, y, weight))

    def go_to_steps(self, x: float, y: float, weight: float | None = None) -> Generator[None, None, LegResult]:
        """:meth:`go_to` one map update at a time (see :meth:`execute_steps`)."""
        cand = self.candidates()
        row, col = cand.grid.world_to_cell(x, y)
        row = min(max(row, 0), cand.grid.height - 1)
        col = min(max(col, 0), cand.grid.width - 1)
        goal_cell = nearest_cell(cand.reachable, (row, col), max_radius=_grid_diagonal(cand.grid))
        path = None if goal_cell is None else self._plan(cand, goal_cell)
        if path is None or goal_cell is None:
            # move_base's answer to a goal it cannot plan to: a recovery rotation, then give up.
            # It costs time, so a point policy cannot pick unreachable cells for free.
            start_time = self.sim_time
            self.aborts += 1
            self._log(weight, (x, y), LegOutcome.ABORTED)
            new_free, new_occ = yield from self._rotate_steps()
            return LegResult(LegOutcome.ABORTED, -1, (x, y), self.sim_time - start_time, 0.0, new_free, new_occ)
        goal = cand.grid.cell_to_world(*goal_cell)
        if math.hypot(goal[0] - self.pose.x, goal[1] - self.pose.y) <= self.config.navigation.goal_tolerance:
            # already there: the robot looks around once, so that no decision is free of time
            start_time = self.sim_time
            self._log(weight, goal, LegOutcome.REACHED)
            new_free, new_occ = yield from self._rotate_steps()
            return LegResult(LegOutcome.REACHED, -1, goal, self.sim_time - start_time, 0.0, new_free, new_occ)
        self.target = goal
        try:
            return (yield from self._drive(path, goal, None, -1, weight, cand.tight))
        finally:
            self.target = None

    # ------------------------------------------------------------- navigation
    def _plan(self, cand: _Candidates, goal_cell: tuple[int, int]) -> NDArray[np.float64] | None:
        """A world-frame path (n, 2) from the robot to ``goal_cell`` of ``cand.grid``, or None."""
        start = cand.grid.world_to_cell(self.pose.x, self.pose.y)
        cells = cand.costmap.plan(start, goal_cell)
        if len(cells) == 0:
            return None
        xy = cand.grid.cells_to_world(cells)
        nav = self.config.navigation
        mates = self._teammates
        here = (self.pose.x, self.pose.y)
        close = mates.positions[mates.distances(here) <= nav.teammate_range]
        if len(close):  # around nearby robots in the way, if there is a way round
            keep_off = mates.radius + self.config.robot.radius + nav.teammate_margin
            gap = np.hypot(xy[:, None, 0] - close[None, :, 0], xy[:, None, 1] - close[None, :, 1])
            goal_xy = cand.grid.cell_to_world(*goal_cell)
            if gap.min() <= keep_off and not mates.within(keep_off, here, goal_xy):
                detour = cand.costmap.with_discs_blocked(close, keep_off).plan(start, goal_cell)
                if len(detour):
                    xy = cand.grid.cells_to_world(detour)
        xy[-1] = cand.grid.cell_to_world(*goal_cell)
        return xy

    def _replan(self, goal: tuple[float, float], tight: bool) -> NDArray[np.float64] | None:
        """A new path to ``goal`` on the current map, on the costmap the leg was planned on: a leg
        through a passage opened by the narrow-passage recovery keeps to it (on the normal
        costmap the robot inside the passage could not move)."""
        cand = self.candidates()
        if tight and not cand.tight:
            cand = self._candidates_on(cand.grid, tight=True)
        g = cand.grid
        row, col = g.world_to_cell(*goal)
        passable = cand.costmap.traversable
        if not (g.in_bounds(row, col) and passable[row, col]):
            nearest = nearest_cell(passable, (row, col), max_radius=int(round(0.5 / g.resolution)))
            if nearest is None:
                return None
            row, col = nearest
        return self._plan(cand, (row, col))

    def _drive(
        self,
        path: NDArray[np.float64],
        goal: tuple[float, float],
        frontier_xy: NDArray[np.float64] | None,
        index: int,
        weight: float | None,
        tight: bool = False,
    ) -> Generator[None, None, LegResult]:
        cfg = self.config
        nav = cfg.navigation
        truth = self.world.grid
        start_time, start_len, start_xy = self.sim_time, self.path_length, (self.pose.x, self.pose.y)
        new_free = new_occ = 0
        path_cells = self.world.grid.world_to_cells(path)
        tail = _tail_lengths(path)
        careful = np.zeros(1, np.bool_)  # the follower's waypoint-by-waypoint mode, per path
        frontier_cells = None if frontier_xy is None else self.world.grid.world_to_cells(frontier_xy)
        index_on_path = 0
        best_remaining = math.inf
        last_progress = self.sim_time
        progress_at = (self.pose.x, self.pose.y)
        next_frontier_check = self.sim_time + nav.frontier_check_period
        recoveries = 0
        outcome = LegOutcome.TIMEOUT
        mates = self._teammates
        clearance = mates.clearance
        teammate_blocked_since: float | None = None
        params = self._follow_params
        while not self.truncated:
            # Drive tick by tick until the mapper wants the next scan (nothing else changes before).
            duration, gate = self._until_next_scan()
            x, y, theta, index_on_path, driven, used, status = follow_path(
                path[:, 0], path[:, 1], index_on_path, self.pose.x, self.pose.y, self.pose.theta, duration,
                params, clearance, truth.origin[0], truth.origin[1], truth.resolution, gate, careful,
            )  # fmt: skip
            self.pose = Pose(x, y, theta)
            self.path_length += driven
            self.sim_time += used
            seen = self._scan()
            yield
            if seen is not None:
                new_free += seen[0]
                new_occ += seen[1]
            if status == 2 and params is not self._follow_params:
                status = 1  # closing in and a wall is in the way: this is as close as it gets
            if status == 1:
                if params is self._follow_params and self._alive(frontier_cells):
                    # Within the goal tolerance and the frontier is still there: close in on the
                    # goal cell itself (a frontier seen through a gap needs the exact viewpoint).
                    params = self._follow_params.copy()
                    params[5] = truth.resolution
                    continue
                outcome = LegOutcome.REACHED
                break
            if self.truncated:
                break  # the sim-time cap: the leg ends as a timeout
            if frontier_cells is not None and self.sim_time >= next_frontier_check:
                next_frontier_check = self.sim_time + nav.frontier_check_period
                if not self._frontier_alive(frontier_cells):
                    outcome = LegOutcome.EXPLORED
                    break
            remaining = math.hypot(path[index_on_path, 0] - x, path[index_on_path, 1] - y) + tail[index_on_path]
            # Progress: the way left got shorter, or the robot got somewhere (a replanned detour
            # can make the way longer while the robot is doing fine).
            moved = math.hypot(x - progress_at[0], y - progress_at[1]) >= nav.oscillation_distance
            if remaining < best_remaining - nav.progress_distance or moved:
                best_remaining = min(best_remaining, remaining)
                last_progress = self.sim_time
                progress_at = (x, y)
            elif self.sim_time - last_progress > nav.progress_timeout:
                outcome = LegOutcome.ABORTED
                break
            if status == 2 and clearance is not mates.true_clearance and mates.touching((self.pose.x, self.pose.y)):
                if teammate_blocked_since is None:
                    teammate_blocked_since = self.sim_time
                if self.sim_time - teammate_blocked_since >= nav.teammate_patience:
                    clearance = mates.true_clearance  # squeeze past for the rest of the leg
                else:
                    yield from self.wait_steps()  # give the other robot a moment to pass
                continue
            elif status == 2:
                self._bump()
            blocked = status == 2 or (
                seen is not None  # only a map update can put a new obstacle on the path
                and self._path_blocked(path_cells, index_on_path, tight)
            )
            if blocked:
                new_path = self._replan(goal, tight)
                while new_path is None and recoveries < nav.max_recoveries and not self.truncated:
                    recoveries += 1
                    f, o = yield from self._rotate_steps()
                    new_free += f
                    new_occ += o
                    new_path = self._replan(goal, tight)
                if new_path is None:
                    outcome = LegOutcome.TIMEOUT if self.truncated else LegOutcome.ABORTED
                    break
                path = new_path
                path_cells = self.world.grid.world_to_cells(path)
                tail = _tail_lengths(path)
                careful[0] = False
                index_on_path = 0
        # At the goal the frontier may still be there (seen edge-on, or hidden in the LiDAR's
        # blind zone). Wait for the next map update; if it is still there, the robot cannot
        # resolve it from here, so it is blacklisted: otherwise the same frontier would be chosen
        # again and again, at no cost in time, for ever.
        if outcome is LegOutcome.REACHED and self._alive(frontier_cells):
            yield from self.wait_steps()
            if self._alive(frontier_cells):
                self.blacklist.fail(*goal, self.mapper.state)
                self._candidates = None
        if outcome is LegOutcome.ABORTED:
            self.aborts += 1
            self.blacklist.fail(*goal, self.mapper.state)
            self._candidates = None
        self._log(weight, goal, outcome, start=(start_time, start_xy))
        return LegResult(
            outcome, index, goal, self.sim_time - start_time, self.path_length - start_len, new_free, new_occ
        )

    def _path_blocked(self, path_cells: NDArray[np.int64], first: int, tight: bool) -> bool:
        """Whether the robot's map puts a wall on the path (world cells) from index ``first`` on;
        for a leg of the narrow-passage recovery, the map with its walls thinned around the path,
        as it was planned on."""
        rows, cols = path_cells[first:, 0], path_cells[first:, 1]
        state = self.mapper.state
        if tight:
            reach = int(np.abs(self._footprint).max()) + 2  # the peel looks two cells beyond a cell
            r0, c0 = max(int(rows.min()) - reach, 0), max(int(cols.min()) - reach, 0)
            r1, c1 = int(rows.max()) + reach + 1, int(cols.max()) + reach + 1
            state = thin_walls(state[r0:r1, c0:c1], self.mapper.felt[r0:r1, c0:c1])
            rows, cols = rows - r0, cols - c0
        return path_blocked(state, rows, cols, 0, self._footprint)

    def _alive(self, cells: NDArray[np.int64] | None) -> bool:
        """:meth:`_frontier_alive` for a leg's frontier, False for a leg to a point."""
        return cells is not None and self._frontier_alive(cells)

    def _frontier_alive(self, cells: NDArray[np.int64]) -> bool:
        """Whether more than ``min_frontier_cells`` of a frontier's cells are still fringe cells."""
        return count_fringe(self.mapper.state, cells[:, 0], cells[:, 1]) > self.config.min_frontier_cells

    def wait_steps(self) -> Generator[None, None, None]:
        """Stand still until the mapper has folded in the next scan (or the sim-time cap), yielding
        after every LiDAR tick: a robot waiting for its team."""
        while not self.truncated:
            duration, _ = self._until_next_scan()
            self.sim_time += duration
            seen = self._scan()
            yield
            if seen is not None:
                return

    def _until_next_scan(self) -> tuple[float, NDArray[np.float64]]:
        """How long (s) to drive before the mapper's time trigger, in whole LiDAR ticks (at most
        to the sim-time cap), and the ``gate`` of :func:`follow_path` for its motion triggers."""
        period = self.config.lidar.period
        mapper_cfg = self.config.mapper
        left = self.max_sim_time - self.sim_time
        last = self.mapper.last_update
        if last is None:
            return min(period, left), np.array([period, self.pose.x, self.pose.y, self.pose.theta, 0.0, 0.0])
        last_pose, last_time = last
        if mapper_cfg.temporal_update > 0:
            wait = mapper_cfg.temporal_update - 1e-9 - (self.sim_time - last_time)
            ticks = max(1, math.ceil(wait / period))
            duration = min(ticks * period, left)
        else:
            duration = left
        gate = np.array(
            [period, last_pose.x, last_pose.y, last_pose.theta, mapper_cfg.linear_update, mapper_cfg.angular_update]
        )
        return duration, gate

    def _bump(self) -> None:
        """The robot ran into a wall its map did not show (the LiDAR is blind closer than its
        minimum range): the wall cells it touches are marked occupied, as a bumper would."""
        g = self.world.grid
        reach = self.config.robot.radius + 1.5 * g.resolution
        row, col = g.world_to_cell(self.pose.x, self.pose.y)
        n = int(math.ceil(reach / g.resolution))
        r0, c0 = max(row - n, 0), max(col - n, 0)
        window = g.data[r0 : row + n + 1, c0 : col + n + 1] == CellState.OCCUPIED
        rows, cols = np.nonzero(window)
        centres_x = g.origin[0] + (cols + c0 + 0.5) * g.resolution
        centres_y = g.origin[1] + (rows + r0 + 0.5) * g.resolution
        near = np.hypot(centres_x - self.pose.x, centres_y - self.pose.y) <= reach
        self.mapper.mark_occupied(rows[near] + r0, cols[near] + c0)
        self._candidates = None

    def _rotate_steps(self) -> Generator[None, None, tuple[int, int]]:
        """A recovery behaviour: one full turn at max angular speed, scanning as it goes; yields
        after every LiDAR tick and returns the cells first seen free and occupied."""
        period = self.config.lidar.period
        omega = self.config.robot.max_angular_speed
        steps = int(math.ceil(2.0 * math.pi / (omega * period)))
        new_free = new_occ = 0
        for _ in range(steps):
            if self.truncated:
                break
            step = min(period, self.max_sim_time - self.sim_time)
            self.pose = Pose(self.pose.x, self.pose.y, (self.pose.theta + omega * step) % (2 * math.pi))
            self.sim_time += step
            seen = self._scan()
            yield
            if seen is not None:
                new_free += seen[0]
                new_occ += seen[1]
        return new_free, new_occ

    def _log(
        self,
        weight: float | None,
        goal: tuple[float, float],
        outcome: LegOutcome,
        start: tuple[float, tuple[float, float]] | None = None,
    ) -> None:
        time_s, (x, y) = start if start is not None else (self.sim_time, (self.pose.x, self.pose.y))
        self.decisions.append(
            DecisionRecord(float(time_s), float(x), float(y), float(goal[0]), float(goal[1]), weight, outcome.value)
        )

    # ---------------------------------------------------------------- results
    def result(self, wall_time_s: float) -> EpisodeResult:
        """The episode's metrics so far (an episode still under way has end reason None)."""
        times = np.asarray(self._times, dtype=np.float64)
        curve = np.asarray(self._explored, dtype=np.float64) / max(self.world.explorable_count, 1)
        ended = self.truncated or self.finished
        left = self.frontiers_left() if ended else ()  # computed once: the end reason reads it too
        reason = None if not ended else EndReason.TIME_CAP if self.truncated else self._reason_from(left)
        free = self.world.grid.data == CellState.FREE
        return EpisodeResult(
            sim_time_s=self.sim_time,
            path_length_m=self.path_length,
            coverage=self.coverage,
            t90_s=time_to_coverage(times, curve, 0.90),
            t99_s=time_to_coverage(times, curve, 0.99),
            decisions=len(self.decisions),
            aborts=self.aborts,
            done=reason is EndReason.EXPLORED,
            truncated=self.truncated,
            wall_time_s=wall_time_s,
            end_reason=None if reason is None else reason.value,
            free_coverage=int(np.count_nonzero(self.mapper.seen & free)) / max(int(np.count_nonzero(free)), 1),
            unknown_left_m2=sum(f.unknown_m2 for f in left),
            coverage_times_s=times,
            coverage_curve=curve,
            trajectory=self.trajectory(),
            decision_log=tuple(self.decisions),
            final_map=self.mapper.occupancy_grid(),
            frontiers_left=left,
        )


def _grid_diagonal(grid: OccupancyGrid) -> int:
    """The longest distance (cells) between two cells of ``grid``, rounded up."""
    return int(math.ceil(math.hypot(*grid.shape)))


def _tail_lengths(path: NDArray[np.float64]) -> NDArray[np.float64]:
    """For each waypoint, the length (m) of the path from it to the end."""
    seg = np.hypot(*np.diff(path, axis=0).T)
    return np.concatenate((np.cumsum(seg[::-1])[::-1], [0.0]))


def reachable_frontiers(
    grid: OccupancyGrid,
    pose: Pose,
    config: SimConfig,
    min_cells: int | None = None,
    scratch: SearchScratch | None = None,
    thin_except: NDArray[np.bool_] | None = None,
) -> tuple[Costmap, NDArray[np.bool_], Frontiers]:
    """The navigator's costmap of ``grid`` (its searches using ``scratch``), the known free cells
    the robot at ``pose`` can reach, and the frontier clusters larger than ``min_cells`` (default
    ``config.min_frontier_cells``) that touch them: what a decision chooses from, before any
    blacklist. With ``thin_except`` (a mask of ``grid``'s shape), the costmap is that of the
    narrow-passage recovery: the map's walls thinned by a cell except at those cells
    (:func:`~frontier_rl.core.navigation.thin_walls.thin_walls`)."""
    if thin_except is None:
        costmap = Costmap.build(grid, config.robot, config.navigation, scratch)
        reachable = costmap.reachable_known(grid.world_to_cell(pose.x, pose.y))
    else:
        thinned = OccupancyGrid(thin_walls(grid.data, thin_except), grid.resolution, grid.origin)
        costmap = Costmap.build(thinned, config.robot, config.navigation, scratch)
        reachable = costmap.reachable_known(grid.world_to_cell(pose.x, pose.y)) & (grid.data == CellState.FREE)
    cells = config.min_frontier_cells if min_cells is None else min_cells
    frontiers = detect_frontiers(
        grid, pose, reachable, cells, config.frontier_segment_length, config.frontier_goal_reach
    )
    return costmap, reachable, frontiers


def unresolved(left: Sequence[FrontierLeft], config: SimConfig) -> bool:
    """Whether real space is left unseen beside the frontiers left: more than
    ``min_frontier_cells`` cells that are unknown in the map and free in the true world, beside
    one of them (fewer is a speck, as the thesis treats fringe clusters that small). A frontier
    whose unknown side is all wall (cells no beam reached, or range noise that marked cells inside
    a wall free) leaves nothing to explore."""
    return any(f.unseen_free_cells > config.min_frontier_cells for f in left)


_T = TypeVar("_T")


def run_leg(steps: Generator[None, None, _T]) -> _T:
    """Run a stepwise leg (:meth:`ExplorationSimulator.execute_steps`, ...) to its end; its result."""
    while True:
        try:
            next(steps)
        except StopIteration as stop:
            return stop.value  # type: ignore[no-any-return]
