"""Compiled log-odds update of an occupancy grid from LiDAR beams.

A scan is folded in two steps. First its beams *mark* cells in a ``pending`` byte grid: the cells
a beam crosses get :data:`PASS`, the cell it ends in gets :data:`HIT`, and a hit overwrites a
pass, so beams that graze a wall do not erase it. Marking only writes, it never reads, so the
beam loops run at the speed of the grid traversal. Then :func:`apply_pending` sweeps the window
the scan could reach, applies one update per marked cell and clears the marks.
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np
from numpy.typing import NDArray

from frontier_rl.core.grid import CellState
from frontier_rl.core.lidar import add_range_noise
from frontier_rl.core.raycast import FASTMATH, cast_rays, ray_start

PASS = np.int8(1)  # a beam crossed the cell: evidence of free space
HIT = np.int8(2)  # a beam ended in the cell: evidence of an obstacle
_UNKNOWN = np.int8(CellState.UNKNOWN)
_FREE = np.int8(CellState.FREE)
_OCCUPIED = np.int8(CellState.OCCUPIED)


@nb.njit(cache=True, fastmath=FASTMATH)
def mark_beams(
    pending: NDArray[np.int8],
    cx: float,
    cy: float,
    dir_x: NDArray[np.float64],
    dir_y: NDArray[np.float64],
    ranges: NDArray[np.float64],
    usable: float,
) -> None:
    """Mark the cells the beams cross and end in; lengths in cells.

    ``ranges`` (cells) holds ``inf`` for "no return" (free up to ``usable``) and ``nan`` for
    invalid beams (nothing marked). Beams are cropped at ``usable`` (Gmapping's maxUrange): free
    up to it and no hit beyond it. A cell is crossed if the beam leaves it before its end.
    """
    rows, cols = pending.shape
    flat = pending.reshape(-1)
    for i in range(ranges.shape[0]):
        r = ranges[i]
        if math.isnan(r):
            continue
        # A cell counts as crossed if the beam leaves it before its end; the 1e-9 cells of slack
        # keep a noise-free beam that ends exactly on a cell boundary from losing that last cell
        # to the rounding of metres <-> cells.
        limit = min(r, usable) + 1e-9
        row, col, s_r, s_c, tm_r, tm_c, td_r, td_c = ray_start(cx, cy, dir_x[i], dir_y[i])
        cell = row * cols + col
        row_step = s_r * cols
        # Selects instead of branches: the DDA's next step is unpredictable, and a mispredicted
        # branch per cell would cost more than the step itself.
        while min(tm_r, tm_c) <= limit and 0 <= row < rows and 0 <= col < cols:
            flat[cell] = PASS  # write-only: hits are marked after all passes, and win
            along_col = tm_c < tm_r
            cell += s_c if along_col else row_step
            col += s_c if along_col else 0
            row += 0 if along_col else s_r
            tm_c = tm_c + td_c if along_col else tm_c
            tm_r = tm_r if along_col else tm_r + td_r
    for i in range(ranges.shape[0]):
        r = ranges[i]
        if math.isfinite(r) and r <= usable:
            row = int(math.floor(cy + (r + 1e-4) * dir_y[i]))
            col = int(math.floor(cx + (r + 1e-4) * dir_x[i]))
            if 0 <= row < rows and 0 <= col < cols:
                pending[row, col] = HIT


@nb.njit(cache=True)
def apply_pending(
    pending: NDArray[np.int8],
    window: tuple[int, int, int, int],
    logodds: NDArray[np.float32],
    state: NDArray[np.int8],
    seen: NDArray[np.bool_],
    explorable: NDArray[np.bool_],
    params: NDArray[np.float64],
    bbox: NDArray[np.int64],
    counters: NDArray[np.int64],
) -> None:
    """Update every marked cell in ``window`` (row0, row1, col0, col1; exclusive ends), clear its mark.

    ``params`` = (clamp_min, clamp_max, free_below, occupied_above, hit, miss). A cell's class
    follows its log-odds past the thresholds; in between, a classified cell keeps its class (a
    seen cell never turns unknown again). ``counters`` += cells first classified free, occupied,
    and explorable; ``bbox`` grows to hold every classified cell.
    """
    low, high, free_below, occupied_above, hit, miss = (
        params[0], params[1], params[2], params[3], params[4], params[5],
    )  # fmt: skip
    r0, r1, c0, c1 = window
    for row in range(max(r0, 0), min(r1, pending.shape[0])):
        for col in range(max(c0, 0), min(c1, pending.shape[1])):
            mark = pending[row, col]
            if mark == 0:
                continue
            pending[row, col] = 0
            value = min(max(logodds[row, col] + (hit if mark == HIT else miss), low), high)
            logodds[row, col] = value
            if value > occupied_above:
                new_state = _OCCUPIED
            elif value < free_below:
                new_state = _FREE
            else:
                new_state = state[row, col]
            state[row, col] = new_state
            if new_state != _UNKNOWN and not seen[row, col]:
                seen[row, col] = True
                counters[0 if new_state == _FREE else 1] += 1
                if explorable[row, col]:
                    counters[2] += 1
                bbox[0] = min(bbox[0], row)
                bbox[1] = max(bbox[1], row)
                bbox[2] = min(bbox[2], col)
                bbox[3] = max(bbox[3], col)


@nb.njit(cache=True, fastmath=FASTMATH)
def simulate_beams(
    blocked_padded: NDArray[np.bool_],
    cx: float,
    cy: float,
    cos_t: float,
    sin_t: float,
    cos_offsets: NDArray[np.float64],
    sin_offsets: NDArray[np.float64],
    normals: NDArray[np.float64],
    noise: NDArray[np.float64],
    ranges: NDArray[np.float64],
    dir_x: NDArray[np.float64],
    dir_y: NDArray[np.float64],
) -> None:
    """A noisy scan on the ground truth, in cells: the same ranges, bit for bit, as
    :class:`~frontier_rl.core.lidar.Lidar`'s ``scan`` divided by the resolution.

    ``noise`` = (resolution, min_range, max_range, sigma_abs, sigma_rel, rel_from), lengths in m.
    Writes ranges (cells; ``inf`` = no return, ``nan`` = invalid) and beam directions.
    """
    res = noise[0]
    cast_rays(blocked_padded, cx, cy, cos_t, sin_t, cos_offsets, sin_offsets, noise[2] / res, ranges, dir_x, dir_y)
    add_range_noise(ranges, normals, noise)
    for i in range(ranges.shape[0]):
        ranges[i] /= res
