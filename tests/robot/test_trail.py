"""The real robot's trail: kept in the map frame, drawn on each map's cells as it grows."""

from __future__ import annotations

import numpy as np

from frontier_rl.core.sim.trail import mark_path
from frontier_rl.core.world.grid import OccupancyGrid
from frontier_rl.robot.trail import TRAIL_JUMP_M, TRAIL_SPACING_M, Trail


def _grid(shape: tuple[int, int] = (40, 60), origin: tuple[float, float] = (0.0, 0.0)) -> OccupancyGrid:
    return OccupancyGrid(np.zeros(shape, np.int8), 0.05, origin)


def _walk() -> np.ndarray:
    """An L of poses 2 cm apart: east along y = 0.52 m, then north along x = 2.02 m."""
    east = np.column_stack((0.12 + 0.02 * np.arange(96), np.full(96, 0.52)))
    north = np.column_stack((np.full(60, 2.02), 0.54 + 0.02 * np.arange(60)))
    return np.concatenate((east, north))


def test_the_trail_is_the_polyline_of_the_poses_and_poses_closer_than_its_spacing_add_nothing() -> None:
    trail, points = Trail(), _walk()
    for x, y in points:
        trail.add(float(x), float(y))
        trail.add(float(x) + TRAIL_SPACING_M / 2, float(y))
    trail.add(float("nan"), 1.0)
    assert len(trail) == len(points)
    grid = _grid()
    expected = np.zeros(grid.shape, np.bool_)
    mark_path(expected, grid, points)
    assert np.array_equal(trail.on(grid), expected)


def test_drawn_as_the_robot_goes_is_drawn_at_once_and_a_grown_map_draws_the_same_places() -> None:
    grid, points = _grid(), _walk()
    as_it_goes = Trail()
    for i, (x, y) in enumerate(points):
        as_it_goes.add(float(x), float(y))
        if i % 7 == 0:
            as_it_goes.on(grid)
    at_once = Trail()
    for x, y in points:
        at_once.add(float(x), float(y))
    assert np.array_equal(as_it_goes.on(grid), at_once.on(grid))
    grown = _grid((60, 90), origin=(-0.5, -0.25))  # a SLAM map grows west and south: 10 and 5 cells
    assert np.array_equal(at_once.on(grown)[5:45, 10:70], at_once.on(grid))
    assert np.count_nonzero(at_once.on(grown)) == np.count_nonzero(at_once.on(grid))


def test_a_pose_that_jumps_starts_a_new_stretch_not_a_line_across() -> None:
    trail = Trail()
    for x in np.arange(0.1, 0.6, 0.02):
        trail.add(float(x), 0.5)
    far = 0.58 + TRAIL_JUMP_M + 0.2  # a relocalisation: no way the robot drove
    trail.add(far, 0.5)
    trail.add(far + 0.02, 0.5)
    row = trail.on(_grid())[10]
    landed = int(far / 0.05)
    assert row[2:12].all() and not row[12:landed].any() and row[landed]


def test_poses_half_a_metre_apart_as_slam_toolbox_publishes_them_are_one_line() -> None:
    trail = Trail()
    for x in (0.1, 0.65, 1.2, 1.75, 2.3, 2.85):
        trail.add(x, 0.5)
    assert trail.on(_grid())[10, 2:58].all()


def test_a_diagonal_drawn_pose_by_pose_is_the_diagonal_drawn_at_once() -> None:
    grid, points = _grid(), np.column_stack((0.12 + 0.013 * np.arange(120), 0.11 + 0.011 * np.arange(120)))
    pose_by_pose, at_once = Trail(), Trail()
    for x, y in points:
        pose_by_pose.add(float(x), float(y))
        pose_by_pose.on(grid)  # drawn as each pose comes: each piece joined to the one before
        at_once.add(float(x), float(y))
    assert np.array_equal(pose_by_pose.on(grid), at_once.on(grid))
