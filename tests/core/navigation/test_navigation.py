"""Tests of frontier_rl.core.navigation.follower, planner and astar: A* against known paths and scipy's
Dijkstra, the inflated costmap, nearest_cell, the robot footprint and the path follower's timing
and collision check."""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
import pytest
from numpy.typing import NDArray
from scipy import ndimage
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import dijkstra

from frontier_rl.core.navigation import astar as astar_module
from frontier_rl.core.navigation.astar import SearchScratch, astar, astar_padded
from frontier_rl.core.navigation.config import NavigationConfig
from frontier_rl.core.navigation.costmap import Costmap, felt_keep_out, nearest_cell
from frontier_rl.core.navigation.follower import (
    FollowerParams,
    FollowStatus,
    careful_flags,
    follow_path,
    footprint_offsets,
)
from frontier_rl.core.navigation.path_costs import cost_to_go_padded
from frontier_rl.core.sim.teammates import obstacle_distance
from frontier_rl.core.world.catalog import generate_world
from frontier_rl.core.world.grid import CellState, OccupancyGrid
from frontier_rl.core.world.robot import RobotConfig
from frontier_rl.errors import ConfigError

FREE, OCC, UNKNOWN = CellState.FREE.value, CellState.OCCUPIED.value, CellState.UNKNOWN.value
TextGrid = Callable[..., OccupancyGrid]
SQRT2 = math.sqrt(2.0)


def path_cost(path: NDArray[np.int64], penalty: NDArray[np.float64]) -> float:
    """A* cost of a cell path: each step's length times (1 + penalty of the cell entered)."""
    steps = np.diff(path, axis=0)
    lengths = np.hypot(steps[:, 0], steps[:, 1])
    return float(np.sum(lengths * (1.0 + penalty[path[1:, 0], path[1:, 1]])))


def assert_valid_path(path: NDArray[np.int64], passable: NDArray[np.bool_], start: tuple[int, int],
                      goal: tuple[int, int]) -> None:  # fmt: skip
    assert tuple(path[0]) == start and tuple(path[-1]) == goal
    steps = np.diff(path, axis=0)
    assert np.all(np.abs(steps).max(axis=1) == 1), "steps are to one of the 8 neighbours"
    assert np.all(passable[path[1:, 0], path[1:, 1]])
    for (r, c), (dr, dc) in zip(path[:-1], steps, strict=True):
        if dr and dc:  # a diagonal may not cut a corner
            assert passable[r + dr, c] and passable[r, c + dc]


def octile(dr: int, dc: int) -> float:
    a, b = abs(dr), abs(dc)
    return max(a, b) + (SQRT2 - 1.0) * min(a, b)


# ------------------------------------------------------------------------------------------- A*
@pytest.mark.parametrize(
    ("start", "goal"),
    [((5, 5), (5, 15)), ((5, 5), (15, 5)), ((0, 0), (19, 19)), ((3, 17), (12, 2)), ((7, 7), (7, 7)), ((2, 9), (19, 0))],
)
def test_astar_on_an_empty_grid_is_the_octile_distance(start: tuple[int, int], goal: tuple[int, int]) -> None:
    passable = np.ones((20, 20), bool)
    penalty = np.zeros((20, 20))
    path = astar(passable, penalty, *start, *goal)
    assert_valid_path(path, passable, start, goal)
    expected = octile(goal[0] - start[0], goal[1] - start[1])
    assert path_cost(path, penalty) == pytest.approx(expected, abs=1e-9)
    assert len(path) == max(abs(goal[0] - start[0]), abs(goal[1] - start[1])) + 1


def test_astar_straight_line_on_an_open_grid() -> None:
    passable = np.ones((10, 30), bool)
    path = astar(passable, np.zeros((10, 30)), 4, 2, 4, 27)
    np.testing.assert_array_equal(path, np.column_stack((np.full(26, 4), np.arange(2, 28))))


def test_astar_l_shaped_corridor(grid_from_text: TextGrid) -> None:
    g = grid_from_text(
        [
            "##########",
            "#########.",
            "########.#",  # a diagonal step into (7, 8) would cut a corner: not allowed
            "########.#",
            "########.#",
            "########.#",
            "########.#",
            "########.#",
            "#........#",
            "##########",
        ]
    )
    passable = g.data == FREE
    path = astar(passable, np.zeros(g.shape), 1, 1, 7, 8)
    assert_valid_path(path, passable, (1, 1), (7, 8))
    assert path_cost(path, np.zeros(g.shape)) == pytest.approx(7 + 6)
    # (8, 9) is only diagonally connected to (7, 8): a corner-cut, so no path
    assert astar(passable, np.zeros(g.shape), 1, 1, 8, 9).shape == (0, 2)


def test_astar_with_no_way_through_a_wall_returns_an_empty_path() -> None:
    passable = np.ones((15, 15), bool)
    passable[:, 7] = False
    path = astar(passable, np.zeros((15, 15)), 3, 2, 10, 12)
    assert path.shape == (0, 2) and path.dtype == np.int64
    passable[14, 7] = True  # a door at the end of the wall
    path = astar(passable, np.zeros((15, 15)), 3, 2, 10, 12)
    assert_valid_path(path, passable, (3, 2), (10, 12))


def test_astar_does_not_cut_corners() -> None:
    passable = np.ones((2, 2), bool)
    passable[0, 1] = False
    path = astar(passable, np.zeros((2, 2)), 0, 0, 1, 1)
    assert path.tolist() == [[0, 0], [1, 0], [1, 1]]  # around, not diagonally past the blocked cell
    passable[1, 0] = False
    assert astar(passable, np.zeros((2, 2)), 0, 0, 1, 1).shape == (0, 2)  # only a diagonal contact


def dijkstra_cost(passable: NDArray[np.bool_], penalty: NDArray[np.float64], start: tuple[int, int],
                  goal: tuple[int, int]) -> float:  # fmt: skip
    rows, cols = passable.shape
    src, dst, weight = [], [], []
    for r in range(rows):
        for c in range(cols):
            if not passable[r, c] and (r, c) != start:
                continue
            for dr in (-1, 0, 1):
                for dc in (-1, 0, 1):
                    rr, cc = r + dr, c + dc
                    if (dr or dc) and 0 <= rr < rows and 0 <= cc < cols and passable[rr, cc]:
                        if dr and dc and not (passable[r + dr, c] and passable[r, c + dc]):
                            continue
                        src.append(r * cols + c)
                        dst.append(rr * cols + cc)
                        weight.append(math.hypot(dr, dc) * (1.0 + penalty[rr, cc]))
    graph = csr_matrix((weight, (src, dst)), shape=(rows * cols, rows * cols))
    dist = dijkstra(graph, directed=True, indices=start[0] * cols + start[1])
    return float(dist[goal[0] * cols + goal[1]])


@pytest.mark.parametrize("seed", range(8))
def test_astar_cost_equals_dijkstra_on_random_grids(seed: int) -> None:
    rng = np.random.default_rng(seed)
    shape = (18, 23)
    passable = rng.random(shape) < 0.72
    penalty = np.where(rng.random(shape) < 0.5, rng.uniform(0.0, 4.0, shape), 0.0)
    cells = np.argwhere(passable)
    for _ in range(6):
        start = tuple(int(v) for v in cells[rng.integers(len(cells))])
        goal = tuple(int(v) for v in cells[rng.integers(len(cells))])
        expected = dijkstra_cost(passable, penalty, start, goal)  # type: ignore[arg-type]
        path = astar(passable, penalty, *start, *goal)
        if math.isinf(expected):
            assert path.shape == (0, 2)
        else:
            assert_valid_path(path, passable, start, goal)  # type: ignore[arg-type]
            assert path_cost(path, penalty) == pytest.approx(expected, rel=1e-9)


@pytest.mark.parametrize("seed", range(4))
def test_cost_to_go_equals_dijkstra_on_random_grids(seed: int) -> None:
    rng = np.random.default_rng(100 + seed)
    shape = (15, 19)
    passable = rng.random(shape) < 0.72
    penalty = np.where(rng.random(shape) < 0.5, rng.uniform(0.0, 4.0, shape), 0.0)
    cells = np.argwhere(passable)
    start = tuple(int(v) for v in cells[rng.integers(len(cells))])
    field = cost_to_go_padded(np.pad(passable, 1), np.pad(1.0 + penalty, 1, constant_values=1.0), start)  # type: ignore[arg-type]
    assert field.shape == shape and field[start] == 0.0
    for goal in map(tuple, cells[:: max(len(cells) // 12, 1)]):
        expected = dijkstra_cost(passable, penalty, start, goal)  # type: ignore[arg-type]
        if math.isinf(expected):
            assert math.isinf(field[goal])
        else:
            assert field[goal] == pytest.approx(expected, rel=1e-9)
    assert np.isinf(field[~passable]).all()


# -------------------------------------------------------------------------------------- costmap
def one_obstacle(shape: tuple[int, int] = (61, 61), res: float = 0.05, state: int = FREE) -> OccupancyGrid:
    data = np.full(shape, state, np.int8)
    data[shape[0] // 2, shape[1] // 2] = OCC
    return OccupancyGrid(data, res)


@pytest.mark.parametrize(
    "res",
    [0.05, 0.04375, 0.1, 0.025],
)
def test_cells_within_radius_plus_half_a_cell_of_a_wall_are_not_traversable(res: float) -> None:
    rng = np.random.default_rng(int(res * 1e5))
    data = np.where(rng.random((60, 80)) < 0.02, OCC, FREE).astype(np.int8)
    grid = OccupancyGrid(data, res)
    robot = RobotConfig()
    cm = Costmap.build(grid, robot, NavigationConfig())
    exact = ndimage.distance_transform_edt(data != OCC) * res
    lethal = robot.radius + 0.5 * res
    np.testing.assert_array_equal(cm.traversable, exact >= lethal - 1e-9)
    assert not cm.traversable[data == OCC].any()


@pytest.mark.parametrize(
    ("radius", "res"),
    [
        (0.105, 0.05),
        (0.2, 0.05),
        (0.3, 0.05),
        (0.105, 0.02),
        (0.105, 0.01),
    ],
)
def test_traversable_cells_are_never_closer_than_the_radius_to_a_wall(radius: float, res: float) -> None:
    """The planner may only route the robot centre over cells the follower will accept: the
    follower refuses cells whose exact centre-to-wall-centre distance is below the radius."""
    rng = np.random.default_rng(7)
    data = np.where(rng.random((120, 120)) < 0.004, OCC, FREE).astype(np.int8)
    grid = OccupancyGrid(data, res)
    cm = Costmap.build(grid, RobotConfig(radius=radius), NavigationConfig())
    exact = obstacle_distance(data == OCC, res)
    assert np.all(exact[cm.traversable] >= radius)


def test_penalty_by_hand() -> None:
    nav = NavigationConfig()
    grid = one_obstacle()
    cm = Costmap.build(grid, RobotConfig(), nav)
    c = 30
    lethal_cells = (0.105 + 0.025) / 0.05  # 2.6
    # 5 cells straight out: chamfer exact; penalty decays from the lethal distance
    expected = nav.inflation_cost * math.exp(-nav.cost_scaling * 0.05 * (5 - lethal_cells))
    assert cm.penalty[c, c + 5] == pytest.approx(expected)
    assert cm.clearance[c, c + 5] == pytest.approx(0.25)
    assert cm.penalty[c, c + 12] == 0.0  # beyond the 0.55 m inflation radius
    assert cm.penalty[c + 2, c] == pytest.approx(nav.inflation_cost)  # inside the lethal zone: full cost
    assert np.all(cm.penalty >= 0)


def test_unknown_cells_get_the_unknown_penalty() -> None:
    nav = NavigationConfig(unknown_cost=2.5)
    data = np.full((40, 40), FREE, np.int8)
    data[:, 20:] = UNKNOWN
    data[5, 5] = OCC
    cm = Costmap.build(OccupancyGrid(data, 0.05), RobotConfig(), nav)
    far_unknown = np.zeros((40, 40), bool)
    far_unknown[20:, 20:] = True  # more than 0.55 m from the obstacle
    assert np.all(cm.penalty[far_unknown] == 2.5)
    assert np.all(cm.penalty[30:, :10] == 0.0)  # far free cells
    assert np.all(cm.traversable[data == UNKNOWN])  # unknown is passable
    assert cm.penalty[5, 8] > 0 and cm.penalty[5, 8] < nav.inflation_cost


def test_reachable_known(grid_from_text: TextGrid) -> None:
    rows = [
        "##############################",
        "#............#...............#",
        "#............#...............#",
        "#............#...............#",
        "#............#...............#",
        "#.......................??...#",
        "#.......................??...#",
        "#............#.........?????.#",
        "#............#.........??????#",
        "#............#.........??????#",
        "#............#.........??????#",
        "#............#...............#",
        "##############################",
    ]
    g = grid_from_text(rows)
    cm = Costmap.build(g, RobotConfig(), NavigationConfig())
    start = (6, 4)
    reach = cm.reachable_known(start)
    assert reach[start]
    assert np.all(g.data[reach] == FREE) and np.all(cm.traversable[reach])
    # the door (rows 6-7 of column 13) is 2 cells = 0.1 m wide: too narrow for a 0.21 m robot
    assert not reach[:, 14:].any()
    # everything known-free and traversable on the start side is reached
    left = np.zeros(g.shape, bool)
    left[:, :13] = True
    np.testing.assert_array_equal(reach, left & cm.traversable & (g.data == FREE))


def test_reachable_known_through_a_wide_door_but_not_through_unknown() -> None:
    data = np.full((40, 80), FREE, np.int8)
    data[[0, -1], :] = OCC
    data[:, [0, -1]] = OCC
    data[:, 30] = OCC
    data[14:26, 30] = FREE  # a 0.6 m door
    data[:, 55:58] = UNKNOWN  # the right part is known only through unknown cells
    grid = OccupancyGrid(data, 0.05)
    cm = Costmap.build(grid, RobotConfig(), NavigationConfig())
    reach = cm.reachable_known((20, 10))
    assert reach[20, 45] and reach[20, 30]
    assert not reach[:, 55:].any()
    labels, _ = ndimage.label(cm.traversable & (data == FREE), structure=np.ones((3, 3), bool))
    np.testing.assert_array_equal(reach, labels == labels[20, 10])


def test_reachable_known_snaps_a_start_near_a_wall_and_gives_up_outside() -> None:
    data = np.full((40, 40), FREE, np.int8)
    data[[0, -1], :] = OCC
    data[:, [0, -1]] = OCC
    cm = Costmap.build(OccupancyGrid(data, 0.05), RobotConfig(), NavigationConfig())
    assert not cm.traversable[1, 1]
    reach = cm.reachable_known((1, 1))  # inside the inflated zone: it may back away from the walls
    assert reach[20, 20] and reach[1, 1] and np.all(reach[cm.traversable])
    escape = reach & ~cm.traversable  # the cells it crosses to get out, no closer to a wall than (1, 1)
    assert escape.sum() > 0 and np.all(cm.clearance[escape] >= cm.clearance[1, 1])
    assert not reach[0].any() and not reach[:, 0].any()  # never a wall cell
    assert not cm.reachable_known((-1, 5)).any()
    assert not cm.reachable_known((5, 40)).any()


def test_plan_escapes_from_an_inflated_start_but_not_through_walls() -> None:
    data = np.full((40, 40), FREE, np.int8)
    data[:, 0] = OCC
    data[20, 10:] = OCC
    grid = OccupancyGrid(data, 0.05)
    cm = Costmap.build(grid, RobotConfig(), NavigationConfig())
    start = (10, 1)  # 0.05 m from the wall: not traversable, but the robot may back away
    assert not cm.traversable[start]
    path = cm.plan(start, (10, 20))
    assert len(path) > 0 and tuple(path[0]) == start and tuple(path[-1]) == (10, 20)
    assert np.all(cm.traversable[path[3:, 0], path[3:, 1]])
    assert np.all(data[path[:, 0], path[:, 1]] != OCC)
    # a goal inside the inflated zone or a wall cannot be planned to
    assert cm.plan((10, 20), (20, 20)).shape == (0, 2)
    assert cm.plan((10, 20), (19, 20)).shape == (0, 2)
    assert cm.plan((10, 20), (50, 20)).shape == (0, 2)


def test_a_robot_too_close_to_a_wall_sets_out_from_where_it_can_back_away_to() -> None:
    """The path-cost searches cannot cross the cells the planner lets a robot back away across;
    they set out from the nearest traversable cell the robot gets to across them (with the way
    there), from :meth:`Costmap.departure_near` on a wall cell, and from the robot's cell itself
    when it is traversable or nothing leads out."""
    data = np.full((40, 40), FREE, np.int8)
    data[:, 0] = data[:, -1] = OCC
    cm = Costmap.build(OccupancyGrid(data, 0.05), RobotConfig(), NavigationConfig())
    assert cm.set_out((10, 10)) == [((10, 10), 0.0)]  # traversable
    assert not cm.traversable[10, 1] and not cm.traversable[10, 2] and cm.traversable[10, 3]
    assert cm.set_out((10, 1)) == [((10, 3), pytest.approx(0.1))]  # backs away across (10, 2)
    assert cm.set_out((10, 0)) == [((10, 3), pytest.approx(0.15))]  # on the wall: across free cells
    assert cm.set_out((39, 1)) == [((39, 3), pytest.approx(0.1))]  # on the map's edges
    assert cm.set_out((0, 38)) == [((0, 36), pytest.approx(0.1))]
    data[:, 1:3] = OCC  # now three cells deep: nothing but walls to cross
    cm = Costmap.build(OccupancyGrid(data, 0.05), RobotConfig(), NavigationConfig())
    assert cm.departure_near((10, 0)) == (10, 5)
    assert cm.set_out((10, 0)) == [((10, 5), pytest.approx(0.25))]
    pocket = np.full((20, 20), OCC, np.int8)
    pocket[9:12, 9:12] = FREE  # no cell of it is traversable, none near it either
    cm = Costmap.build(OccupancyGrid(pocket, 0.05), RobotConfig(), NavigationConfig())
    assert cm.set_out((10, 10)) == [((10, 10), 0.0)]
    assert cm.set_out((-1, 3)) == [((-1, 3), 0.0)]  # off the map


def test_a_robot_in_a_gap_sets_out_both_ways() -> None:
    """A robot in a gap narrower than itself (where a leg on the narrow-passage recovery's costmap
    ended) may back out on either side, and the planner has paths both ways."""
    data = np.full((41, 40), FREE, np.int8)
    data[20, :] = OCC
    data[20, 18:22] = FREE  # 0.2 m: closed on the normal costmap
    cm = Costmap.build(OccupancyGrid(data, 0.05), RobotConfig(), NavigationConfig())
    assert not cm.traversable[20, 18:22].any()
    ways = cm.set_out((20, 20))
    assert sorted(cell[0] < 20 for cell, _ in ways) == [False, True]  # one above the wall, one below
    for cell, lead in ways:
        assert cm.traversable[cell] and 0.1 <= lead <= 0.3
    assert len(cm.plan((20, 20), (5, 20))) and len(cm.plan((20, 20), (35, 20)))


@pytest.mark.parametrize("seed", range(3))
def test_plan_works_out_the_step_costs_it_needs_exactly_as_the_cost_array(seed: int) -> None:
    """Costmap.plan computes each cell's cost where it reaches it; on a half-explored office map
    (walls, free and unknown cells, inflation) its paths are those of A* on the whole cost array."""
    world = generate_world("office", seed)
    rng = np.random.default_rng(seed)
    data = world.grid.data.copy()
    data[rng.random(data.shape) < 0.3] = UNKNOWN
    data[:, data.shape[1] // 2 :] = UNKNOWN
    cm = Costmap.build(OccupancyGrid(data, world.grid.resolution), RobotConfig(), NavigationConfig())
    cells = np.argwhere(cm.traversable)
    no_inflation = (np.zeros(data.shape, np.int8), np.zeros(1), 0.0, 0.0)
    for _ in range(15):
        start, goal = (tuple(int(v) for v in cells[k]) for k in rng.choice(len(cells), 2))
        scratch, stamp = SearchScratch().next_search(cm.open_padded.size)
        escape = 0.25 / world.grid.resolution  # Costmap.plan's default
        given = astar_padded(cm.open_padded, cm.clearance_padded, no_inflation, cm.cost_padded, *start, *goal, escape,
                             scratch, stamp)  # fmt: skip
        np.testing.assert_array_equal(cm.plan(start, goal), given)


def test_search_scratch_reused_across_maps_and_stamps_gives_fresh_results() -> None:
    """One scratch serves searches on maps of growing and shrinking size, and survives running out
    of stamps: every path is the one a fresh scratch gives."""
    rng = np.random.default_rng(3)
    shared = SearchScratch()
    for k, size in enumerate((20, 45, 30, 60, 25)):
        data = np.where(rng.random((size, size)) < 0.25, OCC, FREE).astype(np.int8)
        data[rng.random((size, size)) < 0.2] = UNKNOWN
        grid = OccupancyGrid(data, 0.05)
        fresh = Costmap.build(grid, RobotConfig(radius=0.02), NavigationConfig())
        reused = Costmap.build(grid, RobotConfig(radius=0.02), NavigationConfig(), shared)
        if k == 3:
            shared._stamp = astar_module._MAX_STAMP - 1  # the next search must start the stamps afresh
            arrays, stamp = shared.next_search(cells=10)
            assert stamp + 1 <= np.iinfo(np.int32).max  # its closed mark still fits the int32 stamps
            assert not arrays[2].any()  # no stamp left from the searches before
        cells = np.argwhere(fresh.traversable)
        for _ in range(10):
            start, goal = (tuple(int(v) for v in cells[i]) for i in rng.choice(len(cells), 2))
            np.testing.assert_array_equal(reused.plan(start, goal), fresh.plan(start, goal))
    assert shared._stamp < 100  # the stamps did start afresh


# --------------------------------------------------------------------------------- nearest_cell
@pytest.mark.parametrize("seed", range(6))
def test_nearest_cell_matches_brute_force(seed: int) -> None:
    rng = np.random.default_rng(seed)
    mask = rng.random((50, 60)) < 0.01
    cells = np.argwhere(mask)
    for _ in range(20):
        target = (int(rng.integers(50)), int(rng.integers(60)))
        d2 = ((cells - np.array(target)) ** 2).sum(axis=1)
        best = nearest_cell(mask, target, max_radius=100)
        assert best is not None
        assert mask[best]
        assert (best[0] - target[0]) ** 2 + (best[1] - target[1]) ** 2 == d2.min()


def test_nearest_cell_on_the_target_and_none_when_too_far() -> None:
    mask = np.zeros((30, 30), bool)
    mask[5, 5] = True
    assert nearest_cell(mask, (5, 5), max_radius=3) == (5, 5)
    assert nearest_cell(mask, (5, 9), max_radius=4) == (5, 5)
    assert nearest_cell(mask, (20, 20), max_radius=4) is None
    assert nearest_cell(np.zeros((30, 30), bool), (3, 3), max_radius=100) is None


# ------------------------------------------------------------------------------------ footprint
def test_footprint_offsets_for_the_turtlebot() -> None:
    offsets = footprint_offsets(0.105, 0.05)  # reach 2.6 cells: the 5 x 5 square less its corners
    assert offsets.dtype == np.int64 and offsets.shape == (21, 2)
    got = {tuple(o) for o in offsets.tolist()}
    square = {(r, c) for r in range(-2, 3) for c in range(-2, 3)}
    assert got == square - {(-2, -2), (-2, 2), (2, -2), (2, 2)}


@pytest.mark.parametrize(("radius", "res"), [(0.105, 0.05), (0.2, 0.05), (0.105, 0.025), (0.01, 0.05), (0.5, 0.1)])
def test_footprint_offsets_are_the_cells_within_radius_plus_half_a_cell(radius: float, res: float) -> None:
    reach = radius / res + 0.5
    n = int(math.ceil(reach)) + 1
    expected = {(r, c) for r in range(-n, n + 1) for c in range(-n, n + 1) if r * r + c * c < reach * reach}
    offsets = footprint_offsets(radius, res)
    assert {tuple(o) for o in offsets.tolist()} == expected
    assert len(offsets) == len(expected)
    assert [0, 0] in offsets.tolist()  # the robot's own cell


# ------------------------------------------------------------------------------- path following
ROBOT = RobotConfig()
NAV = NavigationConfig()


def params(turn_angle: float = ROBOT.turn_in_place_angle, tol: float = NAV.goal_tolerance,
           radius: float = ROBOT.radius) -> FollowerParams:  # fmt: skip
    return FollowerParams.of(ROBOT, NAV)._replace(turn_in_place_angle=turn_angle, goal_tolerance=tol, radius=radius)


OPEN = np.full((100, 200), 10.0)  # clearance (m) everywhere: no walls
OPEN_ORIGIN = (-1.0, -1.0)


NO_GATE = np.array([1e9, 0.0, 0.0, 0.0, np.inf, np.inf])  # one endless tick, no scan trigger
NO_MATES = np.zeros((0, 2))


def drive(path_xy: NDArray[np.float64], x: float, y: float, theta: float, duration: float,
          p: FollowerParams, clearance: NDArray[np.float64] = OPEN,
          origin: tuple[float, float] = OPEN_ORIGIN, res: float = 0.05,
          gate: NDArray[np.float64] = NO_GATE) -> tuple[float, ...]:  # fmt: skip
    return tuple(
        follow_path(path_xy[:, 0].copy(), path_xy[:, 1].copy(), 0, x, y, theta, duration, p, clearance,
                    NO_MATES, 0.0, origin[0], origin[1], res, gate, careful_flags())
    )  # fmt: skip


def straight(length: float, n: int = 61) -> NDArray[np.float64]:
    return np.column_stack((np.linspace(0.0, length, n), np.zeros(n)))


@pytest.mark.parametrize("length", [1.0, 3.0, 5.5])
@pytest.mark.parametrize("tol", [0.15, 0.02])
def test_follow_path_drives_a_straight_path_at_full_speed(length: float, tol: float) -> None:
    x, y, theta, index, driven, elapsed, status = drive(straight(length), 0.0, 0.0, 0.0, 1000.0, params(tol=tol))
    assert status == 1
    assert index == 60
    assert math.hypot(length - x, y) <= tol + 1e-9
    expected = (length - tol) / ROBOT.max_linear_speed
    assert abs(elapsed - expected) <= 2 * NAV.control_dt
    assert driven == pytest.approx(length - tol, abs=ROBOT.max_linear_speed * NAV.control_dt)
    assert abs(theta) < 1e-6


def test_follow_path_stops_at_the_duration() -> None:
    x, y, _, _, driven, elapsed, status = drive(straight(3.0), 0.0, 0.0, 0.0, 1.0, params())
    assert status == 0
    assert elapsed == pytest.approx(1.0)
    assert driven == pytest.approx(ROBOT.max_linear_speed * 1.0)
    assert x == pytest.approx(0.22) and y == pytest.approx(0.0, abs=1e-9)


def test_follow_path_on_the_goal_reports_reached_at_once() -> None:
    out = drive(straight(1.0), 1.0, 0.05, 0.0, 5.0, params())
    assert out[6] == 1 and out[5] == 0.0 and out[4] == 0.0


def test_follow_path_turns_in_place_when_the_heading_error_is_large() -> None:
    x, y, theta, _, driven, elapsed, status = drive(straight(3.0), 0.0, 0.0, math.pi / 2, 0.2, params())
    assert status == 0
    assert (x, y, driven) == (0.0, 0.0, 0.0)
    assert theta == pytest.approx(math.pi / 2 - ROBOT.max_angular_speed * 0.2)
    assert elapsed == pytest.approx(0.2)


@pytest.mark.parametrize("heading", [math.pi / 2, math.pi / 4, -math.pi / 3, 3.0, -2.0])
def test_turning_in_place_costs_angle_over_omega_max(heading: float) -> None:
    p = params(turn_angle=1e-9)  # turn fully in place before driving
    path = straight(2.0)
    base = drive(path, 0.0, 0.0, 0.0, 1000.0, p)
    turned = drive(path, 0.0, 0.0, heading, 1000.0, p)
    assert base[6] == turned[6] == 1
    assert turned[5] - base[5] == pytest.approx(abs(heading) / ROBOT.max_angular_speed, abs=1e-6)
    assert turned[4] == pytest.approx(base[4], abs=1e-9)  # turning drives no distance


def wall_world() -> tuple[NDArray[np.float64], OccupancyGrid]:
    """1 m x 3 m, a wall across it at x in [1.5, 1.6) m (columns 30-31)."""
    data = np.full((20, 60), FREE, np.int8)
    data[:, 30:32] = OCC
    grid = OccupancyGrid(data, 0.05)
    return obstacle_distance(data == OCC, 0.05), grid


def test_follow_path_refuses_to_enter_cells_closer_than_the_radius_to_a_wall() -> None:
    clearance, grid = wall_world()
    path = np.column_stack((np.linspace(0.525, 2.8, 50), np.full(50, 0.525)))
    x, y, theta, pose_index = 0.525, 0.525, 0.0, 0
    careful = careful_flags()
    status = 0
    for _ in range(400):  # tick by tick, checking every pose on the way
        x, y, theta, pose_index, _, _, status = follow_path(
            path[:, 0],
            path[:, 1],
            pose_index,
            x,
            y,
            theta,
            0.2,
            params(),
            clearance,
            NO_MATES,
            0.0,
            0.0,
            0.0,
            0.05,
            NO_GATE,
            careful,
        )
        row, col = grid.world_to_cell(x, y)
        assert clearance[row, col] >= ROBOT.radius
        if status != 0:
            break
    assert status == 2
    assert x < 1.40  # cell 28 (centre 1.425 m) is 0.1 m from the wall cell centre 1.525 m: too close
    assert x > 1.3


def test_follow_path_with_no_clearance_at_all_is_blocked_at_once() -> None:
    clearance = np.zeros((100, 200))
    out = drive(straight(2.0), 0.0, 0.0, 0.0, 5.0, params(), clearance=clearance)
    assert out[6] == 2
    assert out[0] == 0.0 and out[4] == 0.0
    assert out[5] == 5.0  # blocked, the robot waits out its (single, endless) tick up to the duration


def test_follow_path_stops_at_the_first_tick_where_the_scan_gate_opens() -> None:
    gate = np.array([0.2, 0.0, 0.0, 0.0, 0.5, 10.0])  # ticks of 0.2 s, a scan after 0.5 m
    x, _, _, _, _, elapsed, status = drive(straight(3.0), 0.0, 0.0, 0.0, 100.0, params(), gate=gate)
    assert status == 0
    # at 0.22 m/s the robot passes 0.5 m after 2.27 s: the gate opens at the next tick, 2.4 s
    assert elapsed == pytest.approx(2.4)
    assert x == pytest.approx(0.22 * 2.4)


def test_follow_path_blocked_mid_tick_waits_until_the_tick_ends() -> None:
    clearance = np.zeros((100, 200))
    gate = np.array([0.2, 0.0, 0.0, 0.0, np.inf, np.inf])
    out = drive(straight(2.0), 0.0, 0.0, 0.0, 5.0, params(), clearance=clearance, gate=gate)
    assert out[6] == 2 and out[5] == pytest.approx(0.2)


# ---------------------------------------------------------------------------------------- config
@pytest.mark.parametrize(
    ("kwargs", "named"),
    [
        ({"inflation_radius": 0.0}, "0.0"),
        ({"goal_tolerance": -0.1}, "-0.1"),
        ({"lookahead": math.nan}, "nan"),
        ({"control_dt": math.inf}, "inf"),
        ({"progress_timeout": 0.0}, "0.0"),
        ({"max_recoveries": -1}, "-1"),
        ({"control_dt": 1e-9}, "1e-09"),
        ({"heading_gain": 0.0}, "heading_gain"),
        ({"frontier_check_period": -1.0}, "-1.0"),
        ({"cost_scaling": -50.0}, "-50.0"),
        ({"cost_scaling": math.inf}, "inf"),
        ({"progress_distance": -1.0}, "-1.0"),
        ({"oscillation_distance": math.nan}, "nan"),
        ({"blacklist_radius": -0.1}, "-0.1"),
        ({"inflation_cost": -10.0}, "-10.0"),
        ({"unknown_cost": 1e12}, "1000000000000.0"),
        ({"unknown_cost": math.nan}, "nan"),
        ({"detour_factor": 0.5}, "0.5"),
        ({"detour_factor": math.inf}, "inf"),
        ({"detour_slack": -1.0}, "-1.0"),
        ({"detour_slack": math.nan}, "nan"),
        ({"recovery_detour_factor": 0.9}, "0.9"),
        ({"recovery_detour_slack": -0.5}, "-0.5"),
    ],
)
def test_bad_navigation_config_raises_config_error_naming_the_value(kwargs: dict[str, float], named: str) -> None:
    with pytest.raises(ConfigError, match=named.replace(".", r"\.")):
        NavigationConfig(**kwargs)  # type: ignore[arg-type]


@pytest.mark.parametrize("seed", range(4))
def test_every_reachable_cell_can_be_planned_to(seed: int) -> None:
    """Reachability and the planner agree: on a cluttered, half-known map, every cell the flood
    calls reachable has an A* path from the start (a reachable goal that cannot be planned to
    was blacklisted on real maps, where the flood crossed corners the planner may not cut)."""
    rng = np.random.default_rng(seed)
    data = np.where(rng.random((60, 60)) < 0.04, OCC, FREE).astype(np.int8)
    data[rng.random((60, 60)) < 0.1] = CellState.UNKNOWN
    grid = OccupancyGrid(data, 0.05)
    cm = Costmap.build(grid, RobotConfig(), NavigationConfig())
    starts = np.argwhere(cm.traversable & (data == FREE))[::97]
    # the start with the largest reach among a spread of candidates
    start, reach = max(
        (((int(r), int(c)), cm.reachable_known((int(r), int(c)))) for r, c in starts), key=lambda sr: sr[1].sum()
    )
    cells = np.argwhere(reach)
    assert len(cells) > 20
    for goal in cells[rng.integers(len(cells), size=20)]:
        assert len(cm.plan(start, (int(goal[0]), int(goal[1])))) > 0


@pytest.mark.parametrize("seed", range(4))
def test_a_robot_on_a_wall_cell_of_its_map_plans_to_every_cell_it_can_reach(seed: int) -> None:
    """Wall cells under and around the robot (specks its LiDAR drew there, or a gap only the
    narrow-passage recovery's costmap opened, where a leg ended): what it can reach is flooded
    from the nearest traversable free cell within 0.5 m, and the planner sets out from there too.
    It had planned from the wall cell, found no path to any of the candidates, and blacklisted
    them all (26 goals in one decision on ``willow_full``)."""
    rng = np.random.default_rng(seed)
    free = np.where(rng.random((60, 60)) < 0.04, OCC, FREE).astype(np.int8)
    free[rng.random((60, 60)) < 0.1] = CellState.UNKNOWN
    tried = 0
    for r, c in rng.integers(5, 55, size=(15, 2)):
        data = free.copy()
        data[r - 2 : r + 3, c - 2 : c + 3] = OCC  # the robot's cell, two cells deep in a wall
        cm = Costmap.build(OccupancyGrid(data, 0.05), RobotConfig(), NavigationConfig())
        start = (int(r), int(c))
        departure, reach = cm.departure_near(start), cm.reachable_known(start)
        if departure is None or reach.sum() < 20:
            continue
        tried += 1
        cells = np.argwhere(reach)
        for goal in cells[rng.integers(len(cells), size=5)]:
            path = cm.plan(start, (int(goal[0]), int(goal[1])))
            assert len(path) > 0 and tuple(path[0]) == departure
    assert tried >= 8


@pytest.mark.parametrize("off", [0.3, -0.3, 0.45, -0.45])
def test_a_robot_in_a_slot_one_cell_wide_turns_to_its_waypoint_and_gets_through(off: float) -> None:
    """Only one column of a slot is far enough from both walls; the robot stands at its edge,
    heading a little off the path (less than the turn-in-place angle). Driving on while turning
    would leave the column at the first step; it must face the waypoint on the spot, then go. It
    stood still for ever on stage/mbicp before."""
    data = np.full((40, 9), FREE, np.int8)
    data[:, [0, 1, 7, 8]] = OCC  # free columns 2-6; only column 4 is >= the radius from both walls
    clearance = obstacle_distance(data == OCC, 0.05)
    assert clearance[:, 4].min() >= ROBOT.radius and clearance[:, [3, 5]].max() < ROBOT.radius
    x = 0.2499 if off > 0 else 0.2001  # column 4 spans [0.20, 0.25)
    path = np.column_stack((np.full(30, 0.225), np.linspace(0.35, 1.8, 30)))
    # heading off toward the near wall: a positive ``off`` points right, from the right edge
    *_, status = drive(path, x, 0.3, math.pi / 2 - off, 30.0, params(), clearance, (0.0, 0.0))
    assert status == 1  # reached


def _drive_to_the_end(path_cells: NDArray[np.int64], grid: OccupancyGrid, clearance: NDArray[np.float64]) -> int:
    """The follower's status after driving along ``path_cells`` on the true ``clearance``, a
    half-second at a time with its flags kept for the path, as a leg does: REACHED, or BLOCKED
    where it stops."""
    xy = grid.cells_to_world(path_cells)
    x, y, theta, index, status = float(xy[0, 0]), float(xy[0, 1]), math.pi, 0, 0
    careful = careful_flags()
    for _ in range(200):
        x, y, theta, index, _, _, status = follow_path(
            xy[:, 0], xy[:, 1], index, x, y, theta, 0.5, params(), clearance, NO_MATES, 0.0, *grid.origin,
            grid.resolution, NO_GATE, careful,
        )  # fmt: skip
        if status != FollowStatus.DRIVING:
            break
    return int(status)


def test_a_path_keeps_off_a_wall_the_robot_touched_where_its_map_draws_it_too_near() -> None:
    """The wedge seen on a held-out SLAM map: the map draws a wall a cell nearer than it is, so the
    robot stands, by its map, closer than its radius to it, and the start's escape zone lets a path
    cross the cell beside it, which the true wall (a cell the robot touched) holds closer than the
    radius: the follower refuses it at every replan. Kept off the touched wall, the path goes round."""
    truth = np.full((40, 60), FREE, np.int8)
    truth[:, [0, -1]] = OCC
    truth[25:, :] = OCC
    truth[:16, :] = OCC  # a corridor, rows 16 to 24
    truth[22:25, 29] = OCC  # a pillar reaching up from its floor, beside the robot's column
    mapped = truth.copy()
    mapped[22, 28:31] = OCC  # the map draws the pillar a cell wider on each side
    grid = OccupancyGrid(mapped, 0.05)
    clearance = obstacle_distance(truth == OCC, 0.05)
    start, goal = (20, 30), (20, 10)
    assert clearance[start] >= ROBOT.radius > clearance[20, 29]  # the robot may stand there, not beside
    plain = Costmap.build(grid, ROBOT, NAV)
    assert plain.clearance[start] < ROBOT.radius  # by its map it stands too close: the escape zone is open
    path = plain.plan(start, goal)
    assert (20, 29) in {(int(r), int(c)) for r, c in path}  # across the cell the true pillar is too near
    assert _drive_to_the_end(path, grid, clearance) == FollowStatus.BLOCKED
    felt = np.zeros(truth.shape, bool)
    felt[22, 29] = True  # what the bumper marked when the follower stopped there
    kept_off = plain.with_felt_walls(felt, ROBOT.radius)
    around = kept_off.plan(start, goal)
    assert len(around) and (int(around[-1, 0]), int(around[-1, 1])) == goal
    assert np.all(np.hypot(around[:, 0] - 22, around[:, 1] - 29) * 0.05 >= ROBOT.radius)
    assert _drive_to_the_end(around, grid, clearance) == FollowStatus.REACHED
    assert plain.with_felt_walls(np.zeros(truth.shape, bool), ROBOT.radius) is plain  # nothing felt: as it was


def test_walls_touched_block_the_cells_a_dilation_of_the_whole_map_would() -> None:
    """With touched walls at the map's edges and in its middle, the cells kept off are exactly the
    touched walls dilated by the keep-out disc over the whole map."""
    data = np.full((60, 80), FREE, np.int8)
    cm = Costmap.build(OccupancyGrid(data, 0.05), ROBOT, NAV)
    rng = np.random.default_rng(3)
    for cells in (
        [(0, 0)],
        [(59, 79), (0, 40)],
        [(30, 2), (31, 77)],
        list(zip(rng.integers(0, 60, 5), rng.integers(0, 80, 5), strict=True)),
    ):
        felt = np.zeros(data.shape, bool)
        felt[tuple(np.array(cells).T)] = True
        expected = ndimage.binary_dilation(felt, felt_keep_out(ROBOT.radius, 0.05))
        kept_off = cm.with_felt_walls(felt, ROBOT.radius)
        assert cm.clearance.min() > 0  # open ground: only the blocked cells have no clearance
        np.testing.assert_array_equal(kept_off.clearance == 0, expected)
        np.testing.assert_array_equal(kept_off.traversable, cm.traversable & ~expected)
