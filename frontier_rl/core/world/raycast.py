"""Grid ray traversal (Amanatides & Woo DDA), compiled with numba.

Rays are traced in *cell units*: a point (x, y) in metres is ``((x - ox) / res, (y - oy) / res)``
in continuous cell coordinates, where column = floor(cx) and row = floor(cy). Every kernel that
walks a ray (LiDAR casting, map updates, information gain) starts from :func:`ray_start`.
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np
from numpy.typing import NDArray

# LLVM fast-math flags that keep inf and NaN semantics: the kernels rely on ``inf`` ranges and
# ``nan`` markers, which the "nnan"/"ninf" flags would let the compiler assume away.
FASTMATH = {"nsz", "arcp", "contract", "afn", "reassoc"}


@nb.njit(cache=True, inline="always")
def ray_start(cx: float, cy: float, dx: float, dy: float) -> tuple[int, int, int, int, float, float, float, float]:
    """DDA state of a ray from (cx, cy) along unit direction (dx, dy), all in cell units.

    Returns (row, col, step_row, step_col, t_max_row, t_max_col, t_delta_row, t_delta_col): the
    ray parameter t (cells) at which it crosses the next row / column boundary and the t between
    two such crossings.
    """
    col = int(math.floor(cx))
    row = int(math.floor(cy))
    if dx > 0.0:
        step_col, t_max_col, t_delta_col = 1, (col + 1.0 - cx) / dx, 1.0 / dx
    elif dx < 0.0:
        step_col, t_max_col, t_delta_col = -1, (cx - col) / -dx, -1.0 / dx
    else:
        step_col, t_max_col, t_delta_col = 0, np.inf, np.inf
    if dy > 0.0:
        step_row, t_max_row, t_delta_row = 1, (row + 1.0 - cy) / dy, 1.0 / dy
    elif dy < 0.0:
        step_row, t_max_row, t_delta_row = -1, (cy - row) / -dy, -1.0 / dy
    else:
        step_row, t_max_row, t_delta_row = 0, np.inf, np.inf
    return row, col, step_row, step_col, t_max_row, t_max_col, t_delta_row, t_delta_col


@nb.njit(cache=True, inline="always")
def dda_step(
    row: int, col: int, s_r: int, s_c: int, tm_r: float, tm_c: float, td_r: float, td_c: float
) -> tuple[int, int, float, float, float]:
    """One DDA step of a ray in the state :func:`ray_start` gives: into the next cell along
    whichever boundary comes first. Returns (row, col, t_max_row, t_max_col, t), t being the ray
    parameter (cells) at which the ray enters the new cell."""
    if tm_c < tm_r:
        return row, col + s_c, tm_r, tm_c + td_c, tm_c
    return row + s_r, col, tm_r + td_r, tm_c, tm_r


def pad_blocked(blocked: NDArray[np.bool_]) -> NDArray[np.bool_]:
    """``blocked`` with a one-cell blocked border, so ray loops need no bounds checks."""
    return np.pad(np.ascontiguousarray(blocked, dtype=np.bool_), 1, constant_values=True)


@nb.njit(cache=True, fastmath=FASTMATH)
def cast_rays(
    blocked_padded: NDArray[np.bool_],
    cx: float,
    cy: float,
    cos_t: float,
    sin_t: float,
    cos_offsets: NDArray[np.float64],
    sin_offsets: NDArray[np.float64],
    max_range: float,
    out: NDArray[np.float64],
    out_dx: NDArray[np.float64],
    out_dy: NDArray[np.float64],
) -> None:
    """Distance (cells) from (cx, cy) to the first blocked cell along each beam.

    ``blocked_padded`` comes from :func:`pad_blocked`; (cx, cy) are unpadded cell coordinates,
    which must lie inside the grid. Beam i points at heading + offset i, given as cosines and
    sines (the heading's as ``cos_t``, ``sin_t``). Rays that hit nothing within ``max_range``
    (cells) get ``inf``. Distances are written into ``out``, beam directions into ``out_dx``,
    ``out_dy``.
    """
    cols = blocked_padded.shape[1]
    flat = blocked_padded.reshape(-1)
    for i in range(cos_offsets.shape[0]):
        dx = cos_t * cos_offsets[i] - sin_t * sin_offsets[i]
        dy = sin_t * cos_offsets[i] + cos_t * sin_offsets[i]
        out_dx[i] = dx
        out_dy[i] = dy
        # The DDA runs in unpadded coordinates (so that every kernel steps through the same
        # sequence of crossings) and indexes the padded grid.
        row, col, s_r, s_c, tm_r, tm_c, td_r, td_c = ray_start(cx, cy, dx, dy)
        # Selects instead of branches: a DDA's next step is unpredictable, and a mispredicted
        # branch per cell costs more than the step itself.
        idx = (row + 1) * cols + col + 1
        row_step = s_r * cols
        t = 0.0
        hit = np.inf
        while t <= max_range:
            if flat[idx]:
                hit = t
                break
            along_col = tm_c < tm_r
            t = tm_c if along_col else tm_r
            idx += s_c if along_col else row_step
            tm_c = tm_c + td_c if along_col else tm_c
            tm_r = tm_r if along_col else tm_r + td_r
        out[i] = hit
