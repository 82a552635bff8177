"""The rubble field of the ``cluttered`` world: ruined walls and heaps of rubble pieces, drawn on
a coarse grid, and the two grid operations it needs (closing corner contacts, upsampling)."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from frontier_rl.core.world import layout

RUBBLE_M = (0.1, 0.8)  # rubble piece size range (m)
RUBBLE_GAP_M = 0.5  # cluttered world: slots between rubble narrower than this are filled (m)


def close_diagonal_contacts(occ: NDArray[np.bool_]) -> NDArray[np.bool_]:
    """Copy of ``occ`` where no two walls touch only at a corner (a 2x2 checkerboard): one free
    cell of each such pattern is filled, so no ray or robot slips through the corner."""
    occ = occ.copy()
    for _ in range(occ.size):
        a, b, c, d = occ[:-1, :-1], occ[1:, 1:], occ[:-1, 1:], occ[1:, :-1]
        main, anti = a & b & ~c & ~d, c & d & ~a & ~b
        if not (main.any() or anti.any()):
            break
        occ[:-1, 1:] |= main
        occ[:-1, :-1] |= anti
    return occ


def upsample(occ: NDArray[np.bool_], factor: int) -> NDArray[np.bool_]:
    """Each cell of ``occ`` becomes a ``factor`` x ``factor`` block."""
    return np.asarray(np.repeat(np.repeat(occ, factor, axis=0), factor, axis=1))


def _piece(rng: np.random.Generator, res: float, yx: NDArray[np.float64]) -> NDArray[np.bool_]:
    """One rubble piece (cells at ``res``): a block, a rotated slab or an irregular blob, drawn on
    the centred cell coordinates ``yx`` (shape (2, n, n))."""
    lo, hi = RUBBLE_M
    kind = rng.random()
    if kind < 0.3:
        return np.ones((layout.cells(rng.uniform(lo, hi), res), layout.cells(rng.uniform(lo, hi), res)), dtype=np.bool_)
    y, x = yx
    if kind < 0.65:
        length, width, angle = rng.uniform(0.3, hi) / res, rng.uniform(lo, 0.4) / res, rng.uniform(0, math.pi)
        u = x * math.cos(angle) + y * math.sin(angle)
        v = y * math.cos(angle) - x * math.sin(angle)
        mask = (np.abs(u) <= length / 2) & (np.abs(v) <= width / 2)
    else:
        phi = np.arctan2(y, x)
        radius = np.full_like(phi, rng.uniform(lo, hi) / (2 * res))
        for k in (2, 3, 5):
            radius *= 1.0 + rng.uniform(0.0, 0.25) * np.cos(k * phi + rng.uniform(0, 2 * math.pi))
        mask = np.hypot(x, y) <= radius
    half = y.shape[0] // 2
    mask[half, half] = True
    rows, cols = np.flatnonzero(mask.any(axis=1)), np.flatnonzero(mask.any(axis=0))
    return np.asarray(mask[rows[0] : rows[-1] + 1, cols[0] : cols[-1] + 1])


def rubble_layout(rng: np.random.Generator, n_rows: int, n_cols: int, resolution: float) -> NDArray[np.bool_]:
    """USAR rubble field: a walled area with a few ruined (broken, some L-shaped) walls and 0.1-0.8 m
    rubble pieces, scattered and heaped in clusters, some piled against the walls.

    Raw pieces: narrow slots are left for the caller to close. One cell of ``resolution`` (about
    0.1 m) is the wall thickness; upsample the result for a finer map."""
    pad = layout.cells(RUBBLE_M[1], resolution) + 2
    occ = np.zeros((n_rows + 2 * pad, n_cols + 2 * pad), dtype=np.bool_)  # padded: pieces may stick out
    inner = occ[pad:-pad, pad:-pad]
    inner[...] = layout.bordered((n_rows, n_cols), 1)
    for _ in range(int(rng.integers(2, 6))):  # ruined walls: some L-shaped, some broken
        a, b = layout.cells(rng.uniform(1.5, 4.0), resolution), layout.cells(rng.uniform(0.8, 2.0), resolution)
        wall = np.zeros((b, a), dtype=np.bool_)
        wall[0, :] = True
        wall[:, 0] = rng.random() < 0.5
        if rng.random() < 0.5:
            hole = int(rng.integers(1, a))
            wall[0, hole : hole + layout.cells(1.0, resolution)] = False
        wall = np.rot90(wall, int(rng.integers(4)))
        r, c = int(rng.integers(n_rows)), int(rng.integers(n_cols))
        inner[r : r + wall.shape[0], c : c + wall.shape[1]] |= wall[: n_rows - r, : n_cols - c]
    walls = np.flatnonzero(inner[1:-1, 1:-1])  # anchors of the rubble piled against walls
    half = layout.cells(RUBBLE_M[1], resolution) // 2 + 1
    yx = np.mgrid[-half : half + 1, -half : half + 1].astype(np.float64)
    spread = 0.5 / resolution  # cluster radius (cells)
    centres = [
        (rng.uniform(0, n_rows), rng.uniform(0, n_cols), int(rng.integers(2, 7)))
        for _ in range(int(rng.integers(8, 15)))
    ]
    centres += [(rng.uniform(0, n_rows), rng.uniform(0, n_cols), 1) for _ in range(int(rng.integers(25, 45)))]
    if walls.size:
        for idx in rng.choice(walls, size=int(rng.integers(4, 9))):
            r, c = divmod(int(idx), n_cols - 2)
            centres.append((r + 1.0, c + 1.0, int(rng.integers(1, 4))))
    for cr, cc, count in centres:
        for dr, dc in rng.normal(0.0, spread, size=(count, 2)) * (count > 1):
            piece = _piece(rng, resolution, yx)
            r = int(min(max(cr + dr, 0.0), n_rows - 1.0)) + pad - piece.shape[0] // 2
            c = int(min(max(cc + dc, 0.0), n_cols - 1.0)) + pad - piece.shape[1] // 2
            occ[r : r + piece.shape[0], c : c + piece.shape[1]] |= piece
    return np.asarray(inner)
