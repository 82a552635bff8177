"""Walls a cell thinner than the map shows: the map for the narrow-passage recovery.

Range noise makes about half the returns of a wall fall a little short, into the free cell in
front of it, and a hit outweighs a miss in the log-odds update (as in Gmapping and OctoMap), so a
mapped wall is about one cell thicker than the true one on each side the LiDAR saw, and a passage
about two cells narrower. A gap the robot fits through by a few centimetres is closed on its map.
When the normal costmap leaves no frontier to go to, the simulator plans once more on a map whose
walls have their outer layer peeled (:func:`thin_walls`); the robot's collision check on the true
map still holds it back where the gap really is too narrow, and the wall cells it touches are kept
from then on.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from frontier_rl.core.world.grid import CellState

_FREE = np.int8(CellState.FREE)
_OCCUPIED = np.int8(CellState.OCCUPIED)


def thin_walls(state: NDArray[np.int8], felt: NDArray[np.bool_] | None = None) -> NDArray[np.int8]:
    """A copy of ``state`` in which every occupied cell that faces a free cell (4-neighbour), with
    an occupied cell right behind it and no free cell right behind that, is free: each wall loses
    the layer it grew on every side it was seen from, and a wall never loses its last cell, nor a
    wall two cells thick one of them (it may be one true cell seen from either side). Cells set
    in ``felt`` (walls the robot touched, same shape) are kept."""
    occupied = state == _OCCUPIED
    free = np.pad(state == _FREE, 2)
    wall = np.pad(occupied, 2)
    peel = np.zeros_like(occupied)
    rows, cols = state.shape
    for dr, dc in ((-1, 0), (1, 0), (0, -1), (0, 1)):
        in_front = free[2 + dr : 2 + dr + rows, 2 + dc : 2 + dc + cols]
        behind = wall[2 - dr : 2 - dr + rows, 2 - dc : 2 - dc + cols]
        beyond_free = free[2 - 2 * dr : 2 - 2 * dr + rows, 2 - 2 * dc : 2 - 2 * dc + cols]
        peel |= in_front & behind & ~beyond_free
    peel &= occupied
    if felt is not None:
        peel &= ~felt
    out = state.copy()
    out[peel] = _FREE
    return out
