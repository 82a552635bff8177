"""Frontier detection: fringe cells, 8-connected clusters, size filter, centres, information gain.

A *fringe* cell is a FREE cell with an UNKNOWN 4-neighbour. Fringe cells are grouped into
8-connected clusters; clusters of ``min_cells`` or fewer are dropped (LiDAR noise specks), and only
clusters that touch the region the robot can reach through known free space are candidates.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import cached_property

import numba as nb
import numpy as np
from numpy.typing import NDArray

from frontier_rl.core.frontiers.fringe import cluster_fringe
from frontier_rl.core.frontiers.segments import disc_offsets, split_segments, summarise_segments
from frontier_rl.core.world.grid import OCCUPIED_I8, UNKNOWN_I8, OccupancyGrid
from frontier_rl.core.world.raycast import FASTMATH, dda_step, ray_start
from frontier_rl.core.world.robot import Pose
from frontier_rl.errors import ConfigError

_SLACK = 1e-6
"""Radians more either side of a cell's angle that :func:`_mark_rays` casts, for rounding: a ray
along the square's edge (the thesis's LiDAR has a ray a degree)."""


def visible_unknown(
    state: NDArray[np.int8],
    centres: NDArray[np.float64],
    n_rays: int,
    max_range: float,
    box: tuple[float, float, float, float] | None = None,
    entries: NDArray[np.int64] | None = None,
) -> NDArray[np.int64]:
    """For each centre ((n, 2) as (col, row), cell units), the unknown cells a scan from it would
    reveal: rays pass through free and unknown cells and stop at occupied ones or the grid's edge;
    each cell counts once per centre.

    Two hints give the same counts for far fewer ray steps where the unknown is a small pocket: a
    ``box`` (top, bottom, left, right: cell units, the cells' edges) that holds every unknown cell
    a scan could reach (rays are cast only if they meet it, and only until they leave it), and
    ``entries``, (m, 2) the cells (row, col) where a ray can meet the unknown first: every unknown
    cell with a free 4-neighbour, no centre in an unknown cell (only the rays through one of them
    within range are cast)."""
    edges = np.zeros(4, np.float64) if box is None else np.asarray(box, np.float64)
    gates = np.zeros((0, 2), np.int64) if entries is None else np.ascontiguousarray(entries, np.int64)
    every_ray = entries is None or len(gates) > n_rays // 4  # more: marking them costs more than the rays
    origins = np.ascontiguousarray(centres, np.float64)
    return _visible_unknown(state, origins, n_rays, max_range, edges, gates, box is not None, every_ray)


@nb.njit(cache=True, fastmath=FASTMATH)
def _box_span(cx: float, cy: float, dx: float, dy: float, box: NDArray[np.float64]) -> tuple[float, float]:
    """The ray parameters (cells) at which the ray from (cx, cy) along (dx, dy) enters and leaves
    ``box`` (top, bottom, left, right), widened by half a cell; (inf, -inf) where it misses it."""
    enter, leave = -np.inf, np.inf
    for origin, step, low, high in ((cx, dx, box[2] - 0.5, box[3] + 0.5), (cy, dy, box[0] - 0.5, box[1] + 0.5)):
        if step == 0.0:
            if origin < low or origin > high:
                return np.inf, -np.inf
            continue
        near, far = (low - origin) / step, (high - origin) / step
        enter, leave = max(enter, min(near, far)), min(leave, max(near, far))
    return enter, leave


@nb.njit(cache=True)  # no fast-math: the angles decide which rays are cast at all
def _mark_rays(cast: NDArray[np.bool_], cx: float, cy: float, entries: NDArray[np.int64], max_range: float) -> None:
    """Mark in ``cast`` the rays (of ``len(cast)`` evenly spaced, the first along +x) from
    (cx, cy) that may pass through one of the ``entries`` cells (row, col) within ``max_range``
    (cells): those within the angle each cell's square subtends (and :data:`_SLACK` either side)."""
    n_rays = len(cast)
    step = 2.0 * math.pi / n_rays
    for j in range(entries.shape[0]):
        row, col = float(entries[j, 0]), float(entries[j, 1])
        near_x, near_y = min(max(cx, col), col + 1.0), min(max(cy, row), row + 1.0)
        gap = math.hypot(near_x - cx, near_y - cy)
        if gap > max_range:
            continue
        if gap == 0.0:  # the centre is in (or on) the cell
            cast[:] = True
            return
        base = math.atan2(row + 0.5 - cy, col + 0.5 - cx)
        low, high = 0.0, 0.0
        for corner_x, corner_y in ((col, row), (col + 1.0, row), (col, row + 1.0), (col + 1.0, row + 1.0)):
            turn = math.atan2(corner_y - cy, corner_x - cx) - base
            turn -= 2.0 * math.pi * round(turn / (2.0 * math.pi))  # within (-pi, pi]: the square subtends less
            low, high = min(low, turn), max(high, turn)
        first, last = math.ceil((base + low - _SLACK) / step), math.floor((base + high + _SLACK) / step)
        for i in range(int(first), int(last) + 1):
            cast[i % n_rays] = True


@nb.njit(cache=True, fastmath=FASTMATH)
def _visible_unknown(
    state: NDArray[np.int8],
    centres: NDArray[np.float64],
    n_rays: int,
    max_range: float,
    box: NDArray[np.float64],
    entries: NDArray[np.int64],
    boxed: bool,
    every_ray: bool,
) -> NDArray[np.int64]:
    """:func:`visible_unknown` with its hints (``boxed``: use the ``box``; ``every_ray``: ignore
    the ``entries``), the information gain's hot path asking neither. The cells counted are
    stamped in a window of the scan's extent around the centre, not in a map-sized array: on a
    large map zeroing (and touching) one cost more than the rays."""
    rows, cols = state.shape
    side = 2 * int(math.ceil(max_range)) + 5  # rays enter cells up to ceil(max_range) + 1 from its cell
    height, width = min(side, rows), min(side, cols)  # a window larger than the grid: the grid
    stamp = np.zeros((height, width), np.int32)
    cos_a, sin_a = np.empty(n_rays), np.empty(n_rays)
    for i in range(n_rays):
        a = 2.0 * math.pi * i / n_rays
        cos_a[i], sin_a[i] = math.cos(a), math.sin(a)
    totals = np.zeros(centres.shape[0], np.int64)
    cast = np.ones(n_rays, np.bool_)
    for k in range(centres.shape[0]):
        cx, cy = centres[k, 0], centres[k, 1]
        if not every_ray:
            cast[:] = False
            _mark_rays(cast, cx, cy, entries, max_range)
        # the window around the centre, shifted inside the grid: it still holds every cell of
        # the grid within range
        top = min(max(int(math.floor(cy)) - side // 2, 0), rows - height)
        left = min(max(int(math.floor(cx)) - side // 2, 0), cols - width)
        total = 0
        for i in range(n_rays):
            if not cast[i]:
                continue  # it meets no unknown cell first
            limit = max_range
            if boxed:  # past the box no cell counts
                limit = min(max_range, _box_span(cx, cy, cos_a[i], sin_a[i], box)[1] + 1.0)
            row, col, s_r, s_c, tm_r, tm_c, td_r, td_c = ray_start(cx, cy, cos_a[i], sin_a[i])
            t = 0.0
            while t <= limit and 0 <= row < rows and 0 <= col < cols:
                value = state[row, col]
                if value == OCCUPIED_I8:
                    break
                wr, wc = row - top, col - left
                assert 0 <= wr < height and 0 <= wc < width  # the window spans the range
                if value == UNKNOWN_I8 and stamp[wr, wc] != k + 1:
                    stamp[wr, wc] = k + 1
                    total += 1
                row, col, tm_r, tm_c, t = dda_step(row, col, s_r, s_c, tm_r, tm_c, td_r, td_c)
        totals[k] = total
    return totals


@dataclass(frozen=True)
class Frontiers:
    """The candidate frontiers of one map, as parallel arrays (one entry per frontier).

    A frontier is a fringe cluster, or a segment of one: clusters longer than the segment length
    are split (:func:`split_segments`) so that each goal resolves a part the robot can see.

    Attributes:
        grid: the map they were found on.
        centers: (n, 2) frontier centres, the mean of the cells' centres, world (x, y) in m
            (eq. 3.1's d is measured to it; it may lie off the frontier, e.g. inside an arc).
        sizes: (n,) number of fringe cells (eq. 3.1's g).
        distances: (n,) straight-line distance from the robot to the centre (m).
        min_distances: (n,) straight-line distance from the robot to the nearest cell centre (m).
        flat_cells: flat indices into ``grid`` of the cells of all frontiers, grouped by frontier.
        spans: (n, 2) start and end of each frontier's cells in ``flat_cells``.
        goal_cells: (n, 2) the goal of each frontier, (row, col) in ``grid``: a cell the robot can
            reach that sees the frontier (see :func:`summarise_segments`).
    """

    grid: OccupancyGrid
    centers: NDArray[np.float64]
    sizes: NDArray[np.int64]
    distances: NDArray[np.float64]
    min_distances: NDArray[np.float64]
    flat_cells: NDArray[np.int64] = field(repr=False)
    spans: NDArray[np.int64] = field(repr=False)
    goal_cells: NDArray[np.int64] = field(repr=False)

    def __len__(self) -> int:
        return int(self.sizes.shape[0])

    @property
    def goals(self) -> NDArray[np.float64]:
        """(n, 2) goal points, world (x, y) in m: the centres of the goal cells."""
        return self.grid.cells_to_world(self.goal_cells)

    def cells_of(self, index: int) -> NDArray[np.int64]:
        """(size, 2) row and column indices in ``grid`` of frontier ``index``'s cells."""
        start, end = self.spans[index]
        rows, cols = np.divmod(self.flat_cells[start:end], self.grid.width)
        return np.column_stack((rows, cols)).astype(np.int64)

    @cached_property
    def cells(self) -> tuple[NDArray[np.int64], ...]:
        """Per frontier, the (row, col) indices of its cells in ``grid``, shape (size, 2)."""
        return tuple(self.cells_of(i) for i in range(len(self)))

    def subset(self, idx: NDArray[np.bool_] | NDArray[np.int64]) -> Frontiers:
        """The frontiers where a boolean mask ``idx`` is True (in the same order), or at indices
        ``idx`` (in that order)."""
        return Frontiers(
            self.grid,
            self.centers[idx],
            self.sizes[idx],
            self.distances[idx],
            self.min_distances[idx],
            self.flat_cells,
            self.spans[idx],
            self.goal_cells[idx],
        )

    def information_gain(self, sensor_range: float, n_rays: int = 180) -> NDArray[np.int64]:
        """Unknown cells a scan of range ``sensor_range`` (m) from each centre would reveal."""
        grid = self.grid
        if not sensor_range >= 0:
            raise ConfigError(f"sensor_range must be >= 0 m, got {sensor_range!r}")
        centres = (self.centers - np.asarray(grid.origin, np.float64)) / grid.resolution
        reach = min(sensor_range / grid.resolution, math.hypot(*grid.shape) + 2.0)  # beyond: every ray has left
        return visible_unknown(grid.data, centres.reshape(-1, 2), n_rays, reach)


def detect_frontiers(
    grid: OccupancyGrid,
    robot: Pose,
    reachable: NDArray[np.bool_] | None = None,
    min_cells: int = 4,
    segment_length: float = math.inf,
    goal_reach: float = 3.0,
    keep: Callable[[NDArray[np.int64], NDArray[np.int64]], NDArray[np.bool_]] | None = None,
) -> Frontiers:
    """Frontier clusters of ``grid`` larger than ``min_cells``, split into segments of at most
    about ``segment_length`` (m), that the robot can get to see.

    Args:
        grid: the robot's map.
        robot: robot pose (m); distances are measured from it.
        reachable: cells the robot can reach through known free space (same shape as the grid);
            a segment is kept when one of them within ``goal_reach`` (m) of it sees it (its goal).
            ``None`` accepts every segment, with its goal on the segment itself.
        min_cells: clusters of this many cells or fewer are dropped (the thesis drops <= 4; the
            simulator passes fewer on cells coarser than 0.05 m, so that no more than 0.2 m is dropped).
        segment_length: the largest span (m) of a segment; ``inf`` keeps clusters whole.
        goal_reach: how far (m) from a segment its goal may be.
        keep: which segments to go on with (a boolean mask, one entry per segment), given their
            cells (flat indices into the grid, grouped by segment) and sizes: the others are
            dropped before their goals are looked for, which is most of the cost where the map
            has many specks. ``None`` keeps all.
    """
    res = grid.resolution
    robot_col = (robot.x - grid.origin[0]) / res
    robot_row = (robot.y - grid.origin[1]) / res
    reach = np.ones(grid.shape, np.bool_) if reachable is None else reachable
    counts, _, flat = cluster_fringe(grid.data, reach, robot_row, robot_col)
    radius = segment_length / (2.0 * res) if math.isfinite(segment_length) else np.inf
    cells, sizes = split_segments(flat, counts[:, 0].copy(), min_cells, grid.width, radius)
    if keep is not None:
        kept = keep(cells, sizes)
        cells, sizes = cells[np.repeat(kept, sizes)], sizes[kept]
    offsets = disc_offsets(int(goal_reach / res) if reachable is not None else 0)
    centres, min_d2, goals = summarise_segments(grid.data, reach, cells, sizes, offsets, robot_row, robot_col)
    ends = np.cumsum(sizes)
    spans = np.column_stack((ends - sizes, ends)).astype(np.int64).reshape(-1, 2)
    xy = np.column_stack((grid.origin[0] + (centres[:, 1] + 0.5) * res, grid.origin[1] + (centres[:, 0] + 0.5) * res))
    distances = np.hypot(xy[:, 0] - robot.x, xy[:, 1] - robot.y)
    everything = Frontiers(grid, xy.reshape(-1, 2), sizes, distances, np.sqrt(min_d2) * res, cells, spans, goals)
    return everything.subset(goals[:, 0] >= 0)
