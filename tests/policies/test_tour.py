"""Tests of frontier_rl.policies.tour: the first stop of the shortest open tour over the frontiers."""

from __future__ import annotations

import numpy as np
import pytest

from frontier_rl.core.sim.candidates import reachable_frontiers
from frontier_rl.core.sim.config import SimConfig
from frontier_rl.core.sim.episode import DecisionContext, run_episode
from frontier_rl.core.world.catalog import generate_world
from frontier_rl.core.world.grid import CellState, OccupancyGrid
from frontier_rl.core.world.robot import Pose
from frontier_rl.observation.frontier_table import (
    FEATURE_BOUND,
    UNREACHABLE_COST_M,
    frontier_path_costs,
    tour_regret,
)
from frontier_rl.policies import FrontierTour, make_policy


def _corridor() -> tuple[OccupancyGrid, Pose]:
    """A 1 m wide corridor (rows 10-29, 0.05 m cells) whose left end opens into unknown space 2.1 m
    from the robot, with three openings in its top wall 1.5, 2.5 and 3.5 m to the robot's right."""
    data = np.full((40, 200), CellState.UNKNOWN, np.int8)
    data[8:32, 18:172] = CellState.OCCUPIED
    data[10:30, 18:170] = CellState.FREE  # column 18, the left end, against the unknown beyond
    for x in (1.5, 2.5, 3.5):
        col = 60 + round(x / 0.05)
        data[8:10, col - 4 : col + 5] = CellState.FREE  # a gap in the top wall, unknown above it
    return OccupancyGrid(data, 0.05), Pose(60 * 0.05 + 0.025, 20 * 0.05 + 0.025)


def test_tour_clears_the_lone_frontier_behind_before_the_row_ahead() -> None:
    grid, pose = _corridor()
    config = SimConfig()
    costmap, _, frontiers = reachable_frontiers(grid, pose, config)
    assert len(frontiers) == 4
    context = DecisionContext(
        grid, frontiers, pose, 0.0, config.lidar.max_range, costmap, robot_radius=config.robot.radius
    )
    rng = np.random.default_rng(0)
    behind = int(np.argmin(frontiers.centers[:, 0]))
    nearest = make_policy("nearest").rank(context, rng).order
    order = FrontierTour().rank(context, rng).order
    assert nearest[0] != behind  # the first opening ahead is nearer (1.5 m against 2.1 m)
    assert order[0] == behind  # but going there first leaves it 5.5 m behind the last opening
    assert order[1:].tolist() == sorted(order[1:].tolist(), key=lambda i: frontiers.centers[i, 0])
    assert sorted(order.tolist()) == list(range(len(frontiers)))


def test_model_7s_tour_column_is_zero_for_the_tours_first_stop() -> None:
    grid, pose = _corridor()
    costmap, _, frontiers = reachable_frontiers(grid, pose, SimConfig())
    behind = int(np.argmin(frontiers.centers[:, 0]))
    regret = tour_regret(costmap, pose, frontiers, SimConfig().robot.radius)
    assert regret[behind] == 0.0
    others = np.delete(regret, behind)
    assert np.all((others > 0.05) & (others < FEATURE_BOUND))  # each costs the tour more than 0.5 m
    assert np.all(tour_regret(costmap, pose, frontiers.subset(np.arange(1)), SimConfig().robot.radius) == 0.0)


def test_a_robot_against_a_wall_ranks_by_its_paths_from_where_it_sets_out() -> None:
    """A robot 0.05 m from the corridor's wall stands on a cell the path-cost searches could not
    leave: every frontier cost "no path" (model 7's table all 100 m, the tour's order by straight
    distance), though the planner backs the robot away from the wall and has a path to each."""
    grid, middle = _corridor()
    config = SimConfig()
    costmap, _, frontiers = reachable_frontiers(grid, middle, config)
    against = Pose(middle.x, 10 * 0.05 + 0.025)  # row 10, next to the wall's row 9
    assert not costmap.traversable[grid.world_to_cell(against.x, against.y)]
    costs = frontier_path_costs(costmap, against, frontiers, config.robot.radius)
    assert np.all(costs < UNREACHABLE_COST_M)
    from_middle = frontier_path_costs(costmap, middle, frontiers, config.robot.radius)
    assert np.array_equal(np.argsort(costs), np.argsort(from_middle))  # 0.5 m off the middle, in the wall's cost
    assert np.all(np.abs(costs - from_middle) < 1.0)
    context = DecisionContext(
        grid, frontiers, against, 0.0, config.lidar.max_range, costmap, robot_radius=config.robot.radius
    )
    assert FrontierTour().rank(context, np.random.default_rng(0)).order[0] == np.argmin(frontiers.centers[:, 0])
    assert np.all(tour_regret(costmap, against, frontiers, config.robot.radius) < FEATURE_BOUND)


def test_tour_ranks_every_frontier_when_there_are_more_than_it_tours() -> None:
    grid, pose = _corridor()
    config = SimConfig()
    costmap, _, frontiers = reachable_frontiers(grid, pose, config)
    context = DecisionContext(
        grid, frontiers, pose, 0.0, config.lidar.max_range, costmap, robot_radius=config.robot.radius
    )
    order = FrontierTour(max_frontiers=2).rank(context, np.random.default_rng(0)).order
    assert sorted(order.tolist()) == list(range(len(frontiers)))


def test_tour_without_a_costmap_falls_back_to_nearest() -> None:
    grid, pose = _corridor()
    config = SimConfig()
    _, _, frontiers = reachable_frontiers(grid, pose, config)
    context = DecisionContext(grid, frontiers, pose, 0.0, config.lidar.max_range, robot_radius=config.robot.radius)
    rng = np.random.default_rng(0)
    assert FrontierTour().rank(context, rng).order.tolist() == make_policy("nearest").rank(context, rng).order.tolist()


def test_tour_bounds_are_checked() -> None:
    with pytest.raises(ValueError, match="max_frontiers"):
        FrontierTour(max_frontiers=0)
    with pytest.raises(ValueError, match="max_frontiers"):
        FrontierTour(max_frontiers=17)


def test_tour_explores_an_office_to_the_end_and_is_deterministic() -> None:
    world = generate_world("office", 1)
    first = run_episode(world, make_policy("tour"), seed=1)
    again = run_episode(world, make_policy("tour"), seed=1)
    assert first.end_reason == "explored"
    assert first.sim_time_s == again.sim_time_s and first.path_length_m == again.path_length_m
