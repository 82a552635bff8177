"""Tests of frontier_rl.core.world.worlds: World, make_world and the procedural world generators."""

from __future__ import annotations

import math
from functools import cache

import numpy as np
import pytest
from numpy.typing import NDArray
from scipy import ndimage

from frontier_rl.core.world.catalog import WORLD_GENERATORS, cluttered_world, generate_world, office_world, rooms_world
from frontier_rl.core.world.grid import CellState, OccupancyGrid
from frontier_rl.core.world.robot import Pose
from frontier_rl.core.world.scale import MAPPING_RANGE_M, ROBOT_RADIUS_M, START_MARGIN_M
from frontier_rl.core.world.visibility import visible_from
from frontier_rl.core.world.worlds import World, dilate, make_world
from frontier_rl.errors import ConfigError, MapError, UnknownNameError

NAMES = sorted(WORLD_GENERATORS)
SEEDS = [0, 1, 7, 2024]
CASES = [(name, seed) for name in NAMES for seed in SEEDS]
FREE, OCC, UNKNOWN = CellState.FREE.value, CellState.OCCUPIED.value, CellState.UNKNOWN.value
EIGHT = np.ones((3, 3), dtype=bool)


@cache
def world(name: str, seed: int) -> World:
    return generate_world(name, seed)


def grid_of(rows: list[str], resolution: float = 0.05, origin: tuple[float, float] = (0.0, 0.0)) -> OccupancyGrid:
    """Grid from text rows, top row first: '.' free, '#' occupied, '?' unknown."""
    value = {".": FREE, "#": OCC, "?": UNKNOWN}
    data = np.array([[value[ch] for ch in row] for row in reversed(rows)], dtype=np.int8)
    return OccupancyGrid(data, resolution, origin)


def open_room(rows: int, cols: int, resolution: float = 0.05) -> OccupancyGrid:
    data = np.full((rows, cols), OCC, dtype=np.int8)
    data[2:-2, 2:-2] = FREE
    return OccupancyGrid(data, resolution)


def reference(grid: OccupancyGrid, start_cell: tuple[int, int], radius: float) -> tuple[NDArray[np.bool_], ...]:
    """(free component, reachable, explorable) from the definitions: distance transforms, labels
    (4-connected, as the planner moves) and the line-of-sight kernel (tested on its own)."""
    res = grid.resolution
    free = grid.data == FREE
    components, _ = ndimage.label(free)
    inside = components == components[start_cell]
    clearance = ndimage.distance_transform_edt(np.pad(free, 1))[1:-1, 1:-1] * res
    parts, _ = ndimage.label(clearance >= radius)
    reachable = parts == parts[start_cell]
    explorable = visible_from(inside, reachable, MAPPING_RANGE_M / res)
    return inside, reachable, explorable


def start_cell(w: World) -> tuple[int, int]:
    return w.grid.world_to_cell(w.start.x, w.start.y)


# ----------------------------------------------------------------------------- generated worlds
@pytest.mark.parametrize("name", NAMES)
def test_same_seed_gives_the_same_world(name: str) -> None:
    a, b = generate_world(name, 11), generate_world(name, 11)
    c = generate_world(name, np.random.default_rng(11))
    for other in (b, c):
        assert np.array_equal(a.grid.data, other.grid.data)
        assert np.array_equal(a.explorable, other.explorable)
        assert a.start == other.start
    assert a.name == name


@pytest.mark.parametrize("name", NAMES)
def test_different_seeds_give_different_worlds(name: str) -> None:
    grids = [world(name, seed).grid.data for seed in SEEDS]
    for i in range(len(grids)):
        for j in range(i + 1, len(grids)):
            assert not np.array_equal(grids[i], grids[j])
    assert len({world(name, seed).start for seed in SEEDS}) == len(SEEDS)


@pytest.mark.parametrize(("name", "seed"), CASES)
def test_only_free_and_occupied_cells(name: str, seed: int) -> None:
    data = world(name, seed).grid.data
    assert data.dtype == np.int8
    assert set(np.unique(data).tolist()) == {FREE, OCC}


@pytest.mark.parametrize(("name", "seed"), CASES)
def test_border_is_a_wall_at_least_two_cells_thick(name: str, seed: int) -> None:
    occ = world(name, seed).grid.data == OCC
    assert occ[:2, :].all() and occ[-2:, :].all() and occ[:, :2].all() and occ[:, -2:].all()


@pytest.mark.parametrize(("name", "seed"), [case for case in CASES if case[0] != "slam_building"])
def test_walls_are_never_one_cell_thin(name: str, seed: int) -> None:
    # slam_building is left out by design: a SLAM map's specks, slits and streaks are one cell wide
    occ = world(name, seed).grid.data == OCC
    # every occupied cell lies in a fully occupied 2x2 block ...
    block = occ[:-1, :-1] & occ[1:, :-1] & occ[:-1, 1:] & occ[1:, 1:]
    covered = np.zeros_like(occ)
    for dr in (0, 1):
        for dc in (0, 1):
            covered[dr : dr + block.shape[0], dc : dc + block.shape[1]] |= block
    assert not (occ & ~covered).any(), np.argwhere(occ & ~covered)[:5]
    # ... and no two walls touch only at a corner (a ray could slip between them)
    a, b, c, d = occ[:-1, :-1], occ[1:, 1:], occ[:-1, 1:], occ[1:, :-1]
    assert not ((a & b & ~c & ~d) | (c & d & ~a & ~b)).any()


@pytest.mark.parametrize(("name", "seed"), CASES)
def test_free_space_is_one_component_and_start_is_reachable(name: str, seed: int) -> None:
    w = world(name, seed)
    free = w.grid.data == FREE
    _, count = ndimage.label(free)
    assert count == 1
    cell = start_cell(w)
    assert w.grid.in_bounds(*cell) and free[cell]
    _, reachable, _ = reference(w.grid, cell, ROBOT_RADIUS_M)
    assert reachable[cell]
    clearance = ndimage.distance_transform_edt(np.pad(free, 1))[1:-1, 1:-1] * w.grid.resolution
    assert clearance[cell] >= ROBOT_RADIUS_M + START_MARGIN_M - 1e-9
    assert -math.pi <= w.start.theta < math.pi


@pytest.mark.parametrize(("name", "seed"), CASES)
def test_explorable_is_free_and_covers_nearly_all_of_it(name: str, seed: int) -> None:
    w = world(name, seed)
    free = w.grid.data == FREE
    assert w.explorable.dtype == np.bool_ and w.explorable.shape == w.grid.shape
    assert not (w.explorable & ~free).any()
    assert w.explorable_count >= 0.95 * np.count_nonzero(free)
    assert w.explorable_count == np.count_nonzero(w.explorable)
    # most of the map is floor, not wall
    assert np.count_nonzero(free) >= 0.5 * free.size


@pytest.mark.parametrize(("name", "seed"), CASES)
def test_explorable_matches_its_definition(name: str, seed: int) -> None:
    w = world(name, seed)
    _, _, explorable = reference(w.grid, start_cell(w), ROBOT_RADIUS_M)
    assert np.array_equal(w.explorable, explorable)


@pytest.mark.parametrize(("name", "seed"), CASES)
def test_world_arrays_are_read_only(name: str, seed: int) -> None:
    w = world(name, seed)
    with pytest.raises(ValueError, match="read-only"):
        w.grid.data[5, 5] = FREE
    with pytest.raises(ValueError, match="read-only"):
        w.explorable[5, 5] = True


def test_world_sizes() -> None:
    office = world("office", 0)
    assert office.grid.shape == (250, 250) and office.grid.resolution == 0.05
    assert office.grid.origin == (0.0, 0.0)
    assert world("rooms", 0).grid.shape == (240, 320)  # 16 m wide (x, columns), 12 m high
    assert world("cluttered", 0).grid.shape == (240, 240)
    rng = np.random.default_rng(3)
    assert office_world(rng, size_m=8.0, resolution=0.1).grid.shape == (80, 80)
    assert rooms_world(rng, size_m=(10.0, 6.0)).grid.shape == (120, 200)
    assert cluttered_world(rng, size_m=6.0).grid.shape == (120, 120)


@pytest.mark.parametrize("seed", SEEDS)
def test_office_is_a_walled_maze_with_pillars(seed: int) -> None:
    occ = world("office", seed).grid.data == OCC
    labels, _ = ndimage.label(occ, structure=EIGHT)
    sizes = np.bincount(labels.ravel())[1:]
    assert np.count_nonzero(sizes <= 64) >= 1  # free-standing pillars: squares of at most 0.4 m
    assert sizes.max() >= 0.08 * occ.size  # the outer wall and the inner walls joined to it


@pytest.mark.parametrize("seed", SEEDS)
def test_cluttered_world_has_many_obstacles(seed: int) -> None:
    occ = world("cluttered", seed).grid.data == OCC
    assert ndimage.label(occ, structure=EIGHT)[1] >= 15
    assert 0.08 <= np.count_nonzero(occ) / occ.size <= 0.5


def test_generator_size_errors_name_the_value() -> None:
    rng = np.random.default_rng(0)
    with pytest.raises(ConfigError, match="-1"):
        office_world(rng, size_m=-1.0)
    with pytest.raises(ConfigError, match="nan"):
        rooms_world(rng, size_m=(float("nan"), 12.0))
    with pytest.raises(ConfigError, match=r"got 0\.0"):
        cluttered_world(rng, resolution=0.0)
    with pytest.raises(ConfigError, match="narrower"):
        office_world(rng, size_m=1.0)


def test_unknown_world_name() -> None:
    with pytest.raises(UnknownNameError, match="'forest'") as info:
        generate_world("forest", 0)
    message = str(info.value)
    assert all(name in message for name in NAMES)
    assert isinstance(info.value, KeyError)


def test_registry_is_read_only() -> None:
    assert set(WORLD_GENERATORS) == {"office", "rooms", "cluttered", "building", "cave", "slam_building"}
    with pytest.raises(TypeError):
        WORLD_GENERATORS["forest"] = office_world  # type: ignore[index]


# ----------------------------------------------------------------------------------- make_world
def test_make_world_turns_unknown_and_cut_off_free_cells_into_walls() -> None:
    data = np.full((40, 60), OCC, dtype=np.int8)
    data[2:38, 2:30] = FREE  # main room
    data[10:20, 10:20] = UNKNOWN  # unknown island inside it
    data[2:38, 34:58] = FREE  # a second room, cut off by a wall
    grid = OccupancyGrid(data, 0.05, (-1.0, 2.0))
    start = Pose(-1.0 + 5 * 0.05 + 0.025, 2.0 + 5 * 0.05 + 0.025, 0.5)
    w = make_world(grid, "two rooms", start=start)
    assert w.start == start and w.name == "two rooms"
    assert w.grid.origin == (-1.0, 2.0) and w.grid.resolution == 0.05
    expected = np.full_like(data, OCC)
    expected[2:38, 2:30] = FREE
    expected[10:20, 10:20] = OCC
    assert np.array_equal(w.grid.data, expected)
    assert data[10, 10] == UNKNOWN  # the input is left alone
    inside, _, explorable = reference(grid, (5, 5), ROBOT_RADIUS_M)
    assert np.array_equal(w.explorable, explorable)
    assert np.array_equal(inside, expected == FREE)


def test_make_world_matches_the_definitions_on_a_ragged_map() -> None:
    rng = np.random.default_rng(5)
    noise = ndimage.uniform_filter(rng.random((120, 150)), 5)
    data = np.where(noise > 0.47, FREE, OCC).astype(np.int8)
    data[rng.random(data.shape) < 0.01] = UNKNOWN
    grid = OccupancyGrid(data, 0.05)
    for seed in range(5):
        w = make_world(grid, "ragged", rng=np.random.default_rng(seed), robot_radius=0.12)
        cell = start_cell(w)
        inside, reachable, explorable = reference(grid, cell, 0.12)
        assert np.array_equal(w.grid.data == FREE, inside)
        assert np.array_equal(w.explorable, explorable)
        # the random start lies in the largest region the robot can move in, with the extra margin
        clearance = ndimage.distance_transform_edt(np.pad(data == FREE, 1))[1:-1, 1:-1] * 0.05
        parts, _ = ndimage.label(clearance >= 0.12)
        assert parts[cell] == np.argmax(np.bincount(parts.ravel())[1:]) + 1
        assert reachable[cell] and clearance[cell] >= 0.12 + START_MARGIN_M


def test_make_world_random_start_is_seeded() -> None:
    grid = open_room(50, 70)
    a = make_world(grid, "room", rng=np.random.default_rng(3))
    b = make_world(grid, "room", rng=np.random.default_rng(3))
    c = make_world(grid, "room", rng=np.random.default_rng(4))
    assert a.start == b.start and a.start != c.start


def test_dilate_matches_the_distance_transform() -> None:
    rng = np.random.default_rng(2)
    mask = rng.random((60, 80)) < 0.02
    dist = ndimage.distance_transform_edt(~mask)
    for radius in (1.0, 2.1, 3.0, 4.1, 6.5):
        assert np.array_equal(dilate(mask, radius), dist <= radius)
        assert np.array_equal(dilate(mask, radius, strict=True), dist < radius)


@pytest.mark.parametrize(
    ("start", "match"),
    [
        (Pose(0.06, 0.06), r"start pose \(0\.06, 0\.06\) is inside a wall"),
        (Pose(5.0, 0.5), r"start pose \(5\.00, 0\.50\) is outside the grid"),
        (Pose(0.5, -0.01), r"start pose \(0\.50, -0\.01\) is outside the grid"),
        (Pose(0.12, 0.5), r"start pose \(0\.12, 0\.50\) is too close to a wall: clearance 0\.050 m"),
        (Pose(float("nan"), 0.5), r"start pose \(nan, 0\.50\)"),
        (Pose(1e300, -1e300), r"start pose \(1e\+300, -1e\+300\) is outside the grid \(x in"),  # not 300 digits
    ],
)
def test_make_world_rejects_bad_starts(start: Pose, match: str) -> None:
    with pytest.raises(MapError, match=match):
        make_world(open_room(30, 40), "room", start=start)  # 2.0 m x 1.5 m, free from 0.10 m to 1.90 m


def test_make_world_rejects_a_start_on_unknown_cells() -> None:
    grid = grid_of(["######", "#??..#", "#....#", "######"], resolution=0.5)
    with pytest.raises(MapError, match=r"start pose \(0\.75, 1\.25\) is on an unknown cell"):
        make_world(grid, "unknown", start=Pose(0.75, 1.25))


def test_make_world_rejects_maps_without_room_for_the_robot() -> None:
    no_free = OccupancyGrid(np.full((20, 20), OCC, dtype=np.int8), 0.05)
    with pytest.raises(MapError, match="map has no free cell with clearance for the robot"):
        make_world(no_free, "solid", rng=np.random.default_rng(0))
    unknown = OccupancyGrid(np.full((20, 20), UNKNOWN, dtype=np.int8), 0.05)
    with pytest.raises(MapError, match="map has no free cell"):
        make_world(unknown, "unknown", start=Pose(0.5, 0.5))
    slot = np.full((20, 40), OCC, dtype=np.int8)
    slot[9:12, 2:38] = FREE  # a corridor 0.15 m wide: the robot (radius 0.105 m) does not fit
    with pytest.raises(MapError, match=r"no free cell with clearance for the robot \(radius 0\.105 m"):
        make_world(OccupancyGrid(slot, 0.05), "slot", rng=np.random.default_rng(0))
    slot[8:13, 2:38] = FREE  # 0.25 m wide: fits the robot, but not a random start's extra margin
    with pytest.raises(MapError, match=r"a random start needs 0\.155 m"):
        make_world(OccupancyGrid(slot, 0.05), "slot", rng=np.random.default_rng(0))
    w = make_world(OccupancyGrid(slot, 0.05), "slot", start=Pose(1.0, 0.525))  # a given start may be tight
    assert w.explorable_count == np.count_nonzero(slot == FREE)


def test_make_world_config_errors() -> None:
    with pytest.raises(ConfigError, match="start=None, rng=None"):
        make_world(open_room(30, 30), "room")
    with pytest.raises(ConfigError, match=r"robot_radius .* got -0\.1"):
        make_world(open_room(30, 30), "room", rng=np.random.default_rng(0), robot_radius=-0.1)


def test_world_rejects_a_mismatched_explorable_mask() -> None:
    grid = open_room(10, 10)
    with pytest.raises(MapError, match=r"shape \(10, 10\)"):
        World("bad", grid, Pose(0.25, 0.25), np.ones((5, 5), dtype=bool))
