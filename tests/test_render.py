"""Tests of frontier_rl.render and the episode pictures: what a reader needs to read a run."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from frontier_rl import recording
from frontier_rl.core.sim.config import SimConfig
from frontier_rl.core.sim.episode import run_episode
from frontier_rl.core.world.catalog import generate_world
from frontier_rl.core.world.grid import CellState, OccupancyGrid
from frontier_rl.policies import make_policy
from frontier_rl.recording import LEGEND, PLACE_MIN_M2, EpisodeRecorder, UnseenPlace, save_team_png
from frontier_rl.render import FrameCanvas
from frontier_rl.swarm import TeamConfig, run_team_episode

_ROBOT = (200, 0, 120)
_UNSEEN = (240, 160, 0)


def test_a_path_shows_where_it_started_and_where_the_robot_is() -> None:
    canvas = FrameCanvas(OccupancyGrid(np.full((40, 40), CellState.FREE, np.int8), 0.05), scale=2)
    image = canvas.truth()
    trajectory = np.array([[0.5, 0.5, 0.0], [1.0, 1.0, 0.0], [1.5, 1.5, 0.0]])
    canvas.draw_path(image, trajectory)
    (x0, y0), (x1, y1) = [(round(x / 0.05 * 2), round((40 - y / 0.05) * 2)) for x, y, _ in trajectory[[0, -1]]]
    r = 3 * canvas.scale
    pixels = np.asarray(image)
    assert tuple(pixels[y0, x0 - r]) == _ROBOT  # the start square's left side
    assert tuple(pixels[y0 + r - 2, x0 - r + 2]) != _ROBOT  # hollow: the start is not the robot
    assert tuple(pixels[y1, x1 - r + 2]) == _ROBOT  # the robot's disc at the end
    assert tuple(pixels[y1, x1 - r - 3]) != _ROBOT


def test_an_episode_picture_carries_its_legend() -> None:
    world = generate_world("office", 0)
    recorder = EpisodeRecorder(world)
    result = run_episode(world, make_policy("nearest"), seed=0, on_decision=recorder)
    picture = recorder.final_picture(result, "office / nearest")
    assert picture.height == 2 * world.grid.height + 32  # two panels of the map under two lines of caption
    assert "start" in LEGEND and "robot" in LEGEND and LEGEND.isascii()


def test_the_final_picture_shows_the_explorable_space_left_unseen_in_amber() -> None:
    """An episode cut short: the amber cells of the true map are the explorable space its map left
    unknown (as much as the result says is left), none of it where the robot mapped, and the places
    named are those pieces, largest first, with how near the path came."""
    world = generate_world("office", 0)
    recorder = EpisodeRecorder(world)
    config = SimConfig(max_sim_time=60.0, min_time_cap=60.0, time_per_area=0.1)
    result = run_episode(world, make_policy("nearest"), config, seed=0, on_decision=recorder)
    assert result.end_reason == "time_cap" and result.coverage < 0.9
    unseen = recorder.unseen(result)
    assert unseen.sum() * world.grid.resolution**2 == pytest.approx(result.explorable_left_m2, abs=0.01)
    cols = world.grid.shape[1]
    mapped = FrameCanvas(world.grid).states(result.final_map) != CellState.UNKNOWN
    assert not (unseen & mapped).any() and (unseen | mapped | ~world.explorable).all()
    picture = np.asarray(recorder.final_picture(result, "office / nearest"))[32:, : 2 * cols]  # the true map
    amber = np.all(picture == _UNSEEN, axis=2)[::2, ::2][::-1]  # one pixel a cell, row 0 at the bottom
    assert (amber == unseen).mean() > 0.99  # all but the path and the robot drawn over it
    places = recorder.unseen_places(result)
    assert [p.area_m2 for p in places] == sorted((p.area_m2 for p in places), reverse=True)
    assert places[0].area_m2 > 5 and all(p.area_m2 >= PLACE_MIN_M2 for p in places)
    assert sum(p.area_m2 for p in places) <= result.explorable_left_m2 + 1e-9
    path = result.trajectory[:, :2]
    for place in places:
        assert place.path_within_m > 0  # unseen space lies off the path
        assert world.grid.in_bounds(*world.grid.world_to_cell(place.x, place.y))
    assert np.hypot(*(path - [places[0].x, places[0].y]).T).min() >= places[0].path_within_m
    assert UnseenPlace(5.26, 7.64, -2.58, 0.33).describe() == "5.3 m² around (7.6, -2.6) m, the path within 0.3 m"


def test_an_animation_of_many_decisions_keeps_a_bounded_number_of_frames(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A policy that stood still until the time cap made 1,487 frames: 4.5 GB, then a MemoryError."""
    monkeypatch.setattr(recording, "MAX_GIF_FRAMES", 10)
    world = generate_world("office", 0)
    recorder = EpisodeRecorder(world, frames=True)
    config = SimConfig(max_sim_time=120.0)
    result = run_episode(world, make_policy("nearest"), config, seed=0, on_decision=recorder)
    assert result.decisions > 40
    stride = 1  # thinned to every 2nd, 4th, ... decision, until the frames fit
    while result.decisions > 10 * stride:
        stride *= 2
    assert len(recorder._frames) == len(range(0, result.decisions, stride)) <= 10
    with Image.open(recorder.save_gif(tmp_path / "a.gif", result, "office")) as gif:
        assert gif.n_frames == len(recorder._frames) + 1  # and the final picture


def test_an_episode_that_leaves_nothing_unseen_names_no_place() -> None:
    world = generate_world("office", 0)
    recorder = EpisodeRecorder(world)
    result = run_episode(world, make_policy("nearest"), seed=0, on_decision=recorder)
    assert result.coverage > 0.999 and recorder.unseen_places(result) == []
    assert recorder.unseen(result).sum() * world.grid.resolution**2 == pytest.approx(result.explorable_left_m2)


def test_a_team_picture_shows_what_the_team_map_left_unseen(tmp_path: Path) -> None:
    world = generate_world("office", 1)
    config = SimConfig(max_sim_time=40.0, min_time_cap=40.0, time_per_area=0.1)
    result = run_team_episode(world, make_policy("nearest"), config, TeamConfig(robots=2), seed=1)
    assert result.coverage < 0.9
    save_team_png(tmp_path / "team.png", world, result, "office / nearest")
    picture = np.asarray(Image.open(tmp_path / "team.png").convert("RGB"))[32:, : 2 * world.grid.shape[1]]
    amber = np.all(picture == _UNSEEN, axis=2)[::2, ::2][::-1]
    unseen = FrameCanvas(world.grid).unseen(result.team_map, world.explorable)
    assert unseen.any() and (amber == unseen).mean() > 0.99


def test_a_picture_shows_the_free_space_and_its_margin_not_a_wide_border_of_wall() -> None:
    data = np.full((100, 120), CellState.OCCUPIED, np.int8)
    data[40:60, 30:50] = CellState.FREE  # 1 m x 1 m of free space far inside a 5 m x 6 m map
    world = OccupancyGrid(data, 0.05)
    path = np.array([[1.6, 2.1, 0.0], [2.4, 2.9, 0.0]])
    whole = FrameCanvas(world, scale=2).episode(None, path)
    cropped = FrameCanvas(world, scale=2, crop_margin=0.25).episode(None, path)
    assert whole.size == (2 * 120 * 2 + 8, 100 * 2)
    assert cropped.size == (2 * 30 * 2 + 8, 30 * 2)  # 20 free cells and 5 of margin on each side
    panel = np.asarray(cropped)[:, : 30 * 2]
    assert tuple(panel[5 * 2, 5 * 2]) == (225, 235, 245)  # the free block's top-left corner, a margin in
    assert tuple(panel[5 * 2 - 1, 5 * 2 - 1]) == (25, 25, 30)  # the margin: wall
    edge = FrameCanvas(world, scale=2, crop_margin=10.0).episode(None, path)
    assert edge.size == whole.size  # a margin beyond the map stops at its edge
