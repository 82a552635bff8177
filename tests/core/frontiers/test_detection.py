"""Tests of frontier_rl.core.frontiers.detection on hand-made grids and against scipy.ndimage.label."""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
import pytest
from numpy.typing import NDArray
from scipy import ndimage

from frontier_rl.core.frontiers.detection import Frontiers, detect_frontiers, visible_unknown
from frontier_rl.core.frontiers.fringe import count_fringe, fringe_mask
from frontier_rl.core.mapping.mapper import LogOddsMapper
from frontier_rl.core.sensing.lidar import Lidar
from frontier_rl.core.world.catalog import generate_world
from frontier_rl.core.world.grid import CellState, OccupancyGrid
from frontier_rl.core.world.raycast import dda_step, ray_start
from frontier_rl.core.world.robot import Pose
from frontier_rl.errors import ConfigError

FREE, OCC, UNKNOWN = CellState.FREE.value, CellState.OCCUPIED.value, CellState.UNKNOWN.value
EIGHT = np.ones((3, 3), dtype=bool)
TextGrid = Callable[..., OccupancyGrid]


def fringe_reference(state: NDArray[np.int8]) -> NDArray[np.bool_]:
    """FREE cells with an UNKNOWN 4-neighbour; beyond the edge counts as not unknown."""
    unknown = np.pad(state == UNKNOWN, 1, constant_values=False)
    near = unknown[:-2, 1:-1] | unknown[2:, 1:-1] | unknown[1:-1, :-2] | unknown[1:-1, 2:]
    return np.asarray((state == FREE) & near)


def diagonal_grid(n: int, origin: tuple[float, float] = (0.0, 0.0), res: float = 0.1) -> OccupancyGrid:
    """All unknown but n FREE cells on the diagonal (i + 1, i + 1): one 8-connected chain."""
    data = np.full((n + 2, n + 2), UNKNOWN, np.int8)
    idx = np.arange(1, n + 1)
    data[idx, idx] = FREE
    return OccupancyGrid(data, res, origin)


# ------------------------------------------------------------------------------------- fringe
def test_fringe_cells_by_hand(grid_from_text: TextGrid) -> None:
    g = grid_from_text(
        [
            "#####?",  # row 4
            "#...#?",  # row 3
            "#.#.??",  # row 2
            "?....#",  # row 1
            "#.?.#.",  # row 0
        ]
    )
    by_hand = np.zeros(g.shape, bool)
    by_hand[1, 1] = True  # left neighbour (1, 0) is unknown
    by_hand[0, 1] = True  # right neighbour (0, 2) is unknown
    by_hand[0, 3] = True  # left neighbour (0, 2) is unknown
    by_hand[1, 2] = True  # lower neighbour (0, 2) is unknown
    by_hand[2, 3] = True  # right neighbour (2, 4) is unknown
    by_hand[1, 4] = True  # upper neighbour (2, 4) is unknown
    # not fringe: (1, 3) has only free 4-neighbours; (3, 1..3) have none unknown (the unknown
    # (4, 5) and (3, 5) touch only walls); (0, 5) sits on the edge between two walls
    np.testing.assert_array_equal(fringe_mask(g.data), by_hand)
    np.testing.assert_array_equal(fringe_mask(g.data), fringe_reference(g.data))


def test_only_free_cells_with_a_4_neighbour_unknown_are_fringe(grid_from_text: TextGrid) -> None:
    g = grid_from_text(
        [
            "?#?",
            "#.#",
            "?#?",
        ]
    )
    assert not fringe_mask(g.data).any()  # unknown only diagonally
    g = grid_from_text(["?#", "#?"])
    assert not fringe_mask(g.data).any()  # occupied cells next to unknown are not fringe
    g = grid_from_text(["...", "...", "..."])
    assert not fringe_mask(g.data).any()  # the grid's edge is not unknown


@pytest.mark.parametrize("seed", range(5))
def test_fringe_mask_matches_the_definition_on_random_grids(seed: int) -> None:
    rng = np.random.default_rng(seed)
    state = rng.choice(np.array([FREE, OCC, UNKNOWN], np.int8), size=(31, 47), p=[0.5, 0.2, 0.3])
    np.testing.assert_array_equal(fringe_mask(state), fringe_reference(state))


def test_count_fringe(grid_from_text: TextGrid) -> None:
    g = grid_from_text(
        [
            "????",
            "....",
            "....",
        ]
    )
    rows = np.array([0, 0, 1, 1, 2], np.int64)
    cols = np.array([0, 3, 0, 3, 1], np.int64)
    assert count_fringe(g.data, rows, cols) == 2  # row 1 borders the unknown row 2; row 2 is unknown
    assert count_fringe(g.data, np.array([], np.int64), np.array([], np.int64)) == 0
    data = g.data.copy()
    data[2, :] = FREE  # the unknown got explored
    assert count_fringe(data, rows, cols) == 0


# ---------------------------------------------------------------------------------- clustering
@pytest.mark.parametrize("n", range(1, 9))
def test_clusters_of_4_cells_or_fewer_are_dropped(n: int) -> None:
    f = detect_frontiers(diagonal_grid(n), Pose(0.0, 0.0), min_cells=4)
    assert len(f) == (1 if n > 4 else 0)
    if n > 4:
        assert f.sizes.tolist() == [n]  # the diagonal chain is one 8-connected cluster


@pytest.mark.parametrize(("n", "min_cells"), [(5, 5), (5, 0), (3, 2), (3, 3), (8, 7)])
def test_min_cells_is_the_largest_size_dropped(n: int, min_cells: int) -> None:
    f = detect_frontiers(diagonal_grid(n), Pose(0.0, 0.0), min_cells=min_cells)
    assert len(f) == int(n > min_cells)


def test_cluster_cells_are_the_chain(grid_from_text: TextGrid) -> None:
    f = detect_frontiers(diagonal_grid(6), Pose(0.0, 0.0))
    cells = {tuple(c) for c in f.cells[0].tolist()}
    assert cells == {(i, i) for i in range(1, 7)}
    assert f.cells[0].shape == (6, 2) and f.cells[0].dtype == np.int64


def test_four_connected_neighbours_and_separate_clusters(grid_from_text: TextGrid) -> None:
    # two rows of fringe cells split by a wall cell: two clusters (the unknown cell under the
    # wall touches only walls)
    g = grid_from_text(
        [
            "??????????????",
            "......#.......",
            "......#.......",
            "######?#######",
        ]
    )
    f = detect_frontiers(g, Pose(0.0, 0.0))
    assert sorted(f.sizes.tolist()) == [6, 7]  # the top free row on each side of the wall
    # a single free cell between them joins nothing: (1, 6) is occupied
    g2 = grid_from_text(
        [
            "??????????????",
            "..............",
            "######?#######",
        ]
    )
    f2 = detect_frontiers(g2, Pose(0.0, 0.0))
    assert f2.sizes.tolist() == [14]


@pytest.mark.parametrize("origin", [(0.0, 0.0), (-3.25, 7.5), (100.0, -42.0)])
@pytest.mark.parametrize("res", [0.05, 0.1])
def test_centres_sizes_and_distances_in_world_coordinates(origin: tuple[float, float], res: float) -> None:
    n = 7
    g = diagonal_grid(n, origin, res)
    robot = Pose(origin[0] + 0.3, origin[1] - 0.2, 1.0)
    f = detect_frontiers(g, robot)
    assert len(f) == 1
    cells = np.arange(1, n + 1)
    cx = origin[0] + (cells + 0.5) * res  # cell centres: x from the column, y from the row
    cy = origin[1] + (cells + 0.5) * res
    assert f.centers.shape == (1, 2)
    assert f.centers[0] == pytest.approx([cx.mean(), cy.mean()], abs=1e-9)
    assert f.sizes.tolist() == [n]
    assert f.distances[0] == pytest.approx(math.hypot(cx.mean() - robot.x, cy.mean() - robot.y), abs=1e-9)
    assert f.min_distances[0] == pytest.approx(np.hypot(cx - robot.x, cy - robot.y).min(), abs=1e-9)
    assert f.grid is g


def test_centre_of_an_l_shaped_cluster(grid_from_text: TextGrid) -> None:
    g = grid_from_text(
        [
            "#####",
            "#?..#",
            "#?..#",
            "#?..#",
            "#####",
        ],
        resolution=1.0,
        origin=(10.0, 20.0),
    )
    f = detect_frontiers(g, Pose(10.0, 20.0), min_cells=0)
    # fringe: column 2 (rows 1-3): three cells with unknown to the left; column 3 has none
    assert f.sizes.tolist() == [3]
    assert f.centers[0] == pytest.approx([10.0 + 2.5, 20.0 + 2.5])


def test_reachability_filter(grid_from_text: TextGrid) -> None:
    g = grid_from_text(
        [
            "?????#??????",
            ".....#......",
            ".....#......",
        ]
    )
    robot = Pose(0.0, 0.0)
    both = detect_frontiers(g, robot)
    assert sorted(both.sizes.tolist()) == [5, 6]
    reachable = np.zeros(g.shape, bool)
    assert len(detect_frontiers(g, robot, reachable)) == 0  # nothing reachable: no candidate
    reachable[0, :5] = True  # the left room's lower row sees the left fringe, not the right one behind the wall
    left = detect_frontiers(g, robot, reachable)
    assert left.sizes.tolist() == [5]
    assert left.centers[0, 0] < 5 * g.resolution
    assert left.goal_cells[0, 0] == 0 and left.goal_cells[0, 1] < 5  # its goal is a reachable cell
    assert len(detect_frontiers(g, robot, reachable, goal_reach=0.0)) == 0  # too far for a goal at 0 m
    reachable[1, 2] = True  # the fringe cell nearest the cluster's centre is reachable: the goal is on it
    assert detect_frontiers(g, robot, reachable, goal_reach=0.0).sizes.tolist() == [5]
    reachable[0, 11] = True
    assert len(detect_frontiers(g, robot, reachable)) == 2


def test_subset_keeps_parallel_arrays_in_order() -> None:
    data = np.full((12, 30), UNKNOWN, np.int8)
    data[1, 1:8] = FREE
    data[5, 3:20] = FREE
    data[9, 10:16] = FREE
    f = detect_frontiers(OccupancyGrid(data, 0.05), Pose(0.0, 0.0))
    assert len(f) == 3
    sub = f.subset(np.array([True, False, True]))
    assert len(sub) == 2
    np.testing.assert_array_equal(sub.sizes, f.sizes[[0, 2]])
    np.testing.assert_array_equal(sub.centers, f.centers[[0, 2]])
    np.testing.assert_array_equal(sub.distances, f.distances[[0, 2]])
    np.testing.assert_array_equal(sub.cells[1], f.cells[2])


def scanned_office(seed: int) -> tuple[OccupancyGrid, Pose]:
    """The map of an office world after six scans from random free cells, and a robot at its middle."""
    w = generate_world("office", seed)
    lidar = Lidar(w.grid)
    mapper = LogOddsMapper(w.grid, explorable=w.explorable)
    rng = np.random.default_rng(seed)
    free = np.argwhere(w.grid.data == FREE)
    for k in range(6):
        r, c = free[rng.integers(len(free))]
        mapper.integrate_simulated(lidar, Pose(*w.grid.cell_to_world(r, c), 0.0), rng, float(k))
    grid = mapper.occupancy_grid(margin=2)
    return grid, Pose(*grid.cell_to_world(grid.height // 2, grid.width // 2), 0.0)


@pytest.mark.parametrize("seed", [0, 3])
def test_detect_frontiers_matches_scipy_components_on_a_real_map(seed: int) -> None:
    """After a few scans of an office world: unsplit, the clusters are exactly the 8-connected
    components of the fringe mask with more than 4 cells."""
    grid, robot = scanned_office(seed)
    f = detect_frontiers(grid, robot)  # every cluster, unsplit
    labels, n = ndimage.label(fringe_reference(grid.data), structure=EIGHT)
    expected = []
    for k in range(1, n + 1):
        comp = labels == k
        if comp.sum() > 4:
            expected.append(frozenset(map(tuple, np.argwhere(comp).tolist())))
    got = [frozenset(map(tuple, cells.tolist())) for cells in f.cells]
    assert len(got) > 0
    assert sorted(got, key=sorted) == sorted(expected, key=sorted)
    for cells, size, centre in zip(f.cells, f.sizes, f.centers, strict=True):
        assert len(cells) == size
        xs = grid.origin[0] + (cells[:, 1] + 0.5) * grid.resolution
        ys = grid.origin[1] + (cells[:, 0] + 0.5) * grid.resolution
        assert centre == pytest.approx([xs.mean(), ys.mean()], abs=1e-9)


@pytest.mark.parametrize("seed", [0, 3])
def test_keep_drops_segments_as_a_filter_afterwards_would(seed: int) -> None:
    """Segments ``keep`` refuses are dropped before their goals are looked for: the frontiers left
    are those of the whole detection that it keeps, every array the same."""
    grid, robot = scanned_office(seed)
    reachable = grid.data == FREE
    asked: list[int] = []

    def small_or_odd(cells: NDArray[np.int64], sizes: NDArray[np.int64]) -> NDArray[np.bool_]:
        """Segments of 3 cells or fewer, or whose first cell has an odd flat index."""
        asked.append(len(sizes))
        assert len(cells) == sizes.sum()
        firsts = cells[np.cumsum(sizes) - sizes]
        return np.asarray((sizes <= 3) | (firsts % 2 == 1))

    every = detect_frontiers(grid, robot, reachable, 0, 1.0)
    kept = detect_frontiers(grid, robot, reachable, 0, 1.0, keep=small_or_odd)
    assert asked and asked[0] >= len(every)  # asked of every segment, before the goals' filter
    firsts = every.flat_cells[every.spans[:, 0]]
    expected = every.subset((every.sizes <= 3) | (firsts % 2 == 1))
    assert 0 < len(kept) < len(every)
    assert len(kept) == len(expected)
    for name in ("centers", "sizes", "distances", "min_distances", "goal_cells"):
        np.testing.assert_array_equal(getattr(kept, name), getattr(expected, name))
    for mine, theirs in zip(kept.cells, expected.cells, strict=True):
        np.testing.assert_array_equal(mine, theirs)


def test_a_map_without_unknown_cells_has_no_frontier() -> None:
    data = np.full((20, 20), FREE, np.int8)
    data[[0, -1], :] = OCC
    f = detect_frontiers(OccupancyGrid(data, 0.05), Pose(0.5, 0.5))
    assert len(f) == 0
    assert f.centers.shape == (0, 2)
    assert f.information_gain(3.5).shape == (0,)


# ------------------------------------------------------------------------------ information gain
def single_frontier(grid: OccupancyGrid, row: int, col: int, make: Callable[..., Frontiers]) -> Frontiers:
    """Two one-cell 'frontiers' both centred on cell (row, col), for information-gain checks."""
    x, y = grid.cell_to_world(row, col)
    return make(grid, [[x, y], [x, y]], [1, 1])


def test_information_gain_counts_unknown_cells_and_stops_at_walls(
    grid_from_text: TextGrid, frontiers_from: Callable[..., Frontiers]
) -> None:
    walled = grid_from_text(["###########", "#.????#???#", "###########"], resolution=0.1, origin=(2.0, -1.0))
    # from cell (1, 1), a corridor one cell high: only cells (1, 2..5) can be seen, (1, 7..9)
    # lie behind the wall at (1, 6); every other ray ends in the corridor's walls
    assert single_frontier(walled, 1, 1, frontiers_from).information_gain(10.0).tolist() == [
        4,
        4,
    ]  # each centre counts alone
    opened = grid_from_text(["###########", "#.???????##", "###########"], resolution=0.1, origin=(2.0, -1.0))
    assert single_frontier(opened, 1, 1, frontiers_from).information_gain(10.0).tolist() == [7, 7]
    # range 0.22 m = 2.2 cells: the ray enters (1, 2) at 0.5 cells, (1, 3) at 1.5, (1, 4) at 2.5
    assert single_frontier(opened, 1, 1, frontiers_from).information_gain(0.22).tolist() == [2, 2]


def reference_gain(state: np.ndarray, cx: float, cy: float, n_rays: int, max_range: float) -> int:
    """The definition, one ray at a time, with a set of the unknown cells the rays enter."""
    seen: set[tuple[int, int]] = set()
    for i in range(n_rays):
        a = 2.0 * math.pi * i / n_rays
        row, col, s_r, s_c, tm_r, tm_c, td_r, td_c = ray_start(cx, cy, math.cos(a), math.sin(a))
        t = 0.0
        while t <= max_range and 0 <= row < state.shape[0] and 0 <= col < state.shape[1]:
            if state[row, col] == CellState.OCCUPIED:
                break
            if state[row, col] == CellState.UNKNOWN:
                seen.add((row, col))
            row, col, tm_r, tm_c, t = dda_step(row, col, s_r, s_c, tm_r, tm_c, td_r, td_c)
    return len(seen)


@pytest.mark.parametrize("seed", range(3))
def test_information_gain_is_the_rays_count_anywhere_on_the_map(
    seed: int, frontiers_from: Callable[..., Frontiers]
) -> None:
    # the cells counted are stamped in a window around each centre: centres by the map's edges
    # and ranges longer than the map must count as the rays do
    rng = np.random.default_rng(seed)
    values = np.array([CellState.FREE, CellState.UNKNOWN, CellState.OCCUPIED], np.int8)
    state = values[rng.choice(3, size=(90, 130), p=[0.3, 0.67, 0.03])]
    grid = OccupancyGrid(state, 0.05, (-1.0, 2.0))
    cells = np.array([[0, 0], [89, 129], [45, 0], [0, 64], [45, 64], [88, 3]])
    centres = grid.cells_to_world(cells) + rng.uniform(-0.02, 0.02, (len(cells), 2))
    frontiers = frontiers_from(grid, centres, np.ones(len(cells), np.int64))
    for sensor_range in (0.3, 1.7, 3.5, 1e9):
        expected = [
            reference_gain(state, (x + 1.0) / 0.05, (y - 2.0) / 0.05, 90, min(sensor_range / 0.05, 1e6))
            for x, y in centres
        ]
        assert frontiers.information_gain(sensor_range, n_rays=90).tolist() == expected
    for bad in (float("nan"), -0.5):
        with pytest.raises(ConfigError, match="sensor_range"):
            frontiers.information_gain(bad)


def test_information_gain_in_a_small_room(grid_from_text: TextGrid, frontiers_from: Callable[..., Frontiers]) -> None:
    rows = [
        "#######",
        "#?????#",
        "#?????#",
        "#??.??#",
        "#?????#",
        "#?????#",
        "#######",
    ]
    room = grid_from_text(rows, resolution=1.0)
    assert single_frontier(room, 3, 3, frontiers_from).information_gain(10.0)[0] == 24  # every unknown cell of the room
    # a wall segment at column 4, rows 2-4 hides the whole column 5 (rows 1-5) from the centre
    blocked = [row[:4] + ("#" if 1 < i < 5 else row[4]) + row[5:] for i, row in enumerate(rows)]
    g = grid_from_text(blocked, resolution=1.0)
    assert single_frontier(g, 3, 3, frontiers_from).information_gain(10.0)[0] == 24 - 3 - 5


def walled_pocket(rng: np.random.Generator) -> tuple[NDArray[np.int8], NDArray[np.float64]]:
    """A random floor with pillars, an unknown pocket walled round but for a few holes, and
    viewpoints on free cells (half on cells' centres, where rays pass through cells' corners)."""
    rows, cols = rng.integers(20, 90, 2)
    state = np.where(rng.random((rows, cols)) < 0.15, CellState.OCCUPIED, CellState.FREE).astype(np.int8)
    top, left = rng.integers(0, rows - 3), rng.integers(0, cols - 3)
    bottom, right = rng.integers(top + 1, rows + 1), rng.integers(left + 1, cols + 1)
    pocket = np.zeros((rows, cols), np.bool_)
    pocket[top:bottom, left:right] = rng.random((bottom - top, right - left)) < 0.8
    state[ndimage.binary_dilation(pocket) & ~pocket & (rng.random((rows, cols)) < 0.9)] = CellState.OCCUPIED
    state[pocket] = CellState.UNKNOWN
    free = np.argwhere(state == CellState.FREE)
    if not pocket.any() or len(free) == 0:
        return walled_pocket(rng)
    cells = free[rng.integers(0, len(free), 30)]
    return state, cells[:, ::-1] + (0.5 if rng.random() < 0.5 else rng.random((30, 2)))


def pocket_hints(state: NDArray[np.int8]) -> tuple[tuple[float, float, float, float], NDArray[np.int64]]:
    """The box of ``state``'s unknown cells (cell edges) and those with a free 4-neighbour."""
    unknown = state == CellState.UNKNOWN
    rows, cols = np.nonzero(unknown)
    box = (float(rows.min()), float(rows.max() + 1), float(cols.min()), float(cols.max() + 1))
    return box, np.argwhere(unknown & ndimage.binary_dilation(state == CellState.FREE))


@pytest.mark.parametrize("seed", range(4))
def test_the_hints_of_a_pocket_change_no_count(seed: int) -> None:
    # the box and the entries only spare rays that could not count: hundreds of random pockets
    # and viewpoints, at ranges from a few cells to past the floor, count as every ray does
    rng = np.random.default_rng(seed)
    counted = 0
    for _ in range(100):
        state, centres = walled_pocket(rng)
        sight = float(rng.uniform(3.0, 60.0))
        every = visible_unknown(state, centres, 360, sight)
        assert visible_unknown(state, centres, 360, sight, *pocket_hints(state)).tolist() == every.tolist()
        counted += int(np.count_nonzero(every))
    assert counted > 100  # the pockets were seen, not only missed


def test_the_hints_are_used(grid_from_text: TextGrid) -> None:
    # a box or entries that leave the pocket out leave it uncounted: the rays really are spared
    room = grid_from_text(["#######", "#.....#", "###.###", "#?????#", "#######"], resolution=1.0).data
    centre = np.array([[3.5, 3.5]])  # (col, row): above the door (row 2) to the pocket (row 1)
    assert visible_unknown(room, centre, 360, 10.0).tolist() == [3]  # (1, 2), (1, 3), (1, 4)
    assert visible_unknown(room, centre, 360, 10.0, (1.0, 2.0, 1.0, 6.0), np.array([[1, 3]])).tolist() == [3]
    # a box from column 5: the rays towards (1, 2) are not cast
    assert visible_unknown(room, centre, 360, 10.0, (1.0, 2.0, 5.0, 6.0), np.array([[1, 3]])).tolist() == [2]
    assert visible_unknown(room, centre, 360, 10.0, (1.0, 2.0, 1.0, 6.0), np.array([[3, 1]])).tolist() == [0]
