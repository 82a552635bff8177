"""What a viewpoint sees: candidate viewpoints spread over the reachable cells, the cells a coverage
tour should get mapped, and which of them a noise-free 360° scan from each viewpoint marks (a
compiled ray walk). The coverage tour (:mod:`frontier_rl.core.navigation.coverage_tour`) chooses
its viewpoints from these.
"""

from __future__ import annotations

import numba as nb
import numpy as np
from numpy.typing import NDArray

from frontier_rl.core.sensing.lidar import LidarConfig
from frontier_rl.core.world.grid import CellState
from frontier_rl.core.world.raycast import FASTMATH, pad_blocked, ray_start
from frontier_rl.core.world.worlds import World, dilate


def candidate_cells(reachable: NDArray[np.bool_], spacing_cells: int) -> NDArray[np.int64]:
    """One reachable cell per ``spacing_cells``-square block of the grid (the one nearest the block
    centre, ties to the lowest row then column), as (n, 2) rows and columns in row-major block
    order; blocks without a reachable cell give none."""
    k = max(int(spacing_cells), 1)
    rows, cols = reachable.shape
    br, bc = -(-rows // k), -(-cols // k)
    padded = np.zeros((br * k, bc * k), np.bool_)
    padded[:rows, :cols] = reachable
    off = np.arange(k) - (k - 1) / 2.0
    d2 = off[:, None] ** 2 + off[None, :] ** 2  # distance² to the block centre, per in-block cell
    blocks = padded.reshape(br, k, bc, k).transpose(0, 2, 1, 3).reshape(br, bc, k * k)
    score = np.where(blocks, d2.reshape(-1)[None, None, :], np.inf)
    best = np.argmin(score, axis=2)
    has = np.take_along_axis(score, best[:, :, None], axis=2)[:, :, 0] < np.inf
    bi, bj = np.nonzero(has)
    inner = best[bi, bj]
    return np.stack((bi * k + inner // k, bj * k + inner % k), axis=1).astype(np.int64)


@nb.njit(cache=True, fastmath=FASTMATH)
def _scan_cells(  # noqa: C901 (numba kernel: the ray walk written out)
    occupied_padded: NDArray[np.bool_],
    near_padded: NDArray[np.bool_],
    target: NDArray[np.bool_],
    cells: NDArray[np.int64],
    dir_x: NDArray[np.float64],
    dir_y: NDArray[np.float64],
    min_range: float,
    usable: float,
    graze: int,
) -> tuple[NDArray[np.int64], NDArray[np.int32]]:
    """Target cells a noise-free scan from the centre of each of ``cells`` marks, in CSR form
    (indptr, flat cell indices); lengths in cells.

    As in the mapper, a beam marks the cells it leaves before it hits an occupied cell or
    reaches ``usable``, and the occupied cell it hits (within ``usable``); a hit nearer than
    ``min_range`` makes the beam invalid. Unlike a real beam, it also stops after ``graze``
    cells in a row inside ``near_padded`` (close to a wall) without hitting one: what lies past
    a corner the beam only grazes is not counted as seen."""
    rows, cols = target.shape
    pcols = cols + 2
    flat_target = target.reshape(-1)
    flat_occ = occupied_padded.reshape(-1)
    flat_near = near_padded.reshape(-1)
    stamp = np.full(rows * cols, -1, np.int64)
    beam = np.empty(int(2.0 * usable) + 8, np.int64)  # a beam's cells: at most |dx| + |dy| + 1 steps
    indptr = np.zeros(cells.shape[0] + 1, np.int64)
    out = np.empty(max(cells.shape[0], 1) * 4096, np.int32)
    pos = 0
    for v in range(cells.shape[0]):
        cx, cy = cells[v, 1] + 0.5, cells[v, 0] + 0.5
        for i in range(dir_x.shape[0]):
            row, col, s_r, s_c, tm_r, tm_c, td_r, td_c = ray_start(cx, cy, dir_x[i], dir_y[i])
            n = 0
            t = 0.0
            valid = True
            run = 0  # cells in a row near a wall
            while True:
                padded = (row + 1) * pcols + col + 1
                if flat_occ[padded]:
                    valid = t >= min_range
                    if t <= usable and 0 <= row < rows and 0 <= col < cols:
                        beam[n] = row * cols + col  # the cell it ends in
                        n += 1
                    break
                run = run + 1 if flat_near[padded] else 0
                if run > graze:
                    break
                t = min(tm_r, tm_c)
                if t > usable + 1e-9:
                    break
                beam[n] = row * cols + col
                n += 1
                if tm_c < tm_r:
                    col += s_c
                    tm_c += td_c
                else:
                    row += s_r
                    tm_r += td_r
            if not valid:
                continue
            if pos + n > out.shape[0]:
                grown = np.empty(2 * out.shape[0] + n, np.int32)
                grown[:pos] = out[:pos]
                out = grown
            for k in range(n):
                cell = beam[k]
                if flat_target[cell] and stamp[cell] != v:
                    stamp[cell] = v
                    out[pos] = cell
                    pos += 1
        indptr[v + 1] = pos
    return indptr, out[:pos].copy()


def coverage_targets(world: World) -> NDArray[np.bool_]:
    """The cells a coverage tour should get mapped: the explorable cells and their 4-neighbours
    (mostly walls), since an unknown cell beside a mapped free one is a frontier."""
    exp = world.explorable
    out = exp.copy()
    out[1:] |= exp[:-1]
    out[:-1] |= exp[1:]
    out[:, 1:] |= exp[:, :-1]
    out[:, :-1] |= exp[:, 1:]
    return out


def visibility(
    world: World,
    lidar: LidarConfig,
    usable_range_m: float,
    cells: NDArray[np.int64],
    target: NDArray[np.bool_] | None = None,
    margin_cells: float = 1.0,
    graze_cells: int = 3,
) -> tuple[NDArray[np.int64], NDArray[np.int32]]:
    """The ``target`` cells (default: :func:`coverage_targets`) each viewpoint of ``cells`` (row,
    col) sees with ``lidar``'s beams out to the mapper's ``usable_range_m`` (m), in CSR form:
    viewpoint ``v`` sees the flat world cells ``indices[indptr[v]:indptr[v + 1]]``.

    A beam that runs more than ``graze_cells`` cells in a row within ``margin_cells`` of a wall
    without hitting it stops there: a cell seen only past a corner that a beam grazes is not
    counted, since a robot that stops a few centimetres off the viewpoint, or a noisy range,
    would miss it."""
    res = world.grid.resolution
    offsets = lidar.beam_offsets
    occupied = world.grid.data == CellState.OCCUPIED
    near = dilate(occupied, margin_cells) if margin_cells > 0 else occupied
    usable = min(lidar.max_range, usable_range_m) / res
    target = coverage_targets(world) if target is None else target
    return _scan_cells(
        pad_blocked(occupied),
        pad_blocked(near),
        np.ascontiguousarray(target, np.bool_),
        np.ascontiguousarray(cells, np.int64),
        np.cos(offsets),
        np.sin(offsets),
        lidar.min_range / res,
        usable,
        int(graze_cells),
    )
