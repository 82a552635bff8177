"""Tests of frontier_rl.render and the episode pictures: what a reader needs to read a run."""

from __future__ import annotations

import numpy as np

from frontier_rl.core.sim.episode import run_episode
from frontier_rl.core.world.catalog import generate_world
from frontier_rl.core.world.grid import CellState, OccupancyGrid
from frontier_rl.policies import make_policy
from frontier_rl.recording import LEGEND, EpisodeRecorder
from frontier_rl.render import FrameCanvas

_ROBOT = (200, 0, 120)


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
