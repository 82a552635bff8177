"""The runs shown in the report: each method's first episode on the first worlds, drawn again
(episodes are deterministic, so the picture is the episode of the first row), and optionally an
animation of one of them."""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

from PIL import Image

from frontier_rl.core.sim.episode import run_episode, warm_up
from frontier_rl.core.sim.metrics import EpisodeSummary
from frontier_rl.evaluation.report.table import short_labels
from frontier_rl.evaluation.running.experiment import EpisodeJob, ExperimentConfig, job_parts
from frontier_rl.recording import EpisodeRecorder, save_team_png
from frontier_rl.render import save_image
from frontier_rl.swarm import run_team_episode

PICTURES_FOLDER = "pictures"
"""The sub-folder of the results folder the pictures are written to."""

MAX_PICTURE_PX = 1600
"""Pictures wider or taller than this (large maps) are scaled down to it (pixels)."""


@dataclass(frozen=True)
class RunPicture:
    """A drawn episode.

    Attributes:
        world: the world as in the experiment (generator name or map file).
        method: the method as in the experiment.
        path: the PNG (or, for the animation, the GIF).
        title: world and method.
        caption: what it shows, with the episode's seed, time, coverage and end reason.
    """

    world: str
    method: str
    path: Path
    title: str
    caption: str


@dataclass(frozen=True)
class AnimatedRun:
    """The episode a report animates: the first of ``method`` on ``world``, as the experiment
    names them."""

    world: str
    method: str


def draw_runs(config: ExperimentConfig, out: Path, worlds: int, animate: AnimatedRun | None = None) -> list[RunPicture]:
    """Draw the first episode of every method on each of the first ``worlds`` worlds of
    ``config`` into ``out/pictures/``; ``animate`` also writes a GIF with a frame per decision of
    that episode. Returns the pictures, world by world, in method order."""
    if worlds <= 0 and animate is None:
        return []
    folder = out / PICTURES_FOLDER
    folder.mkdir(exist_ok=True)
    warm_up()
    method_labels, world_labels = short_labels(config.methods), short_labels(config.worlds)
    pictures = []
    chosen = list(config.worlds[:worlds])
    if animate is not None and animate.world not in chosen:
        chosen.append(animate.world)
    for world_name in chosen:
        for method in config.methods:
            gif = animate == AnimatedRun(world_name, method)
            if world_name not in config.worlds[:worlds] and not gif:
                continue
            stem = _file_stem(f"{world_labels[world_name]}_{method_labels[method]}")
            title = f"{world_labels[world_name]} / {method_labels[method]}"
            job = EpisodeJob(method, world_name, 0, config.seed, config.parsed_methods[method])
            pictures += _draw(config, job, folder / stem, title, gif)
    return pictures


def _draw(config: ExperimentConfig, job: EpisodeJob, stem: Path, title: str, gif: bool) -> list[RunPicture]:
    world, policy, team = job_parts(job, config.settings())
    if team is not None:
        team_result = run_team_episode(world, policy, config.sim, team, seed=job.seed)
        path = _fit(save_team_png(stem.with_name(stem.name + ".png"), world, team_result, title))
        summary: EpisodeSummary = team_result.summary()
    else:
        recorder = EpisodeRecorder(world, frames=gif)
        result = run_episode(world, policy, config.sim, seed=job.seed, on_decision=recorder)
        path = save_image(_shrink(recorder.final_picture(result, title)), stem.with_name(stem.name + ".png"))
        summary = result.summary()
    ended = summary.end_reason.label if summary.end_reason else "-"
    caption = (
        f"Episode 0 (seed {job.seed}): {summary.sim_time_s:.1f} s, coverage "
        f"{100 * summary.coverage:.1f} %, ended {ended}. Left: the true "
        "map, the path driven and, in amber, the space the robot could have seen and did not; right: the map "
        "the robot built"
        + ("." if team is not None else ", with the frontiers ranked at the last decision (green: the chosen one).")
    )
    pictures = [RunPicture(job.world, job.method, path, title, caption)]
    if gif and team is None:
        frames = recorder.save_gif(stem.with_name(stem.name + ".gif"), result, title)
        pictures.append(RunPicture(job.world, job.method, frames, f"{title}, animated", "One frame per decision."))
    return pictures


def _file_stem(name: str) -> str:
    return re.sub(r"[^A-Za-z0-9.]+", "_", name.removesuffix(".zip")).strip("_") or "run"


def _shrink(image: Image.Image) -> Image.Image:
    if max(image.size) > MAX_PICTURE_PX:
        image = image.copy()
        image.thumbnail((MAX_PICTURE_PX, MAX_PICTURE_PX), Image.Resampling.LANCZOS)
    return image


def _fit(path: Path) -> Path:
    """Scale a written picture down to :data:`MAX_PICTURE_PX` if it is larger."""
    with Image.open(path) as image:
        image.load()
        if max(image.size) <= MAX_PICTURE_PX:
            return path
        return save_image(_shrink(image), path)
