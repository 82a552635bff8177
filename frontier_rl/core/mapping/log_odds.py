"""Compiled log-odds update of an occupancy grid from LiDAR beams.

A scan is folded in two steps. First its beams *mark* cells in a ``pending`` grid (``int16``): a
beam adds one to each cell it crosses, and sets the :data:`HIT` bit of the cell it ends in, so a
hit wins over any number of passes and beams that graze a wall do not erase it. Then
:func:`apply_pending` sweeps the window the scan could reach, applies one update per marked cell
and clears the marks. :func:`cast_and_mark` does the first step for a simulated scan in a single
traversal per beam: it casts on the ground truth and marks the map as it goes.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numba as nb
import numpy as np
from numpy.typing import NDArray

from frontier_rl.core.sensing.lidar import RangeNoise, noisy_range
from frontier_rl.core.world.grid import FREE_I8, OCCUPIED_I8, UNKNOWN_I8
from frontier_rl.core.world.raycast import FASTMATH, ray_start

HIT = np.int16(0x4000)  # bit set when a beam ended in the cell; the bits below count passes
_RING = 32  # the last cells of a beam kept to undo when the noisy reading falls short
MAX_LOOKS = np.uint16(np.iinfo(np.uint16).max)
"""The most looks a cell counts (and the count of a wall the robot touched, which no teammate's
scans outweigh in a merge)."""


class LogOddsRule(NamedTuple):
    """The update's constants as :func:`apply_pending` takes them (a tuple numba reads by field
    name): see :class:`~frontier_rl.core.mapping.mapper.MapperConfig`."""

    clamp_min: float
    clamp_max: float
    free_below: float
    occupied_above: float
    hit: float
    miss: float


@nb.njit(cache=True, fastmath=FASTMATH, inline="always")
def _mark_crossed(
    flat: NDArray[np.int16],
    rows: int,
    cols: int,
    row: int,
    col: int,
    s_r: int,
    s_c: int,
    tm_r: float,
    tm_c: float,
    td_r: float,
    td_c: float,
    limit: float,
) -> None:
    """Count a pass in every cell the DDA state leaves before ``limit`` (cells), inside the grid."""
    cell = row * cols + col
    row_step = s_r * cols
    # Selects instead of branches: the DDA's next step is unpredictable, and a mispredicted
    # branch per cell would cost more than the step itself.
    while min(tm_r, tm_c) <= limit and 0 <= row < rows and 0 <= col < cols:
        flat[cell] += 1
        along_col = tm_c < tm_r
        cell += s_c if along_col else row_step
        col += s_c if along_col else 0
        row += 0 if along_col else s_r
        tm_c = tm_c + td_c if along_col else tm_c
        tm_r = tm_r if along_col else tm_r + td_r


@nb.njit(cache=True)
def _mark_hits(
    pending: NDArray[np.int16],
    cx: float,
    cy: float,
    dir_x: NDArray[np.float64],
    dir_y: NDArray[np.float64],
    ranges: NDArray[np.float64],
    usable: float,
) -> None:
    """Set the HIT bit of the cell each beam ends in (beams with a return within ``usable``)."""
    rows, cols = pending.shape
    for i in range(ranges.shape[0]):
        r = ranges[i]
        if math.isfinite(r) and r <= usable:
            row = int(math.floor(cy + (r + 1e-4) * dir_y[i]))
            col = int(math.floor(cx + (r + 1e-4) * dir_x[i]))
            if 0 <= row < rows and 0 <= col < cols:
                pending[row, col] |= HIT


@nb.njit(cache=True, fastmath=FASTMATH)
def mark_beams(
    pending: NDArray[np.int16],
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
        _mark_crossed(flat, rows, cols, row, col, s_r, s_c, tm_r, tm_c, td_r, td_c, limit)
    _mark_hits(pending, cx, cy, dir_x, dir_y, ranges, usable)


@nb.njit(cache=True)
def apply_pending(
    pending: NDArray[np.int16],
    window: tuple[int, int, int, int],
    logodds: NDArray[np.float32],
    state: NDArray[np.int8],
    seen: NDArray[np.bool_],
    observed: NDArray[np.bool_],
    looks: NDArray[np.uint16],
    explorable: NDArray[np.bool_],
    rule: LogOddsRule,
    bbox: NDArray[np.int64],
    changed: NDArray[np.int64],
    counters: NDArray[np.int64],
) -> None:
    """Update every marked cell in ``window`` (row0, row1, col0, col1; exclusive ends), clear its mark,
    set it in ``observed`` (the cells this map's own sensor has reached) and count the look in
    ``looks`` (up to :data:`MAX_LOOKS`).

    ``rule``: the update's constants. A cell's class follows its log-odds past the thresholds; in
    between, a classified cell keeps its class (a seen cell never turns unknown again).
    ``counters`` += cells first classified free, occupied, and explorable; ``bbox`` grows to hold
    every classified cell, ``changed`` (row_min, row_max, col_min, col_max) every updated one.
    """
    low, high, free_below, occupied_above = rule.clamp_min, rule.clamp_max, rule.free_below, rule.occupied_above
    hit, miss = rule.hit, rule.miss
    r0, r1, c0, c1 = window
    for row in range(max(r0, 0), min(r1, pending.shape[0])):
        for col in range(max(c0, 0), min(c1, pending.shape[1])):
            mark = pending[row, col]
            if mark == 0:
                continue
            pending[row, col] = 0
            observed[row, col] = True
            changed[0] = min(changed[0], row)
            changed[1] = max(changed[1], row)
            changed[2] = min(changed[2], col)
            changed[3] = max(changed[3], col)
            if looks[row, col] < MAX_LOOKS:
                looks[row, col] += 1
            value = min(max(logodds[row, col] + (hit if mark & HIT else miss), low), high)
            logodds[row, col] = value
            if value > occupied_above:
                new_state = OCCUPIED_I8
            elif value < free_below:
                new_state = FREE_I8
            else:
                new_state = state[row, col]
            state[row, col] = new_state
            if new_state != UNKNOWN_I8 and not seen[row, col]:
                seen[row, col] = True
                counters[0 if new_state == FREE_I8 else 1] += 1
                if explorable[row, col]:
                    counters[2] += 1
                bbox[0] = min(bbox[0], row)
                bbox[1] = max(bbox[1], row)
                bbox[2] = min(bbox[2], col)
                bbox[3] = max(bbox[3], col)


@nb.njit(cache=True, fastmath=FASTMATH)
def cast_and_mark(
    blocked_padded: NDArray[np.bool_],
    pending: NDArray[np.int16],
    cx: float,
    cy: float,
    cos_t: float,
    sin_t: float,
    cos_offsets: NDArray[np.float64],
    sin_offsets: NDArray[np.float64],
    normals: NDArray[np.float64],
    noise: RangeNoise,
    usable: float,
    ranges: NDArray[np.float64],
    extent: NDArray[np.int64],
) -> None:
    """A noisy scan cast on the ground truth and marked: the same ranges and marks, bit for bit, as
    :class:`~frontier_rl.core.sensing.lidar.Lidar`'s ``scan`` then :func:`mark_beams`, in one traversal per
    beam. Lengths in cells; ``noise`` the range model (lengths in m), ``usable`` the range where
    beams are cropped. Writes the ranges (cells; ``inf``
    = no return, ``nan`` = invalid) into ``ranges``, and into ``extent`` (row0, row1, col0, col1;
    exclusive ends) a window that holds every cell it marked, for :func:`apply_pending`.

    Each cell is marked as the beam crosses it on the ground truth, before the noisy reading is
    known; a reading that falls short of the wall then takes back the marks beyond it (kept in
    a small ring, or found again by a second traversal when it falls far short), and one that
    overshoots goes on through the wall.
    """
    res, max_r = noise.resolution, noise.max_range
    max_cells = max_r / res
    rows, cols = pending.shape
    pcols = cols + 2
    blocked = blocked_padded.reshape(-1)
    flat = pending.reshape(-1)
    ring_cell = np.empty(_RING, np.int64)
    ring_exit = np.empty(_RING)
    dirs = np.empty((cos_offsets.shape[0], 2))
    row0, col0 = int(math.floor(cy)), int(math.floor(cx))
    extent[0], extent[1], extent[2], extent[3] = row0, row0, col0, col0
    for i in range(cos_offsets.shape[0]):
        dx = cos_t * cos_offsets[i] - sin_t * sin_offsets[i]
        dy = sin_t * cos_offsets[i] + cos_t * sin_offsets[i]
        dirs[i, 0], dirs[i, 1] = dx, dy
        row, col, s_r, s_c, tm_r, tm_c, td_r, td_c = ray_start(cx, cy, dx, dy)
        padded = (row + 1) * pcols + col + 1
        cell = row * cols + col
        t = 0.0
        t_hit = np.inf
        n_marked = 0
        while t <= max_cells:
            if blocked[padded]:
                t_hit = t
                break
            along_col = tm_c < tm_r
            t_exit = tm_c if along_col else tm_r
            if t_exit <= usable + 1e-9:
                flat[cell] += 1
                ring_cell[n_marked % _RING] = cell
                ring_exit[n_marked % _RING] = t_exit
                n_marked += 1
            padded += s_c if along_col else s_r * pcols
            cell += s_c if along_col else s_r * cols
            col += s_c if along_col else 0
            row += 0 if along_col else s_r
            tm_c = tm_c + td_c if along_col else tm_c
            tm_r = tm_r if along_col else tm_r + td_r
            t = t_exit
        r = noisy_range(t_hit, normals[i], noise)
        r_cells = r / res
        ranges[i] = r_cells
        limit = -1.0 if math.isnan(r_cells) else min(r_cells, usable) + 1e-9
        if n_marked > 0 and ring_exit[(n_marked - 1) % _RING] > limit:  # short: take back marks
            oldest = max(n_marked - _RING, 0)
            if ring_exit[oldest % _RING] > limit and oldest > 0:
                _unmark_beyond(flat, cols, cx, cy, dx, dy, limit, usable, n_marked)
            else:
                k = n_marked - 1
                while k >= oldest and ring_exit[k % _RING] > limit:
                    flat[ring_cell[k % _RING]] -= 1
                    k -= 1
        elif math.isfinite(t_hit) and limit > t_hit:  # long: on through the wall
            _mark_crossed(flat, rows, cols, row, col, s_r, s_c, tm_r, tm_c, td_r, td_c, limit)
        # The beam's marks (crossed cells and its hit) lie on it up to here, give or take a cell.
        reach = min(usable, max(t_hit, 0.0 if math.isnan(r_cells) else r_cells))
        end_row, end_col = int(math.floor(cy + reach * dy)), int(math.floor(cx + reach * dx))
        extent[0], extent[1] = min(extent[0], end_row), max(extent[1], end_row)
        extent[2], extent[3] = min(extent[2], end_col), max(extent[3], end_col)
    extent[0], extent[1], extent[2], extent[3] = extent[0] - 1, extent[1] + 2, extent[2] - 1, extent[3] + 2
    _mark_hits(pending, cx, cy, dirs[:, 0], dirs[:, 1], ranges, usable)


@nb.njit(cache=True)
def _unmark_beyond(
    flat: NDArray[np.int16],
    cols: int,
    cx: float,
    cy: float,
    dx: float,
    dy: float,
    limit: float,
    usable: float,
    n_marked: int,
) -> None:
    """Take back the marks of the first ``n_marked`` cells of a beam that lie beyond ``limit``."""
    row, col, s_r, s_c, tm_r, tm_c, td_r, td_c = ray_start(cx, cy, dx, dy)
    seen = 0
    while seen < n_marked:
        t_exit = min(tm_r, tm_c)
        if t_exit <= usable + 1e-9:
            if t_exit > limit:
                flat[row * cols + col] -= 1
            seen += 1
        if tm_c < tm_r:
            col += s_c
            tm_c += td_c
        else:
            row += s_r
            tm_r += td_r


@nb.njit(cache=True)
def drop_marks(
    pending: NDArray[np.int16],
    xs: NDArray[np.float64],
    ys: NDArray[np.float64],
    radius: float,
    origin_x: float,
    origin_y: float,
    resolution: float,
) -> None:
    """Clear the marks of every cell whose centre lies within ``radius`` (m) of a point (xs, ys)
    (m): a scan filter that leaves known moving objects (other robots) out of the map."""
    rows, cols = pending.shape
    reach = int(math.ceil(radius / resolution)) + 1
    for k in range(xs.shape[0]):
        row = int(math.floor((ys[k] - origin_y) / resolution))
        col = int(math.floor((xs[k] - origin_x) / resolution))
        for r in range(max(row - reach, 0), min(row + reach + 1, rows)):
            cy = origin_y + (r + 0.5) * resolution
            for c in range(max(col - reach, 0), min(col + reach + 1, cols)):
                cx = origin_x + (c + 0.5) * resolution
                if math.hypot(cx - xs[k], cy - ys[k]) <= radius:
                    pending[r, c] = 0
