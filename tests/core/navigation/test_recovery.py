"""The recoveries of a robot in a tight spot: the careful follower's waypoints, and the narrow-passage
recovery's costmap (the map thinned, the robot half a cell slimmer, the walls it touched kept whole)."""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
import pytest
from numpy.typing import NDArray

from frontier_rl.core.frontiers.blacklist import Blacklist
from frontier_rl.core.navigation.config import NavigationConfig
from frontier_rl.core.navigation.costmap import Costmap, felt_keep_out
from frontier_rl.core.navigation.follower import (
    FollowerParams,
    _nearest_waypoint,
    careful_flags,
    follow_path,
    footprint_offsets,
)
from frontier_rl.core.navigation.thin_walls import Recovery, recovery_costmap, recovery_robot
from frontier_rl.core.sim.body import touched_walls
from frontier_rl.core.sim.candidates import find_candidates
from frontier_rl.core.sim.config import SimConfig
from frontier_rl.core.sim.paths import map_blocks_path, recovery_blocks_path
from frontier_rl.core.sim.simulator import ExplorationSimulator
from frontier_rl.core.sim.teammates import obstacle_distance
from frontier_rl.core.sim.trail import mark_path
from frontier_rl.core.world.grid import CellState, OccupancyGrid
from frontier_rl.core.world.robot import Pose, RobotConfig
from frontier_rl.core.world.worlds import make_world

FREE, OCC = CellState.FREE, CellState.OCCUPIED
ROBOT, NAV = RobotConfig(), NavigationConfig()
RES = 0.1  # the coarse SLAM maps where the robot got stuck
NO_MATES = np.zeros((0, 2))
NO_GATE = np.array([1e9, 0.0, 0.0, 0.0, np.inf, np.inf])


def _params() -> FollowerParams:
    return FollowerParams.of(ROBOT, NAV)


def _careful_mode() -> NDArray[np.bool_]:
    """The follower's flags for a robot already following the waypoints one by one."""
    careful = careful_flags()
    careful[0] = True
    return careful


def _centres(cells: list[tuple[int, int]]) -> NDArray[np.float64]:
    return np.array([((c + 0.5) * RES, (r + 0.5) * RES) for r, c in cells])


def test_the_nearest_waypoint_is_found_past_a_path_that_winds_round_a_corner() -> None:
    # down, left, left, up, left, left: the robot stands on the first; the first local minimum
    # searching back from the last lies past the corner
    path = _centres([(5, 5), (6, 5), (6, 4), (6, 3), (5, 3), (5, 2), (5, 1)])
    x, y = path[0, 0] - 0.04, path[0, 1]
    assert _nearest_waypoint(path[:, 0], path[:, 1], 6, x, y, NAV.lookahead) == 0


def test_a_stretch_of_path_driven_long_ago_is_not_searched_even_where_it_passes_closer() -> None:
    # out along row 5 to column 30, down a row, back along row 6: the robot on the way back at
    # column 5, nearer to the way out (0.04 m) than to its own waypoint (0.06 m)
    path = _centres([(5, c) for c in range(31)] + [(6, c) for c in range(30, -1, -1)])
    here = 31 + 25  # (6, 5)
    x, y = path[here, 0], path[here, 1] - 0.06
    assert _nearest_waypoint(path[:, 0], path[:, 1], here + 2, x, y, NAV.lookahead) == here


def _corner_world() -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """A robot at the left edge of cell (5, 5) with a wall at (4, 4): cell (5, 4) is too close to
    the wall to stand in, the planned path goes round it through (6, 5) and (6, 4)."""
    data = np.full((12, 12), FREE, np.int8)
    data[4, 4] = OCC
    clearance = obstacle_distance(data == OCC, RES)
    assert clearance[5, 4] < ROBOT.radius <= clearance[5, 5]
    return clearance, _centres([(5, 5), (6, 4), (6, 3), (6, 2), (6, 1)])


def _follow(path: NDArray[np.float64], clearance: NDArray[np.float64], x: float, y: float, theta: float,
            ticks: int) -> tuple[float, float, list[tuple[int, int]]]:  # fmt: skip
    careful = _careful_mode()
    index, cells = 0, []
    for _ in range(ticks):
        x, y, theta, index, _, _, status = follow_path(
            path[:, 0], path[:, 1], index, x, y, theta, 0.2, _params(), clearance, NO_MATES, 0.0, 0.0, 0.0, RES,
            NO_GATE, careful,
        )  # fmt: skip
        cells.append((math.floor(y / RES), math.floor(x / RES)))
        if status == 1:
            break
    return x, y, cells


def test_a_careful_robot_at_its_cells_edge_steps_back_onto_its_waypoint_instead_of_stalling() -> None:
    clearance, path = _corner_world()
    start_x, start_y = 5 * RES + 0.001, 5.4 * RES  # the cell's left edge, facing the wall's corner
    x, y, cells = _follow(path, clearance, start_x, start_y, math.atan2(path[1, 1] - start_y, path[1, 0] - start_x),
                          200)  # fmt: skip
    assert math.hypot(x - path[-1, 0], y - path[-1, 1]) <= NAV.goal_tolerance + 1e-9  # it got there
    assert all(clearance[c] >= ROBOT.radius for c in cells)  # never into a cell too close to the wall


def test_a_careful_robot_blocked_on_its_waypoint_reports_blocked() -> None:
    clearance, _ = _corner_world()
    path = _centres([(5, 5), (5, 4), (5, 3)])  # straight through the cell too close to the wall
    careful = _careful_mode()
    *_, status = follow_path(path[:, 0], path[:, 1], 0, 5.5 * RES, 5.5 * RES, math.pi, 2.0, _params(), clearance,
                             NO_MATES, 0.0, 0.0, 0.0, RES, NO_GATE, careful)  # fmt: skip
    assert status == 2  # blocked: the bumper may feel the wall, and the leg replans


@pytest.mark.parametrize(
    ("res", "level", "radius"),
    [(0.05, Recovery.NONE, 0.105), (0.05, Recovery.HALF_CELL, 0.08), (0.1, Recovery.HALF_CELL, 0.055),
     (0.05, Recovery.WHOLE_CELL, 0.055), (0.1, Recovery.WHOLE_CELL, 0.025), (0.3, Recovery.HALF_CELL, 0.075)],
)  # fmt: skip
def test_each_recovery_level_plans_for_a_robot_half_a_cell_slimmer_never_thinner_than_a_quarter_cell(
    res: float, level: Recovery, radius: float
) -> None:
    assert recovery_robot(ROBOT, res, level).radius == pytest.approx(radius)


def _gap_map(width: int) -> OccupancyGrid:
    """A wall three cells thick across a 3 m x 2 m map, with a gap ``width`` cells wide (0.1 m cells)."""
    data = np.full((20, 30), FREE, np.int8)
    data[10:13, :] = OCC
    data[10:13, 14 : 14 + width] = FREE
    return OccupancyGrid(data, RES)


def test_a_gap_the_map_closed_opens_on_the_recovery_costmap_and_closes_again_where_it_was_felt() -> None:
    grid = _gap_map(2)  # 0.2 m: the map's walls grew a cell into it (the true gap is wider)
    start, goal = (3, 15), (17, 15)
    assert len(Costmap.build(grid, ROBOT, NAV).plan(start, goal)) == 0
    felt = np.zeros(grid.shape, np.bool_)
    assert len(recovery_costmap(grid, felt, ROBOT, NAV, Recovery.HALF_CELL).plan(start, goal)) > 0
    felt[10:13, 13] = felt[10:13, 16] = True  # the robot touched both sides: the gap really is that narrow
    assert len(recovery_costmap(grid, felt, ROBOT, NAV, Recovery.HALF_CELL).plan(start, goal)) == 0
    blocked = ~recovery_costmap(grid, felt, ROBOT, NAV, Recovery.HALF_CELL).traversable
    assert blocked[9, 13] and blocked[9, 16] and blocked[10, 14]  # within the radius of a felt cell


def test_a_row_of_posts_a_whole_cell_slimmer_robot_fits_between_is_a_candidate_at_the_last_level_only() -> None:
    # single-cell posts 0.2 m apart (the peel never takes a wall's last cell) with the frontier
    # beyond: between two posts the clearance is 2 cells, below the
    # normal (2.6) and the half-cell level's (2.1) margins, above the whole-cell level's (1.6)
    res = 0.05
    data = np.full((110, 61), CellState.UNKNOWN, np.int8)  # a post at either edge
    data[:100, :] = FREE
    data[28, ::4] = OCC  # the frontier 3.6 m beyond them: no goal on this side sees it
    grid = OccupancyGrid(data, res)
    pose = Pose(1.5, 0.5, 0.0)
    config = SimConfig()
    found = {}
    for level in Recovery:
        blacklist = Blacklist(0.25, 2, res, (0.0, 0.0))
        found[level] = len(find_candidates(grid, pose, config, blacklist, data, recovery=level).frontiers)
    assert found[Recovery.NONE] == found[Recovery.HALF_CELL] == 0 < found[Recovery.WHOLE_CELL]


def test_a_step_across_a_corner_whose_two_side_cells_are_too_close_to_a_wall_is_refused() -> None:
    # cells (4, 5) and (5, 4) beside a wall, (4, 4) and (5, 5) clear: the robot in (5, 5) may not
    # slip into (4, 4) across the corner it shares with them
    data = np.full((10, 10), FREE, np.int8)
    data[3, 6] = data[6, 3] = OCC
    clearance = obstacle_distance(data == OCC, RES)
    clearance[4, 5] = clearance[5, 4] = 0.0  # as if walls stood right beside them
    assert clearance[4, 4] >= ROBOT.radius and clearance[5, 5] >= ROBOT.radius
    path = _centres([(5, 5), (4, 4), (3, 3)])
    start_x, start_y = 5 * RES + 0.002, 5 * RES + 0.002  # at the corner
    careful = _careful_mode()
    *_, status = follow_path(path[:, 0], path[:, 1], 0, start_x, start_y, math.atan2(-1.0, -1.0), 2.0, _params(),
                             clearance, NO_MATES, 0.0, 0.0, 0.0, RES, NO_GATE, careful)  # fmt: skip
    assert status == 2  # blocked: through a corner the planner never cuts, the robot does not slip either


def test_a_careful_robot_that_cannot_cross_a_corner_reports_blocked_instead_of_circling() -> None:
    # a staircase one cell wide along a diagonal, as a slimmer robot's plan may take it: the
    # waypoints' cells are clear, the cells beside them too close to a wall, so every step to the
    # next waypoint crosses a corner the robot may not cut. Steering at the next waypoint with an
    # error within the turn-in-place angle, it drifts into a cell beside, steps back onto its
    # waypoint, and used to do so for ever, driving in circles until the leg's progress check
    # gave up 30 s later, with nothing felt, so that the next leg planned the same way.
    clearance = np.zeros((12, 12))
    for k in range(2, 10):
        clearance[k, k] = math.sqrt(2) * RES
    path = _centres([(k, k) for k in range(8, 1, -1)])
    x, y = path[0, 0], path[0, 1]
    theta = math.atan2(-1.0, -1.0) - 0.45  # within the turn-in-place angle of the next waypoint
    careful = _careful_mode()
    index, elapsed, status = 0, 0.0, 0
    while status == 0 and elapsed < 10.0:
        x, y, theta, index, _, used, status = follow_path(
            path[:, 0], path[:, 1], index, x, y, theta, 0.2, _params(), clearance, NO_MATES, 0.0, 0.0, 0.0, RES,
            NO_GATE, careful,
        )  # fmt: skip
        elapsed += max(used, 0.2)
        assert clearance[math.floor(y / RES), math.floor(x / RES)] >= ROBOT.radius  # never into a cell beside
    assert status == 2  # blocked: the bumper feels the walls, and the way is planned anew without the corner


def test_a_staircase_a_slimmer_robot_fits_is_closed_on_the_recovery_costmap_once_the_robot_felt_its_walls() -> None:
    # a diagonal corridor three cells across, its walls where the map has them: the robot's centre
    # fits on the middle cells only, and a step between two of them crosses a corner. Planned a
    # whole cell slimmer the way is open; the robot that reported BLOCKED on it feels the walls
    # round it, and the way is shut there, as the planner never cuts a corner
    data = np.full((16, 16), OCC, np.int8)
    for k in range(16):
        data[k, max(k - 1, 0) : k + 2] = FREE
    grid = OccupancyGrid(data, RES)
    start, goal = (1, 1), (14, 14)
    felt = np.zeros(grid.shape, np.bool_)
    assert len(recovery_costmap(grid, felt, ROBOT, NAV, Recovery.WHOLE_CELL).plan(start, goal)) > 0
    felt[touched_walls(grid, Pose(7.5 * RES, 7.5 * RES, 0.0), ROBOT.radius)] = True
    assert len(recovery_costmap(grid, felt, ROBOT, NAV, Recovery.WHOLE_CELL).plan(start, goal)) == 0


def test_the_way_the_robot_came_stays_open_on_the_recovery_costmap_but_not_beside_a_felt_wall() -> None:
    data = np.full((20, 20), FREE, np.int8)
    data[10, 10] = data[10, 14] = OCC  # single posts: the peel never takes them
    grid = OccupancyGrid(data, RES)
    felt = np.zeros(grid.shape, np.bool_)
    trail = np.zeros(grid.shape, np.bool_)
    trail[11, 8:16] = True  # the robot drove along row 11, a cell from both posts
    plain = recovery_costmap(grid, felt, ROBOT, NAV, Recovery.HALF_CELL).traversable
    assert not plain[11, 10] and not plain[11, 14]  # within the half-cell level's margin of a post
    opened = recovery_costmap(grid, felt, ROBOT, NAV, Recovery.HALF_CELL, trail=trail).traversable
    assert opened[11, 10] and opened[11, 14]
    felt[10, 14] = True  # the robot touched that post: the cell beside it is too close after all
    touched = recovery_costmap(grid, felt, ROBOT, NAV, Recovery.HALF_CELL, trail=trail).traversable
    assert touched[11, 10] and not touched[11, 14]


def test_a_diagonal_trail_is_four_connected_with_both_corner_cells() -> None:
    grid = OccupancyGrid(np.full((10, 10), FREE, np.int8), RES)
    trail = np.zeros(grid.shape, np.bool_)
    mark_path(trail, grid, np.array([[0.25, 0.25], [0.45, 0.45]]))  # cell (2, 2) to cell (4, 4), diagonally
    assert trail[2, 2] and trail[3, 3] and trail[4, 4]
    assert trail[2, 3] and trail[3, 2] and trail[3, 4] and trail[4, 3]
    assert trail.sum() == 7


def _recovery_check(
    data: NDArray[np.int8], felt: NDArray[np.bool_], trail: NDArray[np.bool_], level: Recovery
) -> Callable[[NDArray[np.int64]], bool]:
    """The path check of a leg on ``level``'s costmap, one path cell at a time, as the navigator makes it."""
    footprint = footprint_offsets(recovery_robot(ROBOT, RES, level).radius, RES)
    keep_out = felt_keep_out(ROBOT.radius, RES)

    def blocked(cells: NDArray[np.int64]) -> bool:
        return recovery_blocks_path(data, cells, footprint, felt, trail, keep_out)

    return blocked


def test_the_path_check_leaves_the_trail_open_as_the_recovery_costmap_does_unless_a_felt_wall_is_beside_it() -> None:
    data = np.full((20, 20), FREE, np.int8)
    data[10, 10] = OCC
    felt = np.zeros(data.shape, np.bool_)
    trail = np.zeros(data.shape, np.bool_)
    trail[11, 8:16] = True
    path = np.array([[11, c] for c in range(8, 16)])
    footprint = footprint_offsets(recovery_robot(ROBOT, RES, Recovery.HALF_CELL).radius, RES)
    assert map_blocks_path(data, path, footprint, felt)  # the post beside (11, 10), ignoring the trail
    assert not _recovery_check(data, felt, trail, Recovery.HALF_CELL)(path)
    felt[10, 10] = True
    assert _recovery_check(data, felt, trail, Recovery.HALF_CELL)(path)


@pytest.mark.parametrize("level", [Recovery.HALF_CELL, Recovery.WHOLE_CELL])
def test_no_cell_the_recovery_costmap_lets_the_robot_stand_on_is_walled_for_the_path_check(level: Recovery) -> None:
    # A leg replans when the check finds its path walled: had it called walled a path the planner
    # gives again, the robot would have turned to and fro on the spot, replanning, until the leg
    # was given up, and again for every goal (a robot on its trail beside a wall, 3,100 s of a 50 m
    # floor's episode). Random clutter, unknown cells, felt walls and trail.
    rng = np.random.default_rng(7)
    for _ in range(4):
        data = np.where(rng.random((24, 24)) < 0.12, OCC, FREE).astype(np.int8)
        data[rng.random(data.shape) < 0.05] = CellState.UNKNOWN
        felt = (data == OCC) & (rng.random(data.shape) < 0.3)
        trail = rng.random(data.shape) < 0.3
        standing = recovery_costmap(OccupancyGrid(data, RES), felt, ROBOT, NAV, level, trail=trail).traversable
        blocked = _recovery_check(data, felt, trail, level)
        walled = [(r, c) for r, c in np.argwhere(standing[3:-3, 3:-3]) + 3 if blocked(np.array([[r, c]]))]
        assert walled == []


def test_the_navigator_checks_a_recovery_path_on_the_robots_trail_as_the_recovery_costmap_planned_it() -> None:
    # The robot's map puts a speck beside the cell it stands on, which its trail crossed: the
    # recovery costmap plans from there, so the check of a recovery leg's path must not wall it
    data = np.full((22, 62), FREE, np.int8)
    data[[0, -1], :] = data[:, [0, -1]] = OCC
    sim = ExplorationSimulator(make_world(OccupancyGrid(data, 0.05), "room", start=Pose(1.025, 0.525, 0.0)))
    here = np.array([sim.world.grid.world_to_cell(sim.pose.x, sim.pose.y)])
    sim.mapper.state[here[0, 0] + 1, here[0, 1]] = OCC
    assert sim.navigator.path_blocked(here, 0, Recovery.NONE)
    assert not sim.navigator.path_blocked(here, 0, Recovery.HALF_CELL)
    sim.mapper.felt[here[0, 0] + 1, here[0, 1]] = True  # felt: too close after all
    assert sim.navigator.path_blocked(here, 0, Recovery.HALF_CELL)
