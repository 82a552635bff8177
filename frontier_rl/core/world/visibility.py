"""Which free cells a robot's LiDAR could ever see: line of sight within range of a reachable pose.

This is the *explorable* space of a world (issue 13): a cell counts toward coverage only if some
pose the robot's centre can reach from its start sees it along free cells, within the sensor's
range. A room behind a door narrower than the robot counts only as far as the robot can look into
it through the door.

Line of sight is symmetric, so instead of casting from every reachable cell (hundreds of
thousands on a large floor) each candidate cell casts rays *towards* the reachable cells: first
straight at the nearest one (which settles almost every cell), then a fan of rays dense enough
that neighbouring rays are at most one cell apart at full range.
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np
from numpy.typing import NDArray
from scipy import ndimage

from frontier_rl.core.world.raycast import FASTMATH, dda_step, ray_start


@nb.njit(cache=True, fastmath=FASTMATH)
def _sees_viewer(
    blocked: NDArray[np.bool_], viewer: NDArray[np.bool_], cx: float, cy: float, dx: float, dy: float, reach: float
) -> bool:
    """Whether the ray from (cx, cy) along (dx, dy) meets a viewer cell before a blocked one
    within ``reach`` cells. Both grids carry a one-cell blocked rim (unpadded coordinates here)."""
    row, col, s_r, s_c, tm_r, tm_c, td_r, td_c = ray_start(cx, cy, dx, dy)
    t = 0.0
    while t <= reach:
        if blocked[row + 1, col + 1]:
            return False
        if viewer[row + 1, col + 1]:
            return True
        row, col, tm_r, tm_c, t = dda_step(row, col, s_r, s_c, tm_r, tm_c, td_r, td_c)
    return False


@nb.njit(cache=True, fastmath=FASTMATH)
def _visible(
    blocked: NDArray[np.bool_],
    viewer: NDArray[np.bool_],
    rows: NDArray[np.int64],
    cols: NDArray[np.int64],
    near_rows: NDArray[np.int64],
    near_cols: NDArray[np.int64],
    reach: float,
    n_rays: int,
) -> NDArray[np.bool_]:
    out = np.zeros(rows.shape[0], np.bool_)
    for i in range(rows.shape[0]):
        cy, cx = rows[i] + 0.5, cols[i] + 0.5
        dy, dx = near_rows[i] + 0.5 - cy, near_cols[i] + 0.5 - cx
        norm = math.sqrt(dx * dx + dy * dy)
        if _sees_viewer(blocked, viewer, cx, cy, dx / norm, dy / norm, reach):
            out[i] = True
            continue
        for k in range(n_rays):
            angle = 2.0 * math.pi * k / n_rays
            if _sees_viewer(blocked, viewer, cx, cy, math.cos(angle), math.sin(angle), reach):
                out[i] = True
                break
    return out


def visible_from(free: NDArray[np.bool_], viewers: NDArray[np.bool_], max_range: float) -> NDArray[np.bool_]:
    """Free cells in line of sight of a viewer cell within ``max_range`` cells, viewers included.

    Args:
        free: cells a ray passes through; every other cell stops it.
        viewers: cells the sensor can stand on (a subset of ``free``).
        max_range: sensor range (cells, centre to centre).
    """
    if not viewers.any():
        return np.zeros_like(viewers)
    distance, (near_r, near_c) = ndimage.distance_transform_edt(~viewers, return_indices=True)
    candidates = free & ~viewers & (distance <= max_range)
    rows, cols = np.nonzero(candidates)
    blocked = np.pad(~free, 1, constant_values=True)
    padded_viewers = np.pad(viewers, 1)
    n_rays = max(8, math.ceil(2.0 * math.pi * max_range))
    seen = _visible(
        blocked,
        padded_viewers,
        rows.astype(np.int64),
        cols.astype(np.int64),
        near_r[rows, cols].astype(np.int64),
        near_c[rows, cols].astype(np.int64),
        float(max_range),
        n_rays,
    )
    out = viewers.copy()
    out[rows[seen], cols[seen]] = True
    return out
