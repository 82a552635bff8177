"""Pictures of an episode: the true map, the built map, the ranked frontiers, the path and, at the
end, the explorable space the robot left unseen.

Drawn with Pillow straight from the grids (one pixel block per cell), so a frame costs about a
millisecond and an episode's GIF a fraction of a second.
"""

from __future__ import annotations

import io
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray
from PIL import Image, ImageDraw

from frontier_rl.atomic_write import write_bytes_atomic
from frontier_rl.core.world.grid import CellState, OccupancyGrid
from frontier_rl.errors import ConfigError, short_path

_COLOURS = {
    CellState.UNKNOWN: (150, 150, 160),
    CellState.FREE: (250, 250, 250),
    CellState.OCCUPIED: (25, 25, 30),
}
_TRUE_FREE = (225, 235, 245)
_UNSEEN = (240, 160, 0)  # amber: explorable space the robot's map left unknown
_PATH = (220, 40, 40)
_ROBOT = (200, 0, 120)
_BEST = np.array([20, 170, 60])
_WORST = np.array([250, 150, 20])


def grid_to_rgb(data: NDArray[np.int8]) -> NDArray[np.uint8]:
    """An (rows, cols, 3) image of a cell-state grid, row 0 at the *bottom* (map convention)."""
    rgb = np.empty((*data.shape, 3), np.uint8)
    rgb[:] = _COLOURS[CellState.UNKNOWN]
    rgb[data == CellState.FREE] = _COLOURS[CellState.FREE]
    rgb[data >= CellState.OCCUPIED // 2] = _COLOURS[CellState.OCCUPIED]
    return rgb[::-1]


class FrameCanvas:
    """Draws maps of one world at a fixed scale, in the world's frame.

    Args:
        world: the ground-truth grid; it fixes the extent and the frame.
        scale: pixels per cell.
        crop_margin: if given, the pictures of :meth:`episode` and :meth:`team` show only the
            world's free space and this margin (m) around it, not a map file's wide border of wall.
    """

    def __init__(self, world: OccupancyGrid, scale: int = 2, crop_margin: float | None = None) -> None:
        self.world = world
        self.scale = max(int(scale), 1)
        self._truth: Image.Image | None = None  # drawn once: a recorder draws it at every frame
        self._box = None if crop_margin is None else self._free_box(crop_margin)

    def _free_box(self, margin: float) -> tuple[int, int, int, int] | None:
        """The pixel box (left, top, right, bottom) of the world's free cells and ``margin`` (m)
        around them, within the world; None if it has no free cell."""
        rows, cols = np.nonzero(self.world.data == CellState.FREE)
        if len(rows) == 0:
            return None
        pad = int(np.ceil(margin / self.world.resolution))
        height, width = self.world.shape
        r0, r1 = max(int(rows.min()) - pad, 0), min(int(rows.max()) + pad, height - 1)
        c0, c1 = max(int(cols.min()) - pad, 0), min(int(cols.max()) + pad, width - 1)
        s = self.scale
        return c0 * s, (height - 1 - r1) * s, (c1 + 1) * s, (height - r0) * s

    def _cropped(self, image: Image.Image) -> Image.Image:
        return image if self._box is None else image.crop(self._box)

    def _to_px(self, xy: NDArray[np.float64]) -> NDArray[np.float64]:
        g = self.world
        px = (xy[:, 0] - g.origin[0]) / g.resolution * self.scale
        py = (g.height - (xy[:, 1] - g.origin[1]) / g.resolution) * self.scale
        return np.column_stack((px, py))

    def states(self, grid: OccupancyGrid | None) -> NDArray[np.int8]:
        """The cell states of ``grid`` in the world's frame and shape, row 0 at the bottom: unknown
        wherever ``grid`` does not reach (everywhere if None)."""
        states = np.full(self.world.shape, CellState.UNKNOWN, np.int8)
        if grid is not None:
            r0, c0 = self.world.world_to_cell(
                grid.origin[0] + 0.5 * grid.resolution, grid.origin[1] + 0.5 * grid.resolution
            )
            rows = slice(max(r0, 0), min(r0 + grid.height, self.world.height))
            cols = slice(max(c0, 0), min(c0 + grid.width, self.world.width))
            states[rows, cols] = grid.data[rows.start - r0 : rows.stop - r0, cols.start - c0 : cols.stop - c0]
        return states

    def unseen(self, grid: OccupancyGrid | None, explorable: NDArray[np.bool_]) -> NDArray[np.bool_]:
        """The ``explorable`` cells (a mask of the world's shape) ``grid`` leaves unknown."""
        return np.asarray(explorable & (self.states(grid) == CellState.UNKNOWN))

    def base(self, grid: OccupancyGrid | None) -> Image.Image:
        """The world's extent with ``grid`` pasted where it lies (all unknown if None)."""
        return self._image(grid_to_rgb(self.states(grid)))

    def _image(self, rgb: NDArray[np.uint8]) -> Image.Image:
        """An (rows, cols, 3) picture, row 0 at the top, at the canvas's scale."""
        image = Image.fromarray(np.ascontiguousarray(rgb))
        return image.resize((image.width * self.scale, image.height * self.scale), Image.Resampling.NEAREST)

    def truth(self, unseen: NDArray[np.bool_] | None = None) -> Image.Image:
        """The ground truth (free space tinted so it reads as 'the real building'), with the
        ``unseen`` cells (a mask of the world's shape: :meth:`unseen`) in amber: a new image to draw on."""
        if unseen is not None and unseen.any():
            rgb = self._truth_rgb()
            rgb[unseen[::-1]] = _UNSEEN
            return self._image(rgb)
        if self._truth is None:
            self._truth = self._image(self._truth_rgb())
        return self._truth.copy()

    def _truth_rgb(self) -> NDArray[np.uint8]:
        rgb = grid_to_rgb(self.world.data)
        rgb[(self.world.data == CellState.FREE)[::-1]] = _TRUE_FREE
        return rgb

    def draw_path(
        self, image: Image.Image, trajectory: NDArray[np.float64], colour: tuple[int, int, int] | None = None
    ) -> None:
        """The robot's path, its start (a hollow square) and its last pose (a disc), in ``colour`` for
        one robot of a team."""
        draw = ImageDraw.Draw(image)
        if len(trajectory) >= 2:
            line = colour or _PATH
            draw.line([tuple(p) for p in self._to_px(trajectory[:, :2])], fill=line, width=max(self.scale, 1))
        if len(trajectory):
            (x0, y0), (x, y) = self._to_px(trajectory[[0, -1], :2])
            r = 3 * self.scale
            draw.rectangle((x0 - r, y0 - r, x0 + r, y0 + r), outline=colour or _ROBOT, width=max(self.scale, 2))
            draw.ellipse((x - r, y - r, x + r, y + r), fill=colour or _ROBOT, outline=(0, 0, 0))

    def draw_frontiers(self, image: Image.Image, centers_ranked: NDArray[np.float64]) -> None:
        """Frontier centres, best first: green for the best, orange for the worst."""
        draw = ImageDraw.Draw(image)
        n = len(centers_ranked)
        r = 3 * self.scale
        for rank, (x, y) in reversed(list(enumerate(self._to_px(centers_ranked)))):
            mix = rank / max(n - 1, 1)
            colour = tuple(int(v) for v in (1 - mix) * _BEST + mix * _WORST)
            draw.ellipse((x - r, y - r, x + r, y + r), fill=colour, outline=(0, 0, 0))

    def frame(
        self,
        grid: OccupancyGrid | None,
        trajectory: NDArray[np.float64],
        centers_ranked: NDArray[np.float64] | None = None,
    ) -> Image.Image:
        """The built map with the path so far and the ranked frontiers."""
        image = self.base(grid)
        self.draw_path(image, trajectory)
        if centers_ranked is not None and len(centers_ranked):
            self.draw_frontiers(image, centers_ranked)
        return image

    def episode(
        self,
        grid: OccupancyGrid | None,
        trajectory: NDArray[np.float64],
        centers_ranked: NDArray[np.float64] | None = None,
        unseen: NDArray[np.bool_] | None = None,
    ) -> Image.Image:
        """One robot's picture: the true world with the path and the ``unseen`` cells in amber |
        the built map ``grid`` with the path and the ranked frontiers (best first)."""
        truth = self.truth(unseen)
        self.draw_path(truth, trajectory)
        return side_by_side(self._cropped(truth), self._cropped(self.frame(grid, trajectory, centers_ranked)))

    def team(
        self,
        grid: OccupancyGrid | None,
        trajectories: Sequence[NDArray[np.float64]],
        unseen: NDArray[np.bool_] | None = None,
    ) -> Image.Image:
        """A team's picture: the true world with every robot's path and the ``unseen`` cells in amber |
        the team's map ``grid`` with them, one colour per robot (:data:`TEAM_COLOURS`)."""
        truth, built = self.truth(unseen), self.base(grid)
        for index, trajectory in enumerate(trajectories):
            for image in (truth, built):
                self.draw_path(image, trajectory, TEAM_COLOURS[index % len(TEAM_COLOURS)])
        return side_by_side(self._cropped(truth), self._cropped(built))


#: One colour per robot of a team (matplotlib's tab10).
TEAM_COLOURS = (
    (31, 119, 180),
    (255, 127, 14),
    (44, 160, 44),
    (214, 39, 40),
    (148, 103, 189),
    (140, 86, 75),
    (227, 119, 194),
    (127, 127, 127),
)


def captioned(image: Image.Image, text: str, height: int) -> Image.Image:
    """``image`` under a white band ``height`` pixels high holding ``text`` (lines 3 pixels apart)."""
    out = Image.new("RGB", (image.width, image.height + height), (255, 255, 255))
    ImageDraw.Draw(out).multiline_text((4, 3), text, fill=(0, 0, 0), spacing=3)
    out.paste(image, (0, height))
    return out


def rgb_array(image: Image.Image) -> NDArray[np.uint8]:
    """``image`` as a Gymnasium ``rgb_array`` frame: (height, width, 3) uint8."""
    return np.asarray(image.convert("RGB"), dtype=np.uint8)


def side_by_side(left: Image.Image, right: Image.Image, gap: int = 8) -> Image.Image:
    """Two images next to each other on a white background."""
    out = Image.new("RGB", (left.width + gap + right.width, max(left.height, right.height)), (255, 255, 255))
    out.paste(left, (0, 0))
    out.paste(right, (left.width + gap, 0))
    return out


#: Picture formats by file suffix (lower case): what :func:`save_image` writes.
IMAGE_FORMATS = {".png": "PNG", ".gif": "GIF"}


def save_image(image: Image.Image, path: str | Path, **params: Any) -> Path:
    """Write ``image`` to ``path`` in the format its suffix names (:data:`IMAGE_FORMATS`), all or
    nothing: encoded in memory, then written with
    :func:`~frontier_rl.atomic_write.write_bytes_atomic`, so that a failed write (a full disk)
    never leaves a truncated picture in place of a good one. ``params`` go to
    :meth:`PIL.Image.Image.save`.

    Raises:
        ConfigError: a suffix other than .png or .gif.
        OutputWriteError: the picture could not be written (``path`` is then unchanged).
    """
    path = Path(path)
    fmt = IMAGE_FORMATS.get(path.suffix.lower())
    if fmt is None:
        raise ConfigError(f"picture {short_path(path)}: unknown suffix {path.suffix!r} (use .png or .gif)")
    buffer = io.BytesIO()
    image.save(buffer, format=fmt, **params)
    path.parent.mkdir(parents=True, exist_ok=True)  # a folder the command line's check let it make
    write_bytes_atomic(path, buffer.getvalue())
    return path


def save_gif(frames: Sequence[Image.Image], path: str | Path, frame_ms: int = 120) -> Path:
    """Write ``frames`` as a looping GIF (``path`` ends in .gif); the last frame is held for a second."""
    if not frames:
        raise ValueError("no frames to write")
    path = Path(path)
    if path.suffix.lower() != ".gif":
        raise ConfigError(f"animation {short_path(path)} must be a .gif file name, got suffix {path.suffix!r}")
    durations = [frame_ms] * (len(frames) - 1) + [1000]
    params = {"save_all": True, "append_images": list(frames[1:]), "duration": durations, "loop": 0}
    return save_image(frames[0], path, optimize=False, **params)
