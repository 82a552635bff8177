"""The inflation a robot's costmap keeps from map to map equals the inflation of each map worked out
whole, bit for bit, whatever changed between them; and it works out only what a change can reach."""

from __future__ import annotations

import numpy as np
import pytest
from numpy.typing import NDArray

from frontier_rl.core.navigation import inflation
from frontier_rl.core.navigation.inflation import InflationMemory, inflate
from frontier_rl.core.world.grid import CellState, OccupancyGrid

RES = 0.05


def a_map(rng: np.random.Generator, shape: tuple[int, int]) -> NDArray[np.int8]:
    """Free and unknown cells with walls and pillars."""
    data = np.where(rng.random(shape) < 0.3, np.int8(CellState.UNKNOWN), np.int8(CellState.FREE)).astype(np.int8)
    for _ in range(shape[0] * shape[1] // 2000):
        r, c = rng.integers(0, shape[0]), rng.integers(0, shape[1])
        data[r : r + rng.integers(1, 4), c : c + rng.integers(1, 30)] = CellState.OCCUPIED
    return data


def crop(world: NDArray[np.int8], r0: int, r1: int, c0: int, c1: int) -> OccupancyGrid:
    """The cells ``r0:r1``, ``c0:c1`` of ``world``, as a map placed where they lie."""
    return OccupancyGrid(world[r0:r1, c0:c1].copy(), RES, (c0 * RES, r0 * RES))


def assert_whole(memory: InflationMemory, grid: OccupancyGrid, lethal: float, radius: float) -> None:
    clearance, traversable = memory.inflate(grid, lethal, radius)
    whole_clearance, whole_traversable = inflate(grid.data, lethal, radius)
    np.testing.assert_array_equal(clearance, whole_clearance)
    np.testing.assert_array_equal(traversable, whole_traversable)


@pytest.mark.parametrize(("lethal", "radius"), [(2.6, 11.0), (2.9, 6.0), (4.2, 18.3)])
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_a_growing_and_changing_map_inflates_as_a_whole_one(seed: int, lethal: float, radius: float) -> None:
    """A crop that grows on every side in turn while walls appear and vanish (at its edges too,
    and cells turn from unknown to free): each inflation equals the whole map's (lethal 2.9
    puts chamfer values between lethal and surely clear, where the exact look decides)."""
    rng = np.random.default_rng(seed)
    world = a_map(rng, (260, 300))
    memory = InflationMemory()
    r0, r1, c0, c1 = 100, 160, 120, 190
    for step in range(24):
        side = step % 5
        grow = int(rng.integers(1, 25))
        if side == 0:
            r0 = max(r0 - grow, 0)
        elif side == 1:
            r1 = min(r1 + grow, world.shape[0])
        elif side == 2:
            c0 = max(c0 - grow, 0)
        elif side == 3:
            c1 = min(c1 + grow, world.shape[1])
        for _ in range(int(rng.integers(0, 4))):  # walls appear and vanish, and cells become known
            r, c = int(rng.integers(r0, r1)), int(rng.integers(c0, c1))
            world[r : r + 2, c : c + 3] = rng.choice(np.array([CellState.OCCUPIED, CellState.FREE], np.int8))
        world[r0, int(rng.integers(c0, c1))] = CellState.OCCUPIED  # on the crop's edge
        assert_whole(memory, crop(world, r0, r1, c0, c1), lethal, radius)


def test_maps_it_cannot_build_on_are_inflated_whole() -> None:
    """A crop that shrank, one off the lattice of the last, another resolution, another robot:
    each inflated whole, and right."""
    world = a_map(np.random.default_rng(3), (200, 200))
    memory = InflationMemory()
    assert_whole(memory, crop(world, 20, 180, 20, 180), 2.6, 11.0)
    assert_whole(memory, crop(world, 30, 180, 20, 180), 2.6, 11.0)  # shrank
    shifted = crop(world, 20, 180, 20, 180)
    assert_whole(memory, OccupancyGrid(shifted.data, RES, (shifted.origin[0] + 0.02, shifted.origin[1])), 2.6, 11.0)
    assert_whole(memory, OccupancyGrid(shifted.data, 0.03, shifted.origin), 2.6, 11.0)
    assert_whole(memory, crop(world, 20, 180, 20, 180), 3.1, 9.0)


def test_only_what_a_change_can_reach_is_worked_out_again(monkeypatch: pytest.MonkeyPatch) -> None:
    """The same map again costs no inflation, nor do unknown cells turned free (the arrays are
    given again); a wall added in the middle of a large map is inflated on a window around it,
    not on the map."""
    world = a_map(np.random.default_rng(4), (600, 600))
    memory = InflationMemory()
    first = memory.inflate(crop(world, 0, 600, 0, 600), 2.6, 11.0)
    windows: list[tuple[int, int]] = []

    def counted(state: NDArray[np.int8], lethal: float, radius: float) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
        windows.append(state.shape)
        return inflate(state, lethal, radius)

    monkeypatch.setattr(inflation, "inflate", counted)
    assert_whole(memory, crop(world, 0, 600, 0, 600), 2.6, 11.0)
    world[world == CellState.UNKNOWN] = CellState.FREE
    assert_whole(memory, crop(world, 0, 600, 0, 600), 2.6, 11.0)
    assert windows == []
    again = memory.inflate(crop(world, 0, 600, 0, 600), 2.6, 11.0)
    assert again[0] is first[0] and again[1] is first[1]  # the same walls: given again, not copied
    world[300, 300] = CellState.OCCUPIED if world[300, 300] != CellState.OCCUPIED else CellState.FREE
    assert_whole(memory, crop(world, 0, 600, 0, 600), 2.6, 11.0)
    assert len(windows) == 1 and max(windows[0]) < 100, windows
