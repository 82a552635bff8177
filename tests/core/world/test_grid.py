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


# ------------------------------------------------------------------------------------- resampling
def random_grid(shape: tuple[int, int], res: float, seed: int) -> OccupancyGrid:
    draw = np.random.default_rng(seed).random(shape)
    data = np.full(shape, CellState.FREE, np.int8)
    data[draw < 0.04] = CellState.OCCUPIED
    data[(draw >= 0.04) & (draw < 0.06)] = CellState.UNKNOWN
    return OccupancyGrid(data, res, (-0.7, 1.3))


@pytest.mark.parametrize("factor", [2, 4])
def test_resampling_by_a_whole_factor_pools_blocks(factor: int) -> None:
    g = random_grid((4 * factor, 3 * factor), 0.0125, factor)
    coarse = g.resampled(0.0125 * factor)
    blocks = g.data.reshape(4, factor, 3, factor).transpose(0, 2, 1, 3).reshape(4, 3, -1)
    expected = np.where(
        (blocks == CellState.OCCUPIED).any(axis=2),
        CellState.OCCUPIED,
        np.where((blocks == CellState.FREE).all(axis=2), CellState.FREE, CellState.UNKNOWN),
    )
    np.testing.assert_array_equal(coarse.data, expected)
    assert coarse.resolution == pytest.approx(0.0125 * factor) and coarse.origin == g.origin


@pytest.mark.parametrize(("res", "seed"), [(0.03, 0), (0.032, 1), (0.012, 2), (0.025, 3)])
def test_resampling_keeps_every_wall_where_it_is_and_frees_only_free_space(res: float, seed: int) -> None:
    g = random_grid((47, 53), res, seed)
    coarse = g.resampled(0.05)
    assert coarse.shape == (int(np.ceil(47 * res / 0.05 - 1e-9)), int(np.ceil(53 * res / 0.05 - 1e-9)))
    for state in (CellState.OCCUPIED, CellState.UNKNOWN):
        # every point of a wall cell (its corners, pulled in a hair) lies in an occupied coarse
        # cell, every point of an unknown one in a cell that is not free
        cells = np.argwhere(g.data == state)
        for dr, dc in [(0.001, 0.001), (0.999, 0.001), (0.001, 0.999), (0.999, 0.999)]:
            xy = g.cells_to_world(cells) + (np.array([dc, dr]) - 0.5) * res
            hit = coarse.data[tuple(coarse.world_to_cells(xy).T)]
            assert (hit == CellState.OCCUPIED).all() if state == CellState.OCCUPIED else (hit != CellState.FREE).all()
    # so a free coarse cell overlaps free cells only; and it lies within the grid
    free = np.argwhere(coarse.data == CellState.FREE)
    assert len(free) > 0
    top_right = coarse.cells_to_world(free) + 0.5 * 0.05 - 1e-6
    assert (top_right < np.array(g.origin) + np.array([g.width, g.height]) * res).all()


def test_a_cell_past_the_far_edge_is_not_free() -> None:
    data = np.full((5, 7), CellState.FREE, np.int8)
    coarse = OccupancyGrid(data, 0.03).resampled(0.05)  # 0.15 × 0.21 m: the last column half outside
    assert coarse.shape == (3, 5)
    assert (coarse.data[:, :4] == CellState.FREE).all() and (coarse.data[:, 4] == CellState.UNKNOWN).all()


def test_resampling_to_finer_cells_is_refused() -> None:
    with pytest.raises(MapError, match=r"0\.01 m cells"):
        grid(res=0.05).resampled(0.01)
