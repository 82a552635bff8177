"""The audit before an episode gives up (issue 58): a goal the robot's map still has a way to gets
its tries again within a budget, and the frontiers left say whether the final map had a path."""

from __future__ import annotations

import numpy as np

from frontier_rl.core.frontiers.blacklist import AUDIT_BUDGET, Blacklist
from frontier_rl.core.sim.candidates import find_candidates
from frontier_rl.core.sim.config import SimConfig
from frontier_rl.core.sim.episode import run_episode
from frontier_rl.core.sim.simulator import ExplorationSimulator
from frontier_rl.core.world.grid import CellState, OccupancyGrid
from frontier_rl.core.world.robot import Pose
from frontier_rl.core.world.worlds import make_world
from frontier_rl.policies import make_policy
from tests.core.sim.test_completion import door_world

FREE = np.int8(CellState.FREE)
RES = 0.05
MAX_FAILURES = SimConfig().navigation.max_goal_failures


def test_the_audit_budget_lifts_goals_that_used_their_tries_once_more_and_then_never() -> None:
    state = np.full((40, 40), FREE, np.int8)
    bl = Blacklist(radius=0.25, max_failures=MAX_FAILURES, resolution=RES, origin=(0.0, 0.0))
    goal = np.array([[1.0, 1.0]])
    for _ in range(MAX_FAILURES):
        bl.fail(1.0, 1.0, state)
    bl.retry()
    assert bl.blocked(goal).all()  # used its tries
    bl.retry(AUDIT_BUDGET * MAX_FAILURES)
    assert not bl.blocked(goal).any()  # the audit's: as many again
    for _ in range(AUDIT_BUDGET * MAX_FAILURES - MAX_FAILURES):
        bl.fail(1.0, 1.0, state)
    bl.retry(AUDIT_BUDGET * MAX_FAILURES)
    assert bl.blocked(goal).all()  # the budget is spent: given up for good


def test_a_goal_reached_twice_in_vain_is_unrevealable_and_the_audit_leaves_it() -> None:
    state = np.full((40, 40), FREE, np.int8)
    bl = Blacklist(radius=0.25, max_failures=MAX_FAILURES, resolution=RES, origin=(0.0, 0.0))
    goal = np.array([[1.0, 1.0]])
    bl.fail(1.0, 1.0, state, reached=True)
    bl.retry()
    assert not bl.blocked(goal).any()  # one visit: tried again once, from wherever the robot then is
    bl.fail(1.0, 1.0, state, reached=True)
    assert bl.history_of(goal) == (MAX_FAILURES, True)
    bl.retry(AUDIT_BUDGET * MAX_FAILURES)
    assert bl.blocked(goal).all()  # the view it was chosen for revealed nothing, twice: not chased again
    bl.fail(2.0, 2.0, state)
    bl.fail(2.0, 2.0, state, reached=True)
    bl.retry(AUDIT_BUDGET * MAX_FAILURES)
    assert not bl.blocked(np.array([[2.0, 2.0]])).any()  # an abort and a visit: the audit tries it again


def test_a_frontier_that_reappears_elsewhere_keeps_its_history() -> None:
    state = np.full((40, 40), FREE, np.int8)
    bl = Blacklist(radius=0.25, max_failures=MAX_FAILURES, resolution=RES, origin=(0.0, 0.0))
    streak = np.column_stack((np.full(5, 1.025), 0.525 + RES * np.arange(5)))  # a frontier along x = 1 m
    bl.fail(0.6, 0.6, state, reached=True, frontier=streak)
    moved = streak + np.array([RES, 2 * RES])  # a cell to the side and two on: the same frontier, its goal 0.5 m away
    bl.fail(1.1, 0.6, state, reached=True, frontier=moved)
    assert len(bl.entries) == 1 and bl.entries[0].visits == 2
    assert bl.blocked(np.array([[0.6, 0.6], [1.1, 0.6], [1.6, 0.6]])).tolist() == [True, True, False]
    assert bl.history_of(moved + np.array([0.0, RES])) == (2, True)
    far = streak + np.array([0.5, 0.0])  # ten cells away: another frontier
    bl.fail(1.6, 0.6, state, frontier=far)
    assert len(bl.entries) == 2 and bl.history_of(far) == (1, False)


def _sim_on_two_rooms() -> ExplorationSimulator:
    grid, start = door_world(0.8)
    return ExplorationSimulator(make_world(grid, "two rooms", start=start), SimConfig(), np.random.default_rng(0))


def _fail_every_candidate(sim: ExplorationSimulator, times: int) -> None:
    goals = [sim.map().cell_to_world(*cell) for cell in sim.frontiers().goal_cells]
    for x, y in goals:
        for _ in range(times):
            sim.blacklist.fail(x, y, sim.mapper.state)
    sim.refresh()


def test_a_frontier_the_map_has_a_way_to_is_retried_after_its_tries_within_the_budget() -> None:
    sim = _sim_on_two_rooms()
    before = len(sim.frontiers())
    _fail_every_candidate(sim, MAX_FAILURES)
    assert len(sim.frontiers()) == before  # the audit gave them their tries again
    _fail_every_candidate(sim, AUDIT_BUDGET * MAX_FAILURES)
    assert sim.finished
    left = sim.frontiers_left()
    assert left and any(f.has_path for f in left)  # given up although the map has a way
    result = sim.result(0.0)
    assert result.end_reason == "unreachable"
    assert result.frontiers_with_path_left == sum(f.has_path for f in left) > 0
    assert result.summary()["frontiers_with_path_left"] == result.frontiers_with_path_left


def test_frontiers_behind_a_door_narrower_than_the_robot_have_no_path() -> None:
    grid, start = door_world(0.15)
    result = run_episode(make_world(grid, "door", start=start), make_policy("nearest"), seed=0)
    assert result.end_reason == "unreachable"
    assert result.frontiers_with_path_left == 0  # given up for want of a way, not after tries
    assert all(not f.has_path for f in result.frontiers_left)


def test_find_candidates_retries_within_the_audit_budget_only_when_nothing_else_is_left() -> None:
    data = np.full((60, 60), CellState.UNKNOWN, np.int8)
    data[:, :30] = FREE
    grid = OccupancyGrid(data, RES)
    pose = Pose(0.5, 1.5, 0.0)
    config = SimConfig()
    bl = Blacklist(0.25, MAX_FAILURES, RES, (0.0, 0.0))
    first = find_candidates(grid, pose, config, bl, data)
    for x, y in (grid.cell_to_world(*cell) for cell in first.frontiers.goal_cells):
        for _ in range(MAX_FAILURES):
            bl.fail(x, y, data)
    assert len(find_candidates(grid, pose, config, bl, data).frontiers) == len(first.frontiers)
    for x, y in (grid.cell_to_world(*cell) for cell in first.frontiers.goal_cells):
        for _ in range(AUDIT_BUDGET * MAX_FAILURES):
            bl.fail(x, y, data)
    assert len(find_candidates(grid, pose, config, bl, data).frontiers) == 0
