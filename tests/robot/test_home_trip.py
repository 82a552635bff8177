"""The way home as a node drives it (:class:`~frontier_rl.robot.home_trip.HomeTrip`): its path kept
to the map while the robot follows it, and the tries Nav2 may give it up."""

from __future__ import annotations

import math

import numpy as np

from frontier_rl.core.navigation.thin_walls import Recovery
from frontier_rl.core.world.grid import CellState, OccupancyGrid
from frontier_rl.core.world.robot import Pose
from frontier_rl.policies.registry import make_policy
from frontier_rl.robot.explorer import FrontierExplorer
from frontier_rl.robot.home_trip import HomeTrip
from frontier_rl.robot.way_home import HOME_TRIES
from tests.robot.test_explorer import rooms_with_a_narrow_door


def _trip() -> tuple[HomeTrip, OccupancyGrid]:
    explorer = FrontierExplorer(make_policy("nearest"))
    grid = rooms_with_a_narrow_door()
    assert explorer.tick(grid, Pose(1.0, 1.5, 0.0), 0.0) is not None  # the start, in the west room
    return HomeTrip(explorer), grid


def test_the_path_home_is_planned_afresh_round_what_the_map_now_draws_on_it() -> None:
    trip, grid = _trip()
    home = trip.send(grid, Pose(4.0, 1.5, 0.0))
    assert home is not None and home.path is not None and home.recovery is Recovery.HALF_CELL
    assert trip.under_way and trip.tries == 1
    assert np.any(np.hypot(home.path[:, 0] - 3.0, home.path[:, 1] - 1.5) < 0.1)  # straight for the door
    redrawn = OccupancyGrid(grid.data.copy(), grid.resolution, grid.origin)
    redrawn.data[22:38, 58:62] = CellState.OCCUPIED  # a wall drawn across the old path at x = 3 m
    renewal = trip.renew(redrawn, Pose(3.5, 1.5, 0.0))
    assert renewal is not None and renewal.goal.path is not None and trip.goal is renewal.goal
    renewed = renewal.goal
    assert math.dist(renewed.path[0], (3.5, 1.5)) < 0.1 and math.dist(renewed.path[-1], (1.0, 1.5)) < 0.05
    assert not np.any(np.hypot(renewed.path[:, 0] - 3.0, renewed.path[:, 1] - 1.5) < 0.3)  # round it
    assert trip.tries == 1  # planned afresh is no new try


def test_a_path_home_with_no_way_left_to_its_end_is_not_renewed() -> None:
    trip, grid = _trip()
    home = trip.send(grid, Pose(4.0, 1.5, 0.0))
    closed = OccupancyGrid(grid.data.copy(), grid.resolution, grid.origin)
    closed.data[28:32, 49:51] = CellState.OCCUPIED  # the door drawn shut
    assert trip.renew(closed, Pose(4.0, 1.5, 0.0)) is None and trip.goal is home  # the controller gives it up


def test_a_point_goal_home_is_left_to_nav2_to_replan() -> None:
    trip, grid = _trip()
    home = trip.send(grid, Pose(2.0, 1.0, 0.0))  # in the start's room: no path of ours
    assert home is not None and home.path is None
    assert trip.renew(grid, Pose(1.8, 1.1, 0.0)) is None


def test_the_tries_count_the_ways_sent_but_not_those_sent_again_after_a_pause() -> None:
    trip, grid = _trip()
    assert not trip.under_way and trip.renew(grid, Pose(4.0, 1.5, 0.0)) is None
    for _ in range(HOME_TRIES - 1):
        trip.send(grid, Pose(4.0, 1.5, 0.0))
    trip.send(grid, Pose(4.0, 1.5, 0.0), counted=False)
    assert trip.tries_left
    trip.send(grid, Pose(4.0, 1.5, 0.0))
    assert not trip.tries_left
    trip.end()
    assert not trip.under_way


def test_no_way_home_before_the_explorer_ticked() -> None:
    trip = HomeTrip(FrontierExplorer(make_policy("nearest")))
    assert trip.send(rooms_with_a_narrow_door(), Pose(4.0, 1.5, 0.0)) is None and not trip.under_way
