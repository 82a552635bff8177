"""A simulated robot that takes goals as a navigation stack does, without ROS: what ``frontier-rl
ros2 sim`` serves as Nav2's ``NavigateToPose``, and what the explorer is tried on in-process.

The robot is the engine's: its LiDAR, its map (as SLAM would build it) and its navigation (plans on
the map it builds, follows, replans, recovers and gives up as move_base does). A goal is driven one
map update at a time (about 0.5 s of simulated time), so that a node can publish between steps and
pace them against the wall clock.
"""

from __future__ import annotations

import math
from collections.abc import Generator
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from frontier_rl.core.sensing.lidar import Lidar, Scan
from frontier_rl.core.sim.config import SimConfig
from frontier_rl.core.sim.leg_result import LegOutcome, LegResult
from frontier_rl.core.sim.metrics import EpisodeResult
from frontier_rl.core.sim.paths import path_to_follow
from frontier_rl.core.sim.simulator import ExplorationSimulator
from frontier_rl.core.world.grid import OccupancyGrid
from frontier_rl.core.world.robot import Pose
from frontier_rl.core.world.worlds import World
from frontier_rl.robot.explorer import FrontierExplorer
from frontier_rl.robot.explorer_decision import Finished, Goal, GoalStatus, Renewal


@dataclass(frozen=True)
class GoalEnd:
    """A goal that ended: how, and the leg the robot drove for it."""

    status: GoalStatus
    leg: LegResult


class SimulatedRobot:
    """One robot in one world, driven goal by goal.

    Args:
        world: the world and the start pose.
        config: the simulation settings.
        seed: seeds the sensor noise as an in-process episode of the same seed does
            (:func:`~frontier_rl.core.sim.episode.drive_episode`'s simulation stream).
    """

    def __init__(self, world: World, config: SimConfig | None = None, seed: int = 0) -> None:
        sim_rng, _ = np.random.default_rng(seed).spawn(2)
        self.sim = ExplorationSimulator(world, config, sim_rng)
        self._scanner = Lidar(self.sim.world.grid, self.sim.config.lidar)  # for the published scans only
        self._leg: Generator[None, None, LegResult] | None = None
        self.goal: tuple[float, float] | None = None

    @property
    def pose(self) -> Pose:
        """The robot's pose (m, rad) in the map frame."""
        return self.sim.pose

    @property
    def sim_time(self) -> float:
        """The simulated clock (s): it runs while the robot drives or turns for a goal."""
        return self.sim.sim_time

    @property
    def busy(self) -> bool:
        """Whether a goal is under way."""
        return self._leg is not None

    def map(self) -> OccupancyGrid:
        """The map the robot has built, grown to the seen area (the map frame)."""
        return self.sim.map()

    def scan(self) -> Scan:
        """A LiDAR scan from the pose now, without noise (what a laser topic shows)."""
        return self._scanner.scan(self.pose, None)

    def send_goal(self, x: float, y: float) -> None:
        """Drive to (x, y) (m), replacing any goal under way. The robot drives to the reachable cell
        nearest to it; a goal farther than the goal tolerance from where that leaves it is aborted."""
        if not (math.isfinite(x) and math.isfinite(y)):
            raise ValueError(f"goal ({x!r}, {y!r}) is not a point")
        self.cancel()
        self._leg = self.sim.go_to_steps(x, y)
        self.goal = (x, y)

    def follow_path(self, path: NDArray[np.float64]) -> None:
        """Drive along ``path`` ((n, 2), m, map frame, ending at the goal), replacing any goal under
        way, as Nav2's controller follows a path (:meth:`ExplorationSimulator.follow_steps
        <frontier_rl.core.sim.simulator.ExplorationSimulator.follow_steps>`); its end is judged as
        :meth:`send_goal`'s, at the path's last point. A path to the goal of the path under way
        (within a cell) is taken by the leg under way, its progress kept, as Nav2's controller
        takes a goal's next path."""
        path = np.asarray(path, np.float64)
        if path.ndim != 2 or path.shape[1] != 2 or len(path) == 0 or not np.isfinite(path).all():
            raise ValueError(f"path of shape {path.shape} is not a list of points")
        goal = (float(path[-1, 0]), float(path[-1, 1]))
        leg, resolution = self.sim.leg, self.sim.world.grid.resolution
        under_way = self.goal if self._leg is not None and leg is not None and leg.given_path else None
        same = under_way is not None and math.hypot(goal[0] - under_way[0], goal[1] - under_way[1]) <= resolution
        if leg is not None and same:
            leg.take_path(path_to_follow(path, self.pose, resolution))  # the same goal: the leg goes on
            return
        self.cancel()
        self._leg = self.sim.follow_steps(path)
        self.goal = goal

    def cancel(self) -> None:
        """Stop the goal under way where the robot is."""
        if self._leg is not None:
            self._leg.close()
        self._leg = self.goal = None

    def step(self) -> GoalEnd | None:
        """Drive the goal under way on by one map update (or one LiDAR tick of a turn): its end,
        or None while it goes on (or when there is none)."""
        if self._leg is None:
            return None
        try:
            next(self._leg)
        except StopIteration as stop:
            leg: LegResult = stop.value
            goal, self._leg, self.goal = self.goal, None, None
            assert goal is not None
            there = self.sim.config.navigation.goal_tolerance + self.sim.world.grid.resolution
            reached = (
                leg.outcome is LegOutcome.REACHED and math.hypot(goal[0] - self.pose.x, goal[1] - self.pose.y) <= there
            )
            return GoalEnd(GoalStatus.SUCCEEDED if reached else GoalStatus.ABORTED, leg)
        return None

    def stand(self, until: float) -> None:
        """Stand still, scanning, for one LiDAR period or until ``until`` (simulated s), whichever
        is sooner: a robot without a goal keeps time with a teammate that drives."""
        duration = min(self.sim.config.lidar.period, until - self.sim_time)
        if duration > 0 and not self.sim.truncated:
            self.sim.advance(self.pose, 0.0, duration)

    def see_teammates(self, others: list[SimulatedRobot]) -> None:
        """The other robots of the world, where they stand now: obstacles to plan around, walls
        to the LiDAR, left off the map (:meth:`ExplorationSimulator.set_teammates`)."""
        self.sim.set_teammates(np.array([(o.pose.x, o.pose.y) for o in others], np.float64).reshape(-1, 2))

    def result(self) -> EpisodeResult:
        """The episode's metrics so far (coverage of the explorable space, time, distance)."""
        return self.sim.result(0.0)


def explore_in_process(robot: SimulatedRobot, explorer: FrontierExplorer, max_ticks: int = 100_000) -> Finished:
    """Explore with ``explorer`` deciding and ``robot`` driving, on one clock, as the ROS 2 nodes do
    over DDS: a planner tick every ``1 / planner_frequency`` s of simulated time, the goal's end
    reported as Nav2 reports it. What the ROS 2 closed loop is compared with."""
    period = 1.0 / explorer.params.planner_frequency
    for _ in range(max_ticks):
        decision = explorer.tick(robot.map(), robot.pose, robot.sim_time)
        if isinstance(decision, Finished):
            robot.cancel()
            return decision
        if isinstance(decision, Renewal):
            decision = decision.goal  # the robot follows the path it is given: the path planned afresh
        if isinstance(decision, Goal) and decision.path is not None:
            robot.follow_path(decision.path)  # Nav2's controller: follow_path
        elif isinstance(decision, Goal):
            robot.send_goal(decision.x, decision.y)
        until = robot.sim_time + period
        while robot.busy and robot.sim_time < until:
            end = robot.step()
            explorer.passed(robot.pose)
            if end is not None and end.status is GoalStatus.SUCCEEDED:
                explorer.goal_reached()
            elif end is not None:
                explorer.goal_failed(robot.map())
        if robot.sim.truncated:  # the world's own time cap: the robot drives no more
            robot.cancel()
            return explorer.time_up(robot.map(), robot.pose)
    raise RuntimeError(f"exploration did not end in {max_ticks} planner ticks")
