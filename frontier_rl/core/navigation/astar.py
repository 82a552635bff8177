"""The global planner: 8-connected A* with the octile heuristic on padded costmap arrays.

A step costs its length (1 or √2 cells) times the step cost factor of the cell entered
(:mod:`frontier_rl.core.navigation.step_costs`), and a diagonal step may not cut a corner. The search keeps its
scratch arrays from one search to the next (:class:`SearchScratch`);
:class:`~frontier_rl.core.navigation.costmap.Costmap` is its usual caller.
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np
from numpy.typing import NDArray

from frontier_rl.core.navigation.step_costs import step_cost
from frontier_rl.core.world.grid import UNKNOWN_I8

_SQRT2 = math.sqrt(2.0)
_MAX_STAMP = 2**31 - 2  # a search marks cells with its stamp and stamp + 1, as int32

SearchArrays = tuple[NDArray[np.float64], NDArray[np.int32], NDArray[np.int32], NDArray[np.float64], NDArray[np.int32]]
"""The A* search's scratch: path cost, parent and search stamp per cell, and the heap (priority, cell)."""


class SearchScratch:
    """The A* search's scratch arrays (path cost, parent, a per-cell search stamp and the heap),
    kept from one search to the next. A search reaches about a thousand cells of a map of tens of
    thousands; filling arrays of the map's size at every search took longer than the search.
    One search at a time: a planner that searches in several threads needs one each."""

    def __init__(self, cells: int = 0) -> None:
        """Scratch for searches over up to ``cells`` cells to start with (it grows as needed)."""
        self._stamp = 0
        self._arrays = self._allocate(cells)

    @staticmethod
    def _allocate(cells: int) -> SearchArrays:
        heap = 8 * cells + 8  # a push per improvement: at most 8 per expanded cell, and the start
        return (
            np.empty(cells),
            np.empty(cells, np.int32),
            np.zeros(cells, np.int32),
            np.empty(heap),
            np.empty(heap, np.int32),
        )

    def next_search(self, cells: int) -> tuple[SearchArrays, int]:
        """The arrays for a search over ``cells`` cells (grown if needed) and its stamp."""
        capacity = self._arrays[0].shape[0]
        if capacity < cells or self._stamp + 2 > _MAX_STAMP:  # too small, or out of stamps
            self._arrays = self._allocate(max(capacity, cells))
            self._stamp = 0
        self._stamp += 2
        return self._arrays, self._stamp


def astar(
    passable: NDArray[np.bool_],
    penalty: NDArray[np.float64],
    start_r: int,
    start_c: int,
    goal_r: int,
    goal_c: int,
) -> NDArray[np.int64]:
    """8-connected A* on plain arrays: ``passable`` cells, step cost = length × (1 + ``penalty``
    of the cell entered), no corner cutting. Returns the (n, 2) cell path, empty if none."""
    open_padded = np.pad(np.asarray(passable, np.bool_), 1, constant_values=False)
    cost_padded = np.pad(1.0 + np.asarray(penalty, np.float64), 1, constant_values=1.0)
    no_escape = np.zeros(open_padded.shape)
    scratch, stamp = SearchScratch().next_search(open_padded.size)
    no_inflation = (np.zeros((0, 0), np.int8), np.zeros(1), 0.0, 0.0)  # unused: the costs are given
    return astar_padded(
        open_padded, no_escape, no_inflation, cost_padded, start_r, start_c, goal_r, goal_c, 0.0, scratch, stamp
    )


@nb.njit(inline="always")
def _heap_push(heap_f: NDArray[np.float64], heap_i: NDArray[np.int32], size: int, f: float, item: int) -> int:
    """Push ``item`` with priority ``f`` onto the binary min-heap of ``size`` entries; returns the new size."""
    pos = size
    while pos > 0:
        up = (pos - 1) // 2
        if heap_f[up] <= f:
            break
        heap_f[pos], heap_i[pos] = heap_f[up], heap_i[up]
        pos = up
    heap_f[pos], heap_i[pos] = f, item
    return size + 1


@nb.njit(inline="always")
def _heap_pop(heap_f: NDArray[np.float64], heap_i: NDArray[np.int32], size: int) -> int:
    """Remove the root (read it first) of the min-heap of ``size`` entries; returns the new size."""
    size -= 1  # move the last entry to the root and sift it down
    last_f, last_i = heap_f[size], heap_i[size]
    pos = 0
    while True:
        child = 2 * pos + 1
        if child >= size:
            break
        if child + 1 < size and heap_f[child + 1] < heap_f[child]:
            child += 1
        if heap_f[child] >= last_f:
            break
        heap_f[pos], heap_i[pos] = heap_f[child], heap_i[child]
        pos = child
    heap_f[pos], heap_i[pos] = last_f, last_i
    return size


@nb.njit(cache=True)
def astar_padded(  # noqa: C901 (numba kernel: the search loop with its neighbour steps written out)
    open_padded: NDArray[np.bool_],
    clearance_padded: NDArray[np.float64],
    costs: tuple[NDArray[np.int8], NDArray[np.float64], float, float],
    cost_padded: NDArray[np.float64],
    start_r: int,
    start_c: int,
    goal_r: int,
    goal_c: int,
    escape: float,
    scratch: SearchArrays,
    stamp: int,
) -> NDArray[np.int64]:
    """8-connected A* with octile heuristic on padded costmap arrays (a border of blocked cells).

    A step costs its length × the cost factor of the cell entered: from ``cost_padded`` when it is
    not empty, else worked out from the cell's clearance and its state in the map, as
    :attr:`Costmap.cost_padded` would give it (``costs`` = map, inflation table, inflation radius,
    unknown cost); diagonal steps may not cut a corner. Within ``escape`` cells of the start,
    cells that are not traversable may still be crossed if they are no closer to a wall than the
    start (and not occupied): a robot that ended up too close to a wall may back away from it, not
    squeeze on. ``scratch`` and ``stamp`` come from :meth:`SearchScratch.next_search`. Returns the
    (n, 2) cell path (unpadded rows and columns), empty if there is none.
    """
    prows, pcols = open_padded.shape
    start = (start_r + 1) * pcols + start_c + 1
    goal = (goal_r + 1) * pcols + goal_c + 1
    open_ok = open_padded.copy().reshape(-1)
    clear = clearance_padded.reshape(-1)
    state, table, inflation_radius, unknown_cost = costs
    given = cost_padded.size > 0
    cost = cost_padded.reshape(-1)
    reach = int(math.ceil(escape))
    floor_clear = max(clear[start], 0.5)  # >= 0.5: occupied cells (clearance 0) never open
    for dr in range(-reach, reach + 1):
        for dc in range(-reach, reach + 1):
            r, c = start_r + 1 + dr, start_c + 1 + dc
            if dr * dr + dc * dc <= escape * escape and 1 <= r < prows - 1 and 1 <= c < pcols - 1:
                cell = r * pcols + c
                if clear[cell] >= floor_clear:
                    open_ok[cell] = True
    open_ok[start] = True
    if not open_ok[goal]:
        return np.zeros((0, 2), np.int64)
    # mark[cell] < stamp: not reached by this search; == stamp: reached (g, parent valid);
    # == stamp + 1: closed. Nothing has to be cleared between searches.
    g, parent, mark, heap_f, heap_i = scratch
    closed = stamp + 1
    size = 1
    heap_f[0] = 0.0
    heap_i[0] = start
    g[start] = 0.0
    mark[start] = stamp
    goal_pr, goal_pc = goal_r + 1, goal_c + 1
    while size > 0:
        cur = heap_i[0]
        size = _heap_pop(heap_f, heap_i, size)
        if mark[cur] == closed:
            continue
        mark[cur] = closed
        if cur == goal:
            break
        row = cur // pcols
        col = cur - row * pcols
        up, down, left, right = open_ok[cur - pcols], open_ok[cur + pcols], open_ok[cur - 1], open_ok[cur + 1]
        for k in range(8):  # straight steps need the cell open, diagonal ones both side cells too
            if k == 0:
                nxt, d_row, d_col, step = cur - pcols, -1, 0, 1.0 if up else 0.0
            elif k == 1:
                nxt, d_row, d_col, step = cur + pcols, 1, 0, 1.0 if down else 0.0
            elif k == 2:
                nxt, d_row, d_col, step = cur - 1, 0, -1, 1.0 if left else 0.0
            elif k == 3:
                nxt, d_row, d_col, step = cur + 1, 0, 1, 1.0 if right else 0.0
            elif k == 4:
                nxt, d_row, d_col = cur - pcols - 1, -1, -1
                step = _SQRT2 if up and left and open_ok[nxt] else 0.0
            elif k == 5:
                nxt, d_row, d_col = cur - pcols + 1, -1, 1
                step = _SQRT2 if up and right and open_ok[nxt] else 0.0
            elif k == 6:
                nxt, d_row, d_col = cur + pcols - 1, 1, -1
                step = _SQRT2 if down and left and open_ok[nxt] else 0.0
            else:
                nxt, d_row, d_col = cur + pcols + 1, 1, 1
                step = _SQRT2 if down and right and open_ok[nxt] else 0.0
            seen = mark[nxt]
            if step == 0.0 or seen == closed:
                continue
            if given:
                entry_cost = cost[nxt]
            else:
                unknown = state[row + d_row - 1, col + d_col - 1] == UNKNOWN_I8
                entry_cost = step_cost(clear[nxt], unknown, table, inflation_radius, unknown_cost)
            new_g = g[cur] + step * entry_cost
            if seen < stamp or new_g < g[nxt]:
                g[nxt] = new_g
                parent[nxt] = cur
                mark[nxt] = stamp
                dr = abs(row + d_row - goal_pr)
                dc = abs(col + d_col - goal_pc)
                f = new_g + (_SQRT2 - 1.0) * min(dr, dc) + max(dr, dc)
                size = _heap_push(heap_f, heap_i, size, f, nxt)
    if mark[goal] != closed:
        return np.zeros((0, 2), np.int64)
    length = 1
    cur = goal
    while cur != start:
        cur = parent[cur]
        length += 1
    path = np.empty((length, 2), np.int64)
    cur = goal
    for i in range(length - 1, -1, -1):
        path[i, 0] = cur // pcols - 1
        path[i, 1] = cur % pcols - 1
        cur = parent[cur]
    return path
