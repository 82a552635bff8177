"""Record an episode as pictures: a final PNG and a GIF with one frame per decision."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from numpy.typing import NDArray
from PIL import Image

from frontier_rl.core.sim.episode import DecisionContext, Ranking
from frontier_rl.core.sim.metrics import EpisodeResult
from frontier_rl.core.sim.simulator import ExplorationSimulator
from frontier_rl.core.world.grid import OccupancyGrid
from frontier_rl.core.world.worlds import World
from frontier_rl.render import FrameCanvas, captioned, save_gif, save_image
from frontier_rl.swarm.result import TeamResult

LEGEND = "square: start   disc: robot   dots: frontiers ranked, green best to orange worst"
"""The second line of an episode picture's caption (ASCII: Pillow's default font has no symbols)."""


@dataclass
class EpisodeRecorder:
    """An ``on_decision`` hook for :func:`~frontier_rl.core.sim.episode.run_episode` that keeps the
    last ranking (for the PNG) and, if ``frames`` is on, a GIF frame per decision.

    Attributes:
        world: the episode's world.
        frames: whether to keep a frame at every decision.
        scale: pixels per cell.
    """

    world: World
    frames: bool = False
    scale: int = 2
    _frames: list[Image.Image] = field(default_factory=list, init=False)
    _last_centers: NDArray[np.float64] = field(default_factory=lambda: np.zeros((0, 2)), init=False)

    def __post_init__(self) -> None:
        self._canvas = FrameCanvas(self.world.grid, self.scale)

    def __call__(self, sim: ExplorationSimulator, context: DecisionContext, ranking: Ranking) -> None:
        """Store the ranked frontiers (best first) and, if asked, a frame."""
        self._last_centers = context.frontiers.centers[ranking.order]
        if self.frames:
            caption = f"t = {sim.sim_time:6.1f} s   coverage {100 * sim.coverage:5.1f} %"
            if ranking.weight is not None:
                caption += f"   w = {ranking.weight:.2f}"
            self._frames.append(self._picture(context.grid, sim.trajectory(), self._last_centers, caption))

    def _picture(
        self, grid: OccupancyGrid | None, trajectory: NDArray[np.float64], centers: NDArray[np.float64], caption: str
    ) -> Image.Image:
        return captioned(self._canvas.episode(grid, trajectory, centers), f"{caption}\n{LEGEND}", 32)

    def final_picture(self, result: EpisodeResult, title: str) -> Image.Image:
        """The final picture: true map with the path | built map with the path and the last
        ranked frontiers (green = best), under a caption of ``title`` and the metrics."""
        caption = (
            f"{title}   t = {result.sim_time_s:.1f} s   coverage {100 * result.coverage:.1f} %   "
            f"path {result.path_length_m:.1f} m   decisions {result.decisions}"
        )
        return self._picture(result.final_map, result.trajectory, self._last_centers, caption)

    def save_png(self, path: str | Path, result: EpisodeResult, title: str) -> Path:
        """:meth:`final_picture` written to ``path`` (.png or .gif) through a temporary file."""
        return save_image(self.final_picture(result, title), path)

    def save_gif(self, path: str | Path, result: EpisodeResult | None = None, title: str = "") -> Path:
        """All recorded frames as a looping GIF (``path`` ends in .gif), then, with ``result``, the
        final picture (so an episode that ended before its first decision still has a frame).

        Raises:
            ValueError: no frame at all (no decision recorded and no ``result``).
        """
        frames = self._frames if result is None else [*self._frames, self.final_picture(result, title)]
        return save_gif(frames, path)


def save_team_png(path: str | Path, world: World, result: TeamResult, title: str, scale: int = 2) -> Path:
    """A team episode's picture: true map with every robot's path | the team's merged map with them
    (one colour per robot; a failed robot's path ends where it stopped)."""
    picture = FrameCanvas(world.grid, scale).team(result.team_map, result.trajectories)
    failed = sum(t is not None for t in result.failed_at_s)
    caption = (
        f"{title}   {result.robots} robots, {result.strategy}   t = {result.sim_time_s:.1f} s   "
        f"coverage {100 * result.coverage:.1f} %   overlap {100 * result.overlap:.0f} %"
        + (f"   {failed} failed" if failed else "")
    )
    return save_image(captioned(picture, caption, 18), path)
