"""``benchmark ariadne``: ARiADNE's test protocol on DungeonMaps-style PNGs."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from PIL import Image
from typer.testing import CliRunner

from frontier_rl.cli import app
from frontier_rl.errors import ConfigError
from frontier_rl.evaluation.protocols.published import (
    ARIADNE_SENSOR_PX,
    ARIADNE_START_INDEX,
    ARIADNE_UNSEEN_PX,
    ProtocolRun,
    ariadne_config,
    ariadne_maps,
    ariadne_world,
    run_ariadne,
    summary_rows,
)
from frontier_rl.io.dungeon import DUNGEON_RESOLUTION, marker_pixels

WALL, FREE, START = (127, 127, 127), (195, 195, 194), (255, 216, 0)


def dungeon_png(path: Path, seed: int = 0) -> Path:
    """A small DungeonMaps-style PNG (120 x 160 px): two rooms joined by a door, a start marker."""
    rng = np.random.default_rng(seed)
    image = np.zeros((120, 160, 3), np.uint8)
    image[:] = WALL
    image[5:115, 5:75] = FREE
    image[5:115, 80:155] = FREE
    door = int(rng.integers(20, 90))
    image[door : door + 20, 75:80] = FREE
    image[50:66, 20:36] = START
    Image.fromarray(image).save(path)
    return path


def test_start_is_the_128th_marker_pixel_in_row_major_order(tmp_path: Path) -> None:
    path = dungeon_png(tmp_path / "img_1.png")
    pixels = marker_pixels(path)
    assert pixels.shape == (256, 2)
    assert tuple(pixels[ARIADNE_START_INDEX]) == (50 + 7, 20 + 15)  # row 7, last column of the square
    world = ariadne_world(path)
    row, col = world.grid.world_to_cell(world.start.x, world.start.y)
    assert (world.grid.height - 1 - row, col) == (57, 35)


def test_the_sensor_reaches_80_pixels_and_every_scan_is_mapped() -> None:
    config = ariadne_config()
    assert config.lidar.max_range == pytest.approx(ARIADNE_SENSOR_PX * DUNGEON_RESOLUTION)
    assert config.mapper.usable_range == config.lidar.max_range
    assert 0 < config.mapper.temporal_update < 1e-3


def test_a_run_stops_counting_at_250_unseen_pixels(tmp_path: Path) -> None:
    path = dungeon_png(tmp_path / "img_2.png", seed=3)
    run = run_ariadne("nearest", path)
    assert run.rule_met and run.explored
    whole_px = run.path_length_m / DUNGEON_RESOLUTION
    assert 0 < run.distance_px <= whole_px + 1e-6
    assert ARIADNE_UNSEEN_PX > 0
    assert run_ariadne("nearest", path) == run  # deterministic


def test_summary_prints_the_mean_and_population_std() -> None:
    runs = [ProtocolRun("a", f"m{k}", d, True, 10.0 * k, 2.0, True) for k, d in enumerate((100.0, 200.0, 600.0))]
    runs.append(ProtocolRun("b", "m0", 50.0, False, 5.0, 1.0, False))
    a, b = summary_rows(runs, ["a", "b"])
    assert a.average_length_px == pytest.approx(300.0)
    assert a.length_std_px == pytest.approx(np.sqrt(((100 - 300) ** 2 + (200 - 300) ** 2 + 300**2) / 3))
    assert (a.tests, a.rule_met, b.rule_met, b.explored) == (3, 3, 0, 0)


def test_maps_in_ariadne_order_and_bad_folders(tmp_path: Path) -> None:
    for k in (1, 2, 10):
        dungeon_png(tmp_path / f"img_{k}.png", k)
    assert [p.name for p in ariadne_maps(tmp_path)] == ["img_2.png", "img_10.png", "img_1.png"]  # reverse by name
    assert len(ariadne_maps(tmp_path, limit=2)) == 2
    with pytest.raises(ConfigError, match="not a folder"):
        ariadne_maps(tmp_path / "nope")
    empty = tmp_path / "empty"
    empty.mkdir()
    with pytest.raises(ConfigError, match="no PNG"):
        ariadne_maps(empty)


def test_cli_prints_both_metrics_and_writes_json(tmp_path: Path) -> None:
    maps = tmp_path / "maps"
    maps.mkdir()
    dungeon_png(maps / "img_1.png")
    out = tmp_path / "ariadne.json"
    args = ["benchmark", "ariadne", "--methods", "nearest", "--maps", str(maps), "--workers", "1", "--json", str(out)]
    result = CliRunner().invoke(app, args)
    assert result.exit_code == 0, result.output
    assert "nearest: |#Total test: 1 |#Average length: " in result.output
    payload = json.loads(out.read_text())
    assert payload["protocol"] == "ariadne" and payload["summary"][0]["tests"] == 1
    assert payload["runs"][0]["map_name"] == "img_1.png"


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--methods", "teleport"], "teleport"),
        (["--methods", " , "], "names no policy"),
        (["--limit", "-1"], ">= 0"),
        (["--maps", "/nonexistent/folder"], "no such file or folder"),
        (["--workers", "1000"], "--workers must be at most 256"),
        (["--workers", "0"], "--workers must be a positive integer, got 0"),  # as evaluate's
    ],
)
def test_cli_bad_input_is_one_line(tmp_path: Path, args: list[str], message: str) -> None:
    maps = tmp_path / "maps"
    maps.mkdir()
    dungeon_png(maps / "img_1.png")
    base = ["benchmark", "ariadne", "--maps", str(maps), "--workers", "1"]
    result = CliRunner().invoke(app, base + args)
    assert result.exit_code == 2
    assert message in result.output and "Traceback" not in result.output


def test_when_every_run_fails_one_line_says_so_and_no_empty_table_comes_before(tmp_path: Path) -> None:
    maps = tmp_path / "maps"
    maps.mkdir()
    dungeon_png(maps / "img_1.png")
    policy = tmp_path / "broken.py"
    policy.write_text(
        "class Broken:\n    name = 'broken'\n\n    def rank(self, context, rng):\n        raise RuntimeError('boom')\n"
    )
    args = ["benchmark", "ariadne", "--methods", f"{policy}:Broken", "--maps", str(maps), "--workers", "1"]
    result = CliRunner().invoke(app, args)
    assert result.exit_code == 2, result.output
    assert result.stdout == ""  # no table of nothing
    assert result.stderr.startswith("error: every one of the 1 run(s) failed") and result.stderr.count("\n") == 1
