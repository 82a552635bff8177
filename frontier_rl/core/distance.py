"""Compiled grid kernels for the costmap: a chamfer distance transform and a flood fill.

scipy.ndimage's transforms and labelling are general (n-D, feature indices, all components) and
cost milliseconds on a 250 × 250 map; the planner needs both at every decision, so these 2D
versions are compiled with numba.
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np
from numpy.typing import NDArray

from frontier_rl.core.grid import CellState
from frontier_rl.core.raycast import FASTMATH

_FREE = np.int8(CellState.FREE)


@nb.njit(cache=True)
def chamfer_distance(seeds: NDArray[np.bool_], cap: float) -> NDArray[np.float64]:
    """Distance (cells) from each cell centre to the nearest seed, capped at ``cap``: see
    :func:`chamfer_distance_padded`."""
    return chamfer_distance_padded(seeds, cap)[1:-1, 1:-1].copy()


@nb.njit(cache=True, fastmath=FASTMATH)
def chamfer_distance_padded(seeds: NDArray[np.bool_], cap: float) -> NDArray[np.float64]:
    """Distance (cells) from each cell centre to the nearest seed, by the two-pass 3 × 3 chamfer
    transform (steps 1 and sqrt 2), capped at ``cap``, with a one-cell border of ``cap`` around.

    It never underestimates and overestimates the Euclidean distance by at most about 8 % (at
    22.5 degrees); up to 3 cells it is exact but for offsets (2, 1) and (3, 1). That is
    accurate enough for costmap inflation and runs in a fraction of a millisecond on 250 × 250.
    """
    rows, cols = seeds.shape
    diag = math.sqrt(2.0)
    d = np.full((rows + 2, cols + 2), cap)  # a border of `cap` (returned too) spares bounds checks
    # Each sweep takes the three neighbours of the previous row first (no dependency along the
    # row, so it vectorises), then runs along the row: the same result as the classic mask order.
    for r in range(1, rows + 1):
        for c in range(1, cols + 1):
            up = min(d[r - 1, c] + 1.0, min(d[r - 1, c - 1], d[r - 1, c + 1]) + diag)
            d[r, c] = 0.0 if seeds[r - 1, c - 1] else min(up, cap)
        for c in range(2, cols + 1):
            d[r, c] = min(d[r, c], d[r, c - 1] + 1.0)
    for r in range(rows, 0, -1):
        for c in range(1, cols + 1):
            d[r, c] = min(d[r, c], min(d[r + 1, c] + 1.0, min(d[r + 1, c - 1], d[r + 1, c + 1]) + diag))
        for c in range(cols - 1, 0, -1):
            d[r, c] = min(d[r, c], d[r, c + 1] + 1.0)
    return d


@nb.njit(cache=True)
def flood_known(
    open_padded: NDArray[np.bool_], state: NDArray[np.int8], start_row: int, start_col: int
) -> NDArray[np.bool_]:
    """Cells that are open in ``open_padded`` (a mask with a one-cell False border) and FREE in
    ``state``, 8-connected to (start_row, start_col); all False if the start is not one of them."""
    rows, cols = state.shape
    pcols = cols + 2
    reached = np.zeros((rows + 2) * pcols, np.bool_)
    open_flat = open_padded.reshape(-1)
    state_flat = state.reshape(-1)
    if not (0 <= start_row < rows and 0 <= start_col < cols):
        return np.zeros((rows, cols), np.bool_)
    start = (start_row + 1) * pcols + start_col + 1
    if not (open_flat[start] and state_flat[start_row * cols + start_col] == _FREE):
        return np.zeros((rows, cols), np.bool_)
    offsets = np.array([-pcols - 1, -pcols, -pcols + 1, -1, 1, pcols - 1, pcols, pcols + 1])
    stack = np.empty(rows * cols, np.int64)
    stack[0] = start
    reached[start] = True
    top = 1
    while top > 0:
        top -= 1
        cur = stack[top]
        for k in range(8):
            nxt = cur + offsets[k]
            # open cells are inside the border, so nxt // pcols - 1 and nxt % pcols - 1 are cells
            if open_flat[nxt] and not reached[nxt] and state_flat[nxt - pcols - 1 - 2 * (nxt // pcols - 1)] == _FREE:
                reached[nxt] = True
                stack[top] = nxt
                top += 1
    return reached.reshape(rows + 2, pcols)[1:-1, 1:-1].copy()
