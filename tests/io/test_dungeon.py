"""DungeonMaps PNGs: free/occupied split, start marker, flip, detection, bad input."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from numpy.typing import NDArray
from PIL import Image

from frontier_rl.core.world.grid import CellState
from frontier_rl.errors import MapError
from frontier_rl.io import LoadedMap
from frontier_rl.io.dungeon import DUNGEON_RESOLUTION, is_dungeon_image, load_dungeon_map

WALL, FLOOR, YELLOW = (127, 127, 127), (195, 195, 194), (255, 216, 0)


def synthetic(path: Path, *, start: tuple[int, int] | None = (2, 5), grey: bool = False) -> Path:
    """A 12 x 10 px dungeon-style PNG: a floor rectangle, and a 2 x 2 start square at image (row, col)."""
    rgb = np.full((10, 12, 3), WALL, dtype=np.uint8)
    rgb[1:9, 1:11] = FLOOR
    if start is not None:
        rgb[start[0] : start[0] + 2, start[1] : start[1] + 2] = YELLOW
    image = Image.fromarray(rgb)
    if grey:  # the greyscale an ARiADNE-style loader sees: start 208
        lum = np.full((10, 12), 127, dtype=np.uint8)
        lum[1:9, 1:11] = 195
        if start is not None:
            lum[start[0] : start[0] + 2, start[1] : start[1] + 2] = 208
        image = Image.fromarray(lum)
    image.save(path)
    return path


def start_pixels(path: Path) -> tuple[NDArray[np.intp], NDArray[np.intp]]:
    with Image.open(path) as image:
        rgb = np.asarray(image.convert("RGB"))
    rows, cols = np.nonzero(np.all(rgb == YELLOW, axis=2))
    return rows, cols


def test_synthetic_map_start_and_flip(tmp_path: Path) -> None:
    loaded = load_dungeon_map(synthetic(tmp_path / "d.png"), resolution=1.0)
    assert isinstance(loaded, LoadedMap)
    grid = loaded.grid
    assert grid.shape == (10, 12)
    assert grid.origin == (0.0, 0.0)
    assert grid.count(CellState.FREE) == 80 and grid.count(CellState.OCCUPIED) == 40
    assert grid.count(CellState.UNKNOWN) == 0
    # Image rows 2-3 / cols 5-6 are grid rows 6-7 (flipped): the square spans x 5..7 m, y 6..8 m.
    assert loaded.start is not None
    assert (loaded.start.x, loaded.start.y, loaded.start.theta) == (6.0, 7.0, 0.0)
    assert loaded.source == tmp_path / "d.png"


def test_greyscale_start_marker(tmp_path: Path) -> None:
    loaded = load_dungeon_map(synthetic(tmp_path / "g.png", start=(6, 2), grey=True), resolution=0.5)
    assert loaded.start is not None
    # image rows 6-7 / cols 2-3 -> grid rows 2-3: the square spans x and y 1.0..2.0 m
    assert (loaded.start.x, loaded.start.y) == (1.5, 1.5)
    assert loaded.grid.data[loaded.grid.world_to_cell(loaded.start.x, loaded.start.y)] == CellState.FREE


def test_real_map(real_maps: Path) -> None:
    path = real_maps / "dungeon" / "easy" / "img_1.png"
    loaded = load_dungeon_map(path)
    grid = loaded.grid
    assert grid.shape == (480, 640)
    assert grid.resolution == DUNGEON_RESOLUTION
    assert grid.size_m == pytest.approx((28.0, 21.0))
    with Image.open(path) as image:
        rgb = np.asarray(image.convert("RGB"))
    wall = np.all(rgb == WALL, axis=2)
    np.testing.assert_array_equal(grid.data[::-1] == CellState.OCCUPIED, wall)
    # The start is the centre of the 16 x 16 yellow square.
    rows, cols = start_pixels(path)
    assert rows.size == 256
    assert loaded.start is not None
    row, col = grid.world_to_cell(loaded.start.x, loaded.start.y)
    assert rows.min() <= grid.height - 1 - row <= rows.max()
    assert cols.min() <= col <= cols.max()
    assert loaded.start.x == pytest.approx((cols.mean() + 0.5) * DUNGEON_RESOLUTION)


@pytest.mark.parametrize("folder", ["train", "easy", "medium", "complex"])
def test_every_start_lies_in_free_space(real_maps: Path, folder: str) -> None:
    for path in sorted((real_maps / "dungeon" / folder).glob("*.png"))[:10]:
        loaded = load_dungeon_map(path, resolution=0.05)
        assert loaded.start is not None
        cell = loaded.grid.world_to_cell(loaded.start.x, loaded.start.y)
        assert loaded.grid.in_bounds(*cell)
        assert loaded.grid.data[cell] == CellState.FREE, path


def test_detection(tmp_path: Path, real_maps: Path) -> None:
    assert is_dungeon_image(real_maps / "dungeon" / "easy" / "img_1.png")
    assert is_dungeon_image(synthetic(tmp_path / "d.png"))
    assert not is_dungeon_image(synthetic(tmp_path / "n.png", start=None))
    for path in (real_maps / "stage").glob("*.png"):
        assert not is_dungeon_image(path), path
    photo = np.random.default_rng(0).integers(0, 256, size=(20, 20, 3), dtype=np.uint8)
    photo[0, 0] = YELLOW  # a start-coloured pixel in a non-dungeon palette
    Image.fromarray(photo).save(tmp_path / "photo.png")
    assert not is_dungeon_image(tmp_path / "photo.png")


def test_no_start_marker(tmp_path: Path) -> None:
    with pytest.raises(MapError, match="no start marker"):
        load_dungeon_map(synthetic(tmp_path / "n.png", start=None))


@pytest.mark.parametrize("resolution", [0.0, -0.04, float("nan"), "0.04"])
def test_bad_resolution(tmp_path: Path, resolution: float) -> None:
    with pytest.raises(MapError, match="resolution"):
        load_dungeon_map(synthetic(tmp_path / "d.png"), resolution=resolution)


def test_missing_and_corrupt_files(tmp_path: Path) -> None:
    with pytest.raises(MapError, match=r"not found.*gone\.png"):
        load_dungeon_map(tmp_path / "gone.png")
    (tmp_path / "bad.png").write_bytes(b"\x89PNG\r\n\x1a\n\x00\x00")
    with pytest.raises(MapError, match=r"bad\.png"):
        load_dungeon_map(tmp_path / "bad.png")
    with pytest.raises(MapError, match=r"bad\.png"):
        is_dungeon_image(tmp_path / "bad.png")
