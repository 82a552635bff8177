"""The narrow-passage recovery: walls a cell thinner than the map shows (core/navigation/thin_walls.py)."""

from __future__ import annotations

import numpy as np
import pytest

from frontier_rl.core.navigation import thin_walls as thin_walls_module
from frontier_rl.core.navigation.thin_walls import Recovery, thin_walls
from frontier_rl.core.sim.simulator import ExplorationSimulator
from frontier_rl.core.world.catalog import generate_world
from frontier_rl.core.world.grid import CellState

FREE, OCC, UNKNOWN = (np.int8(v) for v in (CellState.FREE, CellState.OCCUPIED, CellState.UNKNOWN))


def band(thickness: int, beyond: np.int8 = FREE) -> np.ndarray:
    """A vertical wall ``thickness`` cells thick in a 7-row strip, free on its left, ``beyond`` on its right."""
    data = np.full((7, 12), FREE, np.int8)
    data[:, 4 : 4 + thickness] = OCC
    data[:, 4 + thickness :] = beyond
    return data


@pytest.mark.parametrize(("thickness", "left"), [(1, 1), (2, 2), (3, 1), (5, 3)])
def test_a_thick_wall_seen_from_both_sides_loses_a_cell_on_each(thickness: int, left: int) -> None:
    out = thin_walls(band(thickness))
    assert ((out == OCC).sum(axis=1) == left).all()


@pytest.mark.parametrize("thickness", [1, 2])
def test_a_wall_that_may_be_one_true_cell_is_kept(thickness: int) -> None:
    """Two cells with free space on both sides may be one true cell seen from either side."""
    data = band(thickness)
    np.testing.assert_array_equal(thin_walls(data), data)


def test_a_wall_two_cells_thick_seen_from_one_side_loses_its_front_cell() -> None:
    out = thin_walls(band(2, beyond=UNKNOWN))
    assert (out[:, 4] == FREE).all() and (out[:, 5] == OCC).all()


def test_only_the_side_that_faces_free_space_is_peeled() -> None:
    out = thin_walls(band(3, beyond=UNKNOWN))
    assert (out[:, 4] == FREE).all() and (out[:, 5:7] == OCC).all() and (out[:, 7:] == UNKNOWN).all()


def test_walls_the_robot_touched_are_kept() -> None:
    data = band(3)
    felt = np.zeros(data.shape, bool)
    felt[2:5, 4] = True
    out = thin_walls(data, felt)
    assert (out[2:5, 4] == OCC).all() and (out[[0, 1, 5, 6], 4] == FREE).all()
    assert (out[:, 6] == FREE).all()  # the other side is peeled as before


def test_the_input_is_not_changed() -> None:
    data = band(3)
    before = data.copy()
    thin_walls(data)
    np.testing.assert_array_equal(data, before)


def test_the_simulator_keeps_the_walls_the_robot_touched_on_its_cropped_map(monkeypatch: pytest.MonkeyPatch) -> None:
    """The recovery plans on a crop of the world; the touched walls (a world-sized mask) must be
    cropped the same way, or the wrong cells would be kept."""
    world = generate_world("office", 0)
    sim = ExplorationSimulator(world)
    row, col = (int(v) for v in np.argwhere(sim.mapper.state == FREE)[-1])  # a cell the first scan saw
    sim.mapper.mark_occupied(np.array([row]), np.array([col]))
    seen: list[np.ndarray] = []

    def spy(state: np.ndarray, felt: np.ndarray | None = None) -> np.ndarray:
        assert felt is not None and felt.shape == state.shape
        seen.append(felt.copy())
        return thin_walls(state, felt)

    monkeypatch.setattr(thin_walls_module, "thin_walls", spy)
    grid = sim.mapper.occupancy_grid(margin=2)
    cand = sim.navigator.candidates_on(grid, Recovery.HALF_CELL, sim.pose)
    assert cand.recovery is Recovery.HALF_CELL and len(seen) == 1
    top, left = world.grid.world_to_cell(*grid.cell_to_world(0, 0))
    assert np.argwhere(seen[0]).tolist() == [[row - top, col - left]]
    assert grid.data[row - top, col - left] == OCC  # the touched cell, where the crop has it
