"""Tests of frontier_rl.core.navigation.tours: exact tours over a few stops."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from numpy.typing import NDArray

from frontier_rl.core.navigation.costmap import Costmap
from frontier_rl.core.navigation.group_costs import block_factor
from frontier_rl.core.navigation.path_costs import path_costs
from frontier_rl.core.navigation.tours import costs_to_stops, first_stop_costs, open_tour, stop_costs
from frontier_rl.core.sim.config import SimConfig
from frontier_rl.core.world.grid import CellState, OccupancyGrid


def _length(order: NDArray[np.int64], dist: NDArray[np.float64]) -> float:
    stops = [0, *(int(k) + 1 for k in order)]
    return float(sum(dist[a, b] for a, b in itertools.pairwise(stops)))


@pytest.mark.parametrize("n", [1, 2, 3, 5, 7])
def test_open_tour_is_the_shortest_of_all_orders(n: int) -> None:
    rng = np.random.default_rng(n)
    for _ in range(5):
        points = rng.uniform(0, 10, (n + 1, 2))
        dist = np.linalg.norm(points[:, None] - points[None], axis=-1)
        order = open_tour(dist)
        assert sorted(order.tolist()) == list(range(n))
        best = min(_length(np.array(p), dist) for p in itertools.permutations(range(n)))
        assert _length(order, dist) == pytest.approx(best)


@pytest.mark.parametrize("n", [1, 2, 4, 6])
def test_first_stop_costs_are_the_shortest_tours_with_that_stop_first(n: int) -> None:
    rng = np.random.default_rng(10 + n)
    points = rng.uniform(0, 10, (n + 1, 2))
    dist = np.linalg.norm(points[:, None] - points[None], axis=-1)
    costs = first_stop_costs(dist)
    for k in range(n):
        best = min(_length(np.array(p), dist) for p in itertools.permutations(range(n)) if p[0] == k)
        assert costs[k] == pytest.approx(best)
    assert costs.min() == pytest.approx(_length(open_tour(dist), dist))


def _large_room() -> Costmap:
    """A 20 m × 20 m room (400 × 400 cells: searched on blocks) split by a wall with one door."""
    data = np.full((400, 400), CellState.FREE, np.int8)
    data[[0, -1], :] = data[:, [0, -1]] = CellState.OCCUPIED
    data[:, 200] = CellState.OCCUPIED
    data[300:320, 200] = CellState.FREE  # a 1 m door near the bottom
    config = SimConfig()
    return Costmap.build(OccupancyGrid(data, 0.05), config.robot, config.navigation)


def test_stop_costs_on_blocks_estimate_the_exact_costs() -> None:
    costmap, radius = _large_room(), SimConfig().robot.radius
    assert block_factor(costmap.grid.shape, costmap.grid.resolution, radius) > 1
    start = (50, 50)
    goals = np.array([[50, 150], [50, 250], [350, 350], [200, 100], [100, 300]], np.int64)
    estimate = stop_costs(costmap, start, goals, radius)
    exact = path_costs(costmap, np.concatenate(([start], goals)))
    exact = np.minimum(exact, exact.T)
    assert np.array_equal(estimate, estimate.T) and np.all(np.diag(estimate) == 0)
    off = ~np.eye(len(goals) + 1, dtype=bool)
    assert np.all(np.abs(estimate[off] - exact[off]) <= 0.1 * exact[off] + 0.3)  # within 10 % and a block
    assert estimate[1, 2] > 2 * np.hypot(0, 100 * 0.05)  # across the wall: round by the door, as exact


def test_costs_to_stops_on_blocks_find_the_wanted_cheapest() -> None:
    costmap, radius = _large_room(), SimConfig().robot.radius
    goals = np.array([[50, 150], [50, 250], [60, 60], [350, 350]], np.int64)
    costs = costs_to_stops(costmap, (50, 50), goals, radius, want=2)
    assert np.isfinite(costs[[0, 2]]).all() and np.isinf(costs[[1, 3]]).all()  # the two nearest only
    assert costs[2] < costs[0]


def test_costs_from_a_robot_in_a_gap_reach_both_sides() -> None:
    """A robot in a gap narrower than itself has paths to both rooms (it backs out either way); the
    costs from it had been "no path" to all, and from one way out, to the room behind it."""
    data = np.full((41, 40), CellState.FREE, np.int8)
    data[20, :] = CellState.OCCUPIED
    data[20, 18:22] = CellState.FREE
    config = SimConfig()
    costmap = Costmap.build(OccupancyGrid(data, 0.05), config.robot, config.navigation)
    goals = np.array([[5, 20], [35, 20], [5, 5]], np.int64)
    costs = costs_to_stops(costmap, (20, 20), goals, config.robot.radius, want=3)
    assert np.all(np.isfinite(costs))
    exact = [
        min(lead + path_costs(costmap, np.array([c]), goals[k : k + 1])[0, 0] for c, lead in costmap.set_out((20, 20)))
        for k in range(3)
    ]
    assert costs == pytest.approx(exact)
    assert abs(costs[0] - costs[1]) < 0.2  # the gap's middle: as far from either room
