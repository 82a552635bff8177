"""Planner path costs from the robot to groups of cells (the frontiers), in work bounded at any
map size: the search stops once the wanted number of groups is reached, and on a map of more than
:data:`MAX_SEARCH_CELLS` cells it runs on blocks of f × f cells.

The costs are the global planner's (:mod:`frontier_rl.core.navigation.costmap`): a step costs its
length times the cost factor of the cell it enters, diagonals may not cut a corner. On blocks a
block is open when any of its cells is, and costs the least factor among its open cells, so a
path cost on blocks is an estimate (a door narrower than a block stays open; a path's length is
measured on block centres), where on cells it is exact.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numba as nb
import numpy as np
from numpy.typing import NDArray

from frontier_rl.core.navigation.bucket_queue import bucket_ring_mask, neighbour_steps, relax_neighbours
from frontier_rl.core.navigation.step_costs import step_cost
from frontier_rl.core.world.grid import UNKNOWN_I8

if TYPE_CHECKING:  # the costmap keeps its block grids: no import cycle at run time
    from frontier_rl.core.navigation.costmap import Costmap

MAX_SEARCH_CELLS = 300 * 300
"""Maps of up to this many cells (15 m × 15 m at 0.05 m) are searched cell by cell; larger ones on
blocks of the smallest f × f cells that bring the search within it, but no larger than a wall's
closed band allows (:func:`max_block_factor`: 3 cells for the TurtleBot3 at 0.05 m, so a map of
more than 810,000 cells is searched on more blocks than this)."""


def block_factor(shape: tuple[int, int], resolution: float, robot_radius: float) -> int:
    """The edge f (cells) of the blocks a map of ``shape`` is searched on: 1 up to
    :data:`MAX_SEARCH_CELLS` cells, never more than :func:`max_block_factor`."""
    wanted = max(1, math.ceil(math.sqrt(shape[0] * shape[1] / MAX_SEARCH_CELLS)))
    return min(wanted, max_block_factor(resolution, robot_radius))


def max_block_factor(resolution: float, robot_radius: float) -> int:
    """The largest block edge (cells) at which no search crosses a wall: beside a wall one cell
    thick the robot's centre may not stand on k cells either side (k = 2 for the TurtleBot3 at
    0.05 m), so the closed band is 2k + 1 cells; blocks of f cells with 2f - 1 <= 2k + 1 always
    have a whole closed block inside it. Larger blocks could join open cells on both sides of it."""
    lethal = (robot_radius + 0.5 * resolution) / resolution  # the costmap's lethal clearance (cells)
    k = max(math.ceil(lethal) - 1, 0)
    return max(1, (2 * k + 2) // 2)


BlockSource = tuple[NDArray[np.bool_], NDArray[np.float64], NDArray[np.int8], NDArray[np.float64], float, float, int]
"""What a block is worked out from: the cells' padded open mask and clearance (cells), the map's
states, the inflation table and radius (cells), the unknown cells' extra cost and the block edge f."""


TILE = 16
"""Blocks are worked out in tiles of TILE × TILE blocks, when the search first comes next to one
(one at a time would cost more in calls than it saves)."""


@dataclass(frozen=True)
class BlockGrid:
    """The blocks of f × f cells a costmap is searched on, padded with a closed rim: which are
    open, their step cost factors, and which are still ``pending`` (not yet worked out). Its
    tiles are worked out as searches come next to them and kept for the next search on the same
    costmap, so a decision's several searches work each tile out once.

    Attributes:
        open_padded: open blocks.
        cost_padded: each open block's step cost factor (the least of its open cells').
        pending: blocks not yet worked out.
    """

    open_padded: NDArray[np.bool_]
    cost_padded: NDArray[np.float64]
    pending: NDArray[np.bool_]

    @classmethod
    def empty(cls, shape: tuple[int, int], f: int) -> BlockGrid:
        """Nothing worked out yet, for a map of ``shape`` cells on blocks of ``f`` cells."""
        padded = (-(-shape[0] // f) + 2, -(-shape[1] // f) + 2)
        return cls(np.zeros(padded, np.bool_), np.ones(padded), np.ones(padded, np.bool_))


@nb.njit(cache=True)
def _fill_tile(
    block: int, open_b: NDArray[np.bool_], cost_b: NDArray[np.float64], pending: NDArray[np.bool_], src: BlockSource
) -> None:
    """Work out the tile of TILE × TILE blocks that holds ``block`` (a flat index into the padded
    block grid ``open_b``): a block is open when any of its f × f cells is, at the least step cost
    factor of its open cells; the grid's rim stays closed. Its blocks are no longer ``pending``."""
    open_padded, clearance_padded, state, table, inflation_radius, unknown_cost, f = src
    rows, cols = state.shape
    prows, pcols = open_b.shape
    top, left = (block // pcols) // TILE * TILE, (block % pcols) // TILE * TILE
    for pr in range(top, min(top + TILE, prows)):
        for pc in range(left, min(left + TILE, pcols)):
            pending[pr, pc] = False
            if pr == 0 or pc == 0 or pr == prows - 1 or pc == pcols - 1:
                continue
            br, bc = pr - 1, pc - 1
            # a step's cost factor falls as the clearance grows, so a block's least is that of its
            # clearest open cell, known or unknown: two maxima, and a factor for each
            clear_known, clear_unknown = -1.0, -1.0
            for r in range(br * f, min(br * f + f, rows)):
                for c in range(bc * f, min(bc * f + f, cols)):
                    if open_padded[r + 1, c + 1]:
                        if state[r, c] == UNKNOWN_I8:
                            clear_unknown = max(clear_unknown, clearance_padded[r + 1, c + 1])
                        else:
                            clear_known = max(clear_known, clearance_padded[r + 1, c + 1])
                if clear_known >= inflation_radius:  # the least a step can cost
                    break
            least = np.inf
            if clear_known >= 0.0:
                least = step_cost(clear_known, False, table, inflation_radius, unknown_cost)
            if clear_unknown >= 0.0:
                least = min(least, step_cost(clear_unknown, True, table, inflation_radius, unknown_cost))
            if least < np.inf:
                open_b[pr, pc] = True
                cost_b[pr, pc] = least


@nb.njit(cache=True)
def _group_costs(  # noqa: C901 (numba kernel: a Dijkstra that fills blocks as it goes)
    open_padded: NDArray[np.bool_],
    cost_padded: NDArray[np.float64],
    pending: NDArray[np.bool_],
    src: BlockSource,
    source: int,
    members: tuple[NDArray[np.int64], NDArray[np.int64]],
    reach: int,
    n_groups: int,
    want: int,
    max_cost: float,
) -> tuple[NDArray[np.float64], bool]:
    """Path cost (cells) from ``source`` (an unpadded flat index) to each group: the least cost of
    any cell within ``reach`` cells (a square) of one of its members (``members``: unpadded flat
    indices and their groups, a group's members one after another); inf for a group not reached.
    Dial's bucket queue of width 1 (:mod:`~frontier_rl.core.navigation.bucket_queue`; every step
    costs at least 1 and at most ``max_cost``), which stops after the bucket in which
    ``want`` groups were reached: those, and any tied with them, are exact. On blocks, ``pending``
    marks the blocks not yet worked out from ``src``; a tile of them is worked out when the search
    first comes next to one (:func:`_fill_tile`), so its step-cost work grows with the area
    searched, not with the map (its arrays still span the block grid). The flag is True when
    the search ran out of cells instead."""
    member_cells, member_groups = members
    prows, pcols = open_padded.shape
    rows, cols = prows - 2, pcols - 2
    open_ok = open_padded.reshape(-1)
    cost = cost_padded.reshape(-1)
    todo = pending.reshape(-1)
    first = np.full(open_ok.size, -1, np.int64)  # per cell its first group entry, the rest in ``also``
    n_entries = member_cells.shape[0] * (2 * reach + 1) ** 2
    also = np.empty(n_entries, np.int64)
    entry_group = np.empty(n_entries, np.int64)
    n = 0
    for m in range(member_cells.shape[0]):
        row, col = member_cells[m] // cols, member_cells[m] % cols
        for r in range(max(row - reach, 0), min(row + reach + 1, rows)):
            for c in range(max(col - reach, 0), min(col + reach + 1, cols)):
                cell = (r + 1) * pcols + c + 1
                if first[cell] >= 0 and entry_group[first[cell]] == member_groups[m]:
                    continue  # the cell is already in this group (members of a group come together)
                also[n], entry_group[n] = first[cell], member_groups[m]
                first[cell] = n
                n += 1
    steps = neighbour_steps(pcols)
    offsets = steps[0]
    mask = bucket_ring_mask(max_cost)
    head = np.full(mask + 1, -1, np.int64)
    node = np.empty(8 * open_ok.size + 1, np.int64)  # entry pool: one entry per improvement
    link = np.empty(8 * open_ok.size + 1, np.int64)
    g = np.full(open_ok.size, np.inf)
    closed = np.zeros(open_ok.size, np.bool_)
    touched = np.empty(open_ok.size, np.int64)  # the queue's record of cells reached; not needed here
    n_touched = 0
    best = np.full(n_groups, np.inf)
    start = (source // cols + 1) * pcols + source % cols + 1
    g[start] = 0.0
    node[0], link[0], head[0] = start, -1, 0
    used, live, bucket, found = 1, 1, 0, 0
    while live > 0:
        slot = bucket & mask
        entry = head[slot]
        if entry < 0:
            if found >= want:
                break
            bucket += 1
            continue
        head[slot] = link[entry]
        live -= 1
        cur = node[entry]
        if closed[cur]:
            continue
        closed[cur] = True
        j = first[cur]
        while j >= 0:
            group = entry_group[j]
            if best[group] == np.inf:
                found += 1
            best[group] = min(best[group], g[cur])
            j = also[j]
        if todo.size:  # on blocks: the neighbours (the diagonals' sides among them) worked out first
            for k in range(8):
                if todo[cur + offsets[k]]:
                    _fill_tile(cur + offsets[k], open_padded, cost_padded, pending, src)
        used, pushed, n_touched = relax_neighbours(
            cur, g, closed, open_ok, cost, steps, (head, node, link), mask, used, touched, n_touched
        )
        live += pushed
    return best, live == 0


def group_path_costs(
    costmap: Costmap,
    start: tuple[int, int],
    member_cells: NDArray[np.int64],
    member_groups: NDArray[np.int64],
    n_groups: int,
    reach: int,
    robot_radius: float,
    want: int | None = None,
) -> tuple[NDArray[np.float64], bool]:
    """Planner path cost (m) from ``start`` (row, col) to each of ``n_groups`` groups of cells:
    the least cost of any cell within ``reach`` cells (a square window) of a member of the group
    (``member_cells``, flat indices into the map, ``member_groups`` their groups); inf for a group
    not reached. With ``want``, the search stops once the ``want`` cheapest groups are known, so
    its work grows with their distance, not with the map. On a map of more than
    :data:`MAX_SEARCH_CELLS` cells the search runs on blocks (:func:`block_factor`, for a robot of
    ``robot_radius`` m, the costmap's). The flag is True when the search covered all it could
    reach: the groups still at inf have no path."""
    grid = costmap.grid
    if not grid.in_bounds(*start) or n_groups == 0:
        return np.full(n_groups, np.inf), True
    cells = np.ascontiguousarray(member_cells, np.int64).reshape(-1)
    groups = np.ascontiguousarray(member_groups, np.int64).reshape(-1)
    f = block_factor(grid.shape, grid.resolution, robot_radius)
    src: BlockSource = (
        costmap.open_padded,
        costmap.clearance_padded,
        grid.data,
        costmap.inflation_table,
        costmap.inflation_radius,
        costmap.unknown_cost,
        f,
    )
    if f == 1:
        open_p, cost_p, pending = costmap.open_padded, costmap.cost_padded, np.zeros((0, 0), np.bool_)
        source, max_cost = start[0] * grid.width + start[1], float(cost_p.max())
    else:  # blocks, each worked out when a search on this costmap first touches it
        if f not in costmap.block_grids:
            costmap.block_grids[f] = BlockGrid.empty(grid.shape, f)
        blocks = costmap.block_grids[f]
        open_p, cost_p, pending = blocks.open_padded, blocks.cost_padded, blocks.pending
        bcols = open_p.shape[1] - 2
        rows, cols = np.divmod(cells, grid.width)
        cells = (rows // f) * bcols + cols // f  # repeats are dropped by the search's entry lists
        source = (start[0] // f) * bcols + start[1] // f
        reach = math.ceil(reach / f)
        max_cost = 1.0 + float(costmap.inflation_table.max()) + costmap.unknown_cost  # bounds every block's factor
    wanted = n_groups if want is None else min(int(want), n_groups)  # more than there are: all of them
    best, exhausted = _group_costs(
        open_p, cost_p, pending, src, int(source), (cells, groups), int(reach), int(n_groups), wanted, max_cost
    )
    return best * (f * grid.resolution), bool(exhausted)
