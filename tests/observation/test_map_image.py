"""Map images and per-frontier features."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import pytest
from numpy.typing import NDArray

from frontier_rl.core.frontiers.detection import detect_frontiers
from frontier_rl.core.world.grid import CellState, OccupancyGrid
from frontier_rl.core.world.robot import Pose
from frontier_rl.errors import ConfigError
from frontier_rl.observation.map_image import (
    MAP_FREE,
    MAP_OCCUPIED,
    MAP_UNKNOWN,
    MARK,
    POSE_RADIUS_M,
    MapEncoder,
    downsample,
    frontier_features,
)


def _room(rows: int = 40, cols: int = 60) -> OccupancyGrid:
    data = np.full((rows, cols), CellState.UNKNOWN, np.int8)
    data[5:30, 5:40] = CellState.FREE
    data[5:30, 5] = CellState.OCCUPIED
    data[5, 5:40] = CellState.OCCUPIED
    return OccupancyGrid(data, 0.05, (-1.0, 2.0))


def test_thesis_size_is_the_remapped_map_padded_with_unknown() -> None:
    grid = _room()
    enc = MapEncoder(250)
    assert enc.shape == (1, 250, 250) and enc.factor == 1
    pose = Pose(*grid.cell_to_world(15, 20))
    image = enc.encode(grid, pose)[0]
    row0, col0 = enc.window_origin(grid, pose)
    inner = image[-row0 : -row0 + grid.height, -col0 : -col0 + grid.width]
    expected = np.select(
        [grid.data == CellState.OCCUPIED, grid.data == CellState.FREE], [MAP_OCCUPIED, MAP_FREE], MAP_UNKNOWN
    )
    assert np.array_equal(inner, expected)
    assert (image == MAP_UNKNOWN).sum() == 250 * 250 - (grid.data != CellState.UNKNOWN).sum()


def test_downsampled_size_keeps_walls() -> None:
    grid = _room()
    enc = MapEncoder(64)
    assert enc.factor == 4 and enc.window == 256 and enc.shape == (1, 64, 64)
    image = enc.encode(grid, Pose(*grid.cell_to_world(15, 20)))[0]
    assert (image == MAP_OCCUPIED).sum() > 0
    assert set(np.unique(image)) <= {MAP_OCCUPIED, MAP_UNKNOWN, MAP_FREE}


def test_pose_and_frontier_channels() -> None:
    grid = _room()
    pose = Pose(*grid.cell_to_world(15, 20))
    reach = grid.data == CellState.FREE
    frontiers = detect_frontiers(grid, pose, reach)
    enc = MapEncoder(250, frontier_channel=True, pose_channel=True)
    image = enc.encode(grid, pose, frontiers)
    assert image.shape == (3, 250, 250)
    row0, col0 = enc.window_origin(grid, pose)
    marked = np.argwhere(image[1] == MARK) + np.array([row0, col0])
    assert len(marked) == sum(len(c) for c in frontiers.cells)
    for r, c in marked:
        assert grid.data[r, c] == CellState.FREE
    disc = np.argwhere(image[2] == MARK)
    centre = disc.mean(axis=0) + np.array([row0, col0])
    assert np.allclose(centre, (15, 20), atol=0.6)
    with pytest.raises(ConfigError, match="frontier"):
        enc.encode(grid, pose)


@pytest.mark.parametrize("size", [250, 64])
def test_robot_stays_in_the_window_on_a_large_map(size: int) -> None:
    data = np.full((800, 900), CellState.FREE, np.int8)
    grid = OccupancyGrid(data, 0.05)
    enc = MapEncoder(size, pose_channel=True)
    for cell in [(3, 3), (796, 896), (400, 10), (10, 450)]:
        pose = Pose(*grid.cell_to_world(*cell))
        image = enc.encode(grid, pose)
        assert (image[1] == MARK).any()
        row, col = np.argwhere(image[1] == MARK).mean(axis=0).round().astype(int)
        x, y = enc.pixel_to_world(grid, pose, int(row), int(col))
        assert np.hypot(x - pose.x, y - pose.y) <= enc.factor * grid.resolution * 1.5


def test_bad_size_is_named() -> None:
    with pytest.raises(ConfigError, match="4000"):
        MapEncoder(4000)


def test_frontier_features(grid_from_text: Callable[..., OccupancyGrid]) -> None:
    grid = grid_from_text(
        [
            "??????????",
            "#........?",
            "#........?",
            "#........?",
            "#........?",
            "##########",
        ]
    )
    pose = Pose(*grid.cell_to_world(2, 2))
    frontiers = detect_frontiers(grid, pose, grid.data == CellState.FREE)
    costs = np.full(len(frontiers), 0.7)
    feats = frontier_features(frontiers, pose, costs, sensor_range=3.5)
    assert feats.shape == (len(frontiers), 6) and feats.dtype == np.float32
    assert np.allclose(feats[:, 0], frontiers.distances / 10, atol=1e-6)
    assert np.allclose(feats[:, 1], 0.07)
    assert np.allclose(feats[:, 2], frontiers.sizes / 100)
    assert np.all(feats[:, 3] > 0)
    assert np.allclose(feats[:, 4], (frontiers.centers[:, 0] - pose.x) / 10, atol=1e-6)


def _pose_channel_by_definition(enc: MapEncoder, grid: OccupancyGrid, pose: Pose) -> np.ndarray:
    """The pose channel as defined: the disc of cell centres within POSE_RADIUS_M over the whole
    window, max-pooled by the encoder's factor."""
    row0, col0 = enc.window_origin(grid, pose)
    radius = max(POSE_RADIUS_M / grid.resolution, 1.0)
    rows = np.arange(enc.window)[:, None] + row0 + 0.5
    cols = np.arange(enc.window)[None, :] + col0 + 0.5
    r = (pose.y - grid.origin[1]) / grid.resolution
    c = (pose.x - grid.origin[0]) / grid.resolution
    disc = (rows - r) ** 2 + (cols - c) ** 2 <= radius * radius
    n, f = enc.size, enc.factor
    return np.where(disc.reshape(n, f, n, f).any(axis=(1, 3)), MARK, 0).astype(np.uint8)


@pytest.mark.parametrize(
    ("size", "shape", "resolution"),
    [(64, (64, 64), 0.05), (64, (300, 200), 0.1), (64, (1000, 1000), 0.05), (32, (97, 131), 0.025)],
)
def test_the_pose_channel_is_the_pooled_disc_around_the_robot(
    size: int, shape: tuple[int, int], resolution: float
) -> None:
    """Worked out on the disc's bounding box only; equal to the definition for poses anywhere,
    on a cell's edge, near the window's rim and off the map."""
    rng = np.random.default_rng(1)
    grid = OccupancyGrid(np.zeros(shape, np.int8), resolution, (-1.3, 2.7))
    enc = MapEncoder(size, pose_channel=True)
    height, width = shape[0] * resolution, shape[1] * resolution
    poses = [(rng.uniform(-0.5, width + 0.5), rng.uniform(-0.5, height + 0.5)) for _ in range(150)]
    poses += [(0.0, 0.0), (width, height), (0.5 * resolution * 7, 0.25), (-0.3, height + 0.3)]
    for x, y in poses:
        pose = Pose(grid.origin[0] + x, grid.origin[1] + y, 0.0)
        assert np.array_equal(enc.encode(grid, pose)[1], _pose_channel_by_definition(enc, grid, pose)), (x, y)


FREE, OCC, UNKNOWN = CellState.FREE.value, CellState.OCCUPIED.value, CellState.UNKNOWN.value


def _downsample_reference(data: NDArray[np.int8], f: int) -> NDArray[np.int8]:
    rows, cols = data.shape
    out = np.empty((rows // f, cols // f), np.int8)
    for i in range(rows // f):
        for j in range(cols // f):
            block = data[i * f : (i + 1) * f, j * f : (j + 1) * f]
            if (block == OCC).any():
                out[i, j] = OCC
            elif 2 * np.count_nonzero(block == FREE) >= f * f:
                out[i, j] = FREE
            else:
                out[i, j] = UNKNOWN
    return out


@pytest.mark.parametrize(
    ("block", "expected"),
    [
        ([[FREE, FREE], [UNKNOWN, UNKNOWN]], FREE),  # half known free: free
        ([[FREE, UNKNOWN], [UNKNOWN, UNKNOWN]], UNKNOWN),  # under half: unknown
        ([[FREE, FREE], [FREE, OCC]], OCC),  # one wall cell: the block is a wall
        ([[UNKNOWN, UNKNOWN], [UNKNOWN, OCC]], OCC),
        ([[FREE, FREE], [FREE, FREE]], FREE),
        ([[UNKNOWN, UNKNOWN], [UNKNOWN, UNKNOWN]], UNKNOWN),
    ],
)
def test_downsample_block_rule(block: list[list[int]], expected: int) -> None:
    assert downsample(np.array(block, np.int8), 2)[0, 0] == expected


@pytest.mark.parametrize("factor", [1, 2, 3, 5])
def test_downsample_matches_the_rule_on_random_grids(factor: int) -> None:
    rng = np.random.default_rng(factor)
    data = rng.choice(np.array([FREE, OCC, UNKNOWN], np.int8), size=(30, 60), p=[0.6, 0.05, 0.35])
    out = downsample(data, factor)
    np.testing.assert_array_equal(out, _downsample_reference(data, factor))
    if factor == 1:
        np.testing.assert_array_equal(out, data)
    # walls never vanish: every occupied cell lies in an occupied block
    rows, cols = np.nonzero(data == OCC)
    assert np.all(out[rows // factor, cols // factor] == OCC)


@pytest.mark.parametrize("factor", [0, -2, 4, 7])
def test_downsample_rejects_a_factor_that_does_not_divide(factor: int) -> None:
    with pytest.raises(ConfigError, match=str(factor)):
        downsample(np.zeros((30, 45), np.int8), factor)
