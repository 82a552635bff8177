"""The cave generator: one system of tunnels and chambers, no passage too narrow, a cropped map.

The properties every generated world shares (one free component, walls never one cell thin, a
reachable start, the explorable space's definition) are tested over every generator in
``test_worlds.py``."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import ndimage

from frontier_rl.core.world import cave
from frontier_rl.core.world.catalog import CAVE_MIN_M, cave_world
from frontier_rl.core.world.grid import CellState
from frontier_rl.errors import ConfigError

SEEDS = range(8)
EIGHT = np.ones((3, 3), dtype=bool)


@pytest.mark.parametrize("seed", SEEDS)
def test_no_passage_is_narrower_than_half_a_metre(seed: int) -> None:
    """Every floor cell lies in a free square of 0.5 m: an opening by that square keeps them all."""
    world = cave_world(np.random.default_rng(seed))
    floor = world.grid.data == CellState.FREE
    side = round(cave.CAVE_NARROWEST_BLOCKS * cave.CAVE_BLOCK_M / world.grid.resolution)
    assert np.array_equal(ndimage.binary_opening(floor, np.ones((side, side), bool)) & floor, floor)


@pytest.mark.parametrize("seed", SEEDS)
def test_the_map_is_cropped_to_the_cave_with_one_block_of_rock_around(seed: int) -> None:
    world = cave_world(np.random.default_rng(seed))
    floor = world.grid.data == CellState.FREE
    rows, cols = np.flatnonzero(floor.any(axis=1)), np.flatnonzero(floor.any(axis=0))
    block = round(cave.CAVE_BLOCK_M / world.grid.resolution)
    assert (rows[0], cols[0]) == (block, block)
    assert (rows[-1], cols[-1]) == (floor.shape[0] - 1 - block, floor.shape[1] - 1 - block)
    assert floor.shape[0] * 0.05 <= 20.0 + 2 * cave.CAVE_BLOCK_M and floor.shape[1] * 0.05 <= 26.0 + 0.5


@pytest.mark.parametrize("seed", SEEDS)
def test_a_cave_has_chambers_tunnels_and_pillars(seed: int) -> None:
    """Not one open hall and not a mere tunnel: the floor is at most 4/5 of the map, rock stands
    free inside it, and a chamber is 2 m across."""
    world = cave_world(np.random.default_rng(seed))
    floor = world.grid.data == CellState.FREE
    assert cave.CAVE_MIN_FLOOR <= np.count_nonzero(floor) / floor.size <= 0.8
    rock_parts = ndimage.label(~floor, structure=EIGHT)[1]
    assert rock_parts >= 3  # the outer rock and free-standing pillars
    clearance = ndimage.distance_transform_edt(floor) * world.grid.resolution
    assert clearance.max() >= 1.0  # a chamber 2 m across
    assert world.explorable_count >= 0.95 * np.count_nonzero(floor)


def test_a_sparse_draw_is_drawn_again(monkeypatch: pytest.MonkeyPatch) -> None:
    """A draw whose largest system fills under half its box is replaced, up to CAVE_DRAWS times:
    with a rock share that leaves only scattered pockets, every draw is tried and the last taken."""
    draws: list[int] = []
    automaton = cave._automaton

    def counted(rng: np.random.Generator, n_rows: int, n_cols: int) -> np.ndarray:
        draws.append(1)
        return automaton(rng, n_rows, n_cols)

    monkeypatch.setattr(cave, "_automaton", counted)
    usual = cave.cave_layout(np.random.default_rng(0), 60, 80)
    assert 1 <= len(draws) < cave.CAVE_DRAWS
    assert np.count_nonzero(~usual) >= cave.CAVE_MIN_FLOOR * usual.size
    draws.clear()
    monkeypatch.setattr(cave, "CAVE_FILL", 0.56)
    sparse = cave.cave_layout(np.random.default_rng(0), 60, 80)
    assert len(draws) == cave.CAVE_DRAWS
    assert 0 < np.count_nonzero(~sparse) < cave.CAVE_MIN_FLOOR * sparse.size


def test_cave_size_errors_name_the_value() -> None:
    rng = np.random.default_rng(0)
    with pytest.raises(ConfigError, match=r"3\.0"):
        cave_world(rng, size_m=(3.0, 10.0))
    with pytest.raises(ConfigError, match="nan"):
        cave_world(rng, size_m=(10.0, float("nan")))
    with pytest.raises(ConfigError, match=r"got 0\.0"):
        cave_world(rng, resolution=0.0)
    assert CAVE_MIN_M > cave.CAVE_BLOCK_M * 4


def test_a_coarser_resolution_keeps_walls_two_cells_thick() -> None:
    world = cave_world(np.random.default_rng(1), resolution=0.1)  # the coarsest cells: blocks of 2
    occ = world.grid.data == CellState.OCCUPIED
    block = occ[:-1, :-1] & occ[1:, :-1] & occ[:-1, 1:] & occ[1:, 1:]
    covered = np.zeros_like(occ)
    for dr in (0, 1):
        for dc in (0, 1):
            covered[dr : dr + block.shape[0], dc : dc + block.shape[1]] |= block
    assert not (occ & ~covered).any()
