"""Tests of the full-knowledge ``oracle``: the coverage tour (frontier_rl.core.navigation.coverage_tour) and the
policy that drives it (frontier_rl.policies.oracle)."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from numpy.typing import NDArray

from frontier_rl.core.frontiers.detection import detect_frontiers
from frontier_rl.core.navigation.costmap import Costmap
from frontier_rl.core.navigation.coverage_tour import CoverageTour, insertion_cover, plan_coverage_tour
from frontier_rl.core.navigation.path_costs import cost_field, descend, path_costs
from frontier_rl.core.navigation.tours import two_opt
from frontier_rl.core.navigation.viewpoints import coverage_targets, visibility
from frontier_rl.core.sim.config import SimConfig
from frontier_rl.core.sim.episode import DecisionContext, EpisodeAwarePolicy, run_episode
from frontier_rl.core.sim.metrics import EpisodeResult
from frontier_rl.core.world.catalog import generate_world
from frontier_rl.core.world.grid import CellState, OccupancyGrid
from frontier_rl.core.world.robot import Pose
from frontier_rl.core.world.worlds import World, make_world
from frontier_rl.errors import ConfigError
from frontier_rl.policies import POLICY_NAMES, OracleTour, make_policy

SEEDS = (0, 1, 2)  # office worlds raced against fixed:0.75

LIDAR = SimConfig().lidar
USABLE_RANGE_M = SimConfig().mapper.usable_range


@pytest.fixture(scope="module")
def office() -> World:
    return generate_world("office", 0)


@pytest.fixture(scope="module")
def tour(office: World) -> CoverageTour:
    return plan_coverage_tour(office)


@pytest.fixture(scope="module")
def true_costmap(office: World) -> Costmap:
    config = SimConfig()
    return Costmap.build(office.grid, config.robot, config.navigation)


@pytest.fixture(scope="module")
def oracle_runs() -> dict[int, EpisodeResult]:
    return {seed: run_episode(generate_world("office", seed), make_policy("oracle"), seed=seed) for seed in SEEDS}


def _start_cell(world: World) -> tuple[int, int]:
    return world.grid.world_to_cell(world.start.x, world.start.y)


def _length(order: list[int] | NDArray[np.int64], dist: NDArray[np.float64]) -> float:
    return float(sum(dist[a, b] for a, b in itertools.pairwise(order)))


# ------------------------------------------------------------------------------------ the tour
def test_tour_covers_nearly_all_of_the_office(office: World, tour: CoverageTour) -> None:
    assert tour.covered[office.explorable].mean() >= 0.995
    assert tour.coverable[office.explorable].mean() >= 0.999
    # everything the candidate viewpoints could see, up to the cover's small leftovers
    assert np.count_nonzero(tour.coverable & ~tour.covered) <= 10 * len(tour)
    assert not (tour.covered & ~coverage_targets(office)).any()
    assert 5 <= len(tour) <= 80  # a tour, not every candidate


def test_the_start_scan_is_part_of_the_cover(office: World, tour: CoverageTour) -> None:
    indptr, indices = visibility(
        office, SimConfig().lidar, SimConfig().mapper.usable_range, np.array([_start_cell(office)])
    )
    start_seen = indices[indptr[0] : indptr[1]]
    assert start_seen.size > 500
    assert tour.covered.reshape(-1)[start_seen].all()
    # no viewpoint is meant to reveal what the start saw, and the targets do not overlap
    targets = np.concatenate([t[:, 0] * office.grid.width + t[:, 1] for t in tour.targets])
    assert np.unique(targets).size == targets.size
    assert not np.isin(targets, start_seen).any()
    assert np.union1d(targets, start_seen).size == np.count_nonzero(tour.covered)


def test_viewpoints_are_reachable_traversable_cells(office: World, tour: CoverageTour, true_costmap: Costmap) -> None:
    rows, cols = tour.cells[:, 0], tour.cells[:, 1]
    assert true_costmap.traversable[rows, cols].all()
    assert np.isfinite(true_costmap.cost_to_go(_start_cell(office))[rows, cols]).all()
    np.testing.assert_allclose(tour.viewpoints, office.grid.cells_to_world(tour.cells))
    assert all(t.shape[0] >= 10 for t in tour.targets)  # each adds what it was chosen for


def test_tour_starts_at_the_start_and_is_no_longer_than_nearest_neighbour(
    office: World, tour: CoverageTour, true_costmap: Costmap
) -> None:
    nodes = np.concatenate(([_start_cell(office)], tour.cells))
    dist = path_costs(true_costmap, nodes)
    planned = _length(list(range(len(nodes))), dist)
    assert tour.length_m == pytest.approx(planned, rel=0.02)  # from the start, in this order
    order = [0]  # the unoptimised nearest-neighbour order of the same viewpoints
    while len(order) < len(nodes):
        left = [k for k in range(len(nodes)) if k not in order]
        order.append(min(left, key=lambda k: dist[order[-1], k]))
    assert planned <= _length(order, dist) + 1e-6
    improved = two_opt(np.array(order, np.int64), dist)
    assert improved[0] == 0
    assert sorted(improved.tolist()) == list(range(len(nodes)))
    assert _length(improved, dist) <= _length(order, dist) + 1e-9


def test_two_opt_untangles_a_crossing() -> None:
    points = np.array([[0.0, 0.0], [1.0, 1.0], [1.0, 0.0], [2.0, 1.0], [2.0, 0.0]])
    dist = np.hypot(points[:, None, 0] - points[None, :, 0], points[:, None, 1] - points[None, :, 1])
    order = two_opt(np.arange(5, dtype=np.int64), dist)
    assert order[0] == 0
    assert _length(order, dist) < _length(list(range(5)), dist) - 0.5


def test_path_costs_match_the_planner(office: World, true_costmap: Costmap, tour: CoverageTour) -> None:
    start = _start_cell(office)
    reference = true_costmap.cost_to_go(start)
    field = cost_field(true_costmap, start)
    np.testing.assert_array_equal(np.isfinite(field), np.isfinite(reference))
    np.testing.assert_allclose(field[np.isfinite(field)], reference[np.isfinite(reference)], rtol=1e-12)
    costs = path_costs(true_costmap, np.array([start]), tour.cells)[0]
    np.testing.assert_allclose(costs, reference[tour.cells[:, 0], tour.cells[:, 1]], rtol=1e-12)
    target = (int(tour.cells[-1, 0]), int(tour.cells[-1, 1]))
    for field_to_target in (cost_field(true_costmap, target), cost_field(true_costmap, target, until=start)):
        path = descend(field_to_target, start)
        assert tuple(path[0]) == start and tuple(path[-1]) == target
        assert (np.abs(np.diff(path, axis=0)).max(axis=1) == 1).all()  # 8-connected steps
        assert true_costmap.traversable[path[1:, 0], path[1:, 1]].all()


def test_visibility_stops_at_walls_and_where_beams_graze_them() -> None:
    data = np.full((60, 60), CellState.FREE, np.int8)
    data[[0, -1], :] = CellState.OCCUPIED
    data[:, [0, -1]] = CellState.OCCUPIED
    data[:45, 30] = CellState.OCCUPIED  # a wall with a gap above it
    world = make_world(OccupancyGrid(data, 0.05), "wall", start=Pose(0.5, 0.5, 0.0))

    def seen_from(cell: tuple[int, int], margin_cells: float = 1.0) -> NDArray[np.bool_]:
        indptr, indices = visibility(
            world, SimConfig().lidar, SimConfig().mapper.usable_range, np.array([cell]), margin_cells=margin_cells
        )
        seen = np.zeros(data.size, np.bool_)
        seen[indices[indptr[0] : indptr[1]]] = True
        return seen.reshape(data.shape)

    seen = seen_from((10, 10))
    assert seen[10, 10] and seen[10, 25]  # in the open
    assert seen[10, 30]  # the wall cell a beam hits
    assert not seen[10:40, 31:].any()  # behind the wall
    assert not (seen & ~coverage_targets(world)).any()  # only target cells are reported
    # Along the wall face, one cell off it, beams only graze the wall: not counted as seen,
    # unless the margin is switched off.
    assert not seen_from((10, 29))[40, 29]
    assert seen_from((10, 29), margin_cells=0.0)[40, 29]


# --------------------------------------------------------------------------------- the policy
def test_oracle_is_registered() -> None:
    assert "oracle" in POLICY_NAMES
    policy = make_policy("oracle")
    assert isinstance(policy, OracleTour)
    assert isinstance(policy, EpisodeAwarePolicy)
    assert policy.name == "oracle"


def test_rank_without_begin_episode_raises_config_error() -> None:
    data = np.full((30, 60), CellState.UNKNOWN, np.int8)
    data[5:10, 2:20] = CellState.FREE
    grid = OccupancyGrid(data, 0.05)
    context = DecisionContext(
        grid, detect_frontiers(grid, Pose(0.5, 0.4)), Pose(0.5, 0.4), 0.0, 3.5, robot_radius=0.105
    )
    with pytest.raises(ConfigError, match="true map"):
        make_policy("oracle").rank(context, np.random.default_rng(0))


def test_bad_settings_raise_config_error() -> None:
    with pytest.raises(ConfigError, match="leg_m"):
        OracleTour(leg_m=0.0)
    with pytest.raises(ConfigError, match="leftover_cells"):
        OracleTour(leftover_cells=-1)


def test_oracle_explores_the_office_to_the_end(oracle_runs: dict[int, EpisodeResult]) -> None:
    for seed, result in oracle_runs.items():
        assert result.done and not result.truncated, seed
        assert result.coverage >= 0.99, seed


def test_oracle_is_deterministic(oracle_runs: dict[int, EpisodeResult]) -> None:
    again = run_episode(generate_world("office", 0), make_policy("oracle"), seed=0)
    first = oracle_runs[0]
    assert again.sim_time_s == first.sim_time_s
    assert again.decisions == first.decisions
    np.testing.assert_array_equal(again.trajectory, first.trajectory)


def test_oracle_is_faster_than_the_thesis_baseline(oracle_runs: dict[int, EpisodeResult]) -> None:
    baseline = [run_episode(generate_world("office", s), make_policy("fixed:0.75"), seed=s).sim_time_s for s in SEEDS]
    oracle = [oracle_runs[s].sim_time_s for s in SEEDS]
    assert np.mean(oracle) < 0.9 * np.mean(baseline)


def test_viewpoints_beyond_the_search_reach_are_placed_by_gain_with_known_costs() -> None:
    # a 70 m corridor: the two far viewpoints are outside a 15 m search from the start
    data = np.full((31, 1401), CellState.FREE, np.int8)
    data[[0, -1], :] = CellState.OCCUPIED
    data[:, [0, -1]] = CellState.OCCUPIED
    world = make_world(OccupancyGrid(data, 0.05), "corridor", start=Pose(0.5, 0.775, 0.0))
    config = SimConfig()
    costmap = Costmap.build(world.grid, config.robot, config.navigation)
    cand = np.array([[15, 10], [15, 400], [15, 500]], np.int64)
    route, dist = insertion_cover(costmap, cand, visibility(world, LIDAR, USABLE_RANGE_M, cand), 10, 3.0, reach_m=15.0)
    assert sorted(route) == [0, 1, 2] and route[0] == 0
    assert np.all(dist < 1e6), "every edge of the route has a searched path cost"
    assert dist[route.index(0), route.index(1)] == pytest.approx(19.5, abs=0.5)  # 390 cells of 0.05 m
