"""Fringe cells: FREE cells with an UNKNOWN 4-neighbour, and their 8-connected clusters (the
raw frontiers before :mod:`~frontier_rl.core.frontiers.segments` splits them)."""

from __future__ import annotations

import numba as nb
import numpy as np
from numpy.typing import NDArray

from frontier_rl.core.world.grid import FREE_I8, UNKNOWN_I8

NEIGHBOURS_8 = np.array([(-1, -1), (-1, 0), (-1, 1), (0, -1), (0, 1), (1, -1), (1, 0), (1, 1)], np.int64)
"""The offsets (rows, columns) of a cell's 8-neighbours."""


def labels_beside(labels: NDArray[np.int32], rows: NDArray[np.int64], cols: NDArray[np.int64]) -> NDArray[np.int64]:
    """The labels (of an ``ndimage.label`` image, 0 for none) of the regions that touch
    (8-neighbours) one of the cells at ``rows``, ``cols``, each once."""
    r = (rows[:, None] + NEIGHBOURS_8[:, 0]).ravel()
    c = (cols[:, None] + NEIGHBOURS_8[:, 1]).ravel()
    inside = (r >= 0) & (r < labels.shape[0]) & (c >= 0) & (c < labels.shape[1])
    found = np.unique(labels[r[inside], c[inside]])
    return found[found > 0].astype(np.int64)


@nb.njit(cache=True, inline="always")
def _is_fringe(state: NDArray[np.int8], row: int, col: int) -> bool:
    rows, cols = state.shape
    if state[row, col] != FREE_I8:
        return False
    return bool(
        (row > 0 and state[row - 1, col] == UNKNOWN_I8)
        or (row + 1 < rows and state[row + 1, col] == UNKNOWN_I8)
        or (col > 0 and state[row, col - 1] == UNKNOWN_I8)
        or (col + 1 < cols and state[row, col + 1] == UNKNOWN_I8)
    )


@nb.njit(cache=True)
def fringe_mask(state: NDArray[np.int8]) -> NDArray[np.bool_]:
    """FREE cells with an UNKNOWN 4-neighbour (cells beyond the grid's edge are not unknown)."""
    rows, cols = state.shape
    padded = np.full((rows + 2, cols + 2), FREE_I8, np.int8)
    padded[1:-1, 1:-1] = state
    out = np.zeros((rows, cols), np.bool_)
    for r in range(rows):
        for c in range(cols):
            out[r, c] = padded[r + 1, c + 1] == FREE_I8 and (
                (padded[r, c + 1] == UNKNOWN_I8)
                | (padded[r + 2, c + 1] == UNKNOWN_I8)
                | (padded[r + 1, c] == UNKNOWN_I8)
                | (padded[r + 1, c + 2] == UNKNOWN_I8)
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
                    rr = r + NEIGHBOURS_8[k, 0]
                    cc = c + NEIGHBOURS_8[k, 1]
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
) -> tuple[int, NDArray[np.int64]]:
    """How many UNKNOWN cells of ``state`` are 8-neighbours of the given cells (each counted
    once), and the flat indices (row-major in ``state``) of those that are FREE in ``truth`` (a
    grid of the same shape), in the order found."""
    rows, cols = state.shape
    counted = set()
    free = []
    for i in range(rows_idx.shape[0]):
        for k in range(8):
            r, c = rows_idx[i] + NEIGHBOURS_8[k, 0], cols_idx[i] + NEIGHBOURS_8[k, 1]
            if 0 <= r < rows and 0 <= c < cols and state[r, c] == UNKNOWN_I8 and r * cols + c not in counted:
                counted.add(r * cols + c)
                if truth[r, c] == FREE_I8:
                    free.append(r * cols + c)
    return len(counted), np.array(free, dtype=np.int64)
