"""Frontier segments: clusters split into parts the robot can see from one place, each with its
centre, its distance from the robot and a reachable goal cell that sees it."""

from __future__ import annotations

import math
from functools import lru_cache

import numba as nb
import numpy as np
from numpy.typing import NDArray

from frontier_rl.core.world.grid import FREE_I8
from frontier_rl.core.world.raycast import FASTMATH, dda_step, ray_start

_MAX_SIGHT_TRIES = 64


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
        if state[r, c] != FREE_I8:
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
            if state[row, col] != FREE_I8:
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
