"""Planner path costs between many cells at once: one Dijkstra per source on a bucket queue.

The costs are the global planner's (:mod:`frontier_rl.core.navigation.costmap`): a step costs its length
(1 or √2 cells) times the cost factor of the cell it enters, and a diagonal step may not cut a
corner. Every step costs at least 1, so a bucket queue of width 1 (Dial's algorithm) settles the
cells in an exact order, and a search stops as soon as every target it needs is settled. This is
what the ``oracle``'s tour planning runs thousands of times per episode.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numba as nb
import numpy as np
from numpy.typing import NDArray

from frontier_rl.core.navigation.bucket_queue import bucket_ring_mask, neighbour_steps, relax_neighbours

if TYPE_CHECKING:  # the planner's Costmap.cost_to_go runs on this module: no import cycle at run time
    from frontier_rl.core.navigation.costmap import Costmap


@nb.njit(cache=True)
def _path_costs(
    open_padded: NDArray[np.bool_],
    cost_padded: NDArray[np.float64],
    sources: NDArray[np.int64],
    targets: NDArray[np.int64],
    upper: bool,
    keep: bool,
    max_cost: float,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Planner path costs (cells) from each of ``sources`` to each of ``targets`` (unpadded row,
    col), with the planner's step costs (length × cost factor of the cell entered, no corner
    cutting); inf where there is no path or it costs more than ``max_cost``. With ``upper``
    (sources = targets), source i only searches for targets j >= i and fills (i, j) and (j, i):
    a symmetric matrix. With ``keep``, the last search's costs (unpadded) are returned too, else
    that field is empty; without targets, a search covers all it can reach within ``max_cost``.

    One Dijkstra per source, stopped once every target it needs is settled, on a bucket queue of
    width 1: every step costs at least 1 (length >= 1, factor >= 1), so a cell's predecessor on
    its shortest path lies in an earlier bucket and the buckets' order alone makes it exact. So
    is every kept cost at most the last target's: cells cut off later hold upper bounds."""
    pcols = open_padded.shape[1]
    size_all = open_padded.size
    open_ok = open_padded.reshape(-1)
    cost = cost_padded.reshape(-1)
    steps = neighbour_steps(pcols)
    ns, nt = sources.shape[0], targets.shape[0]
    first = np.full(size_all, -1, np.int64)  # per cell, its first target; more in ``also``
    also = np.full(nt, -1, np.int64)
    for j in range(nt - 1, -1, -1):
        cell = (targets[j, 0] + 1) * pcols + targets[j, 1] + 1
        also[j] = first[cell]
        first[cell] = j
    mask = bucket_ring_mask(cost.max())
    head = np.full(mask + 1, -1, np.int64)
    node = np.empty(8 * size_all + 1, np.int64)  # entry pool: one entry per improvement
    link = np.empty(8 * size_all + 1, np.int64)
    g = np.full(size_all, np.inf)
    closed = np.zeros(size_all, np.bool_)
    touched = np.empty(size_all, np.int64)
    dist = np.full((ns, nt), np.inf)
    field = np.zeros((0, 0))
    for s in range(ns):
        source = (sources[s, 0] + 1) * pcols + sources[s, 1] + 1
        low = s if upper else 0
        left = nt - low
        head[:] = -1
        g[source] = 0.0
        touched[0] = source
        n_touched = 1
        node[0], link[0] = source, -1
        head[0] = 0
        used = 1
        live = 1
        bucket = 0
        while live > 0 and (left > 0 or nt == 0) and bucket <= max_cost:
            slot = bucket & mask
            entry = head[slot]
            if entry < 0:
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
                if j >= low:
                    dist[s, j] = g[cur]
                    if upper:
                        dist[j, s] = g[cur]
                    left -= 1
                j = also[j]
            used, pushed, n_touched = relax_neighbours(
                cur, g, closed, open_ok, cost, steps, (head, node, link), mask, used, touched, n_touched
            )
            live += pushed
        if keep and s == ns - 1:
            field = g.reshape(open_padded.shape)[1:-1, 1:-1].copy()
        for k in range(n_touched):
            g[touched[k]] = np.inf
            closed[touched[k]] = False
    return dist, field


@nb.njit(cache=True)
def _descend(field: NDArray[np.float64], row: int, col: int) -> NDArray[np.int64]:
    """The path (n, 2 cells) from (row, col) down ``field`` (a cost-to-go) to its zero: each step
    to the 8-neighbour of least cost, diagonals not cutting a corner. Empty if the start is not on
    the field."""
    rows, cols = field.shape
    if not (0 <= row < rows and 0 <= col < cols) or not math.isfinite(field[row, col]):
        return np.zeros((0, 2), np.int64)
    path = [(row, col)]
    while field[row, col] > 0.0:
        best_r, best_c, best = row, col, field[row, col]
        for dr in range(-1, 2):
            for dc in range(-1, 2):
                r, c = row + dr, col + dc
                if not (0 <= r < rows and 0 <= c < cols) or field[r, c] >= best:
                    continue
                if dr != 0 and dc != 0 and not (math.isfinite(field[row, c]) and math.isfinite(field[r, col])):
                    continue
                best_r, best_c, best = r, c, field[r, c]
        if best_r == row and best_c == col:
            break  # a local minimum cannot happen on a cost-to-go; a guard all the same
        row, col = best_r, best_c
        path.append((row, col))
    out = np.empty((len(path), 2), np.int64)
    for i, (r, c) in enumerate(path):
        out[i, 0], out[i, 1] = r, c
    return out


def path_costs(
    costmap: Costmap, cells: NDArray[np.int64], to: NDArray[np.int64] | None = None, max_m: float = math.inf
) -> NDArray[np.float64]:
    """Planner path costs (m) on ``costmap`` from each of ``cells`` to each of ``to`` (row, col;
    inf where there is no path, or none within ``max_m``). Without ``to``, the symmetric matrix
    between ``cells``, each pair's from the earlier cell to the later (a step costs by the cell
    it enters, so the two directions differ a little)."""
    cells = np.ascontiguousarray(cells, np.int64).reshape(-1, 2)
    targets = cells if to is None else np.ascontiguousarray(to, np.int64).reshape(-1, 2)
    limit = max_m / costmap.grid.resolution
    dist, _ = _path_costs(costmap.open_padded, costmap.cost_padded, cells, targets, to is None, False, limit)
    return dist * costmap.grid.resolution


def cost_to_go_padded(
    open_padded: NDArray[np.bool_],
    cost_padded: NDArray[np.float64],
    cell: tuple[int, int],
    until: tuple[int, int] | None = None,
) -> NDArray[np.float64]:
    """Path cost (cells, weighted by the cell costs) from ``cell`` (unpadded row, col) to every
    cell of a padded open mask and cost grid; inf where there is no path. With ``until``, the
    search stops once that cell is settled: exact up to its cost, inf or too high beyond."""
    one = np.array([cell], np.int64)
    targets = np.zeros((0, 2), np.int64) if until is None else np.array([until], np.int64)
    return _path_costs(open_padded, cost_padded, one, targets, False, True, math.inf)[1]


def cost_field(costmap: Costmap, cell: tuple[int, int], until: tuple[int, int] | None = None) -> NDArray[np.float64]:
    """Planner path cost (m) from ``cell`` (row, col) to every cell on ``costmap``; inf where there
    is no path (:meth:`Costmap.cost_to_go`). With ``until``, the search stops once that cell is
    reached: exact up to its cost, inf or too high beyond."""
    return cost_to_go_padded(costmap.open_padded, costmap.cost_padded, cell, until) * costmap.grid.resolution


def descend(field: NDArray[np.float64], cell: tuple[int, int]) -> NDArray[np.int64]:
    """The shortest path (n, 2 cells) from ``cell`` (row, col) to the source of ``field`` (from
    :func:`cost_field`); empty if ``cell`` has no path there."""
    return _descend(field, int(cell[0]), int(cell[1]))
