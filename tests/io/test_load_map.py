"""load_map: dispatch by suffix and content, resolution overrides, LoadedMap, bad input."""

from __future__ import annotations

import dataclasses
import re
import shutil
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from frontier_rl.core.world.grid import CellState, OccupancyGrid
from frontier_rl.errors import MapError
from frontier_rl.io import LoadedMap, load_map, load_ros_map, save_ros_map
from frontier_rl.io.dungeon import DUNGEON_RESOLUTION
from frontier_rl.io.loaded_map import LoadedMap as LoadedMapDefinition


def test_loaded_map_is_re_exported_and_frozen(tmp_path: Path) -> None:
    assert LoadedMap is LoadedMapDefinition
    grid = OccupancyGrid(np.zeros((2, 2), dtype=np.int8), 0.05)
    loaded = LoadedMap(grid=grid, start=None, source=tmp_path)
    with pytest.raises(dataclasses.FrozenInstanceError):
        loaded.start = None  # type: ignore[misc]


@pytest.mark.parametrize("suffix", [".yaml", ".yml"])
def test_ros_yaml(tmp_path: Path, real_maps: Path, suffix: str) -> None:
    folder = tmp_path / "lse"
    shutil.copytree(real_maps / "lse_arena", folder)
    yaml_path = folder / f"arena{suffix}"
    (folder / "lse_arena.yaml").rename(yaml_path)
    loaded = load_map(yaml_path)
    assert loaded.start is None
    assert loaded.source == yaml_path
    np.testing.assert_array_equal(loaded.grid.data, load_ros_map(yaml_path).data)
    assert loaded.grid.shape == (60, 80)
    assert loaded.grid.resolution == 0.05


def test_image_with_a_yaml_beside_it_uses_the_yaml(real_maps: Path) -> None:
    loaded = load_map(real_maps / "stage" / "cave.png")
    assert loaded.grid.resolution == 0.032
    assert loaded.grid.shape == (500, 500)
    assert load_map(real_maps / "stage" / "cave.png", resolution=0.1).grid.resolution == 0.1


def test_dungeon_png(real_maps: Path) -> None:
    loaded = load_map(real_maps / "dungeon" / "medium" / "img_10.png")
    assert loaded.start is not None
    assert loaded.grid.resolution == DUNGEON_RESOLUTION
    assert loaded.grid.shape == (480, 640)
    coarse = load_map(real_maps / "dungeon" / "medium" / "img_10.png", resolution=0.05)
    assert coarse.grid.resolution == 0.05


def test_houseexpo_json(real_maps: Path) -> None:
    path = real_maps / "houseexpo" / "house_expo_room_0000.json"
    loaded = load_map(path)
    assert loaded.start is None
    assert loaded.grid.resolution == 0.05
    assert load_map(path, resolution=0.1).grid.shape == (91, 111)


@pytest.mark.parametrize("suffix", [".png", ".pgm"])
def test_plain_bitmap(tmp_path: Path, suffix: str) -> None:
    pixels = np.full((4, 6), 255, dtype=np.uint8)
    pixels[0, :] = 0  # a wall along the image's top row
    pixels[2, 3] = 128  # grey: neither free nor wall
    path = tmp_path / f"plain{suffix}"
    Image.fromarray(pixels).save(path, format="PNG" if suffix == ".png" else "PPM")
    loaded = load_map(path)
    assert loaded.start is None
    grid = loaded.grid
    assert (grid.resolution, grid.origin) == (0.05, (0.0, 0.0))
    assert (grid.data[3] == CellState.OCCUPIED).all()  # the top row of the image is the highest y
    assert grid.data[1, 3] == CellState.UNKNOWN
    assert grid.count(CellState.FREE) == 17
    assert load_map(path, resolution=0.2).grid.resolution == 0.2


def test_stage_bitmap_without_its_yaml(tmp_path: Path, real_maps: Path) -> None:
    shutil.copy(real_maps / "stage" / "simple_rooms.png", tmp_path / "rooms.png")
    grid = load_map(tmp_path / "rooms.png").grid
    assert grid.resolution == 0.05
    np.testing.assert_array_equal(grid.data, load_ros_map(real_maps / "stage" / "simple_rooms.yaml").data)


def test_saved_map_loads_back(tmp_path: Path) -> None:
    grid = OccupancyGrid(np.array([[0, 100], [-1, 0]], dtype=np.int8), 0.1, (2.0, -3.0))
    loaded = load_map(save_ros_map(grid, tmp_path / "m.yaml", image_format="png"))
    np.testing.assert_array_equal(loaded.grid.data, grid.data)


# --- bad input -------------------------------------------------------------------------------


def test_missing_file_and_folder(tmp_path: Path) -> None:
    with pytest.raises(MapError, match=r"not found.*gone\.yaml"):
        load_map(tmp_path / "gone.yaml")
    folder = re.escape(str(tmp_path))
    with pytest.raises(MapError, match=f"^{folder} is a folder, not a map file: name one of the maps in it$"):
        load_map(tmp_path)


def test_unsupported_suffix(tmp_path: Path) -> None:
    (tmp_path / "map.txt").write_text("#####\n#...#\n#####\n")
    with pytest.raises(MapError, match=r"unsupported.*'\.txt'"):
        load_map(tmp_path / "map.txt")


def test_corrupt_image(tmp_path: Path) -> None:
    (tmp_path / "broken.png").write_bytes(b"\x89PNG\r\n\x1a\n\x00\x00\x00\rIHDR")
    with pytest.raises(MapError, match=r"broken\.png") as info:
        load_map(tmp_path / "broken.png")
    assert info.value.__cause__ is not None
    (tmp_path / "text.pgm").write_text("P2 oops")
    with pytest.raises(MapError, match=r"text\.pgm"):
        load_map(tmp_path / "text.pgm")


def test_bad_resolution(tmp_path: Path) -> None:
    Image.fromarray(np.full((3, 3), 255, dtype=np.uint8)).save(tmp_path / "white.png")
    for resolution in (0.0, -1.0, float("inf")):
        with pytest.raises(MapError, match="resolution"):
            load_map(tmp_path / "white.png", resolution=resolution)


def test_no_free_cell_raises_in_load_map_only(tmp_path: Path) -> None:
    Image.fromarray(np.zeros((5, 5), dtype=np.uint8)).save(tmp_path / "black.png")
    with pytest.raises(MapError, match="no free cell"):
        load_map(tmp_path / "black.png")
    yaml_path = save_ros_map(OccupancyGrid(np.full((3, 3), -1, dtype=np.int8), 0.05), tmp_path / "u.yaml")
    assert load_ros_map(yaml_path).count(CellState.FREE) == 0  # the loader itself stays pure
    with pytest.raises(MapError, match="no free cell"):
        load_map(yaml_path)


def test_yaml_beside_an_image_is_used_only_if_it_names_that_image(tmp_path: Path) -> None:
    Image.fromarray(np.full((3, 3), 255, dtype=np.uint8)).save(tmp_path / "a.png")
    Image.fromarray(np.full((3, 3), 255, dtype=np.uint8)).save(tmp_path / "other.png")
    fields = "resolution: 0.2\norigin: [0, 0, 0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n"
    (tmp_path / "a.yaml").write_text("image: other.png\n" + fields)
    assert load_map(tmp_path / "a.png").grid.resolution == 0.05  # a plain bitmap
    (tmp_path / "a.yaml").write_text("image: a.png\n" + fields)
    assert load_map(tmp_path / "a.png").grid.resolution == 0.2


@pytest.mark.parametrize("image", ['"x\\0.png"', '"x\\ud800.png"', "loop.png"])
def test_a_yaml_beside_an_image_whose_image_cannot_be_resolved_is_a_map_error(tmp_path: Path, image: str) -> None:
    """A NUL byte, a lone surrogate or a symlink loop in the sibling's ``image`` was a traceback."""
    Image.fromarray(np.full((3, 3), 255, dtype=np.uint8)).save(tmp_path / "a.png")
    (tmp_path / "loop.png").symlink_to(tmp_path / "loop.png")
    fields = "resolution: 0.2\norigin: [0, 0, 0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n"
    (tmp_path / "a.yaml").write_text(f"image: {image}\n" + fields)
    with pytest.raises(MapError, match=r"a\.yaml: its image .* cannot be resolved"):
        load_map(tmp_path / "a.png")
