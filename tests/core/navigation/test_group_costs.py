"""Path costs to groups of cells (model 5's per-frontier path costs): exact against the cost
field and a window minimum, bounded by ``want``, and on blocks for large maps."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.typing import NDArray
from scipy import ndimage

from frontier_rl.core.navigation import group_costs
from frontier_rl.core.navigation.config import NavigationConfig
from frontier_rl.core.navigation.costmap import Costmap
from frontier_rl.core.navigation.group_costs import MAX_SEARCH_CELLS, block_factor, group_path_costs, max_block_factor
from frontier_rl.core.world.catalog import generate_world
from frontier_rl.core.world.grid import CellState, OccupancyGrid
from frontier_rl.core.world.robot import RobotConfig

REACH = 4
RADIUS = RobotConfig().radius


def costmap_of(data: NDArray[np.int8]) -> Costmap:
    return Costmap.build(OccupancyGrid(data, 0.05), RobotConfig(), NavigationConfig())


def reference(
    costmap: Costmap, start: tuple[int, int], cells: NDArray[np.int64], groups: NDArray[np.int64], n: int
) -> NDArray[np.float64]:
    """The definition: the cost field from ``start``, its minimum over a square window, the least
    of that over each group's cells."""
    field = costmap.cost_to_go(start)
    near = ndimage.minimum_filter(field, size=2 * REACH + 1, mode="constant", cval=np.inf).reshape(-1)
    out = np.full(n, np.inf)
    np.minimum.at(out, groups, near[cells])
    return out


def random_groups(rng: np.random.Generator, data: NDArray[np.int8], n: int) -> tuple[NDArray[np.int64], ...]:
    """``n`` groups of 1-40 cells each, drawn along random short lines of the map."""
    rows, cols = data.shape
    cells, groups = [], []
    for g in range(n):
        r, c = int(rng.integers(rows)), int(rng.integers(cols))
        length = int(rng.integers(1, 40))
        horizontal = rng.random() < 0.5
        rr = np.full(length, r) if horizontal else np.clip(np.arange(r, r + length), 0, rows - 1)
        cc = np.clip(np.arange(c, c + length), 0, cols - 1) if horizontal else np.full(length, c)
        cells.append(rr * cols + cc)
        groups.append(np.full(length, g))
    return np.concatenate(cells).astype(np.int64), np.concatenate(groups).astype(np.int64)


def a_map(seed: int) -> NDArray[np.int8]:
    """An office world's grid with an unknown band (passable at extra cost) and a walled-off box."""
    data = generate_world("office", seed).grid.data.copy()
    data[100:140, :] = np.where(data[100:140, :] == CellState.FREE, np.int8(CellState.UNKNOWN), data[100:140, :])
    data[20:40, 20:24] = CellState.OCCUPIED
    return data


@pytest.mark.parametrize("seed", range(5))
def test_exact_on_a_map_searched_cell_by_cell(seed: int) -> None:
    data = a_map(seed)
    costmap = costmap_of(data)
    assert block_factor(data.shape, 0.05, RADIUS) == 1
    rng = np.random.default_rng(seed)
    free = np.argwhere(costmap.traversable)
    row, col = free[rng.integers(len(free))]
    start = (int(row), int(col))
    cells, groups = random_groups(rng, data, 30)
    expected = reference(costmap, start, cells, groups, 30)
    costs, exhausted = group_path_costs(costmap, start, cells, groups, 30, REACH, RADIUS)
    if np.isinf(expected).any():  # a group it could not reach: the search ran out of cells
        assert exhausted
    np.testing.assert_array_equal(costs, expected)


@pytest.mark.parametrize("want", [1, 3, 8])
def test_want_gives_the_cheapest_groups_exactly_and_stops_early(want: int) -> None:
    data = a_map(7)
    costmap = costmap_of(data)
    rng = np.random.default_rng(want)
    free = np.argwhere(costmap.traversable)
    start = (int(free[0][0]), int(free[0][1]))
    cells, groups = random_groups(rng, data, 25)
    expected = reference(costmap, start, cells, groups, 25)
    costs, exhausted = group_path_costs(costmap, start, cells, groups, 25, REACH, RADIUS, want=want)
    found = np.isfinite(costs)
    assert not exhausted
    assert found.sum() >= want
    np.testing.assert_array_equal(costs[found], expected[found])
    cheapest = np.sort(expected)[:want]
    np.testing.assert_array_equal(np.sort(costs[found])[:want], cheapest)
    assert costs[found].max() <= np.sort(expected[np.isfinite(expected)])[found.sum() - 1]  # no gaps


@pytest.mark.parametrize("want", [5, 16, 1000])
def test_wanting_more_groups_than_there_are_stops_once_all_are_found(want: int) -> None:
    # a decision wants its 16 cheapest frontiers; with fewer on the map the search must stop once
    # it has them all, not go on over the whole map for groups that do not exist
    data = np.full((200, 200), CellState.FREE, np.int8)
    costmap = costmap_of(data)
    cells = np.array([50 * 200 + 60, 55 * 200 + 40], np.int64)
    costs, exhausted = group_path_costs(costmap, (50, 50), cells, np.array([0, 1]), 2, REACH, RADIUS, want=want)
    every, every_exhausted = group_path_costs(costmap, (50, 50), cells, np.array([0, 1]), 2, REACH, RADIUS)
    assert not exhausted and not every_exhausted
    np.testing.assert_array_equal(costs, every)
    np.testing.assert_array_equal(costs, reference(costmap, (50, 50), cells, np.array([0, 1]), 2))


def test_groups_without_a_path_are_inf_and_the_search_says_it_ran_out() -> None:
    data = np.full((60, 60), CellState.FREE, np.int8)
    data[:, 28:32] = CellState.OCCUPIED  # a wall from edge to edge
    costmap = costmap_of(data)
    cells = np.array([10 * 60 + 5, 10 * 60 + 55], np.int64)
    costs, exhausted = group_path_costs(costmap, (10, 10), cells, np.array([0, 1]), 2, REACH, RADIUS)
    assert exhausted and math.isfinite(costs[0]) and costs[1] == math.inf


def test_large_maps_are_searched_on_blocks_close_to_the_exact_cost(monkeypatch: pytest.MonkeyPatch) -> None:
    """A 600 x 600 map: blocks of 2 x 2 cells; on open floor with pillars the block estimate of a
    far group lies within 10 % of the exact cost."""
    data = np.full((600, 600), CellState.FREE, np.int8)
    data[:4], data[-4:], data[:, :4], data[:, -4:] = (CellState.OCCUPIED,) * 4
    for r in range(50, 560, 60):
        for c in range(50, 560, 60):
            data[r : r + 8, c : c + 8] = CellState.OCCUPIED
    costmap = costmap_of(data)
    assert block_factor(data.shape, 0.05, RADIUS) == 2 and MAX_SEARCH_CELLS < 600 * 600
    rng = np.random.default_rng(0)
    cells, groups = random_groups(rng, data, 20)
    blocked, _ = group_path_costs(costmap, (20, 20), cells, groups, 20, REACH, RADIUS)
    monkeypatch.setattr(group_costs, "MAX_SEARCH_CELLS", 10**9)
    exact, _ = group_path_costs(costmap, (20, 20), cells, groups, 20, REACH, RADIUS)
    far = np.isfinite(exact) & (exact > 5.0)
    assert far.sum() >= 10
    assert np.all(np.abs(blocked[far] - exact[far]) <= 0.1 * exact[far])


@pytest.mark.parametrize(("shape", "factor"), [((250, 250), 1), ((300, 300), 1), ((301, 300), 2), ((600, 600), 2)])
def test_block_factor_keeps_the_search_within_its_bound(shape: tuple[int, int], factor: int) -> None:
    assert block_factor(shape, 0.05, RADIUS) == factor
    assert math.ceil(shape[0] / factor) * math.ceil(shape[1] / factor) <= MAX_SEARCH_CELLS * 1.01


@pytest.mark.parametrize(("resolution", "largest"), [(0.05, 3), (0.1, 2), (0.03, 4)])
def test_blocks_never_grow_past_a_walls_closed_band(resolution: float, largest: int) -> None:
    assert max_block_factor(resolution, RADIUS) == largest
    assert block_factor((4000, 4000), resolution, RADIUS) == largest


@pytest.mark.parametrize("wall_col", [500, 501, 502, 503, 504])
def test_a_wall_without_a_door_stays_shut_on_blocks(wall_col: int) -> None:
    """A 1,000 x 1,000 map split by a wall two cells thick, wherever it falls on the blocks: the
    other side has no path (a block of four cells could join open cells across its closed band)."""
    data = np.full((1000, 1000), CellState.FREE, np.int8)
    data[:, wall_col : wall_col + 2] = CellState.OCCUPIED
    costmap = costmap_of(data)
    cells = np.array([500 * 1000 + 900], np.int64)
    costs, exhausted = group_path_costs(costmap, (500, 100), cells, np.array([0]), 1, REACH, RADIUS)
    assert exhausted and costs[0] == math.inf


def test_a_start_off_the_map_or_no_groups() -> None:
    costmap = costmap_of(np.full((30, 30), CellState.FREE, np.int8))
    costs, exhausted = group_path_costs(costmap, (40, 5), np.array([3], np.int64), np.array([0]), 1, REACH, RADIUS)
    assert exhausted and costs[0] == math.inf
    costs, _ = group_path_costs(costmap, (5, 5), np.zeros(0, np.int64), np.zeros(0, np.int64), 0, REACH, RADIUS)
    assert costs.shape == (0,)


def test_blocks_are_worked_out_only_where_the_search_goes(monkeypatch: pytest.MonkeyPatch) -> None:
    """A 1,000 x 1,000 map whose start is in a walled 100 x 100 room: the search works out the
    room's tiles of blocks and their neighbours, not the map; the costs are those of a search that
    works out every block first."""
    data = np.full((1000, 1000), CellState.FREE, np.int8)
    data[100:104, 100:204] = data[200:204, 100:204] = CellState.OCCUPIED
    data[100:204, 100:104] = data[100:204, 200:204] = CellState.OCCUPIED
    costmap = costmap_of(data)
    cells = np.array([150 * 1000 + 190, 900 * 1000 + 900], np.int64)
    worked: list[float] = []
    search = group_costs._group_costs

    def spy(*args: object) -> tuple[NDArray[np.float64], bool]:
        pending = args[2]
        assert isinstance(pending, np.ndarray)
        pending_before = pending.copy()
        result = search(*args)  # type: ignore[arg-type]
        worked.append(float(np.mean(pending_before & ~pending)))
        return result

    monkeypatch.setattr(group_costs, "_group_costs", spy)
    costs, exhausted = group_path_costs(costmap, (150, 150), cells, np.array([0, 1]), 2, REACH, RADIUS)
    assert exhausted and math.isfinite(costs[0]) and costs[1] == math.inf
    assert 0 < worked[0] < 0.03  # the room is 1 % of the map

    def eager(*args: object) -> tuple[NDArray[np.float64], bool]:
        open_p, cost_p, pending, src = args[:4]
        for block in range(pending.size):  # type: ignore[attr-defined]
            if pending.reshape(-1)[block]:  # type: ignore[attr-defined]
                group_costs._fill_tile(block, open_p, cost_p, pending, src)  # type: ignore[arg-type]
        return search(*args)  # type: ignore[arg-type]

    monkeypatch.setattr(group_costs, "_group_costs", eager)
    every, _ = group_path_costs(costmap, (150, 150), cells, np.array([0, 1]), 2, REACH, RADIUS)
    np.testing.assert_array_equal(costs, every)


def _blocks_by_numpy(costmap: Costmap, f: int) -> tuple[NDArray[np.bool_], NDArray[np.float64]]:
    """The definition of the block grid, padded: a block is open when any of its cells is, at the
    least step cost factor of its open cells."""
    rows, cols = costmap.grid.shape
    brows, bcols = -(-rows // f), -(-cols // f)
    cell_open = np.zeros((brows * f, bcols * f), np.bool_)
    cell_cost = np.full((brows * f, bcols * f), np.inf)
    cell_open[:rows, :cols] = costmap.open_padded[1:-1, 1:-1]
    cell_cost[:rows, :cols] = np.where(cell_open[:rows, :cols], costmap.cost_padded[1:-1, 1:-1], np.inf)
    least = cell_cost.reshape(brows, f, bcols, f).min(axis=(1, 3))
    open_b = np.zeros((brows + 2, bcols + 2), np.bool_)
    cost_b = np.ones((brows + 2, bcols + 2))
    open_b[1:-1, 1:-1] = np.isfinite(least)
    cost_b[1:-1, 1:-1] = np.where(np.isfinite(least), least, 1.0)
    return open_b, cost_b


@pytest.mark.parametrize("shape", [(1000, 1000), (1003, 1001), (1019, 977)])
def test_the_lazy_blocks_equal_the_definition_up_to_the_maps_edges(shape: tuple[int, int]) -> None:
    """Maps whose edges cut a block and a tile of blocks: the search from a corner, to groups at
    the far edges and everywhere, gives the costs of a search on the block grid worked out by its
    definition beforehand."""
    rng = np.random.default_rng(shape[0])
    data = np.full(shape, CellState.FREE, np.int8)
    for _ in range(150):  # pillars and an unknown patch
        r, c = rng.integers(0, shape[0] - 20), rng.integers(0, shape[1] - 20)
        data[r : r + rng.integers(3, 20), c : c + rng.integers(3, 20)] = CellState.OCCUPIED
    data[400:500, 300:700] = np.where(data[400:500, 300:700] == CellState.FREE, np.int8(CellState.UNKNOWN),
                                      data[400:500, 300:700])  # fmt: skip
    data[:2], data[:, :2] = CellState.OCCUPIED, CellState.OCCUPIED
    costmap = costmap_of(data)
    free = np.argwhere(costmap.traversable)
    start = tuple(int(v) for v in free[np.argmax(free.sum(axis=1))])  # the bottom-right corner
    cells, groups = random_groups(rng, data, 30)
    edge = np.array([(shape[0] - 3) * shape[1] + shape[1] // 2, (shape[0] // 2) * shape[1] + shape[1] - 3])
    cells, groups = np.concatenate((cells, edge)), np.concatenate((groups, [30, 31]))
    f = block_factor(shape, 0.05, RADIUS)
    assert f == 3
    lazy, _ = group_path_costs(costmap, start, cells, groups, 32, REACH, RADIUS)  # type: ignore[arg-type]
    open_b, cost_b = _blocks_by_numpy(costmap, f)
    bcols = open_b.shape[1] - 2
    rows_, cols_ = np.divmod(cells, shape[1])
    src = (costmap.open_padded, costmap.clearance_padded, costmap.grid.data, costmap.inflation_table,
           costmap.inflation_radius, costmap.unknown_cost, f)  # fmt: skip
    best, _ = group_costs._group_costs(
        open_b, cost_b, np.zeros(open_b.shape, np.bool_), src, int((start[0] // f) * bcols + start[1] // f),
        ((rows_ // f) * bcols + cols_ // f, groups), math.ceil(REACH / f), 32, 32, float(cost_b.max()),
    )  # fmt: skip
    np.testing.assert_array_equal(lazy, best * (f * 0.05))
    assert np.isfinite(lazy[30:]).all()  # the groups at the far edges were reached
    blocks = costmap.block_grids[f]  # each block worked out, by its clearest open cells, as defined
    done = ~blocks.pending
    np.testing.assert_array_equal(blocks.open_padded[done], open_b[done])
    np.testing.assert_array_equal(blocks.cost_padded[done], cost_b[done])


def test_searches_on_one_costmap_share_its_blocks_and_cost_the_same() -> None:
    """A decision's several searches on one large costmap (model 7's tour) work each tile of
    blocks out once: the searches give, in any order, the costs each gives on a fresh costmap."""
    data = a_map(3)
    data = np.tile(data, (3, 3))  # 750 x 750 cells: searched on blocks
    rng = np.random.default_rng(3)
    built = costmap_of(data)
    assert block_factor(data.shape, 0.05, RADIUS) > 1
    free = np.argwhere(built.traversable)
    starts = [(int(free[i][0]), int(free[i][1])) for i in rng.integers(len(free), size=4)]
    cells, groups = random_groups(rng, data, 20)
    alone = [group_path_costs(costmap_of(data), s, cells, groups, 20, REACH, RADIUS)[0] for s in starts]
    for order in (range(4), range(3, -1, -1)):
        shared = costmap_of(data)
        for i in order:
            costs, _ = group_path_costs(shared, starts[i], cells, groups, 20, REACH, RADIUS)
            np.testing.assert_array_equal(costs, alone[i])
        (blocks,) = shared.block_grids.values()
        assert not blocks.pending[1:-1, 1:-1].all()  # the searches worked tiles out, and kept them
