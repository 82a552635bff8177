"""Record an episode as pictures: a final PNG and a GIF with one frame per decision."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from numpy.typing import NDArray
from PIL import Image
from scipy import ndimage
from scipy.spatial import cKDTree

from frontier_rl.core.sim.episode import DecisionContext, Ranking
from frontier_rl.core.sim.metrics import EpisodeResult
from frontier_rl.core.sim.simulator import ExplorationSimulator
from frontier_rl.core.world.grid import OccupancyGrid
from frontier_rl.core.world.worlds import World
from frontier_rl.render import FrameCanvas, captioned, save_gif, save_image
from frontier_rl.swarm.result import TeamResult

LEGEND = "square: start   disc: robot   dots: frontiers ranked, green best to orange worst"
"""The second line of an episode picture's caption (ASCII: Pillow's default font has no symbols)."""

UNSEEN_LEGEND = "amber (left): space the robot could have seen and did not"
"""What a final picture adds to :data:`LEGEND`: the explorable cells its map left unknown."""

PICTURE_MARGIN_M = 1.0
"""How much (m) of the world around its free space an episode's pictures show: a map file's border
of unknown, read as wall, is cut off."""

PLACE_MIN_M2 = 0.25
"""The least area (m²) of unseen explorable space :meth:`EpisodeRecorder.unseen_places` names: half
a person lying down; less is a wall's foot or a corner."""


@dataclass(frozen=True)
class UnseenPlace:
    """One connected piece of the explorable space an episode left unseen (an amber patch of its
    picture).

    Attributes:
        area_m2: its area (m²).
        x, y: its centre (m, world frame; the mean of its cells, which may lie outside a bent piece).
        path_within_m: how near (m) the robot's path came to its nearest cell (infinite without a path).
    """

    area_m2: float
    x: float
    y: float
    path_within_m: float

    def describe(self) -> str:
        """As a phrase: ``5.3 m² around (7.6, -2.6) m, the path within 0.3 m``."""
        where = f"{self.area_m2:.1f} m² around ({self.x:.1f}, {self.y:.1f}) m"
        return f"{where}, the path within {self.path_within_m:.1f} m"


MAX_GIF_FRAMES = 300
"""Most frames an animation keeps (office frames are about 0.5 MB each as a GIF holds them): beyond
it every other one is dropped and the decisions between frames double, so that an episode of
thousands of decisions (a policy that stands still until the time cap) animates in bounded memory."""


@dataclass
class EpisodeRecorder:
    """An ``on_decision`` hook for :func:`~frontier_rl.core.sim.episode.run_episode` that keeps the
    last ranking (for the PNG) and, if ``frames`` is on, a GIF frame per decision (every second,
    fourth, ... decision once more than :data:`MAX_GIF_FRAMES` would be kept).

    Attributes:
        world: the episode's world.
        frames: whether to keep a frame at every decision.
        scale: pixels per cell.
    """

    world: World
    frames: bool = False
    scale: int = 2
    _frames: list[Image.Image] = field(default_factory=list, init=False)
    _decisions: int = field(default=0, init=False)
    _stride: int = field(default=1, init=False)  # decisions per frame
    _last_centers: NDArray[np.float64] = field(default_factory=lambda: np.zeros((0, 2)), init=False)
    _explorable: NDArray[np.bool_] | None = field(default=None, init=False)

    def __post_init__(self) -> None:
        self._canvas = FrameCanvas(self.world.grid, self.scale, PICTURE_MARGIN_M)

    def __call__(self, sim: ExplorationSimulator, context: DecisionContext, ranking: Ranking) -> None:
        """Store the ranked frontiers (best first) and, if asked, a frame."""
        self._last_centers = context.frontiers.centers[ranking.order]
        self._explorable = sim.world.explorable  # fitted to the simulated robot: what coverage counts
        self._decisions += 1
        if self.frames and (self._decisions - 1) % self._stride == 0:
            caption = f"t = {sim.sim_time:6.1f} s   coverage {100 * sim.coverage:5.1f} %"
            if ranking.weight is not None:
                caption += f"   w = {ranking.weight:.2f}"
            picture = self._picture(context.grid, sim.trajectory(), self._last_centers, caption)
            # as a GIF stores it (Pillow's own conversion on saving): a third of the memory
            self._frames.append(picture.convert("P", palette=Image.Palette.ADAPTIVE))
            if len(self._frames) > MAX_GIF_FRAMES:
                self._frames, self._stride = self._frames[::2], 2 * self._stride

    def _picture(
        self,
        grid: OccupancyGrid | None,
        trajectory: NDArray[np.float64],
        centers: NDArray[np.float64],
        caption: str,
        unseen: NDArray[np.bool_] | None = None,
    ) -> Image.Image:
        legend = LEGEND if unseen is None else f"{LEGEND}   {UNSEEN_LEGEND}"
        return captioned(self._canvas.episode(grid, trajectory, centers, unseen), f"{caption}\n{legend}", 32)

    def unseen(self, result: EpisodeResult) -> NDArray[np.bool_]:
        """The explorable cells (a mask of the world's grid) ``result``'s final map left unknown: those
        of the simulated robot's world (fitted to its size) once it made a decision, else the world's."""
        explorable = self.world.explorable if self._explorable is None else self._explorable
        return self._canvas.unseen(result.final_map, explorable)

    def unseen_places(self, result: EpisodeResult, most: int = 3) -> list[UnseenPlace]:
        """The ``most`` largest pieces (8-connected) of :meth:`unseen` of at least
        :data:`PLACE_MIN_M2`, largest first: where the space left lies, and how near the robot came."""
        labels, count = ndimage.label(self.unseen(result), structure=np.ones((3, 3), bool))
        grid = self.world.grid
        areas = np.bincount(labels.ravel(), minlength=count + 1)[1:] * grid.resolution**2
        path = cKDTree(result.trajectory[:, :2]) if len(result.trajectory) else None
        places = []
        for index in np.argsort(-areas, kind="stable")[:most]:
            if areas[index] < PLACE_MIN_M2:
                break
            cells = grid.cells_to_world(np.argwhere(labels == index + 1))
            centre = cells.mean(axis=0)
            near = math.inf if path is None else float(path.query(cells)[0].min())
            places.append(UnseenPlace(float(areas[index]), float(centre[0]), float(centre[1]), near))
        return places

    def final_picture(self, result: EpisodeResult, title: str) -> Image.Image:
        """The final picture: true map with the path and the explorable space left unseen (amber) |
        built map with the path and the last ranked frontiers (green = best), under a caption of
        ``title`` and the metrics."""
        caption = (
            f"{title}   t = {result.sim_time_s:.1f} s   coverage {100 * result.coverage:.1f} %   "
            f"path {result.path_length_m:.1f} m   decisions {result.decisions}"
        )
        return self._picture(result.final_map, result.trajectory, self._last_centers, caption, self.unseen(result))

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
    (one colour per robot; a failed robot's path ends where it stopped), and in amber on the true map
    the explorable space the team's map left unknown."""
    canvas = FrameCanvas(world.grid, scale, PICTURE_MARGIN_M)
    picture = canvas.team(result.team_map, result.trajectories, canvas.unseen(result.team_map, world.explorable))
    failed = sum(t is not None for t in result.failed_at_s)
    caption = (
        f"{title}   {result.robots} robots, {result.strategy}   t = {result.sim_time_s:.1f} s   "
        f"coverage {100 * result.coverage:.1f} %   overlap {100 * result.overlap:.0f} %"
        + (f"   {failed} failed" if failed else "")
    )
    return save_image(captioned(picture, f"{caption}\n{UNSEEN_LEGEND}", 32), path)
