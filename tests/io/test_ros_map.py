"""ROS map_server maps: reading (modes, negate, alpha, flip), writing, round trips, bad input."""

from __future__ import annotations

import warnings
from collections.abc import Mapping
from pathlib import Path

import numpy as np
import pytest
from numpy.typing import NDArray
from PIL import Image

from frontier_rl.core.world.grid import CellState, OccupancyGrid
from frontier_rl.errors import MapError, MapWarning
from frontier_rl.io.ros_map import load_ros_map, save_ros_map

FREE, OCC, UNK = CellState.FREE, CellState.OCCUPIED, CellState.UNKNOWN


def write_map(
    folder: Path,
    pixels: NDArray[np.uint8] | Image.Image,
    *,
    fmt: str = "pgm",
    fields: Mapping[str, object] | None = None,
    drop: tuple[str, ...] = (),
) -> Path:
    """A map_server map (image + YAML) in ``folder``; returns the YAML's path."""
    image = pixels if isinstance(pixels, Image.Image) else Image.fromarray(pixels)
    image.save(folder / f"map.{fmt}", format="PPM" if fmt == "pgm" else "PNG")
    doc: dict[str, object] = {
        "image": f"map.{fmt}",
        "resolution": 0.5,
        "origin": "[1.0, 2.0, 0.0]",
        "negate": 0,
        "occupied_thresh": 0.65,
        "free_thresh": 0.196,
    }
    doc.update(fields or {})
    text = "".join(f"{key}: {value}\n" for key, value in doc.items() if key not in drop)
    yaml_path = folder / "map.yaml"
    yaml_path.write_text(text)
    return yaml_path


# A 3 x 2 image (top row first): occupied, free, unknown / free, free, occupied.
PATTERN = np.array([[0, 254, 205], [254, 254, 0]], dtype=np.uint8)


def test_flip_puts_the_image_bottom_row_at_row_zero(tmp_path: Path) -> None:
    grid = load_ros_map(write_map(tmp_path, PATTERN))
    assert grid.data.dtype == np.int8
    assert grid.shape == (2, 3)
    np.testing.assert_array_equal(grid.data, [[FREE, FREE, OCC], [OCC, FREE, UNK]])
    assert grid.resolution == 0.5
    assert grid.origin == (1.0, 2.0)
    # The image's top-left pixel is the map's top-left corner in the world.
    assert grid.world_to_cell(1.25, 2.75) == (1, 0)
    assert grid.data[grid.world_to_cell(1.25, 2.75)] == OCC


def test_negate_swaps_black_and_white(tmp_path: Path) -> None:
    grid = load_ros_map(write_map(tmp_path, PATTERN, fields={"negate": 1}))
    np.testing.assert_array_equal(grid.data, [[OCC, OCC, FREE], [FREE, OCC, OCC]])


def test_trinary_thresholds_are_strict_as_in_map_server(tmp_path: Path) -> None:
    # p = (255 - v) / 255: 205 -> 0.19608 (not < 0.196), 206 -> 0.19216, 89 -> 0.651, 90 -> 0.647
    pixels = np.array([[205, 206, 89, 90, 255, 0]], dtype=np.uint8)
    grid = load_ros_map(write_map(tmp_path, pixels))
    np.testing.assert_array_equal(grid.data[0], [UNK, FREE, OCC, UNK, FREE, OCC])


def test_scale_mode_gives_values_between_the_thresholds(tmp_path: Path) -> None:
    # thresholds 0.25 / 0.75: value = 1 + floor(98 * (p - 0.25) / 0.5); 128 -> p 0.498 -> 49
    pixels = np.array([[255, 191, 128, 64, 0]], dtype=np.uint8)
    fields = {"mode": "scale", "free_thresh": 0.25, "occupied_thresh": 0.75}
    grid = load_ros_map(write_map(tmp_path, pixels, fields=fields))
    np.testing.assert_array_equal(grid.data[0], [FREE, 1, 49, 98, OCC])
    assert grid.data.dtype == np.int8


def test_raw_mode_uses_the_value_and_out_of_range_is_unknown(tmp_path: Path) -> None:
    pixels = np.array([[0, 37, 100, 101, 255]], dtype=np.uint8)
    grid = load_ros_map(write_map(tmp_path, pixels, fields={"mode": "raw"}))
    np.testing.assert_array_equal(grid.data[0], [0, 37, 100, UNK, UNK])


@pytest.mark.parametrize("mode", ["trinary", "scale"])
def test_transparent_pixels_are_unknown(tmp_path: Path, mode: str) -> None:
    grey = np.array([[0, 0, 254, 254]], dtype=np.uint8)
    alpha = np.array([[255, 0, 255, 0]], dtype=np.uint8)
    image = Image.fromarray(np.dstack([grey, alpha]))
    grid = load_ros_map(write_map(tmp_path, image, fmt="png", fields={"mode": mode}))
    np.testing.assert_array_equal(grid.data[0], [OCC, UNK, FREE, UNK])


def test_colour_is_the_mean_of_the_channels(tmp_path: Path) -> None:
    # yellow: mean 170 -> p 0.333 -> unknown (a luma conversion would call it free); red: mean 85 -> occupied
    rgb = np.array([[[255, 255, 0], [255, 0, 0], [255, 255, 255]]], dtype=np.uint8)
    grid = load_ros_map(write_map(tmp_path, rgb, fmt="png"))
    np.testing.assert_array_equal(grid.data[0], [UNK, OCC, FREE])


def test_sixteen_bit_and_palette_images(tmp_path: Path) -> None:
    deep = np.array([[0, 65535, 52685]], dtype=np.uint16)  # 52685 / 257 = 205
    grid = load_ros_map(write_map(tmp_path, Image.fromarray(deep), fmt="png"))
    np.testing.assert_array_equal(grid.data[0], [OCC, FREE, UNK])
    palette = Image.fromarray(PATTERN).convert("P")
    grid = load_ros_map(write_map(tmp_path, palette, fmt="png"))
    np.testing.assert_array_equal(grid.data, [[FREE, FREE, OCC], [OCC, FREE, UNK]])


def test_numeric_strings_and_absolute_image_path(tmp_path: Path) -> None:
    (tmp_path / "img").mkdir()
    absolute = (tmp_path / "img" / "map.pgm").resolve()
    fields = {"resolution": '"0.25"', "image": str(absolute)}
    yaml_path = write_map(tmp_path / "img", PATTERN, fields=fields)
    grid = load_ros_map(yaml_path)
    assert grid.resolution == 0.25


def test_lse_arena(real_maps: Path) -> None:
    yaml_path = real_maps / "lse_arena" / "lse_arena.yaml"
    grid = load_ros_map(yaml_path)
    assert grid.shape == (60, 80)
    assert grid.resolution == 0.05
    assert grid.origin == (0.0, 0.0)
    assert grid.count(UNK) == 0
    assert grid.count(OCC) == 345
    with Image.open(real_maps / "lse_arena" / "lse_arena.pgm") as image:
        pixels = np.asarray(image)
    np.testing.assert_array_equal(grid.data[::-1] == OCC, pixels == 0)


def test_turtlebot3_world(real_maps: Path) -> None:
    grid = load_ros_map(real_maps / "turtlebot3_world" / "map.yaml")  # image: ./map.pgm
    assert grid.shape == (384, 384)
    assert grid.origin == (-10.0, -10.0)
    assert set(np.unique(grid.data)) == {UNK, FREE, OCC}
    # The arena (free between the pillars) sits around the world origin, surrounded by unknown.
    assert grid.data[grid.world_to_cell(0.5, 0.0)] == FREE
    assert grid.data[grid.world_to_cell(0.0, 0.5)] == FREE
    assert grid.data[grid.world_to_cell(-9.9, -9.9)] == UNK


def test_warehouse_is_tall_and_uses_its_own_free_thresh(real_maps: Path) -> None:
    grid = load_ros_map(real_maps / "nav2_warehouse" / "warehouse.yaml")
    assert grid.shape == (1674, 1006)
    assert grid.resolution == 0.03
    assert grid.origin == (-15.1, -25.0)
    assert grid.count(FREE) == 1422292  # 254 and 255 pixels


def slam_map_pixels() -> NDArray[np.uint8]:
    """A 20 x 20 room of white floor inside a black wall, amid grey unknown as map_saver writes it
    (40 x 40 pixels: 324 free, 76 wall, 1,200 grey)."""
    pixels = np.full((40, 40), 205, dtype=np.uint8)
    pixels[10:30, 10:30] = 0
    pixels[11:29, 11:29] = 254
    return pixels


@pytest.mark.parametrize("mode", ["trinary", "scale"])
def test_grey_unknown_that_nav2s_default_threshold_reads_as_free_is_read_as_unknown(tmp_path: Path, mode: str) -> None:
    yaml_path = write_map(tmp_path, slam_map_pixels(), fields={"free_thresh": 0.25, "mode": mode})
    with pytest.warns(MapWarning) as caught:
        grid = load_ros_map(yaml_path)
    assert grid.count(FREE) == 324  # the room, not the room and its surround (1,524 as map_server reads it)
    assert grid.count(CellState.UNKNOWN) == 1200
    (warning,) = caught
    assert str(warning.message) == (
        f"{yaml_path}: 1,200 pixels of grey 205 (map_saver's unknown, 79% of the free cells) read as unknown, "
        "not as free space as free_thresh 0.25 would have them; set free_thresh: 0.196 in the YAML to say so"
    )


@pytest.mark.parametrize("fields", [{}, {"free_thresh": 0.25, "negate": 1}, {"free_thresh": 0.1}])
def test_grey_read_as_unknown_or_occupied_loads_quietly(tmp_path: Path, fields: dict[str, object]) -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        grid = load_ros_map(write_map(tmp_path, slam_map_pixels(), fields=fields))
    assert grid.count(FREE) == (324 if fields.get("negate") != 1 else 76)


def test_a_few_grey_spots_read_as_free_load_quietly(real_maps: Path, tmp_path: Path) -> None:
    pixels = np.full((40, 40), 254, dtype=np.uint8)
    pixels[:2, :] = 205  # 80 grey of 1,600 free: 5 %, as Nav2's depot sample
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert load_ros_map(write_map(tmp_path, pixels, fields={"free_thresh": 0.25})).count(FREE) == 1600
        depot = load_ros_map(real_maps / "nav2_depot" / "depot.yaml")
    assert depot.count(FREE) == 170587 + 8894


@pytest.mark.parametrize("fmt", ["pgm", "png"])
def test_round_trip(tmp_path: Path, fmt: str) -> None:
    rng = np.random.default_rng(7)
    data = rng.choice(np.array([UNK, FREE, OCC], dtype=np.int8), size=(17, 23))
    grid = OccupancyGrid(data, 1.0 / 30.0, (-1.2345678901, 3.5))
    yaml_path = save_ros_map(grid, tmp_path / "out" / "saved.yaml", image_format=fmt)
    assert yaml_path == tmp_path / "out" / "saved.yaml"
    assert (tmp_path / "out" / f"saved.{fmt}").is_file()
    loaded = load_ros_map(yaml_path)
    np.testing.assert_array_equal(loaded.data, grid.data)
    assert loaded.resolution == grid.resolution
    assert loaded.origin == grid.origin
    with Image.open(tmp_path / "out" / f"saved.{fmt}") as image:
        assert image.mode == "L"
        assert set(np.unique(np.asarray(image))) == {0, 205, 254}


def test_saved_yaml_has_the_map_saver_fields(tmp_path: Path) -> None:
    grid = OccupancyGrid(np.zeros((2, 2), dtype=np.int8), 0.05)
    text = save_ros_map(grid, tmp_path / "m.yaml").read_text()
    for line in ("image: m.pgm", "mode: trinary", "negate: 0", "occupied_thresh: 0.65", "free_thresh: 0.196"):
        assert line in text.splitlines()


def test_round_trip_of_a_real_map(tmp_path: Path, real_maps: Path) -> None:
    grid = load_ros_map(real_maps / "turtlebot3_world" / "map.yaml")
    again = load_ros_map(save_ros_map(grid, tmp_path / "tb3.yaml"))
    np.testing.assert_array_equal(again.data, grid.data)
    assert (again.resolution, again.origin) == (grid.resolution, grid.origin)


def test_save_thresholds_non_trinary_values_as_map_saver(tmp_path: Path) -> None:
    data = np.array([[0, 25, 26, 64, 65, 100, -1]], dtype=np.int8)
    loaded = load_ros_map(save_ros_map(OccupancyGrid(data, 0.05), tmp_path / "m.yaml"))
    np.testing.assert_array_equal(loaded.data[0], [FREE, FREE, UNK, UNK, OCC, OCC, UNK])


def test_save_rejects_bad_format_and_path(tmp_path: Path) -> None:
    grid = OccupancyGrid(np.zeros((2, 2), dtype=np.int8), 0.05)
    with pytest.raises(MapError, match="'jpg'"):
        save_ros_map(grid, tmp_path / "m.yaml", image_format="jpg")
    with pytest.raises(MapError, match=r"m\.pgm"):
        save_ros_map(grid, tmp_path / "m.pgm")


# --- bad input -------------------------------------------------------------------------------


def raises_map_error(yaml_path: Path, match: str) -> None:
    with pytest.raises(MapError, match=match) as info:
        load_ros_map(yaml_path)
    assert "\n" not in str(info.value)


def test_missing_yaml(tmp_path: Path) -> None:
    raises_map_error(tmp_path / "nope.yaml", "not found.*nope.yaml")


@pytest.mark.parametrize(
    ("text", "match"),
    [
        ("- a\n- b\n", "mapping.*list"),
        ("just text\n", "mapping.*str"),
        ("image: [unclosed\n", "cannot parse"),
    ],
)
def test_yaml_that_is_not_a_mapping(tmp_path: Path, text: str, match: str) -> None:
    (tmp_path / "m.yaml").write_text(text)
    raises_map_error(tmp_path / "m.yaml", match)


@pytest.mark.parametrize("field", ["image", "resolution", "origin", "negate", "occupied_thresh", "free_thresh"])
def test_missing_field(tmp_path: Path, field: str) -> None:
    raises_map_error(write_map(tmp_path, PATTERN, drop=(field,)), f"missing field '{field}'")


@pytest.mark.parametrize("value", ["0", "-0.05", "abc", "true", ".nan", "[0.05]"])
def test_bad_resolution(tmp_path: Path, value: str) -> None:
    raises_map_error(write_map(tmp_path, PATTERN, fields={"resolution": value}), "resolution")


@pytest.mark.parametrize(
    ("field", "value", "match"),
    [
        ("origin", "[0.0, 0.0, 0.5]", "rotated.*0.5"),
        ("origin", "[0.0, 0.0]", "origin.*must be"),
        ("origin", "[a, 0.0, 0.0]", "origin.*'a'"),
        ("origin", "[1.0e16, 1.0e16, 0.0]", r"origin.*within \+-1e\+06 m"),  # was 'explored' at coverage 0
        ("origin", "[0.0, -2.0e6, 0.0]", r"origin.*within"),
        ("mode", "fuzzy", "mode.*'fuzzy'"),
        ("negate", "2", "negate.*2"),
        ("occupied_thresh", "1.5", "occupied_thresh.*1.5"),
        ("free_thresh", "0.9", "free_thresh 0.9"),
        ("image", "''", "image"),
    ],
)
def test_bad_field(tmp_path: Path, field: str, value: str, match: str) -> None:
    raises_map_error(write_map(tmp_path, PATTERN, fields={field: value}), match)


def test_image_missing(tmp_path: Path) -> None:
    yaml_path = write_map(tmp_path, PATTERN, fields={"image": "gone.pgm"})
    raises_map_error(yaml_path, "image file not found.*gone.pgm")


def test_truncated_png(tmp_path: Path) -> None:
    yaml_path = write_map(tmp_path, PATTERN, fmt="png")
    (tmp_path / "map.png").write_bytes(b"\x89PNG\r\n\x1a\n\x00\x00\x00\rIHDR\x00\x00")
    raises_map_error(yaml_path, "cannot read map image.*map.png")


def test_truncated_pixel_data(tmp_path: Path) -> None:
    yaml_path = write_map(tmp_path, PATTERN)
    (tmp_path / "map.pgm").write_bytes(b"P5\n100 100\n255\n" + bytes(50))
    with pytest.raises(MapError, match=r"map\.pgm") as info:
        load_ros_map(yaml_path)
    assert info.value.__cause__ is not None


def test_file_that_is_not_an_image(tmp_path: Path) -> None:
    yaml_path = write_map(tmp_path, PATTERN)
    (tmp_path / "map.pgm").write_text("this is not an image\n")
    raises_map_error(yaml_path, "cannot read map image")


def test_save_quotes_an_image_name_yaml_would_misread(tmp_path: Path) -> None:
    grid = OccupancyGrid(np.array([[0, 100, -1]], dtype=np.int8), 0.05)
    loaded = load_ros_map(save_ros_map(grid, tmp_path / "lab: #2.yaml"))
    np.testing.assert_array_equal(loaded.data, grid.data)


def test_palette_image_with_a_transparent_entry(tmp_path: Path) -> None:
    image = Image.fromarray(np.array([[0, 254, 0]], dtype=np.uint8)).convert("P")
    image.info["transparency"] = image.getpixel((2, 0))  # palette index of black: all black is transparent
    grid = load_ros_map(write_map(tmp_path, image, fmt="png"))
    np.testing.assert_array_equal(grid.data[0], [UNK, FREE, UNK])


@pytest.mark.parametrize("name", ["[lab.yaml", "@x.yaml", "true.yaml", "1e3.yaml", "a b.yaml"])
def test_save_handles_awkward_names(tmp_path: Path, name: str) -> None:
    grid = OccupancyGrid(np.array([[0, 100, -1]], dtype=np.int8), 0.05)
    np.testing.assert_array_equal(load_ros_map(save_ros_map(grid, tmp_path / name)).data, grid.data)


def test_fields_map_server_does_not_read_are_named_in_a_warning_with_what_they_may_mean(tmp_path: Path) -> None:
    yaml_path = write_map(tmp_path, slam_map_pixels(), fields={"mod": "raw", "comment": "office"})
    with pytest.warns(MapWarning) as caught:
        grid = load_ros_map(yaml_path)
    assert grid.count(FREE) == 324  # read as without them: mode trinary
    (warning,) = caught
    assert str(warning.message) == (
        f"{yaml_path}: fields 'mod' (did you mean mode?), 'comment' ignored: map_server reads only image, "
        "resolution, origin, negate, occupied_thresh, free_thresh, mode"
    )
    many = {f"extra_{i}": i for i in range(7)}
    with pytest.warns(MapWarning, match=r"'extra_4' and 2 more ignored"):
        load_ros_map(write_map(tmp_path, slam_map_pixels(), fields=many))
