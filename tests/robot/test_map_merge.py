"""A robot's map merged with its teammates': its own knowledge kept, theirs filling what it does not
know, a wall winning over free space between teammates, and maps that do not fit refused."""

from __future__ import annotations

import numpy as np
import pytest

from frontier_rl.core.world.grid import CellState, OccupancyGrid
from frontier_rl.errors import MapError
from frontier_rl.robot.map_merge import merged_map, misfit

U, F, W = CellState.UNKNOWN, CellState.FREE, CellState.OCCUPIED  # W: a wall


def _grid(rows: list[list[int]], origin: tuple[float, float] = (0.0, 0.0)) -> OccupancyGrid:
    return OccupancyGrid(np.array(rows, np.int8), 0.5, origin)


def test_the_robots_own_cells_stay_and_its_teammates_fill_the_rest() -> None:
    own = _grid([[F, U], [U, W]])
    mate = _grid([[W, F], [F, F]])  # disagrees on the robot's own known cells: they stay its own
    merged = merged_map(own, [mate])
    assert merged.origin == own.origin
    np.testing.assert_array_equal(merged.data, [[F, F], [F, W]])


def test_the_merged_map_spans_every_map_in_the_robots_frame() -> None:
    own = _grid([[F]], origin=(1.0, 1.0))
    left_below = _grid([[F, U]], origin=(0.0, 0.5))  # a row below and two columns left of it
    merged = merged_map(own, [left_below])
    assert merged.origin == (0.0, 0.5) and merged.shape == (2, 3)
    np.testing.assert_array_equal(merged.data, [[F, U, U], [U, U, F]])


def test_a_wall_in_one_teammates_map_wins_over_free_in_anothers() -> None:
    own = _grid([[U]])
    for mates in ([_grid([[W]]), _grid([[F]])], [_grid([[F]]), _grid([[W]])]):
        assert merged_map(own, mates).data[0, 0] == W


def test_no_teammate_leaves_the_map_as_it_is() -> None:
    own = _grid([[F, W]])
    assert merged_map(own, []) is own


@pytest.mark.parametrize(
    ("other", "needle"),
    [
        (OccupancyGrid(np.zeros((1, 1), np.int8), 0.25), "its cells are 0.25 m"),
        (_grid([[F]], origin=(0.2, 0.0)), "lies off this robot's cells"),
    ],
)
def test_a_map_that_does_not_fit_is_named(other: OccupancyGrid, needle: str) -> None:
    own = _grid([[F]])
    assert needle in misfit(own, other)
    with pytest.raises(MapError, match=needle):
        merged_map(own, [other])
    assert misfit(own, _grid([[F]], origin=(1.5, -2.0))) == ""
