"""A leg's behaviours, one at a time, against a scripted simulator (the leg's port): the 30 s
no-progress abort, a frontier seen before the robot gets there, the bumper, and a replan after a
newly seen obstacle that finds no path, then the recovery rotations."""

from __future__ import annotations

from collections.abc import Callable, Generator

import numpy as np
import pytest
from numpy.typing import NDArray

from frontier_rl.core.navigation.config import NavigationConfig
from frontier_rl.core.navigation.thin_walls import Recovery
from frontier_rl.core.sensing.lidar import Lidar
from frontier_rl.core.sim.config import SimConfig
from frontier_rl.core.sim.leg import Leg, run_leg
from frontier_rl.core.sim.leg_result import AbortCause, LegOutcome
from frontier_rl.core.sim.simulator import ExplorationSimulator
from frontier_rl.core.sim.teammates import Teammates
from frontier_rl.core.world.grid import CellState, OccupancyGrid
from frontier_rl.core.world.robot import Pose
from frontier_rl.core.world.worlds import World, make_world

RES = 0.05
FROM_HERE: list[NDArray[np.float64] | None] = []  # replanning finds the straight path on from the robot
SCAN_PERIOD_S = 0.5


def _hall(wall_at_col: int | None = None) -> World:
    """A 2 m × 10 m hall; optionally a wall across it at column ``wall_at_col``."""
    data = np.full((40, 200), CellState.OCCUPIED, np.int8)
    data[2:-2, 2:-2] = CellState.FREE
    if wall_at_col is not None:
        data[:, wall_at_col : wall_at_col + 4] = CellState.OCCUPIED
    return make_world(OccupancyGrid(data, RES), "hall", start=Pose(0.5, 1.0, 0.0))


class ScriptedPort:
    """The simulator as a leg sees it, with the map's answers scripted: no mapper, one map update
    every 0.5 s, ``alive(t)`` the goal frontier's state at sim time t, ``blocked_after`` the time
    from which the map puts a wall on the path, ``replans`` the paths replanning finds in turn."""

    def __init__(
        self,
        world: World,
        alive: Callable[[float], bool] = lambda t: True,
        blocked_after: float | None = None,
        replans: list[NDArray[np.float64] | None] | None = None,
    ) -> None:
        self.config = SimConfig()
        self.world = world
        self.pose = world.start
        self.sim_time = 0.0
        self.nearby_robots = Teammates(world.grid, Lidar(world.grid, self.config.lidar), self.config.robot.radius)
        self.follow_params = ExplorationSimulator(world, self.config).follow_params
        self.alive = alive
        self.blocked_after = blocked_after
        self.replans = replans if replans is FROM_HERE else list(replans or [])
        self.calls: list[str] = []

    @property
    def truncated(self) -> bool:
        return self.sim_time >= 3600.0

    def advance(self, pose: Pose, driven: float, duration: float) -> tuple[int, int] | None:
        self.pose = pose
        self.sim_time += duration
        return (0, 0)

    def until_next_scan(self) -> tuple[float, NDArray[np.float64]]:
        return SCAN_PERIOD_S, np.array([0.2, 0.0, 0.0, 0.0, np.inf, np.inf])

    def wait_steps(self) -> Generator[None, None, None]:
        self.calls.append("wait")
        self.sim_time += SCAN_PERIOD_S
        yield

    def rotate_steps(self) -> Generator[None, None, tuple[int, int]]:
        self.calls.append("rotate")
        self.sim_time += 2.4
        yield
        return (0, 0)

    def bump(self) -> None:
        self.calls.append("bump")

    @property
    def navigator(self) -> ScriptedPort:
        return self

    def replan(self, goal: tuple[float, float], recovery: Recovery, pose: Pose) -> NDArray[np.float64] | None:
        self.calls.append("replan")
        if self.replans is FROM_HERE:
            return _straight(goal[0], self.pose.x)
        return self.replans.pop(0) if self.replans else None

    def replan_round_teammates(
        self, goal: tuple[float, float], recovery: Recovery, pose: Pose
    ) -> NDArray[np.float64] | None:
        return self.replan(goal, recovery, pose)  # no teammates here

    def path_blocked(self, path_cells: NDArray[np.int64], first: int, recovery: Recovery) -> bool:
        return self.blocked_after is not None and self.sim_time >= self.blocked_after

    def frontier_alive(self, cells: NDArray[np.int64]) -> bool:
        return self.alive(self.sim_time)

    def blacklist_goal(
        self, goal: tuple[float, float], frontier_cells: NDArray[np.int64] | None, *, reached: bool = False
    ) -> None:
        self.calls.append("visited" if reached else "blacklist")


def _straight(x1: float, x0: float = 0.5) -> NDArray[np.float64]:
    xs = np.arange(x0, x1 + 1e-9, RES)
    return np.column_stack((xs, np.full_like(xs, 1.0)))


FRONTIER = np.array([[20, 190]], np.int64)


def test_a_leg_without_progress_for_30_s_is_aborted_and_its_goal_blacklisted() -> None:
    world = _hall(wall_at_col=40)  # a wall 2 m ahead, across the hall
    path = _straight(9.0)
    port = ScriptedPort(world, replans=FROM_HERE)  # replanning finds a path, through the wall again
    leg = Leg(port, path, (9.0, 1.0), FRONTIER, recovery=Recovery.NONE)
    outcome = run_leg(leg.run())
    assert outcome is LegOutcome.ABORTED and leg.abort_cause is AbortCause.NO_PROGRESS
    timeout = port.config.navigation.progress_timeout
    assert timeout < port.sim_time <= timeout + 10.0  # it drove to the wall, then waited out the timeout
    assert port.pose.x < 2.0
    assert port.calls.count("blacklist") == 1 and "bump" in port.calls


def test_a_frontier_seen_before_the_robot_gets_there_ends_the_leg_as_explored() -> None:
    port = ScriptedPort(_hall(), alive=lambda t: t < 3.0)
    outcome = run_leg(Leg(port, _straight(9.0), (9.0, 1.0), FRONTIER, recovery=Recovery.NONE).run())
    assert outcome is LegOutcome.EXPLORED
    period = port.config.navigation.frontier_check_period
    assert 3.0 <= port.sim_time <= 3.0 + period + SCAN_PERIOD_S  # at the first check after it was seen
    assert port.pose.x < 9.0 - 1.0 and "blacklist" not in port.calls


def test_the_bumper_marks_the_wall_the_robot_runs_into() -> None:
    """The simulator's bumper: the wall cells the robot touches become occupied in its map."""
    world = _hall(wall_at_col=40)
    sim = ExplorationSimulator(world, SimConfig(sensor_noise=False))
    sim.advance(Pose(40 * RES - 0.12, 1.0, 0.0), 0.0, 0.0)  # the robot's front at the wall
    sim.mapper.state[:, 40:44] = CellState.UNKNOWN  # a wall its LiDAR has not seen
    sim.bump()
    row = world.grid.world_to_cell(sim.pose.x, sim.pose.y)[0]
    assert sim.mapper.state[row, 40] == CellState.OCCUPIED
    assert not (sim.mapper.state[:, 42:44] == CellState.OCCUPIED).any()  # only what it touches


@pytest.mark.parametrize("recoveries", [0, 1, 2])
def test_a_newly_seen_obstacle_replans_then_rotates_to_recover_before_giving_up(recoveries: int) -> None:
    port = ScriptedPort(_hall(), blocked_after=1.0)  # replanning never finds a path
    port.config = SimConfig(navigation=NavigationConfig(max_recoveries=recoveries))
    leg = Leg(port, _straight(9.0), (9.0, 1.0), FRONTIER, recovery=Recovery.NONE)
    outcome = run_leg(leg.run())
    assert outcome is LegOutcome.ABORTED and leg.abort_cause is AbortCause.NO_PATH
    assert port.calls.count("rotate") == recoveries
    assert port.calls[: 2 * recoveries + 1] == ["replan"] + ["rotate", "replan"] * recoveries
    assert port.calls[-1] == "blacklist"


def test_a_newly_seen_obstacle_with_a_way_round_drives_the_new_path() -> None:
    detour = _straight(5.0)
    port = ScriptedPort(_hall(), blocked_after=1.0, replans=[detour])
    leg = Leg(port, _straight(9.0), (5.0, 1.0), None, recovery=Recovery.NONE)
    steps = leg.run()
    outcome = None
    while outcome is None:
        try:
            next(steps)
            if "replan" in port.calls:
                port.blocked_after = None  # the detour is clear
        except StopIteration as stop:
            outcome = stop.value
    assert outcome is LegOutcome.REACHED and port.calls.count("replan") == 1
    assert abs(port.pose.x - 5.0) <= port.config.navigation.goal_tolerance


class WanderingPort(ScriptedPort):
    """Every map update puts a wall on the path, and replanning finds a way on along the hall, to
    its east end and back: progress by move_base's rule (the robot keeps moving), on ways that never
    lead to the goal (the ``aws_small_house`` map on 0.1 m cells had a leg to a goal 2 m away drive
    80 m so)."""

    def __init__(self, world: World) -> None:
        super().__init__(world, blocked_after=1.0)
        self.east = True
        self.driven = 0.0

    def advance(self, pose: Pose, driven: float, duration: float) -> tuple[int, int] | None:
        self.driven += driven
        return super().advance(pose, driven, duration)

    def replan(self, goal: tuple[float, float], recovery: Recovery, pose: Pose) -> NDArray[np.float64] | None:
        self.calls.append("replan")
        self.east = self.pose.x < 8.5 if self.east else self.pose.x < 1.5
        xs = np.linspace(self.pose.x, 9.5 if self.east else 0.5, 100)
        return np.column_stack((xs, np.full_like(xs, 1.0)))


@pytest.mark.parametrize("detour_factor", [10.0, 1000.0])
def test_a_leg_that_drives_far_beyond_its_plan_is_aborted(detour_factor: float) -> None:
    port = WanderingPort(_hall())
    port.config = SimConfig(navigation=NavigationConfig(detour_factor=detour_factor))
    first = _straight(2.5)  # 2 m to the goal, as planned
    leg = Leg(port, first, (2.5, 1.0), FRONTIER, recovery=Recovery.NONE)
    outcome = run_leg(leg.run())
    if detour_factor == 1000.0:  # no limit to speak of: the robot wanders until the episode's time cap
        assert outcome is LegOutcome.TIMEOUT and port.driven > 200.0 and leg.abort_cause is None
        return
    limit = 10.0 * 2.0 + port.config.navigation.detour_slack
    assert outcome is LegOutcome.ABORTED and limit < port.driven < limit + 0.5
    assert leg.abort_cause is AbortCause.DETOUR
    assert port.calls.count("blacklist") == 1 and port.calls.count("replan") > 30


@pytest.mark.parametrize("recovery", [Recovery.NONE, Recovery.HALF_CELL])
def test_a_leg_through_peeled_walls_gives_up_its_detour_sooner(recovery: Recovery) -> None:
    """On the narrow-passage recovery's costmap a gap may not be there: such a leg may drive only
    ``recovery_detour_factor`` times its first plan and ``recovery_detour_slack`` more."""
    port = WanderingPort(_hall())
    nav = NavigationConfig(recovery_detour_factor=3.0, recovery_detour_slack=4.0)
    port.config = SimConfig(navigation=nav)
    leg = Leg(port, _straight(2.5), (2.5, 1.0), FRONTIER, recovery=recovery)
    assert run_leg(leg.run()) is LegOutcome.ABORTED and leg.abort_cause is AbortCause.DETOUR
    limit = 3.0 * 2.0 + 4.0 if recovery is not Recovery.NONE else 10.0 * 2.0 + nav.detour_slack
    assert limit < port.driven < limit + 0.5
