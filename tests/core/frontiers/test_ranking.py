"""Tests of frontier_rl.core.frontiers.ranking: eq. 3.1 by hand, explore_lite's cost, the classic orders."""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
import pytest

from frontier_rl.checked_values import check_weight
from frontier_rl.core.frontiers.detection import Frontiers
from frontier_rl.core.frontiers.ranking import (
    ExploreLiteParams,
    explore_lite_cost,
    information_gain_cost,
    largest_cost,
    nearest_cost,
    normalise,
    random_cost,
    rank,
    weighted_cost,
)
from frontier_rl.core.world.grid import CellState, OccupancyGrid
from frontier_rl.errors import ConfigError

Make = Callable[..., Frontiers]
FREE, OCC, UNKNOWN = CellState.FREE.value, CellState.OCCUPIED.value, CellState.UNKNOWN.value
GRID = OccupancyGrid(np.zeros((10, 10), np.int8), 0.05)


def hand_frontiers(make: Make, distances: list[float], sizes: list[int], res: float = 0.05) -> Frontiers:
    grid = OccupancyGrid(np.zeros((10, 10), np.int8), res)
    centers = [[d, 0.0] for d in distances]
    return make(grid, centers, sizes, distances)


# ------------------------------------------------------------------------------------ normalise
@pytest.mark.parametrize(
    ("values", "expected"),
    [
        ([2.0, 4.0, 6.0], [0.0, 0.5, 1.0]),
        ([5.0, -5.0, 0.0], [1.0, 0.0, 0.5]),
        ([3.0, 3.0, 3.0], [0.0, 0.0, 0.0]),
        ([7.0], [0.0]),
        ([], []),
    ],
)
def test_normalise(values: list[float], expected: list[float]) -> None:
    out = normalise(np.array(values, dtype=np.float64))
    assert out.dtype == np.float64
    np.testing.assert_allclose(out, expected, rtol=0, atol=1e-12)


def test_normalise_accepts_integers() -> None:
    np.testing.assert_allclose(normalise(np.array([10, 20, 40])), [0, 1 / 3, 1])


# -------------------------------------------------------------------------------------- eq. 3.1
def test_weighted_cost_by_hand(frontiers_from: Make) -> None:
    f = hand_frontiers(frontiers_from, [1.0, 2.0, 3.0], [10, 30, 20])
    # d = [0, 0.5, 1], g = [0, 1, 0.5]
    np.testing.assert_allclose(weighted_cost(f, 0.75), [0.25, 0.375, 0.875])
    np.testing.assert_allclose(weighted_cost(f, 0.5), [0.5, 0.25, 0.75])
    np.testing.assert_allclose(weighted_cost(f, 0.0), [1.0, 0.0, 0.5])
    np.testing.assert_allclose(weighted_cost(f, 1.0), [0.0, 0.5, 1.0])


@pytest.mark.parametrize("seed", range(5))
def test_weight_zero_is_largest_first_and_one_is_nearest_first(frontiers_from: Make, seed: int) -> None:
    rng = np.random.default_rng(seed)
    n = 12
    distances = rng.permutation(n) * 0.5 + 0.3  # distinct
    sizes = rng.permutation(n) + 5
    f = hand_frontiers(frontiers_from, distances.tolist(), sizes.tolist())
    np.testing.assert_array_equal(rank(weighted_cost(f, 0.0)), np.argsort(-sizes, kind="stable"))
    np.testing.assert_array_equal(rank(weighted_cost(f, 1.0)), np.argsort(distances, kind="stable"))
    for w in (0.0, 0.25, 0.75, 1.0):
        d = (distances - distances.min()) / (distances.max() - distances.min())
        g = (sizes - sizes.min()) / (sizes.max() - sizes.min())
        np.testing.assert_allclose(weighted_cost(f, w), w * d + (1 - w) * (1 - g), atol=1e-12)


def test_weighted_cost_with_one_frontier_is_zero_or_one_minus_w(frontiers_from: Make) -> None:
    f = hand_frontiers(frontiers_from, [2.0], [9])
    np.testing.assert_allclose(weighted_cost(f, 0.3), [0.7])  # d = g = 0 when all are equal


@pytest.mark.parametrize("weight", [-0.01, 1.0000001, 1.5, -3, math.nan, math.inf, -math.inf])
def test_weight_outside_0_1_raises_config_error_naming_it(frontiers_from: Make, weight: float) -> None:
    f = hand_frontiers(frontiers_from, [1.0, 2.0], [5, 6])
    with pytest.raises(ConfigError, match=repr(weight).replace(".", r"\.")):
        weighted_cost(f, weight)
    with pytest.raises(ConfigError, match=repr(weight).replace(".", r"\.")):
        check_weight(weight)


@pytest.mark.parametrize("weight", [0, 0.0, 0.75, 1, np.float32(0.5)])
def test_check_weight_accepts_the_closed_interval(weight: float) -> None:
    assert check_weight(weight) == float(weight)


# --------------------------------------------------------------------------------- explore_lite
def test_explore_lite_defaults() -> None:
    p = ExploreLiteParams()
    assert (p.potential_scale, p.gain_scale, p.min_frontier_size) == (3.0, 1.0, 0.75)


def test_explore_lite_cost_by_hand_and_small_frontiers_left_out(frontiers_from: Make) -> None:
    # at 0.05 m, 15 cells = 0.75 m is the smallest frontier explore_lite keeps
    sizes = [14, 15, 40, 4]
    min_d = [0.1, 1.0, 2.0, 0.0]
    f = frontiers_from(GRID, [[0, 0]] * 4, sizes, [5.0] * 4, min_d)
    cost = explore_lite_cost(f)
    assert math.isinf(cost[0]) and math.isinf(cost[3])
    assert cost[1] == pytest.approx(3.0 * 1.0 - 15 * 0.05)
    assert cost[2] == pytest.approx(3.0 * 2.0 - 40 * 0.05)
    assert rank(cost).tolist() == [1, 2]  # 2.25 < 4.0; the small ones are left out


def test_explore_lite_uses_the_distance_to_the_nearest_cell_not_the_centre(frontiers_from: Make) -> None:
    f = frontiers_from(GRID, [[0, 0]] * 2, [20, 20], [1.0, 9.0], [5.0, 0.5])
    assert rank(explore_lite_cost(f)).tolist() == [1, 0]


def test_explore_lite_custom_params(frontiers_from: Make) -> None:
    f = frontiers_from(GRID, [[0, 0]] * 2, [10, 30], [0.0] * 2, [1.0, 2.0])
    p = ExploreLiteParams(potential_scale=1.0, gain_scale=2.0, min_frontier_size=0.5)
    np.testing.assert_allclose(explore_lite_cost(f, p), [1.0 - 2 * 0.5, 2.0 - 2 * 1.5])


# ------------------------------------------------------------------------------- other orders
def test_nearest_and_largest_orders(frontiers_from: Make) -> None:
    f = hand_frontiers(frontiers_from, [3.0, 1.0, 2.0, 0.5], [10, 40, 20, 5])
    assert rank(nearest_cost(f)).tolist() == [3, 1, 2, 0]
    assert rank(largest_cost(f)).tolist() == [1, 2, 0, 3]
    np.testing.assert_array_equal(nearest_cost(f), [3.0, 1.0, 2.0, 0.5])


def test_information_gain_order(frontiers_from: Make) -> None:
    # Two unknown pockets seen from two centres: 8 unknown cells on the left, 2 on the right
    data = np.full((3, 16), OCC, np.int8)
    data[1, 1:9] = UNKNOWN  # left pocket: cells (1, 1..8)
    data[1, 9] = FREE  # centre A
    data[1, 10] = OCC
    data[1, 11] = FREE  # centre B
    data[1, 12:14] = UNKNOWN  # right pocket: cells (1, 12..13)
    grid = OccupancyGrid(data, 0.1)
    a, b = grid.cell_to_world(1, 9), grid.cell_to_world(1, 11)
    f = frontiers_from(grid, [b, a], [5, 5], [1.0, 1.0])
    assert f.information_gain(5.0).tolist() == [2, 8]
    cost = information_gain_cost(f, sensor_range=5.0, distance_decay=0.0)
    np.testing.assert_allclose(cost, [-2.0, -8.0])
    assert rank(cost).tolist() == [1, 0]
    # a distance discount can reverse it: -8 exp(-2 * 1) > -2 exp(-2 * 0) when B is right here
    g = frontiers_from(grid, [b, a], [5, 5], [0.0, 1.0])
    cost = information_gain_cost(g, sensor_range=5.0, distance_decay=2.0)
    np.testing.assert_allclose(cost, [-2.0, -8.0 * math.exp(-2.0)])
    assert rank(cost).tolist() == [0, 1]


@pytest.mark.parametrize("decay", [-0.1, math.nan, math.inf])
def test_information_gain_cost_rejects_a_bad_decay(frontiers_from: Make, decay: float) -> None:
    f = hand_frontiers(frontiers_from, [1.0], [5])
    with pytest.raises(ConfigError, match=repr(decay).replace(".", r"\.")):
        information_gain_cost(f, 3.5, decay)


def test_random_order_is_reproducible_and_a_permutation(frontiers_from: Make) -> None:
    f = hand_frontiers(frontiers_from, list(np.arange(20.0)), [5] * 20)
    a = rank(random_cost(f, np.random.default_rng(3)))
    b = rank(random_cost(f, np.random.default_rng(3)))
    c = rank(random_cost(f, np.random.default_rng(4)))
    np.testing.assert_array_equal(a, b)
    assert sorted(a.tolist()) == list(range(20))
    assert not np.array_equal(a, c)


# --------------------------------------------------------------------------------------- rank
@pytest.mark.parametrize(
    ("costs", "expected"),
    [
        ([1.0, 0.0, 1.0, 0.0], [1, 3, 0, 2]),  # ties keep the frontier order
        ([2.0, 2.0, 2.0], [0, 1, 2]),
        ([3.0, math.inf, 1.0, math.inf], [2, 0]),  # inf is left out
        ([math.nan, 1.0, -math.inf], [1]),  # so are nan and -inf
        ([], []),
        ([math.inf], []),
    ],
)
def test_rank_is_stable_and_drops_non_finite(costs: list[float], expected: list[int]) -> None:
    out = rank(np.array(costs, dtype=np.float64))
    assert out.dtype == np.int64
    assert out.tolist() == expected


def test_rank_ties_in_eq_3_1_keep_the_frontier_order(frontiers_from: Make) -> None:
    f = hand_frontiers(frontiers_from, [1.0, 2.0, 1.0, 2.0], [10, 10, 10, 10])
    assert rank(weighted_cost(f, 0.5)).tolist() == [0, 2, 1, 3]
