"""OccupancyGrid: validation and the world <-> cell transforms (lower-left origin, x = column)."""

from __future__ import annotations

import numpy as np
import pytest

from frontier_rl.core.world.grid import CellState, OccupancyGrid
from frontier_rl.errors import MapError


def grid(origin: tuple[float, float] = (-1.0, 2.5), res: float = 0.05) -> OccupancyGrid:
    data = np.full((40, 60), CellState.UNKNOWN, np.int8)
    data[10:20, 5:30] = CellState.FREE
    data[0, :] = CellState.OCCUPIED
    return OccupancyGrid(data, res, origin)


def test_cell_values_are_the_ros_ones() -> None:
    assert (CellState.UNKNOWN, CellState.FREE, CellState.OCCUPIED) == (-1, 0, 100)


def test_world_to_cell_uses_lower_left_origin_and_x_as_column() -> None:
    g = grid()
    assert g.world_to_cell(-1.0 + 1e-9, 2.5 + 1e-9) == (0, 0)
    assert g.world_to_cell(-1.0 + 0.05 * 7.5, 2.5 + 0.05 * 3.2) == (3, 7)
    assert g.world_to_cell(-1.01, 2.5) == (0, -1)  # left of the grid: a negative column
    assert g.cell_to_world(3, 7) == pytest.approx((-1.0 + 0.05 * 7.5, 2.5 + 0.05 * 3.5))


def test_vectorised_transforms_agree_with_the_scalar_ones() -> None:
    g = grid()
    cells = np.array([[0, 0], [3, 7], [39, 59], [12, 40]])
    xy = g.cells_to_world(cells)
    for (row, col), (x, y) in zip(cells, xy, strict=True):
        assert (x, y) == pytest.approx(g.cell_to_world(row, col))
    np.testing.assert_array_equal(g.world_to_cells(xy), cells)


def test_shape_size_bounds_masks_and_counts() -> None:
    g = grid()
    assert g.shape == (40, 60) and g.height == 40 and g.width == 60
    assert g.size_m == pytest.approx((3.0, 2.0))
    assert g.in_bounds(39, 59) and not g.in_bounds(40, 0) and not g.in_bounds(0, -1)
    assert g.count(CellState.FREE) == 250 and g.mask(CellState.OCCUPIED)[0].all()


@pytest.mark.parametrize(
    ("data", "res", "needle"),
    [
        (np.zeros((3, 3), np.int8), 0.0, "0.0"),
        (np.zeros((3, 3), np.int8), -0.05, "-0.05"),
        (np.zeros((3, 3), np.int8), float("nan"), "nan"),
        (np.zeros((0, 3), np.int8), 0.05, "(0, 3)"),
        (np.zeros(9, np.int8), 0.05, "(9,)"),
        (np.zeros((3, 3), np.int16), 0.05, "int16"),
    ],
)
def test_bad_grids_raise_map_error_naming_the_value(data: np.ndarray, res: float, needle: str) -> None:
    with pytest.raises(MapError, match=needle.replace("(", r"\(").replace(")", r"\)")):
        OccupancyGrid(data, res)


def test_a_crop_knows_where_its_first_cell_lies_in_the_grid_it_came_from() -> None:
    outer = OccupancyGrid(np.zeros((40, 50), np.int8), 0.05, (-1.0, 2.0))
    crop = OccupancyGrid(np.zeros((5, 6), np.int8), 0.05, (-1.0 + 7 * 0.05, 2.0 + 3 * 0.05))
    assert crop.offset_in(outer) == (3, 7)
    assert outer.offset_in(crop) == (-3, -7)
    assert outer.offset_in(outer) == (0, 0)
