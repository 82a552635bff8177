"""Robots of a team in each other's way: they collide as discs, go round one another where there is
room, and otherwise one gives way and chooses again; they never drive through each other."""

from __future__ import annotations

import math

import numpy as np
import pytest

from frontier_rl.core.frontiers.blacklist import AUDIT_BUDGET
from frontier_rl.core.navigation.follower import FollowerParams, FollowStatus, careful_flags, follow_path
from frontier_rl.core.sim import look_state
from frontier_rl.core.sim.candidates import reachable_frontiers
from frontier_rl.core.sim.config import SimConfig
from frontier_rl.core.sim.leg_result import LegOutcome
from frontier_rl.core.sim.simulator import ExplorationSimulator
from frontier_rl.core.world.catalog import generate_world
from frontier_rl.core.world.grid import CellState, OccupancyGrid
from frontier_rl.core.world.robot import Pose
from frontier_rl.core.world.worlds import World, make_world
from frontier_rl.policies import FixedWeight
from frontier_rl.swarm import Failure, Strategy, TeamConfig, TeamSimulator
from frontier_rl.swarm.team import TeamRobot

RADIUS = SimConfig().robot.radius


def room(height_cells: int, length_cells: int = 62, start: Pose | None = None) -> World:
    """A free room ``length_cells`` long (3 m by default) and ``height_cells`` high, walled all
    round; the start 0.4 m from its left end, half way up, unless given."""
    data = np.full((height_cells + 2, length_cells), CellState.FREE, np.int8)
    data[[0, -1], :] = CellState.OCCUPIED
    data[:, [0, -1]] = CellState.OCCUPIED
    y = (height_cells + 2) * 0.05 / 2
    return make_world(OccupancyGrid(data, 0.05), "room", start=start or Pose(0.4, y, 0.0))


def drive_past(world: World, mate: tuple[float, float]) -> tuple[ExplorationSimulator, LegOutcome, float]:
    """Drive from the start toward the far end with a teammate standing at ``mate``: the robot,
    how the leg ended, and the closest (m) it came to the teammate."""
    sim = ExplorationSimulator(world, rng=np.random.default_rng(0))
    sim.set_teammates(np.array([mate]))
    outcome = sim.go_to(2.7, world.start.y).outcome
    xy = sim.trajectory()[:, :2]
    return sim, outcome, float(np.hypot(xy[:, 0] - mate[0], xy[:, 1] - mate[1]).min())


def test_robots_plan_around_each_other() -> None:
    world = room(40)  # 2 m wide: room to pass
    sim, outcome, closest = drive_past(world, (1.5, world.start.y))
    assert outcome is LegOutcome.REACHED and closest >= 2 * RADIUS
    assert math.dist((sim.pose.x, sim.pose.y), (2.7, world.start.y)) < 0.2


def test_a_robot_in_contact_goes_round_after_waiting() -> None:
    world = room(40)
    mate = (world.start.x + 2 * RADIUS + 0.01, world.start.y)  # in contact, straight ahead
    alone = ExplorationSimulator(world, rng=np.random.default_rng(0))
    alone.go_to(2.7, world.start.y)
    sim, outcome, closest = drive_past(world, mate)
    assert outcome is LegOutcome.REACHED and closest >= 2 * RADIUS - 1e-9
    assert sim.sim_time - alone.sim_time >= sim.config.navigation.teammate_patience


def test_a_robot_with_no_way_round_gives_way_instead_of_driving_through() -> None:
    world = room(8)  # 0.4 m wide: no way round another robot
    sim, outcome, closest = drive_past(world, (1.5, world.start.y))
    assert outcome is LegOutcome.GAVE_WAY and closest >= 2 * RADIUS - 1e-9
    assert sim.sim_time >= sim.config.navigation.teammate_patience
    assert not sim.blacklist.entries  # the goal is not given up: the teammate may move on


def test_a_robot_whose_goal_a_teammate_stands_on_gets_as_close_as_it_can() -> None:
    """Not a give-way: robots crowding round one goal had given way to each other for ever (3 robots
    of a 4-robot `rendezvous` team on cluttered seed 2, from 1,500 s to the time cap)."""
    world = room(40)
    mate = (1.5, world.start.y)
    sim = ExplorationSimulator(world, rng=np.random.default_rng(0))
    sim.set_teammates(np.array([mate]))
    result = sim.go_to(*mate)
    assert result.outcome is LegOutcome.REACHED and result.duration_s >= sim.config.navigation.teammate_patience
    assert math.dist((sim.pose.x, sim.pose.y), mate) >= 2 * RADIUS - 1e-9


def test_a_way_round_from_contact_is_driven_in_open_space() -> None:
    """In contact with a teammate at -30 degrees, goal beyond it: the way round planned from the
    robot's own cell began at that cell's centre, inside the teammate's disc, so the follower refused
    it at every try until the leg was given up (review of 2026-11-27, 1 of 100 such cases)."""
    bearing = math.radians(-30)
    start = Pose(0.63, 1.05, bearing)
    mate = (start.x + (2 * RADIUS + 0.005) * math.cos(bearing), start.y + (2 * RADIUS + 0.005) * math.sin(bearing))
    sim = ExplorationSimulator(room(40, start=start), rng=np.random.default_rng(0))
    sim.set_teammates(np.array([mate]))
    result = sim.go_to(start.x + 1.8 * math.cos(bearing), start.y + 1.8 * math.sin(bearing))
    assert result.outcome is LegOutcome.REACHED and not sim.blacklist.entries


def test_a_teammate_standing_for_good_in_a_corridor_ends_the_episode(monkeypatch: pytest.MonkeyPatch) -> None:
    """Robot 1 has given up the corridor's far end for good (its audit budget spent too, and no look
    from elsewhere: as where no cell away from the goals tried sees its unknown) and stands in the
    way of robot 0, whose only frontier lies behind it: robot 0 gives way, finds nothing else, and
    counts the goal as failed each time, so the episode ends (`unreachable`) instead of giving way
    until the time cap."""
    offered = look_state.spent_looks
    monkeypatch.setattr(look_state, "spent_looks", lambda *args: offered(*args).subset(np.zeros(0, np.int64)))
    world = room(8, 200)  # 0.4 m x 9.9 m
    team = TeamSimulator(world, SimConfig(max_sim_time=400.0), TeamConfig(robots=2), np.random.default_rng(0))
    second = team.robots[1]
    for goal in second.sim.frontiers().goals:
        for _ in range(AUDIT_BUDGET * second.sim.blacklist.max_failures):
            second.sim.blacklist.fail(float(goal[0]), float(goal[1]), second.sim.mapper.state)
    second.sim.refresh()
    rng = np.random.default_rng(0)
    while (index := team.next_decision()) is not None:
        team.assign(index, FixedWeight(0.75).rank(team.context(index), rng))
    assert team.done and team.sim_time < 100.0
    assert team.result().end_reason == "unreachable"


def _follow_straight(x0: float, to_x: float) -> tuple[float, int]:
    """Follow a straight path from (x0, 0) to (to_x, 0) (m) for 1 s with a teammate at the origin,
    in open space: where the robot ends (x, m) and the follower's status."""
    params = FollowerParams(0.22, 2.84, 0.7, 2.0, 0.3, 0.02, 0.1, RADIUS)
    path = np.array([[x0, 0.0], [to_x, 0.0]])
    heading = 0.0 if to_x > x0 else math.pi
    gate = np.array([1e9, 0.0, 0.0, 0.0, np.inf, np.inf])
    open_space = np.full((100, 100), 10.0)
    x, *_, status = follow_path(path[:, 0], path[:, 1], 0, x0, 0.0, heading, 1.0, params, open_space, np.zeros((1, 2)),
                                2 * RADIUS, -2.5, -2.5, 0.05, gate, careful_flags())  # fmt: skip
    return x, status


def test_the_follower_lets_a_robot_in_contact_back_away_but_not_press_on() -> None:
    x, _ = _follow_straight(2 * RADIUS - 0.01, 1.0)  # overlapping by 1 cm, driving away
    assert x > 2 * RADIUS + 0.1
    x, status = _follow_straight(2 * RADIUS + 0.05, -1.0)  # driving at the teammate
    assert status == FollowStatus.BLOCKED_BY_ROBOT and 2 * RADIUS - 1e-9 <= x < 2 * RADIUS + 0.03


def test_a_robot_that_gave_way_chooses_among_frontiers_its_teammate_does_not_block() -> None:
    """The teammate is a wall for that decision: no way past it, and no view past it either (a goal
    within 3 m of the frontier that saw it through the teammate stayed a candidate, at the robot's
    own spot, which it then reached at once and blacklisted)."""
    data = np.full((10, 80), CellState.FREE, np.int8)  # a corridor 0.4 m wide, unknown past 3 m
    data[[0, -1], :] = CellState.OCCUPIED
    data[1:-1, 60:] = CellState.UNKNOWN
    grid = OccupancyGrid(data, 0.05)
    config = SimConfig()
    here = Pose(0.6, 0.25, 0.0)
    _, _, open_way = reachable_frontiers(grid, here, config)
    assert len(open_way) == 1  # the unknown end
    mate = np.array([[0.6 + 2 * RADIUS, 0.25]])  # in contact, between the robot and the unknown end
    _, reachable, blocked = reachable_frontiers(grid, here, config, avoid=(mate, RADIUS))
    assert len(blocked) == 0
    row, col = grid.world_to_cell(here.x, here.y)
    assert reachable[row, col - 3] and not reachable[row, col + 3]  # it can still back away


class WatchedTeam(TeamSimulator):
    """A team that records the closest any two robots came at any step (m)."""

    closest = math.inf

    def _step(self, robot: TeamRobot) -> None:
        super()._step(robot)
        for other in self.robots:
            if other is not robot:
                self.closest = min(self.closest, math.dist(robot.xy, other.xy))


@pytest.mark.parametrize(
    ("world", "strategy", "robots", "failures"),
    [
        ("office", "rendezvous", 3, ()),
        ("office", "coordinated", 4, ()),
        ("rooms", "uncoordinated", 4, ()),
        ("office", "rendezvous", 3, (Failure(robot=1, time_s=60.0),)),
    ],
)
@pytest.mark.parametrize("seed", [0, 4])
def test_robots_never_drive_through_each_other(
    world: str, strategy: str, robots: int, failures: tuple[Failure, ...], seed: int
) -> None:
    team = WatchedTeam(generate_world(world, seed), team=TeamConfig(robots, Strategy(strategy), failures=failures),
                       rng=np.random.default_rng(seed))  # fmt: skip
    rng = np.random.default_rng(seed)
    while (index := team.next_decision()) is not None:
        team.assign(index, FixedWeight(0.75).rank(team.context(index), rng))
    assert team.closest >= 2 * RADIUS - 1e-9
    assert team.done and team.coverage >= 0.99
