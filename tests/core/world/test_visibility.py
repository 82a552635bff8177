"""The explorable space: free cells in line of sight and range of a cell the robot can stand on."""

from __future__ import annotations

import numpy as np
import pytest

from frontier_rl.core.sensing.lidar import LidarConfig
from frontier_rl.core.sim.config import SimConfig
from frontier_rl.core.sim.simulator import ExplorationSimulator
from frontier_rl.core.world.catalog import generate_world
from frontier_rl.core.world.scale import MAPPING_RANGE_M, ROBOT_RADIUS_M
from frontier_rl.core.world.visibility import visible_from


def open_room(rows: int = 40, cols: int = 40) -> np.ndarray:
    free = np.zeros((rows, cols), bool)
    free[1:-1, 1:-1] = True
    return free


def test_viewers_are_visible_and_only_free_cells_are() -> None:
    free = open_room()
    free[10:30, 20] = False  # a wall segment inside the room
    viewers = np.zeros_like(free)
    viewers[5, 5] = True
    seen = visible_from(free, viewers, 100.0)
    assert seen[5, 5] and not (seen & ~free).any()


def test_range_limits_what_is_seen() -> None:
    free = np.zeros((3, 60), bool)
    free[1, :] = True  # a corridor one cell wide
    viewers = np.zeros_like(free)
    viewers[1, 0] = True
    seen = visible_from(free, viewers, 20.0)
    assert seen[1, :21].all() and not seen[1, 22:].any()


def test_a_closed_room_is_not_seen_and_a_slot_shows_a_cone() -> None:
    free = open_room(40, 81)
    free[:, 38:43] = False  # a wall five cells thick between two rooms
    viewers = np.zeros_like(free)
    viewers[5:35, 5:35] = True  # the robot moves anywhere in the left room, away from the wall
    assert not visible_from(free, viewers, 200.0)[:, 43:].any()
    free[20, 38:43] = True  # a slot one cell wide through it
    seen = visible_from(free, viewers, 200.0)
    assert seen[20, 43:80].all()  # straight through the slot
    assert seen[:, 43:].sum() < 0.5 * free[:, 43:].sum()  # not the corners beside the wall
    assert not seen[1:5, 43:50].any() and not seen[35:39, 43:50].any()


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_it_agrees_with_a_brute_force_line_check(seed: int) -> None:
    """Against straight lines sampled every 1/16 cell from each cell's centre to points of the
    viewer cell (the robot stands anywhere in it): a line to the viewer's centre that is clear is
    seen; a cell is seen only if a line to some point of the viewer cell is clear. Lines that
    graze a wall's corner may go either way, so a few cells may differ, never many."""
    rng = np.random.default_rng(seed)
    free = open_room(24, 24) & (rng.random((24, 24)) > 0.15)
    viewers = np.zeros_like(free)
    viewers[12, 12] = free[12, 12] = True
    seen = visible_from(free, viewers, 30.0)

    def clear(r: int, c: int, vr: float, vc: float) -> bool:
        n = 16 * max(abs(r - 12), abs(c - 12), 1)
        t = np.linspace(0.0, 1.0, n + 1)
        rows = np.floor(r + 0.5 + (vr - r - 0.5) * t).astype(int)
        cols = np.floor(c + 0.5 + (vc - c - 0.5) * t).astype(int)
        return bool(free[rows, cols].all())

    points = [(12.0 + a, 12.0 + b) for a in (0.05, 0.5, 0.95) for b in (0.05, 0.5, 0.95)]
    to_centre = np.zeros_like(free)
    to_any = np.zeros_like(free)
    for r, c in zip(*np.nonzero(free), strict=True):
        to_centre[r, c] = clear(int(r), int(c), 12.5, 12.5)
        to_any[r, c] = any(clear(int(r), int(c), vr, vc) for vr, vc in points)
    assert to_centre.sum() > 15
    assert np.count_nonzero(to_centre & ~seen) <= 0.05 * np.count_nonzero(to_centre)
    assert np.count_nonzero(seen & ~to_any) <= 0.05 * np.count_nonzero(seen)


def test_a_simulator_with_a_shorter_lidar_recomputes_the_explorable_space() -> None:
    world = generate_world("office", 0)
    assert (world.robot_radius, world.sensor_range) == (ROBOT_RADIUS_M, MAPPING_RANGE_M)
    assert ExplorationSimulator(world).world is world  # the defaults: nothing to recompute
    short = SimConfig(lidar=LidarConfig(max_range=1.0))
    sim = ExplorationSimulator(world, short)
    assert sim.world.sensor_range == 1.0 and sim.world.start == world.start
    assert np.array_equal(sim.world.grid.data, world.grid.data)
    assert not (sim.world.explorable & ~world.explorable).any()
    assert sim.world.explorable_count <= world.explorable_count
