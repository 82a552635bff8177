"""The exploration episode: decide -> drive -> sense -> map, on a simulated clock.

:class:`ExplorationSimulator` is a state machine with one entry point per decision, so that an
episode runner and a Gymnasium env drive it the same way: :meth:`candidates` gives the current
frontiers, :meth:`execute` drives to the first of a ranked list that can be planned to (or :meth:`go_to`
to any point), simulating LiDAR, mapping and navigation until the leg ends. The drive itself is a
:class:`~frontier_rl.core.sim.leg.Leg`; the record, an :class:`~frontier_rl.core.sim.episode_log.EpisodeLog`.
"""

from __future__ import annotations

import math
from collections.abc import Generator, Sequence

import numpy as np
from numpy.typing import NDArray

from frontier_rl.core.frontiers.blacklist import Blacklist
from frontier_rl.core.frontiers.detection import Frontiers
from frontier_rl.core.mapping.mapper import LogOddsMapper
from frontier_rl.core.navigation.astar import SearchScratch
from frontier_rl.core.navigation.follower import FollowerParams
from frontier_rl.core.navigation.inflation import InflationMemory
from frontier_rl.core.navigation.thin_walls import Recovery
from frontier_rl.core.sensing.lidar import Lidar
from frontier_rl.core.sim.body import touched_walls, until_next_scan
from frontier_rl.core.sim.candidates import Candidates, Look
from frontier_rl.core.sim.config import SimConfig
from frontier_rl.core.sim.episode_log import EpisodeLog, completion_reason
from frontier_rl.core.sim.frontiers_left import frontiers_left
from frontier_rl.core.sim.leg import Leg, run_leg
from frontier_rl.core.sim.leg_result import AbortCause, LegOutcome, LegResult
from frontier_rl.core.sim.metrics import EndReason, EpisodeResult, FrontierLeft
from frontier_rl.core.sim.navigator import CANDIDATE_MAP_MARGIN, Navigator
from frontier_rl.core.sim.paths import cells_beyond, path_to_follow, plan_path, point_goal_cell
from frontier_rl.core.sim.teammates import Teammates
from frontier_rl.core.world.grid import CellState, OccupancyGrid
from frontier_rl.core.world.robot import Pose
from frontier_rl.core.world.worlds import World


class ExplorationSimulator:
    """One robot exploring one world.

    Args:
        world: the ground truth and start pose.
        config: simulation settings.
        rng: the only source of randomness (sensor noise); the same seed gives the same episode.
        teammates: other robots' positions (k, 2) (m) at the start, for the first scan.

    Attributes:
        config, world: the settings, and the world with its explorable space fitted to the robot.
        mapper, blacklist, log: the robot's map, its failed goals and the episode's record.
        nearby_robots: the other robots, as obstacles; follow_params: the path follower's settings.
    """

    def __init__(
        self,
        world: World,
        config: SimConfig | None = None,
        rng: np.random.Generator | None = None,
        teammates: NDArray[np.float64] | None = None,
    ) -> None:
        self.config = config or SimConfig()
        self.world = world = self.config.fit_world(world)  # its explorable space fitted to this robot
        self.rng = rng if rng is not None else np.random.default_rng(0)
        self.max_sim_time = self.config.time_cap(world)
        grid = world.grid
        self._lidar = Lidar(grid, self.config.lidar)
        self.nearby_robots = Teammates(grid, self._lidar, self.config.robot.radius)
        # the planner's, reused by every costmap of the episode: they are crops of the world, padded
        self._scratch = SearchScratch((grid.height + 2) * (grid.width + 2))
        self._inflation = InflationMemory()  # the last costmap's, inflated again where the map changed
        self.follow_params = FollowerParams.of(self.config.robot, self.config.navigation)
        self.reset(teammates)

    def reset(self, teammates: NDArray[np.float64] | None = None) -> None:
        """Put the robot back at the start with an empty map and take the first scan (with other
        robots standing at ``teammates``, (k, 2) m, see :meth:`set_teammates`)."""
        self._pose = self.world.start
        self.mapper = LogOddsMapper(self.world.grid, self.config.mapper, self.world.explorable)
        self._sim_time = 0.0
        self.path_length = 0.0
        nav, grid = self.config.navigation, self.world.grid
        self.blacklist = Blacklist(nav.blacklist_radius, nav.max_goal_failures, grid.resolution, grid.origin)
        self.log = EpisodeLog(self.world.explorable_count)
        self.navigator = Navigator(
            self.world,
            self.config,
            self.mapper,
            self.blacklist,
            self.nearby_robots,
            self._scratch,
            self._inflation,
            self.log,
        )
        self.target: tuple[float, float] | None = None  # the frontier centre or point of the leg under way
        self.leg: Leg | None = None  # the leg under way
        self.set_teammates(np.zeros((0, 2)) if teammates is None else teammates)
        self._scan()

    def refresh(self) -> None:
        """The map was changed from outside (merged with a teammate's): forget the cached candidates."""
        self.navigator.forget()

    @property
    def pose(self) -> Pose:
        """The robot's pose now."""
        return self._pose

    @property
    def sim_time(self) -> float:
        """The simulated clock (s)."""
        return self._sim_time

    @property
    def coverage(self) -> float:
        """Fraction of the explorable region mapped so far."""
        return self.mapper.explored_cells / max(self.world.explorable_count, 1)

    @property
    def truncated(self) -> bool:
        """Whether the sim-time cap has been reached."""
        return self._sim_time >= self.max_sim_time - 1e-9

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
        return completion_reason(self.frontiers_left())

    def frontiers_left(self, known: NDArray[np.bool_] | None = None) -> tuple[FrontierLeft, ...]:
        """The frontiers not candidates, with the unseen space beside and behind each (``known``: what a team saw)."""
        state = self.mapper.state if known is None else np.where(known, CellState.FREE, self.mapper.state)
        return frontiers_left(
            self.candidates(),
            self.world.grid,
            self.pose,
            self.config,
            self.blacklist,
            state,
            self.mapper.felt,
            self.navigator.trail(),
            self.world.explorable,
        )

    def trajectory(self) -> NDArray[np.float64]:
        """(n, 3) robot poses (x, y, theta) so far: after every drive step, at least at every map update."""
        return self.log.trajectory()

    def map(self) -> OccupancyGrid:
        """The robot's current map, cropped to the seen area with a margin (the grid the candidates
        are found on); finds no candidates, so it leaves the blacklist as it is."""
        return self.mapper.occupancy_grid(margin=CANDIDATE_MAP_MARGIN)

    def set_teammates(self, positions: NDArray[np.float64], passing: NDArray[np.bool_] | None = None) -> None:
        """Other robots of this one's size at ``positions`` ((k, 2) world points, m), until the next
        call: the follower collides with them, the planner plans around them and the LiDAR's beams
        stop at them. The map leaves out those ``passing`` (all by default; a laser filter drops the
        scan's marks on and around them: they move on), not a robot that stopped for good."""
        self.nearby_robots.place(positions, self.config.robot.radius, (self.pose.x, self.pose.y), passing)

    @property
    def teammates(self) -> NDArray[np.float64]:
        """The other robots' positions, (k, 2) world points (m), as of :meth:`set_teammates`."""
        return self.nearby_robots.positions

    # ----------------------------------------------------------- clock & body
    def advance(self, pose: Pose, driven: float, duration: float) -> tuple[int, int] | None:
        """Move the clock on by ``duration`` (s) and the robot to ``pose``, having driven ``driven``
        (m); then a LiDAR tick (see :meth:`_scan`)."""
        self._pose = pose
        self.path_length += driven
        self._sim_time += duration
        return self._scan()

    def _scan(self) -> tuple[int, int] | None:
        """A LiDAR tick: the mapper folds the scan in when Gmapping would process it. Returns the
        cells first seen free and occupied, or None when the map did not change."""
        self.log.pose(self.pose)
        if not self.mapper.wants_scan(self.pose, self.sim_time):
            return None
        noise = self.rng if self.config.sensor_noise else None
        filtered = self.nearby_robots.laser_filter()
        update = self.mapper.integrate_simulated(self._lidar, self.pose, noise, self.sim_time, filtered)
        self.log.map_update(self.sim_time, self.mapper.explored_cells, self.path_length)
        self.navigator.forget()
        return update.new_free, update.new_occupied

    def until_next_scan(self) -> tuple[float, NDArray[np.float64]]:
        """How long (s) to drive before the mapper's next scan, and the follower's scan gate
        (see :func:`~frontier_rl.core.sim.body.until_next_scan`)."""
        return until_next_scan(self.mapper, self.config, self.pose, self.sim_time, self.max_sim_time)

    def wait_steps(self) -> Generator[None, None, None]:
        """Stand still until the mapper has folded in the next scan (or the sim-time cap), yielding
        after every LiDAR tick: a robot waiting for its team."""
        while not self.truncated:
            duration, _ = self.until_next_scan()
            seen = self.advance(self.pose, 0.0, duration)
            yield
            if seen is not None:
                return

    def rotate_steps(self) -> Generator[None, None, tuple[int, int]]:
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
            seen = self.advance(
                Pose(self.pose.x, self.pose.y, (self.pose.theta + omega * step) % (2 * math.pi)), 0.0, step
            )
            yield
            if seen is not None:
                new_free += seen[0]
                new_occ += seen[1]
        return new_free, new_occ

    def bump(self) -> None:
        """The robot ran into a wall its map did not show (the LiDAR is blind closer than its
        minimum range): the wall cells it touches are marked occupied, as a bumper would."""
        self.mapper.mark_occupied(*touched_walls(self.world.grid, self.pose, self.config.robot.radius))
        self.navigator.forget()

    # -------------------------------------------------------------- decisions
    def candidates(self) -> Candidates:
        """The current map, its costmap and the reachable, non-blacklisted frontiers (cached;
        see :meth:`Navigator.candidates <frontier_rl.core.sim.navigator.Navigator.candidates>`)."""
        return self.navigator.candidates(self.pose)

    def frontiers(self) -> Frontiers:
        """The current candidate frontiers."""
        return self.candidates().frontiers

    def execute(self, order: Sequence[int] | NDArray[np.int64], weight: float | None = None) -> LegResult:
        """Drive to the first frontier of ``order`` (indices into :meth:`frontiers`) that a path
        can be planned to; frontiers that cannot be planned to are blacklisted on the way. The
        decision is logged with the ranking ``weight`` that chose it."""
        return run_leg(self.execute_steps(order, weight))

    def execute_steps(
        self, order: Sequence[int] | NDArray[np.int64], weight: float | None = None
    ) -> Generator[None, None, LegResult]:
        """:meth:`execute` step by step: the leg yields each time its clock has moved on (a drive up
        to the next map update, about 0.5 s of sim time, or one LiDAR tick of a turn) and returns
        its result, so that several robots can share one clock."""
        cand = self.navigator.decision_candidates(self.pose)
        for index in order:
            index = int(index)
            if not 0 <= index < len(cand.frontiers):
                raise IndexError(f"frontier index {index} out of range 0..{len(cand.frontiers) - 1}")
            row, col = (int(v) for v in cand.frontiers.goal_cells[index])
            goal = cand.grid.cell_to_world(row, col)
            path = plan_path(cand, self.pose, (row, col), self.nearby_robots, self.config)
            frontier = cand.grid.cells_to_world(cand.frontiers.cells_of(index))
            if path is None:
                self.blacklist.fail(*goal, self.mapper.state, frontier=frontier)
                self.log.abort(AbortCause.NOT_PLANNED)
                continue
            if cand.looks is not Look.NONE:  # a point goal, the view; a visit of its cluster whatever it shows
                result = yield from self._drive(Leg(self, path, goal, None, cand.recovery), index, weight)
                viewed = result.outcome is LegOutcome.REACHED
                # after an abort the leg has blacklisted the point already: with this visit, two failures
                # in an entry of its own, so the same viewpoint is offered once more, as a leg is retried
                self.blacklist.fail(*goal, self.mapper.state, reached=True, frontier=frontier, viewed=viewed)
                if cand.looks in (Look.SMALL, Look.BLIND):  # whether the looks at small clusters go on
                    self.navigator.looked(result.new_free * self.world.grid.resolution**2, cand.looks is Look.BLIND)
                else:
                    self.navigator.forget()  # the blacklist changed
                return result
            frontier_cells = self.world.grid.world_to_cells(frontier)
            return (yield from self._drive(Leg(self, path, goal, frontier_cells, cand.recovery), index, weight))
        self.navigator.forget()  # the blacklist changed
        result = self._leg_result(LegOutcome.NONE, -1, (math.nan, math.nan), self.sim_time, 0, 0)
        self.log.decision(result, weight)  # a decision that drove nowhere
        return result

    def go_to(self, x: float, y: float, weight: float | None = None) -> LegResult:
        """Drive to the reachable cell nearest to world point (x, y) (m): the point-goal action. A
        point no path leads to costs a recovery rotation and is given up; a point where the robot
        already is costs one turn on the spot. Every call takes simulated time."""
        return run_leg(self.go_to_steps(x, y, weight))

    def go_to_steps(self, x: float, y: float, weight: float | None = None) -> Generator[None, None, LegResult]:
        """:meth:`go_to` one map update at a time (see :meth:`execute_steps`)."""
        cand = self.navigator.decision_candidates(self.pose)
        goal_cell = point_goal_cell(cand.grid, cand.reachable, x, y)
        path = None if goal_cell is None else plan_path(cand, self.pose, goal_cell, self.nearby_robots, self.config)
        if path is None or goal_cell is None:
            # move_base's answer to a goal it cannot plan to: a recovery rotation, then give up.
            # It costs time, so a point policy cannot pick unreachable cells for free.
            self.log.abort(AbortCause.NOT_PLANNED)
            return (yield from self._turn_on_the_spot(LegOutcome.ABORTED, (x, y), weight))
        goal = cand.grid.cell_to_world(*goal_cell)
        if math.hypot(goal[0] - self.pose.x, goal[1] - self.pose.y) <= self.config.navigation.goal_tolerance:
            # already there: the robot looks around once, so that no decision is free of time
            return (yield from self._turn_on_the_spot(LegOutcome.REACHED, goal, weight))
        return (yield from self._drive(Leg(self, path, goal, None, cand.recovery), -1, weight))

    def follow_steps(self, path: NDArray[np.float64]) -> Generator[None, None, LegResult]:
        """Drive along ``path`` ((n, 2), m, ending at its goal) one map update at a time, as Nav2's
        controller follows a path it is given: from its point nearest the robot, for the first of
        the normal robot and the narrow-passage recovery's (walls half a cell and a cell thinner,
        a slimmer robot) whose map lets it along the whole path beyond the planner's escape radius
        (a controller checks the walls its LiDAR sees now, not the map's walls that range noise
        thickened); driven round a wall the map puts on it near the robot (a controller steers round
        what its local costmap shows), given up where there is no way round or the robot makes no
        progress. A path none lets the robot along is aborted, as a
        goal that cannot be planned to."""
        path = path_to_follow(path, self.pose, self.world.grid.resolution)
        goal = (float(path[-1, 0]), float(path[-1, 1]))
        cells = self.world.grid.world_to_cells(path)
        inside = bool(((cells >= 0) & (cells < np.array(self.world.grid.shape))).all())
        far = cells_beyond(path, cells, self.pose)
        for level in Recovery:
            if inside and (len(far) == 0 or not self.navigator.path_blocked(far, 0, level)):
                return (yield from self._drive(Leg(self, path, goal, None, level, given_path=True), -1, None))
        self.log.abort(AbortCause.NOT_PLANNED)
        return (yield from self._turn_on_the_spot(LegOutcome.ABORTED, goal, None))

    def _drive(self, leg: Leg, index: int, weight: float | None) -> Generator[None, None, LegResult]:
        """Run ``leg`` (to frontier ``index``, -1 for a point) and log the decision."""
        start_time, start_len, start_xy = self.sim_time, self.path_length, (self.pose.x, self.pose.y)
        self.target, self.leg = leg.goal, leg
        try:
            outcome = yield from leg.run()
        finally:
            self.target = self.leg = None
        if outcome is LegOutcome.ABORTED and leg.abort_cause is not None:
            self.log.abort(leg.abort_cause)
        result = LegResult(
            outcome,
            index,
            leg.goal,
            self.sim_time - start_time,
            self.path_length - start_len,
            leg.new_free,
            leg.new_occupied,
            start_time,
            start_xy,
        )
        self.log.decision(result, weight)
        return result

    def _turn_on_the_spot(
        self, outcome: LegOutcome, goal: tuple[float, float], weight: float | None
    ) -> Generator[None, None, LegResult]:
        """A point-goal decision answered by one full turn (see :meth:`go_to`)."""
        start_time = self.sim_time
        self.log.decision(self._leg_result(outcome, -1, goal, start_time, 0, 0), weight)
        new_free, new_occ = yield from self.rotate_steps()
        return self._leg_result(outcome, -1, goal, start_time, new_free, new_occ)

    def _leg_result(
        self, outcome: LegOutcome, index: int, goal: tuple[float, float], start_s: float, new_free: int, new_occ: int
    ) -> LegResult:
        """A leg that drove no distance since ``start_s``."""
        xy = (self.pose.x, self.pose.y)
        return LegResult(outcome, index, goal, self.sim_time - start_s, 0.0, new_free, new_occ, start_s, xy)

    # ---------------------------------------------------------------- results
    def result(self, wall_time_s: float) -> EpisodeResult:
        """The episode's metrics so far (an episode still under way has end reason None)."""
        ended = self.truncated or self.finished
        left = self.frontiers_left() if ended else ()  # computed once: the end reason reads it too
        reason = None if not ended else EndReason.TIME_CAP if self.truncated else completion_reason(left)
        free = self.world.grid.data == CellState.FREE
        return self.log.result(
            sim_time_s=self.sim_time,
            path_length_m=self.path_length,
            coverage=self.coverage,
            truncated=self.truncated,
            reason=reason,
            left=left,
            free_coverage=int(np.count_nonzero(self.mapper.seen & free)) / max(int(np.count_nonzero(free)), 1),
            final_map=self.mapper.occupancy_grid(),
            wall_time_s=wall_time_s,
        )
