"""The team simulator: one clock, merged maps, robots as obstacles, coordination, rendezvous,
failures and the frontier request."""

from __future__ import annotations

import math
from functools import cache

import numpy as np
import pytest
from scipy import ndimage

from frontier_rl.core.sim.config import SimConfig
from frontier_rl.core.sim.episode import run_episode
from frontier_rl.core.sim.simulator import ExplorationSimulator
from frontier_rl.core.world.catalog import generate_world
from frontier_rl.core.world.grid import CellState, OccupancyGrid
from frontier_rl.core.world.robot import Pose, RobotConfig
from frontier_rl.core.world.worlds import World, make_world
from frontier_rl.errors import ConfigError
from frontier_rl.policies import FixedWeight, NearestFrontier
from frontier_rl.swarm import (
    Failure,
    Strategy,
    TeamConfig,
    TeamResult,
    TeamSimulator,
    frontier_request,
    run_team_episode,
)
from frontier_rl.swarm.rendezvous import Phase
from frontier_rl.swarm.result import overlap_share
from frontier_rl.swarm.starts import team_starts
from tests.core.sim.test_completion import slot_world
from tests.swarm.test_traffic import room

POLICY = FixedWeight(0.75)


@cache
def office(seed: int) -> World:
    return generate_world("office", seed)


@cache
def team_episode(seed: int, robots: int, strategy: str, failures: tuple[Failure, ...] = ()) -> TeamResult:
    team = TeamConfig(robots=robots, strategy=Strategy(strategy), failures=failures)
    return run_team_episode(office(seed), POLICY, team=team, seed=seed)


@pytest.mark.parametrize("strategy", ["uncoordinated", "coordinated", "rendezvous"])
def test_a_one_robot_team_explores_exactly_as_the_single_robot(strategy: str) -> None:
    """With rendezvous too: a lone robot drove to its own meeting points (rooms seed 2: 431.6 s
    against 392.2 s alone)."""
    single = run_episode(office(3), NearestFrontier(), seed=3)
    alone = TeamConfig(robots=1, strategy=Strategy(strategy))
    team = run_team_episode(office(3), NearestFrontier(), team=alone, seed=3)
    assert np.array_equal(single.trajectory, team.trajectory)
    assert team.sim_time_s == single.sim_time_s and team.coverage == single.coverage


@pytest.mark.parametrize("strategy", ["coordinated", "rendezvous"])
def test_a_team_cut_off_by_the_time_cap_lists_what_it_left(strategy: str) -> None:
    """As one robot's episode does: a team at the cap reported nothing left to explore."""
    config = SimConfig(max_sim_time=60.0)
    single = run_episode(office(3), NearestFrontier(), config, seed=3)
    team = run_team_episode(office(3), NearestFrontier(), config, TeamConfig(robots=1, strategy=Strategy(strategy)), 3)
    assert single.end_reason == team.end_reason == "time_cap" and single.frontiers_left
    assert [f.summary() for f in team.frontiers_left] == [f.summary() for f in single.frontiers_left]
    assert team.unknown_left_m2 == single.unknown_left_m2 > 0
    assert team.robots == 1 and team.overlap == 0.0


@pytest.mark.parametrize("strategy", ["uncoordinated", "coordinated", "rendezvous"])
def test_teams_finish_the_map_and_report_every_robot(strategy: str) -> None:
    result = team_episode(1, 3, strategy)
    assert result.done and not result.truncated and result.coverage >= 0.99
    assert result.robots == 3 and len(result.robot_path_lengths_m) == 3 and len(result.trajectories) == 3
    assert all(length > 0 for length in result.robot_path_lengths_m)
    assert math.isclose(result.path_length_m, sum(result.robot_path_lengths_m))
    assert 0.0 <= result.overlap <= 1.0 and all(0 < c <= 1 for c in result.robot_coverage)
    summary = result.summary().to_json()
    assert summary["robots"] == 3 and len(summary["robot_path_lengths_m"]) == 3 and "overlap" in summary
    times = [d.time_s for d in result.decision_log]  # every robot's decisions (a team's weights were robot 0's)
    assert len(times) == result.decisions and times == sorted(times)


def test_team_episodes_are_deterministic() -> None:
    a = run_team_episode(office(2), POLICY, team=TeamConfig(robots=2, strategy=Strategy.COORDINATED), seed=2)
    b = team_episode(2, 2, "coordinated")
    assert a.sim_time_s == b.sim_time_s
    assert all(np.array_equal(x, y) for x, y in zip(a.trajectories, b.trajectories, strict=True))


def test_two_robots_cover_the_office_sooner_than_one() -> None:
    one = run_episode(office(1), POLICY, seed=1)
    two = team_episode(1, 2, "coordinated")
    assert two.sim_time_s < one.sim_time_s


def test_coordination_never_sends_two_robots_to_one_frontier_while_others_remain() -> None:
    config = TeamConfig(robots=3, strategy=Strategy.COORDINATED)
    team = TeamSimulator(office(4), team=config, rng=np.random.default_rng(4))
    rng = np.random.default_rng(0)
    checked = 0
    while (index := team.next_decision()) is not None:
        claims = team.claims(index)
        centres = team.robots[index].sim.frontiers().goals
        free = [c for c in centres if len(claims) == 0 or np.hypot(*(claims - c).T).min() > config.claim_radius]
        team.assign(index, POLICY.rank(team.context(index), rng))
        sim = team.robots[index].sim
        if free and len(claims) and sim.target is not None:
            black = np.asarray([(e.x, e.y) for e in sim.blacklist.entries if e.active]).reshape(-1, 2)
            unreachable = [len(black) and np.hypot(*(black - c).T).min() < 1e-9 for c in free]
            if not all(unreachable):  # a free frontier it could plan to: it must have taken one
                assert np.hypot(*(claims - np.asarray(sim.target)).T).min() > config.claim_radius
            checked += 1
    assert checked >= 10 and team.done


def test_robots_hide_what_is_behind_them_and_stay_out_of_the_maps() -> None:
    world = room(40)
    mate = np.array([[1.0, world.start.y]])  # 0.6 m ahead of the start, in the LiDAR's view
    alone = ExplorationSimulator(world, rng=np.random.default_rng(0))
    seen = ExplorationSimulator(world, rng=np.random.default_rng(0), teammates=mate)
    g = world.grid
    row, col = g.world_to_cell(2.5, world.start.y)  # straight behind the teammate
    assert alone.mapper.state[row, col] == CellState.FREE and seen.mapper.state[row, col] == CellState.UNKNOWN
    r0, c0 = g.world_to_cell(1.0 - 0.2, world.start.y - 0.2)
    r1, c1 = g.world_to_cell(1.0 + 0.2, world.start.y + 0.2)
    assert not (seen.mapper.state[r0 : r1 + 1, c0 : c1 + 1] == CellState.OCCUPIED).any()  # no phantom wall


def test_windowed_merges_follow_the_rule() -> None:
    config = TeamConfig(robots=2)
    team = TeamSimulator(office(5), team=config, rng=np.random.default_rng(5))
    a, b = team.robots
    assert np.array_equal(a.sim.mapper.state, b.sim.mapper.state)  # they start side by side, in contact
    rng = np.random.default_rng(0)
    for _ in range(20):
        index = team.next_decision()
        assert index is not None
        team.assign(index, POLICY.rank(team.context(index), rng))
    known = (a.sim.mapper.state != CellState.UNKNOWN) & (b.sim.mapper.state != CellState.UNKNOWN)
    agree = a.sim.mapper.state[known] == b.sim.mapper.state[known]
    assert agree.mean() > 0.99  # every scan reached the teammate's map at once
    assert team.coverage >= max(r.sim.coverage for r in team.robots) - 1e-12


def test_the_rendezvous_cycle_meets_merges_and_repeats() -> None:
    config = TeamConfig(robots=3, strategy=Strategy.RENDEZVOUS, explore_period=40.0)
    team = TeamSimulator(office(2), team=config, rng=np.random.default_rng(2))
    assert team.rendezvous is not None
    rng = np.random.default_rng(0)
    meetings = 0
    while (index := team.next_decision()) is not None:
        if len(team.rendezvous.meetings) > meetings:  # a meeting was just held: the commander decides first
            meetings = len(team.rendezvous.meetings)
            _, point, present = team.rendezvous.meetings[-1]
            assert index == 0 and present == (0, 1, 2)
            states = [team.robots[i].sim.mapper.state for i in present]
            assert all(np.array_equal(states[0], s) for s in states[1:])  # merged
            xy = [team.robots[i].xy for i in present]
            contact = team.robots[0].sim.nearby_robots.contact_distance
            for here in xy:  # at the point, or in contact with a robot of the group round it
                near = [math.dist(here, point) <= config.meeting_radius]
                assert any(near + [0 < math.dist(here, other) <= contact for other in xy])
        team.assign(index, POLICY.rank(team.context(index), rng))
        if meetings == 0 and team.rendezvous.point is not None:
            assert team.rendezvous.due == pytest.approx(config.explore_period, abs=1.0)
    assert meetings >= 2 and team.done


@pytest.mark.parametrize(("x", "merges"), [(10.0, False), (4.2, True)])
def test_only_the_robots_at_the_meeting_merge(x: float, merges: bool) -> None:
    """A robot whose way to the meeting point ended short waits where it stands; the meeting merges
    it only if it is within communication range of the group at the point (before, every waiting
    robot merged, wherever it stood)."""
    world = room(40, length_cells=240)  # 12 m by 2 m
    config = TeamConfig(robots=3, strategy=Strategy.RENDEZVOUS)
    team = TeamSimulator(world, team=config, rng=np.random.default_rng(0))
    cycle = team.rendezvous
    assert cycle is not None
    y = world.start.y
    cycle.point, cycle.due = (1.0, y), 0.0
    for robot, at in zip(team.robots, (1.0, 2.5, x), strict=True):  # robot 2 ended its way short of the point
        robot.sim.advance(Pose(at, y, 0.0), 0.0, 0.0)
        robot.phase = Phase.WAITING
    lone = team.robots[2].sim.mapper.state.copy()
    cycle.before_step(team.robots[0])
    _, _, present = cycle.meetings[-1]
    assert present == ((0, 1, 2) if merges else (0, 1))  # 3.2 m from the point, 1.7 m from robot 1: in range
    assert np.array_equal(team.robots[2].sim.mapper.state, lone) is not merges
    assert all(robot.phase is Phase.EXPLORE for robot in team.robots)


def test_a_rendezvous_robot_left_alone_stops_meeting() -> None:
    """Once its teammate has failed, the commander no longer drives to meeting points (alone it did,
    for nothing)."""
    config = TeamConfig(robots=2, strategy=Strategy.RENDEZVOUS, explore_period=40.0, failures=(Failure(1, 30.0),))
    team = TeamSimulator(office(2), team=config, rng=np.random.default_rng(2))
    assert team.rendezvous is not None
    rng = np.random.default_rng(0)
    while (index := team.next_decision()) is not None:
        assert team.robots[0].phase is Phase.EXPLORE or team.robots[1].failed_at is None
        team.assign(index, POLICY.rank(team.context(index), rng))
    assert team.robots[1].failed_at is not None and team.done
    assert team.rendezvous.point is None and not team.rendezvous.meetings  # the first meeting was due at 40 s


def test_a_failed_robot_stops_and_the_others_finish() -> None:
    healthy = team_episode(0, 3, "coordinated")
    failing = team_episode(0, 3, "coordinated", (Failure(2, healthy.sim_time_s / 2),))
    stopped = failing.failed_at_s[2]
    assert stopped is not None and healthy.sim_time_s / 2 <= stopped <= healthy.sim_time_s / 2 + 0.6
    assert failing.failed_at_s[:2] == (None, None)
    assert failing.done and failing.coverage >= 0.99
    assert failing.robot_path_lengths_m[2] < healthy.robot_path_lengths_m[2]


def test_what_a_failed_robot_had_not_shared_is_lost() -> None:
    team = TeamConfig(robots=2, comm_range=0.0, failures=(Failure(1, 40.0),))  # they never share
    result = run_team_episode(office(1), POLICY, team=team, seed=1)
    fell = np.flatnonzero(np.diff(result.coverage_curve) < 0)
    assert len(fell) == 1  # the team's coverage fell once: when robot 1 failed
    assert 40.0 <= result.coverage_times_s[fell[0] + 1] <= 41.0 + 1e-9  # sim time sums ticks: float noise
    assert result.end_reason in ("explored", "unreachable") and result.coverage >= 0.99  # robot 0 saw it all again


def test_a_failed_robot_is_mapped_where_it_stands() -> None:
    """The teammates' laser filter kept a failed robot out of their maps as if it were passing: the
    cells under it stayed unknown for good, and the episode ended ``unreachable`` with its frontier
    the only one left (rooms 1, rendezvous, robot 1 failing at 60 s: 482 s; now explored in 365 s)."""
    team = TeamConfig(robots=3, strategy=Strategy.RENDEZVOUS, failures=(Failure(1, 60.0),))
    result = run_team_episode(generate_world("rooms", 1), NearestFrontier(), team=team, seed=1)
    assert result.failed_at_s[1] is not None and result.end_reason == "explored", result.frontiers_left


def test_space_a_teammate_mapped_is_not_left_unseen() -> None:
    """Robot 0 gave up on a frontier whose unseen cells robot 2 mapped after their last meeting
    (they share nothing between meetings): the team's episode ended ``unreachable`` with 0.0575 m²
    left "unseen" that the team knew, each robot's frontiers judged on its own map alone."""
    team = TeamConfig(robots=3, strategy=Strategy.RENDEZVOUS, comm_range=0.0, failures=(Failure(1, 60.0),))
    result = run_team_episode(generate_world("cave", 0), NearestFrontier(), team=team, seed=0)
    assert result.end_reason == "explored" and result.unknown_left_m2 == 0.0
    assert result.team_map is not None
    for frontier in result.frontiers_left:  # what is left is unseen by every robot
        assert frontier.unknown_cells > 0
        assert (result.team_map.data.ravel()[frontier.unseen_cells] == CellState.UNKNOWN).all()


def test_robots_wider_than_the_default_spacing_start_side_by_side() -> None:
    """A team of robots 0.6 m across could not start: the start spacing was 0.5 m, fixed."""
    config = SimConfig(robot=RobotConfig(radius=0.3))
    team = TeamSimulator(generate_world("rooms", 0), config, TeamConfig(robots=3), np.random.default_rng(0))
    xy = [robot.xy for robot in team.robots]
    assert min(math.dist(a, b) for i, a in enumerate(xy) for b in xy[i + 1 :]) >= 0.7 - 1e-9
    assert TeamConfig().spacing_for(SimConfig().robot.radius) == 0.5  # the TurtleBot's teams start as before
    with pytest.raises(ConfigError, match="diameter"):  # a spacing asked for is kept, and checked
        TeamSimulator(generate_world("rooms", 0), config, TeamConfig(robots=3, start_spacing=0.5))


def test_random_failures_are_seeded() -> None:
    team = TeamConfig(robots=3, failures=(Failure(None, None),), random_failure_horizon=100.0)
    draws = [TeamSimulator(office(0), team=team, rng=np.random.default_rng(s)) for s in (7, 7, 8)]
    fails = [[r.fail_at for r in t.robots] for t in draws]
    assert fails[0] == fails[1] != fails[2]
    assert sum(math.isfinite(f) for f in fails[0]) == 1 and all(f <= 100.0 for f in fails[0] if math.isfinite(f))


def test_frontier_request_answers_in_the_robots_map_frame() -> None:
    world = office(6)
    team = TeamSimulator(world, team=TeamConfig(robots=2), rng=np.random.default_rng(6))
    answer = frontier_request(team, 1)
    assert answer.frame == "robot_1/map" and 1 <= len(answer.frontiers) <= 10 and answer.weight == 0.75
    start = team.robots[1].sim.world.start
    centres = team.robots[1].sim.frontiers().centers
    for f in answer.frontiers:
        c, s = math.cos(start.theta), math.sin(start.theta)
        x, y = start.x + c * f.x - s * f.y, start.y + s * f.x + c * f.y
        assert np.hypot(centres[:, 0] - x, centres[:, 1] - y).min() < 1e-9
    assert len(frontier_request(team, 0, top_k=3).frontiers) <= 3
    with pytest.raises(ConfigError, match="no robot 2"):
        frontier_request(team, 2)
    team.fail(team.robots[0])
    with pytest.raises(ConfigError, match="robot 0 failed"):
        frontier_request(team, 0)


def test_more_robots_than_start_room_is_refused() -> None:
    data = np.full((12, 12), CellState.FREE, np.int8)
    data[[0, -1], :] = CellState.OCCUPIED
    data[:, [0, -1]] = CellState.OCCUPIED
    world = make_world(OccupancyGrid(data, 0.05), "closet", start=Pose(0.3, 0.3, 0.0))
    with pytest.raises(ConfigError, match="room for only 1 robot"):
        team_starts(world, 2, 0.105, 0.5)
    with pytest.raises(ConfigError, match="closet"):
        TeamSimulator(world, team=TeamConfig(robots=3))


def test_team_starts_are_spaced_and_free() -> None:
    world = office(0)
    poses = team_starts(world, 8, 0.105, 0.5)
    assert poses[0] == world.start
    xy = np.array([(p.x, p.y) for p in poses])
    d = np.hypot(xy[:, None, 0] - xy[None, :, 0], xy[:, None, 1] - xy[None, :, 1]) + np.eye(8) * 9
    assert d.min() >= 0.5 - 1e-9


def test_overlap_counts_cells_seen_by_more_than_one() -> None:
    explorable = np.ones((2, 2), np.bool_)
    a = np.array([[True, True], [False, False]])
    b = np.array([[True, False], [True, False]])
    assert overlap_share([a, b], explorable) == pytest.approx(1 / 3)
    assert overlap_share([a], explorable) == 0.0


def test_a_frontier_both_robots_left_is_counted_once() -> None:
    """Two robots that shared their maps end beside the same slot: its frontiers were listed once
    per robot, and the unseen area left twice what it is."""
    grid, start = slot_world()
    team = TeamConfig(robots=2, strategy=Strategy.COORDINATED)
    result = run_team_episode(make_world(grid, "slot", start=start), NearestFrontier(), team=team, seed=0)
    keys = [(f.x, f.y, f.cells) for f in result.frontiers_left]
    assert result.end_reason == "unreachable" and keys and len(set(keys)) == len(keys), keys
    unseen = np.unique(np.concatenate([f.unseen_cells for f in result.frontiers_left]))
    assert result.unknown_left_m2 == pytest.approx(unseen.size * grid.resolution**2)


@pytest.mark.parametrize("strategy", ["uncoordinated", "coordinated", "rendezvous"])
def test_team_maps_hold_no_more_stray_walls_than_one_robots(strategy: str) -> None:
    """Walls in the merged map farther than 2 cells from any true wall: a single robot's map holds
    0-4 of them; with the merge rule occupied > free > unknown this 3-robot team's held 57-425."""
    result = team_episode(1, 3, strategy)
    world = office(1)
    near_wall = ndimage.binary_dilation(world.grid.data == CellState.OCCUPIED, iterations=2)
    merged = result.team_map
    top, left = world.grid.world_to_cell(*merged.cell_to_world(0, 0))
    near = near_wall[top : top + merged.height, left : left + merged.width]
    assert int(np.count_nonzero((merged.data == CellState.OCCUPIED) & ~near)) <= 10
