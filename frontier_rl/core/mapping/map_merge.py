"""Merging two robots' maps, cell by cell: the map that has looked at a cell more often wins it.

What a team shares when its robots meet (:meth:`~frontier_rl.core.mapping.mapper.LogOddsMapper.merge_from`),
compiled: a merge over a whole floor runs at every meeting.
"""

from __future__ import annotations

import numba as nb
import numpy as np
from numpy.typing import NDArray

from frontier_rl.core.world.grid import OCCUPIED_I8, UNKNOWN_I8


@nb.njit(cache=True)
def merge_window(
    state: NDArray[np.int8],
    logodds: NDArray[np.float32],
    looks: NDArray[np.uint16],
    felt: NDArray[np.bool_],
    seen: NDArray[np.bool_],
    explorable: NDArray[np.bool_],
    other_state: NDArray[np.int8],
    other_logodds: NDArray[np.float32],
    other_looks: NDArray[np.uint16],
    other_felt: NDArray[np.bool_],
    window: tuple[int, int, int, int],
    bbox: NDArray[np.int64],
) -> int:
    """Merge the other map into this one over ``window`` (row0, row1, col0, col1; exclusive ends,
    clipped): a cell the other map has looked at more often (``looks``) takes its class, log-odds,
    count and ``felt`` flag; on a tie, the higher log-odds (the more occupied) wins, then occupied,
    so that two maps merged both ways agree. A wall touched counts
    :data:`~frontier_rl.core.mapping.log_odds.MAX_LOOKS`, so the other map's touched walls are
    taken. Returns the explorable cells newly seen; ``bbox`` grows."""
    r0, r1, c0, c1 = window
    gained = 0
    for row in range(max(r0, 0), min(r1, state.shape[0])):
        for col in range(max(c0, 0), min(c1, state.shape[1])):
            theirs_n = other_looks[row, col]
            mine_n = looks[row, col]
            if theirs_n < mine_n:
                continue
            theirs = other_state[row, col]
            if theirs == UNKNOWN_I8:
                continue
            value = other_logodds[row, col]
            if theirs_n == mine_n:  # a tie: the higher log-odds, then occupied
                mine = logodds[row, col]
                if value < mine or (value == mine and (theirs != OCCUPIED_I8 or state[row, col] == OCCUPIED_I8)):
                    continue
            state[row, col] = theirs
            logodds[row, col] = value
            looks[row, col] = theirs_n
            felt[row, col] |= other_felt[row, col]
            if not seen[row, col]:
                seen[row, col] = True
                if explorable[row, col]:
                    gained += 1
                bbox[0] = min(bbox[0], row)
                bbox[1] = max(bbox[1], row)
                bbox[2] = min(bbox[2], col)
                bbox[3] = max(bbox[3], col)
    return gained
