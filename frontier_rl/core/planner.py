"""The costmap and the global planner: inflated obstacles and 8-connected A* on the current map.

Unknown cells are passable at an extra cost (as move_base's ``allow_unknown``); cells closer to a
wall than the robot radius are not, and the cost decays away from walls so that paths keep clear
of them when there is room.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property

import numba as nb
import numpy as np
from numpy.typing import NDArray

from frontier_rl.core.distance import chamfer_distance_padded, flood_known
from frontier_rl.core.grid import CellState, OccupancyGrid
from frontier_rl.core.navigation import NavigationConfig
from frontier_rl.core.path_costs import cost_field
from frontier_rl.core.robot import RobotConfig

_SQRT2 = math.sqrt(2.0)
_OCCUPIED = np.int8(CellState.OCCUPIED)
_UNKNOWN = np.int8(CellState.UNKNOWN)
_COST_STEPS = 64  # inflation table entries per cell of clearance
_MAX_STAMP = 2**31 - 2  # a search marks cells with its stamp and stamp + 1, as int32
_NO_COSTS = np.zeros(0)  # astar_padded works the step costs out itself


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
        return (np.empty(cells), np.empty(cells, np.int32), np.zeros(cells, np.int32), np.empty(heap),
                np.empty(heap, np.int32))  # fmt: skip

    def next_search(self, cells: int) -> tuple[SearchArrays, int]:
        """The arrays for a search over ``cells`` cells (grown if needed) and its stamp."""
        if self._arrays[0].shape[0] < cells or self._stamp > _MAX_STAMP:  # grown, or the stamps wrapped
            self._arrays = self._allocate(cells)
            self._stamp = 0
        self._stamp += 2
        return self._arrays, self._stamp


@dataclass(frozen=True)
class Costmap:
    """Planning costs on one map, kept with a one-cell blocked border (so the compiled planner
    needs no bounds checks); the properties give the unpadded views.

    A cell's step cost factor follows from its clearance and state (:attr:`cost_padded`); the
    planner works it out for the cells it reaches, so that a costmap costs no sweep for it.

    Attributes:
        grid: the map.
        open_padded: traversable cells (not within the robot radius of a wall), padded.
        clearance_padded: distance (cells) from each cell centre to the nearest occupied cell
            centre, by a chamfer transform (exact or up to 8 % over), capped just above the
            inflation radius, padded.
        inflation_table: the inflation cost by clearance, in steps of 1/64 cell.
        inflation_radius: clearance (cells) from which a cell has no inflation cost.
        unknown_cost: extra cost factor of an unknown cell.
        scratch: the planner's scratch arrays.
    """

    grid: OccupancyGrid
    open_padded: NDArray[np.bool_] = field(repr=False)
    clearance_padded: NDArray[np.float64] = field(repr=False)
    inflation_table: NDArray[np.float64] = field(repr=False)
    inflation_radius: float
    unknown_cost: float
    scratch: SearchScratch = field(default_factory=SearchScratch, repr=False, compare=False)

    @classmethod
    def build(
        cls, grid: OccupancyGrid, robot: RobotConfig, config: NavigationConfig, scratch: SearchScratch | None = None
    ) -> Costmap:
        """Inflate the obstacles of ``grid`` for a robot of ``robot.radius``; its searches use
        ``scratch`` (a new one by default: pass one to reuse it from map to map)."""
        res = grid.resolution
        lethal_below = (robot.radius + 0.5 * res) / res  # cell centre to wall surface, in cells
        inflation_radius = config.inflation_radius / res
        clearance_p, open_p = _inflate(grid.data, lethal_below, inflation_radius)
        table = inflation_table(lethal_below, inflation_radius, config.cost_scaling * res, config.inflation_cost)
        return cls(grid, open_p, clearance_p, table, inflation_radius, config.unknown_cost, scratch or SearchScratch())

    @cached_property
    def cost_padded(self) -> NDArray[np.float64]:
        """Step cost factor per cell, 1 + inflation and unknown penalties, padded (made on first use)."""
        return _step_costs(self.grid.data, self.clearance_padded, self.inflation_table, self.inflation_radius,
                           self.unknown_cost)  # fmt: skip

    @property
    def traversable(self) -> NDArray[np.bool_]:
        """Cells the robot centre may occupy (a view)."""
        return self.open_padded[1:-1, 1:-1]

    @property
    def penalty(self) -> NDArray[np.float64]:
        """Extra cost factor per cell (inflation + unknown), >= 0."""
        return self.cost_padded[1:-1, 1:-1] - 1.0

    @property
    def clearance(self) -> NDArray[np.float64]:
        """Distance (m) from each cell centre to the nearest occupied cell centre (chamfer, capped)."""
        return self.clearance_padded[1:-1, 1:-1] * self.grid.resolution

    def with_discs_blocked(self, centres: NDArray[np.float64], radius: float) -> Costmap:
        """A copy in which every cell whose centre lies within ``radius`` (m) of one of ``centres``
        ((k, 2) world points, m) is blocked (and costed) like a wall: other robots, for planning
        around them."""
        open_p = self.open_padded.copy()
        clear_p = self.clearance_padded.copy()
        g = self.grid
        reach = int(math.ceil(radius / g.resolution))
        for x, y in centres:
            row, col = g.world_to_cell(float(x), float(y))
            r0, r1 = max(row - reach, 0), min(row + reach + 1, g.height)
            c0, c1 = max(col - reach, 0), min(col + reach + 1, g.width)
            if r0 >= r1 or c0 >= c1:
                continue
            cy = g.origin[1] + (np.arange(r0, r1) + 0.5) * g.resolution
            cx = g.origin[0] + (np.arange(c0, c1) + 0.5) * g.resolution
            inside = np.hypot(cx[None, :] - x, cy[:, None] - y) <= radius
            open_p[r0 + 1 : r1 + 1, c0 + 1 : c1 + 1] &= ~inside
            clear_p[r0 + 1 : r1 + 1, c0 + 1 : c1 + 1][inside] = 0.0  # so the start's escape zone stays shut
        return Costmap(g, open_p, clear_p, self.inflation_table, self.inflation_radius, self.unknown_cost, self.scratch)

    def reachable_known(self, start: tuple[int, int]) -> NDArray[np.bool_]:
        """Known-free traversable cells connected (8-way) to ``start`` (row, col), or to the nearest
        such cell within 0.5 m when the start itself is not one."""
        r, c = start
        if not self.grid.in_bounds(r, c):
            return np.zeros(self.grid.shape, np.bool_)
        reach = flood_known(self.open_padded, self.grid.data, r, c)
        if not reach[r, c]:
            mask = self.traversable & (self.grid.data == CellState.FREE)
            nearest = nearest_cell(mask, start, max_radius=int(round(0.5 / self.grid.resolution)))
            if nearest is not None:
                reach = flood_known(self.open_padded, self.grid.data, *nearest)
        return reach

    def cost_to_go(self, start: tuple[int, int]) -> NDArray[np.float64]:
        """Planner path cost (m, weighted by the cell costs) from ``start`` (row, col) to every
        traversable cell; inf where there is no path."""
        if not self.grid.in_bounds(*start):
            return np.full(self.grid.shape, np.inf)
        return cost_field(self, start)

    def plan(self, start: tuple[int, int], goal: tuple[int, int], escape_radius: float = 0.25) -> NDArray[np.int64]:
        """A* path (cells, (n, 2) rows and columns) from ``start`` to ``goal``; empty if none.

        Cells within ``escape_radius`` (m) of the start may be crossed even if inflated (not if
        occupied), so that a robot that ended up too close to a wall can still leave.
        """
        if not (self.grid.in_bounds(*start) and self.grid.in_bounds(*goal)):
            return np.zeros((0, 2), np.int64)
        escape = escape_radius / self.grid.resolution
        scratch, stamp = self.scratch.next_search(self.open_padded.size)
        costs = (self.grid.data, self.inflation_table, self.inflation_radius, self.unknown_cost)
        return astar_padded(self.open_padded, self.clearance_padded, costs, _NO_COSTS, start[0], start[1], goal[0],
                            goal[1], escape, scratch, stamp)  # fmt: skip


@nb.njit(cache=True)
def inflation_table(
    lethal_below: float, inflation_radius: float, cost_scaling: float, inflation_cost: float
) -> NDArray[np.float64]:
    """The inflation cost by clearance (cells), in steps of 1/64 cell: ``inflation_cost`` up to the
    lethal distance, then decaying by ``cost_scaling`` per cell. A lookup costs less than exp()
    per cell, and 1/64 cell is far finer than the costmap needs."""
    table = np.empty(int(math.ceil(inflation_radius * _COST_STEPS)) + 2)
    for k in range(table.shape[0]):
        table[k] = inflation_cost * math.exp(-cost_scaling * max(k / _COST_STEPS - lethal_below, 0.0))
    return table


@nb.njit(cache=True, inline="always")
def _step_cost(
    clearance: float, unknown: bool, table: NDArray[np.float64], inflation_radius: float, unknown_cost: float
) -> float:
    """The step cost factor of a cell of ``clearance`` (cells): 1 + inflation + unknown penalties."""
    index = int(min(clearance, inflation_radius) * _COST_STEPS)  # in the table even where it is not used
    extra = table[index] if clearance < inflation_radius else 0.0
    extra += unknown_cost if unknown else 0.0
    return 1.0 + extra


@nb.njit(cache=True)
def _step_costs(
    state: NDArray[np.int8],
    clearance_padded: NDArray[np.float64],
    table: NDArray[np.float64],
    inflation_radius: float,
    unknown_cost: float,
) -> NDArray[np.float64]:
    """The step cost factor of every cell (:func:`_step_cost`), with a border of 1."""
    rows, cols = state.shape
    cost = np.ones((rows + 2, cols + 2))
    for r in range(rows):
        for c in range(cols):
            cost[r + 1, c + 1] = _step_cost(
                clearance_padded[r + 1, c + 1], state[r, c] == _UNKNOWN, table, inflation_radius, unknown_cost
            )
    return cost


@nb.njit(cache=True)
def _inflate(
    state: NDArray[np.int8], lethal_below: float, inflation_radius: float
) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
    """Clearance (cells) and traversable mask of a map, each with a one-cell border (not
    traversable) so that the planner needs no bounds checks; lengths in cells."""
    rows, cols = state.shape
    occupied = np.empty((rows, cols), np.bool_)
    for r in range(rows):
        for c in range(cols):
            occupied[r, c] = state[r, c] == _OCCUPIED
    clearance = chamfer_distance_padded(occupied, inflation_radius + 1.0)
    # Traversability must be exact, and the chamfer distance runs up to 8.24 % long: below the
    # lethal distance it is surely lethal, 8.24 % above it surely clear, and the cells in between
    # (if any: with the default radius no chamfer value falls there) get an exact look at the
    # walls around them.
    traversable = np.zeros((rows + 2, cols + 2), np.bool_)
    surely_clear = lethal_below * 1.0825
    undecided = 0
    for r in range(1, rows + 1):
        for c in range(1, cols + 1):
            d = clearance[r, c]
            traversable[r, c] = d >= surely_clear
            undecided += (d >= lethal_below) & (d < surely_clear)
    if undecided:
        reach = int(math.ceil(lethal_below))
        lethal2 = lethal_below * lethal_below
        for r in range(1, rows + 1):
            for c in range(1, cols + 1):
                if not lethal_below <= clearance[r, c] < surely_clear:
                    continue
                clear = True
                for rr in range(max(r - 1 - reach, 0), min(r + reach, rows)):
                    for cc in range(max(c - 1 - reach, 0), min(c + reach, cols)):
                        if occupied[rr, cc] and (rr - r + 1) ** 2 + (cc - c + 1) ** 2 < lethal2:
                            clear = False
                traversable[r, c] = clear
    return clearance, traversable


def nearest_cell(mask: NDArray[np.bool_], target: tuple[int, int], max_radius: int) -> tuple[int, int] | None:
    """The True cell of ``mask`` nearest to ``target`` (row, col), searched in growing windows
    up to ``max_radius`` cells; None if there is none that close."""
    row, col = _nearest_cell(np.asarray(mask, np.bool_), int(target[0]), int(target[1]), int(max_radius))
    return None if row < 0 else (int(row), int(col))


@nb.njit(cache=True, inline="always")
def _slice_stop(stop: int, size: int) -> int:
    """Where a slice ``[...:stop]`` of an axis of ``size`` ends, as Python counts it."""
    if stop < 0:
        stop += size
    return min(max(stop, 0), size)


@nb.njit(cache=True)
def _nearest_cell(mask: NDArray[np.bool_], r: int, c: int, max_radius: int) -> tuple[int, int]:
    """:func:`nearest_cell`, (-1, -1) for None. Windows of radius 2, 4, 8, ... (capped): the first
    with a True cell within the radius gives the nearest, ties to the first in row-major order."""
    rows, cols = mask.shape
    radius = min(2, max_radius)
    while True:
        r0, c0 = min(max(r - radius, 0), rows), min(max(c - radius, 0), cols)
        r1, c1 = _slice_stop(r + radius + 1, rows), _slice_stop(c + radius + 1, cols)
        best, best_row, best_col = -1, -1, -1
        for rr in range(r0, r1):
            for cc in range(c0, c1):
                if mask[rr, cc]:
                    d2 = (rr - r) ** 2 + (cc - c) ** 2
                    if best < 0 or d2 < best:
                        best, best_row, best_col = d2, rr, cc
        if best >= 0 and best <= radius * radius:
            return best_row, best_col
        if radius >= max_radius:
            return -1, -1
        radius = min(radius * 2, max_radius)


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
    no_inflation = (np.zeros(np.shape(passable), np.int8), np.zeros(1), 0.0, 0.0)
    return astar_padded(open_padded, no_escape, no_inflation, cost_padded, start_r, start_c, goal_r, goal_c, 0.0,
                        scratch, stamp)  # fmt: skip


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
def astar_padded(
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
                step_cost = cost[nxt]
            else:
                unknown = state[row + d_row - 1, col + d_col - 1] == _UNKNOWN
                step_cost = _step_cost(clear[nxt], unknown, table, inflation_radius, unknown_cost)
            new_g = g[cur] + step * step_cost
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
