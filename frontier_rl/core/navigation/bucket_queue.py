"""Dial's bucket queue for the planner's Dijkstra searches, shared by the path-cost kernels
(:mod:`~frontier_rl.core.navigation.path_costs`, :mod:`~frontier_rl.core.navigation.group_costs`).

A search works on a padded grid (a closed border of one cell, so that no neighbour leaves it),
flattened. A step costs its length (1 or √2 cells) times the cost factor of the cell it enters, at
least 1, so a queue of buckets of width 1 settles cells in an exact order: a bucket is a linked list
of entries (``head`` per slot of a ring, ``node`` and ``link`` per entry, one entry per
improvement), the ring spanning more buckets than a step costs (:func:`bucket_ring_mask`).
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np
from numpy.typing import NDArray

_SQRT2 = math.sqrt(2.0)


@nb.njit(cache=True)
def bucket_ring_mask(max_factor: float) -> int:
    """The mask that maps a bucket (an integer path cost, cells) to its slot in the ring of a
    bucket queue whose steps cost at most √2 × ``max_factor``: the ring spans more buckets than a
    step, and has a power-of-two size so that a slot is a mask, not a division (one per push)."""
    span = int(math.ceil(_SQRT2 * max(max_factor, 1.0))) + 2
    size = 1
    while size < span:
        size *= 2
    return size - 1


@nb.njit(cache=True, inline="always")
def neighbour_steps(padded_cols: int) -> tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.int64]]:
    """The flat offsets of a cell's 8 neighbours on a padded grid ``padded_cols`` wide (the four
    sides first), and for each diagonal the offsets of the two side cells it passes between (0 for
    the sides)."""
    offsets = np.array(
        [-padded_cols, padded_cols, -1, 1, -padded_cols - 1, -padded_cols + 1, padded_cols - 1, padded_cols + 1]
    )
    side_row = np.array([0, 0, 0, 0, -padded_cols, -padded_cols, padded_cols, padded_cols])
    side_col = np.array([0, 0, 0, 0, -1, 1, -1, 1])
    return offsets, side_row, side_col


@nb.njit(cache=True, inline="always")
def relax_neighbours(
    cur: int,
    g: NDArray[np.float64],
    closed: NDArray[np.bool_],
    open_ok: NDArray[np.bool_],
    cost: NDArray[np.float64],
    steps: tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.int64]],
    queue: tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.int64]],
    mask: int,
    used: int,
    touched: NDArray[np.int64],
    n_touched: int,
) -> tuple[int, int, int]:
    """Relax the neighbours of the settled cell ``cur``: each open one not yet settled whose cost
    ``g`` the step from ``cur`` lowers gets it, and an entry in the bucket of its integer cost
    (``queue``: ``head``, ``node``, ``link``; ``used`` entries so far). A diagonal step may not cut
    a corner. A cell reached for the first time is recorded in ``touched`` (``n_touched`` so far),
    so that a search can reset only what it changed. Returns ``used``, the entries pushed and
    ``n_touched``."""
    offsets, side_row, side_col = steps
    head, node, link = queue
    pushed = 0
    for k in range(8):
        nxt = cur + offsets[k]
        if closed[nxt] or not open_ok[nxt]:
            continue
        if k < 4:
            step = 1.0
        elif open_ok[cur + side_row[k]] and open_ok[cur + side_col[k]]:
            step = _SQRT2
        else:
            continue  # a diagonal step may not cut a corner
        new_g = g[cur] + step * cost[nxt]
        if new_g < g[nxt]:
            if g[nxt] == np.inf:
                touched[n_touched] = nxt
                n_touched += 1
            g[nxt] = new_g
            into = int(new_g) & mask
            node[used], link[used] = nxt, head[into]
            head[into] = used
            used += 1
            pushed += 1
    return used, pushed, n_touched
