"""Frontier detection: fringe cells, 8-connected clusters, size filter, centres, information gain.

A *fringe* cell is a FREE cell with an UNKNOWN 4-neighbour. Fringe cells are grouped into
8-connected clusters; clusters of ``min_cells`` or fewer are dropped (LiDAR noise specks), and only
clusters that touch the region the robot can reach through known free space are candidates.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property, lru_cache

import numba as nb
import numpy as np
from numpy.typing import NDArray

from frontier_rl.core.world.grid import CellState, OccupancyGrid
from frontier_rl.core.world.raycast import FASTMATH, dda_step, ray_start
from frontier_rl.core.world.robot import Pose

_UNKNOWN = np.int8(CellState.UNKNOWN)
_FREE = np.int8(CellState.FREE)
_OCCUPIED = np.int8(CellState.OCCUPIED)

_MAX_SIGHT_TRIES = 64
_NEIGHBOURS_8 = np.array([(-1, -1), (-1, 0), (-1, 1), (0, -1), (0, 1), (1, -1), (1, 0), (1, 1)], np.int64)


@nb.njit(cache=True, inline="always")
def _is_fringe(state: NDArray[np.int8], row: int, col: int) -> bool:
    rows, cols = state.shape
    if state[row, col] != _FREE:
        return False
    return bool(
        (row > 0 and state[row - 1, col] == _UNKNOWN)
        or (row + 1 < rows and state[row + 1, col] == _UNKNOWN)
        or (col > 0 and state[row, col - 1] == _UNKNOWN)
        or (col + 1 < cols and state[row, col + 1] == _UNKNOWN)
    )


@nb.njit(cache=True)
def fringe_mask(state: NDArray[np.int8]) -> NDArray[np.bool_]:
    """FREE cells with an UNKNOWN 4-neighbour (cells beyond the grid's edge are not unknown)."""
    rows, cols = state.shape
    padded = np.full((rows + 2, cols + 2), _FREE, np.int8)
    padded[1:-1, 1:-1] = state
    out = np.zeros((rows, cols), np.bool_)
    for r in range(rows):
        for c in range(cols):
            out[r, c] = padded[r + 1, c + 1] == _FREE and (
                (padded[r, c + 1] == _UNKNOWN)
                | (padded[r + 2, c + 1] == _UNKNOWN)
                | (padded[r + 1, c] == _UNKNOWN)
                | (padded[r + 1, c + 2] == _UNKNOWN)
            )
    return out


@nb.njit(cache=True)
def cluster_fringe(
    state: NDArray[np.int8],
    reachable: NDArray[np.bool_],
    robot_row: float,
    robot_col: float,
) -> tuple[NDArray[np.int64], NDArray[np.float64], NDArray[np.int64]]:
    """Find the 8-connected fringe clusters and gather their statistics in one pass.

    Args:
        state: grid of cell states.
        reachable: cells the robot can reach through known free space.
        robot_row, robot_col: robot position in continuous cell coordinates.

    Returns:
        counts: (n, 2) cells per cluster and how many of them are reachable.
        stats: (n, 3) sum of row indices, sum of column indices, min squared distance (cells²)
            from the robot to a cell centre.
        cells: flat indices of the fringe cells, grouped by cluster (cluster k owns
            ``cells[offsets[k]:offsets[k+1]]`` where offsets is the cumulative sum of counts).
    """
    rows, cols = state.shape
    todo = fringe_mask(state)  # fringe cells not yet in a cluster
    stack = np.empty(rows * cols, np.int64)
    cells = np.empty(rows * cols, np.int64)
    counts_list = []
    stats_list = []
    n_cells = 0
    n_clusters = 0
    for r0 in range(rows):
        for c0 in range(cols):
            if not todo[r0, c0]:
                continue
            n_clusters += 1
            todo[r0, c0] = False
            top = 0
            stack[top] = r0 * cols + c0
            top += 1
            size = 0
            n_reach = 0
            sum_r = 0.0
            sum_c = 0.0
            min_d2 = np.inf
            while top > 0:
                top -= 1
                flat = stack[top]
                r = flat // cols
                c = flat % cols
                cells[n_cells] = flat
                n_cells += 1
                size += 1
                if reachable[r, c]:
                    n_reach += 1
                sum_r += r
                sum_c += c
                d2 = (r + 0.5 - robot_row) ** 2 + (c + 0.5 - robot_col) ** 2
                min_d2 = min(min_d2, d2)
                for k in range(8):
                    rr = r + _NEIGHBOURS_8[k, 0]
                    cc = c + _NEIGHBOURS_8[k, 1]
                    if 0 <= rr < rows and 0 <= cc < cols and todo[rr, cc]:
                        todo[rr, cc] = False
                        stack[top] = rr * cols + cc
                        top += 1
            counts_list.append((size, n_reach))
            stats_list.append((sum_r, sum_c, min_d2))
    counts = np.zeros((n_clusters, 2), np.int64)
    stats = np.zeros((n_clusters, 3), np.float64)
    for k in range(n_clusters):
        counts[k, 0], counts[k, 1] = counts_list[k]
        stats[k, 0], stats[k, 1], stats[k, 2] = stats_list[k]
    return counts, stats, cells[:n_cells].copy()


@nb.njit(cache=True)
def count_fringe(state: NDArray[np.int8], rows_idx: NDArray[np.int64], cols_idx: NDArray[np.int64]) -> int:
    """How many of the given cells are still fringe cells."""
    n = 0
    for i in range(rows_idx.shape[0]):
        if _is_fringe(state, rows_idx[i], cols_idx[i]):
            n += 1
    return n


@nb.njit(cache=True)
def unknown_beside(
    state: NDArray[np.int8], rows_idx: NDArray[np.int64], cols_idx: NDArray[np.int64], truth: NDArray[np.int8]
) -> tuple[int, int]:
    """How many UNKNOWN cells of ``state`` are 8-neighbours of the given cells (each counted
    once), and how many of those are FREE in ``truth`` (a grid of the same shape)."""
    rows, cols = state.shape
    counted = set()
    free = 0
    for i in range(rows_idx.shape[0]):
        for k in range(8):
            r, c = rows_idx[i] + _NEIGHBOURS_8[k, 0], cols_idx[i] + _NEIGHBOURS_8[k, 1]
            if 0 <= r < rows and 0 <= c < cols and state[r, c] == _UNKNOWN and r * cols + c not in counted:
                counted.add(r * cols + c)
                free += truth[r, c] == _FREE
    return len(counted), free


@nb.njit(cache=True, fastmath=FASTMATH)
def visible_unknown(
    state: NDArray[np.int8],
    stamp: NDArray[np.int32],
    stamp_id: int,
    cx: float,
    cy: float,
    n_rays: int,
    max_range: float,
) -> int:
    """Unknown cells a scan from (cx, cy) (cell units) would reveal: rays pass through free and
    unknown cells and stop at occupied ones or the grid's edge; each cell counts once."""
    rows, cols = state.shape
    total = 0
    for i in range(n_rays):
        a = 2.0 * math.pi * i / n_rays
        row, col, s_r, s_c, tm_r, tm_c, td_r, td_c = ray_start(cx, cy, math.cos(a), math.sin(a))
        t = 0.0
        while t <= max_range and 0 <= row < rows and 0 <= col < cols:
            value = state[row, col]
            if value == _OCCUPIED:
                break
            if value == _UNKNOWN and stamp[row, col] != stamp_id:
                stamp[row, col] = stamp_id
                total += 1
            row, col, tm_r, tm_c, t = dda_step(row, col, s_r, s_c, tm_r, tm_c, td_r, td_c)
    return total


@nb.njit(cache=True)
def split_segments(  # noqa: C901 (numba kernel: one compiled pass, written out)
    flat: NDArray[np.int64], sizes: NDArray[np.int64], min_cells: int, cols: int, radius: float
) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """Split the clusters larger than ``min_cells`` into segments of cells within ``radius``
    (cells) of a seed: seeds are placed farthest-point first (the first at the cell farthest from
    the cluster's first cell, an end of an arc), until every cell is within ``radius`` of one,
    and each cell joins its nearest seed. Smaller clusters are left out.

    Args:
        flat: flat cell indices grouped by cluster (as :func:`cluster_fringe` returns them).
        sizes: cells per cluster.
        min_cells: clusters of this many cells or fewer are dropped.
        cols: the grid's width, to turn flat indices into rows and columns.
        radius: the largest distance (cells) of a cell from its segment's seed; ``inf`` keeps
            every cluster whole.

    Returns:
        the cells grouped by segment, and the cells per segment.
    """
    out = np.empty(flat.shape[0], np.int64)
    seg_sizes = []
    n_out = 0
    start = 0
    r2 = radius * radius
    for k in range(sizes.shape[0]):
        size = sizes[k]
        cells = flat[start : start + size]
        start += size
        if size <= min_cells:
            continue
        rows = cells // cols
        cs = cells % cols
        label = np.zeros(size, np.int64)
        n_seeds = 1
        if radius < np.inf:
            far, seed = -1.0, 0
            for i in range(size):  # the first seed: the cell farthest from the first cell
                d2 = float((rows[i] - rows[0]) ** 2 + (cs[i] - cs[0]) ** 2)
                if d2 > far:
                    far, seed = d2, i
            mind = np.empty(size)
            for i in range(size):
                mind[i] = float((rows[i] - rows[seed]) ** 2 + (cs[i] - cs[seed]) ** 2)
            while True:
                j = int(np.argmax(mind))
                if mind[j] <= r2:
                    break
                for i in range(size):
                    d2 = float((rows[i] - rows[j]) ** 2 + (cs[i] - cs[j]) ** 2)
                    if d2 < mind[i]:
                        mind[i] = d2
                        label[i] = n_seeds
                n_seeds += 1
        counts = np.zeros(n_seeds + 1, np.int64)
        for i in range(size):
            counts[label[i] + 1] += 1
        for s in range(n_seeds):
            if counts[s + 1] > 0:
                seg_sizes.append(counts[s + 1])
            counts[s + 1] += counts[s]
        for i in range(size):  # a counting sort by segment
            out[n_out + counts[label[i]]] = cells[i]
            counts[label[i]] += 1
        n_out += size
    result = np.empty(len(seg_sizes), np.int64)
    for s in range(len(seg_sizes)):
        result[s] = seg_sizes[s]
    return out[:n_out].copy(), result


@nb.njit(cache=True, inline="always")
def _line_of_sight(state: NDArray[np.int8], r0: int, c0: int, r1: int, c1: int) -> bool:
    """Whether the straight line between the centres of two cells crosses only FREE cells
    (sampled every half cell)."""
    steps = 2 * max(abs(r1 - r0), abs(c1 - c0))
    for i in range(1, steps):
        t = i / steps
        r = int(math.floor(r0 + 0.5 + (r1 - r0) * t))
        c = int(math.floor(c0 + 0.5 + (c1 - c0) * t))
        if state[r, c] != _FREE:
            return False
    return True


@nb.njit(cache=True, fastmath=FASTMATH)
def _viewer_by_rays(
    state: NDArray[np.int8], reachable: NDArray[np.bool_], ar: int, ac: int, reach: float
) -> tuple[int, int]:
    """The reachable cell nearest to cell (ar, ac) along a ray of FREE cells from it, within
    ``reach`` cells; (-1, -1) when none. The rays are at most one cell apart at full reach, so a
    viewer through a gap narrower than the robot is found wherever it stands."""
    rows, cols = state.shape
    n_rays = max(8, int(math.ceil(2.0 * math.pi * reach)))
    best_t, best_r, best_c = np.inf, -1, -1
    for i in range(n_rays):
        a = 2.0 * math.pi * i / n_rays
        row, col, s_r, s_c, tm_r, tm_c, td_r, td_c = ray_start(ac + 0.5, ar + 0.5, math.cos(a), math.sin(a))
        t = 0.0
        while t <= min(reach, best_t) and 0 <= row < rows and 0 <= col < cols:
            if state[row, col] != _FREE:
                break
            if reachable[row, col]:
                best_t, best_r, best_c = t, row, col
                break
            row, col, tm_r, tm_c, t = dda_step(row, col, s_r, s_c, tm_r, tm_c, td_r, td_c)
    return best_r, best_c


@nb.njit(cache=True)
def summarise_segments(
    state: NDArray[np.int8],
    reachable: NDArray[np.bool_],
    cells: NDArray[np.int64],
    sizes: NDArray[np.int64],
    offsets: NDArray[np.int64],
    robot_row: float,
    robot_col: float,
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.int64]]:
    """Per segment: the centre (mean row and column, cell units), the squared distance (cells²)
    from the robot to its nearest cell centre, and its goal cell (row, col; -1 when it has none).

    The goal is a reachable cell from which the segment can be seen: its *anchor* (the segment's
    cell nearest its centre) when that is reachable, else the reachable cell nearest to the
    anchor, among ``offsets`` (row and column steps sorted by length), that sees it along a line
    of FREE cells. The nearest ``_MAX_SIGHT_TRIES`` reachable cells are tried first (each try
    walks a line of up to the reach); when none of them sees the anchor, a fan of rays from it
    looks for a viewer further round, e.g. through a gap narrower than the robot.
    """
    rows, cols = state.shape
    n = sizes.shape[0]
    reach = math.sqrt(float(offsets[-1, 0] ** 2 + offsets[-1, 1] ** 2)) if offsets.shape[0] else 0.0
    centres = np.empty((n, 2))
    min_d2 = np.empty(n)
    goals = np.full((n, 2), -1, np.int64)
    start = 0
    for k in range(n):
        seg = cells[start : start + sizes[k]]
        start += sizes[k]
        sum_r = 0.0
        sum_c = 0.0
        best = np.inf
        for flat in seg:
            r, c = flat // cols, flat % cols
            sum_r += r
            sum_c += c
            best = min(best, (r + 0.5 - robot_row) ** 2 + (c + 0.5 - robot_col) ** 2)
        mean_r, mean_c = sum_r / seg.shape[0], sum_c / seg.shape[0]
        centres[k, 0], centres[k, 1] = mean_r, mean_c
        min_d2[k] = best
        anchor, near = seg[0], np.inf
        for flat in seg:
            d2 = (flat // cols - mean_r) ** 2 + (flat % cols - mean_c) ** 2
            if d2 < near:
                anchor, near = flat, d2
        ar, ac = anchor // cols, anchor % cols
        tries = 0
        for i in range(offsets.shape[0]):
            r, c = ar + offsets[i, 0], ac + offsets[i, 1]
            if 0 <= r < rows and 0 <= c < cols and reachable[r, c]:
                if _line_of_sight(state, r, c, ar, ac):
                    goals[k, 0], goals[k, 1] = r, c
                    break
                tries += 1
                if tries == _MAX_SIGHT_TRIES:
                    # Many reachable cells near it and none sees it: look further round
                    goals[k, 0], goals[k, 1] = _viewer_by_rays(state, reachable, ar, ac, reach)
                    break
    return centres, min_d2, goals


@lru_cache(maxsize=8)
def disc_offsets(radius: int) -> NDArray[np.int64]:
    """(row, col) steps of length at most ``radius`` cells, shortest first (ties in row-major order)."""
    dr, dc = np.mgrid[-radius : radius + 1, -radius : radius + 1]
    d2 = (dr * dr + dc * dc).ravel()
    keep = d2 <= radius * radius
    order = np.argsort(d2[keep], kind="stable")
    offsets = np.column_stack((dr.ravel()[keep][order], dc.ravel()[keep][order])).astype(np.int64)
    offsets.flags.writeable = False
    return offsets


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
        stamp = np.zeros(grid.shape, np.int32)
        gains = np.zeros(len(self), np.int64)
        res = grid.resolution
        for i, (x, y) in enumerate(self.centers):
            gains[i] = visible_unknown(
                grid.data,
                stamp,
                i + 1,
                (x - grid.origin[0]) / res,
                (y - grid.origin[1]) / res,
                n_rays,
                sensor_range / res,
            )
        return gains


def detect_frontiers(
    grid: OccupancyGrid,
    robot: Pose,
    reachable: NDArray[np.bool_] | None = None,
    min_cells: int = 4,
    segment_length: float = math.inf,
    goal_reach: float = 3.0,
) -> Frontiers:
    """Frontier clusters of ``grid`` larger than ``min_cells``, split into segments of at most
    about ``segment_length`` (m), that the robot can get to see.

    Args:
        grid: the robot's map.
        robot: robot pose (m); distances are measured from it.
        reachable: cells the robot can reach through known free space (same shape as the grid);
            a segment is kept when one of them within ``goal_reach`` (m) of it sees it (its goal).
            ``None`` accepts every segment, with its goal on the segment itself.
        min_cells: clusters of this many cells or fewer are dropped (the thesis drops <= 4).
        segment_length: the largest span (m) of a segment; ``inf`` keeps clusters whole.
        goal_reach: how far (m) from a segment its goal may be.
    """
    res = grid.resolution
    robot_col = (robot.x - grid.origin[0]) / res
    robot_row = (robot.y - grid.origin[1]) / res
    reach = np.ones(grid.shape, np.bool_) if reachable is None else reachable
    counts, _, flat = cluster_fringe(grid.data, reach, robot_row, robot_col)
    radius = segment_length / (2.0 * res) if math.isfinite(segment_length) else np.inf
    cells, sizes = split_segments(flat, counts[:, 0].copy(), min_cells, grid.width, radius)
    offsets = disc_offsets(int(goal_reach / res) if reachable is not None else 0)
    centres, min_d2, goals = summarise_segments(grid.data, reach, cells, sizes, offsets, robot_row, robot_col)
    ends = np.cumsum(sizes)
    spans = np.column_stack((ends - sizes, ends)).astype(np.int64).reshape(-1, 2)
    xy = np.column_stack((grid.origin[0] + (centres[:, 1] + 0.5) * res, grid.origin[1] + (centres[:, 0] + 0.5) * res))
    distances = np.hypot(xy[:, 0] - robot.x, xy[:, 1] - robot.y)
    everything = Frontiers(grid, xy.reshape(-1, 2), sizes, distances, np.sqrt(min_d2) * res, cells, spans, goals)
    return everything.subset(goals[:, 0] >= 0)
