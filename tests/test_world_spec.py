"""The one world resolver: generators, map files with and without a stored start, and the
per-version cache of map files."""

from __future__ import annotations

import os
import shutil
from pathlib import Path

import numpy as np
import pytest

from frontier_rl import world_spec
from frontier_rl.core.world.catalog import generate_world
from frontier_rl.core.world.grid import CellState, OccupancyGrid
from frontier_rl.core.world.robot import Pose
from frontier_rl.core.world.worlds import make_world
from frontier_rl.errors import ConfigError, MapError, UnknownNameError
from frontier_rl.io import load_map, save_ros_map
from frontier_rl.world_spec import read_map, resolve_world, world_name


def test_a_generator_is_drawn_with_the_seed_and_a_start_replaces_its_own() -> None:
    world = resolve_world("office", 3)
    assert np.array_equal(world.grid.data, generate_world("office", 3).grid.data)
    assert world.start == generate_world("office", 3).start
    moved = resolve_world("office", 3, start=world.start._replace(theta=1.0))
    assert moved.start.theta == 1.0 and np.array_equal(moved.grid.data, world.grid.data)


def test_a_stored_start_is_kept_unless_the_caller_draws_one(real_maps: Path) -> None:
    dungeon = real_maps / "dungeon" / "easy" / "img_1.png"
    stored = load_map(dungeon).start
    assert stored is not None
    assert resolve_world(str(dungeon), 0).start == stored == resolve_world(str(dungeon), 5).start
    drawn = {resolve_world(str(dungeon), seed, stored_start=False).start for seed in range(4)}
    assert stored not in drawn and len(drawn) == 4
    assert (
        resolve_world(str(dungeon), 2, stored_start=False).start
        == resolve_world(str(dungeon), 2, stored_start=False).start
    )  # drawn with the seed


def _room(path: Path, wall_col: int) -> Path:
    data = np.full((30, 40), CellState.FREE, np.int8)
    data[[0, -1], :] = CellState.OCCUPIED
    data[:, [0, -1, wall_col]] = CellState.OCCUPIED
    return save_ros_map(OccupancyGrid(data, 0.05), path)


def test_a_worlds_name_is_known_without_reading_it(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    room = _room(tmp_path / "hall.yaml", 5)
    specs = ("office", "lse_arena", str(room))
    names = [resolve_world(spec, 0).name for spec in specs]

    def no_read(*args: object, **kwargs: object) -> None:
        raise AssertionError("world_name read a map")

    monkeypatch.setattr(world_spec, "read_map", no_read)
    assert [world_name(spec) for spec in specs] == names
    assert world_name(str(room)) == room.stem


def test_a_map_file_is_read_once_per_version(tmp_path: Path) -> None:
    path = _room(tmp_path / "room.yaml", 20)
    first = read_map(str(path))
    assert read_map(str(path)) is first  # cached
    assert read_map(str(tmp_path / "." / "room.yaml")) is first  # one file, one entry
    image = path.with_suffix(".pgm")
    shutil.copy(_room(tmp_path / "other.yaml", 30).with_suffix(".pgm"), image)
    os.utime(path, ns=(1, 1))  # the YAML's version changes: read again, with the new image
    changed = read_map(str(path))
    assert changed is not first and not np.array_equal(changed.grid.data, first.grid.data)
    world = resolve_world(str(path), 0)
    expected = make_world(changed.grid, "room", rng=np.random.default_rng(0))
    assert world.name == "room" and np.array_equal(world.grid.data, expected.grid.data)
    assert world.start == expected.start


@pytest.mark.parametrize(
    ("spec", "kwargs", "error", "needle"),
    [
        ("mars", {}, UnknownNameError, "mars"),
        ("office", {"resolution": 0.5}, ConfigError, "resolution"),
        ("office", {"start": Pose(float("nan"), 0.0)}, ConfigError, "start pose"),
    ],
)
def test_bad_worlds_are_named(spec: str, kwargs: dict[str, object], error: type[Exception], needle: str) -> None:
    with pytest.raises(error, match=needle):
        resolve_world(spec, 0, **kwargs)  # type: ignore[arg-type]


def test_map_errors_name_the_path_as_given(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    Path("broken.yaml").write_text(
        "image: missing.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n"
        "negate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n"
    )
    with pytest.raises(MapError) as raised:
        resolve_world("broken.yaml", 0)
    assert str(tmp_path) not in str(raised.value) and "missing.pgm" in str(raised.value)


def test_a_finely_drawn_map_is_read_on_the_robots_cells(tmp_path: Path) -> None:
    """A robot's SLAM maps on 0.05 m cells whatever the drawing: files finer than 0.04 m are
    resampled to 0.05 m; coarser ones (DungeonMaps' 0.04375 m among them) are read as drawn."""
    path = _room(tmp_path / "room.yaml", 20)  # 30 × 40 cells
    as_drawn = load_map(path).grid
    assert read_map(str(path)).grid.data.tobytes() == as_drawn.data.tobytes()
    for cell, shape in [(0.0125, (8, 10)), (0.03, (18, 24)), (0.0399, (24, 32))]:
        fine = read_map(str(path), cell).grid
        assert fine.resolution == 0.05 and fine.shape == shape
        np.testing.assert_array_equal(fine.data, load_map(path, cell).grid.resampled(0.05).data)
        assert (fine.data[1:-1, 1:-1] == CellState.FREE).any() and (fine.data[0, :] == CellState.OCCUPIED).all()
    assert read_map(str(path), 0.04).grid.resolution == 0.04
    world = resolve_world(str(path), 0, resolution=0.03)
    assert world.grid.resolution == 0.05 and world.grid.shape == (18, 24)


def test_a_map_on_cells_no_world_accepts_is_named_with_its_own_cell_size(tmp_path: Path) -> None:
    path = _room(tmp_path / "room.yaml", 20)
    text = path.read_text().replace("resolution: 0.05", "resolution: 0.001")
    assert text != path.read_text()
    path.write_text(text)
    with pytest.raises(MapError, match=r"cell size 0\.001 m"):
        resolve_world(str(path), 0)


@pytest.mark.parametrize(
    ("path", "shape"), [("stage/uoa_robotics_lab.yaml", (303, 136)), ("stage/cave.yaml", (320, 320))]
)
def test_resampling_a_real_map_keeps_its_rooms(real_maps: Path, path: str, shape: tuple[int, int]) -> None:
    """Thickening the walls by up to a cell loses no room: the explorable area stays within 2 %
    of the map's as drawn (measured 98.5-99.1 % on the four real maps finer than 0.04 m)."""
    drawn = make_world(load_map(real_maps / path).grid, "drawn", rng=np.random.default_rng(0))
    world = resolve_world(str(real_maps / path), 0)
    assert world.grid.resolution == 0.05 and world.grid.shape == shape
    area = [w.explorable.sum() * w.grid.resolution**2 for w in (drawn, world)]
    assert 0.98 * area[0] <= area[1] <= area[0]


def test_a_folder_with_a_symlink_loop_is_refused_naming_it(tmp_path: Path) -> None:
    """Python 3.11's resolve raised a RuntimeError: a traceback at the command line."""
    folder = tmp_path / "maps"
    folder.mkdir()
    (folder / "l1.png").symlink_to("l2.png")
    (folder / "l2.png").symlink_to("l1.png")
    with pytest.raises(MapError, match=r"l1\.png: cannot be resolved"):
        world_spec.parse_world_list(str(folder))


def test_a_map_no_robot_fits_on_is_refused_naming_its_file(tmp_path: Path) -> None:
    from PIL import Image

    path = tmp_path / "closet.png"
    Image.new("L", (3, 3), 254).save(path)  # free, but 15 cm across: no room for the robot
    with pytest.raises(MapError, match=r"closet\.png: map has no free cell with clearance for the robot"):
        world_spec.resolve_world(str(path), seed=0)


def test_an_empty_world_is_unknown_not_the_current_folder() -> None:
    """``--world ''`` said ". is a folder, not a map file"."""
    with pytest.raises(UnknownNameError, match="unknown world ''"):
        world_spec.resolve_world("", seed=0)
