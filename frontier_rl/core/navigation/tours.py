"""Tours over stops on the planner's path costs. Exact over a few stops: the shortest open path
from the robot through every stop (Held-Karp), and for each stop the shortest such path that visits
it first; what ``tour`` ranks frontiers by (:mod:`frontier_rl.policies.tour`) and model 7's table
column (:mod:`frontier_rl.observation.frontier_table`) are built on these. Heuristic over many:
2-opt on an open path (:func:`two_opt`), which orders the coverage tour's viewpoints
(:mod:`frontier_rl.core.navigation.coverage_tour`).
"""

from __future__ import annotations

import numba as nb
import numpy as np
from numpy.typing import NDArray

from frontier_rl.core.navigation.costmap import Costmap
from frontier_rl.core.navigation.group_costs import block_factor, group_path_costs
from frontier_rl.core.navigation.path_costs import path_costs

UNREACHABLE_M = 1.0e6
"""Path cost (m) standing in for no path between two stops, so that a tour always exists."""


@nb.njit(cache=True)
def _paths_through_all(
    dist: NDArray[np.float64], start: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """Held-Karp over nodes 1..n of ``dist`` ((n + 1, n + 1)): ``best[mask, j]``, the shortest path
    that begins at node k + 1 at a cost of ``start[k]``, visits the nodes of ``mask`` and ends at
    node j + 1, and ``came``, the node before j on it (-1 at the beginning). O(2ⁿ·n²)."""
    n = dist.shape[0] - 1
    full = 1 << n
    best = np.full((full, n), np.inf)
    came = np.full((full, n), -1, np.int64)
    for j in range(n):
        best[1 << j, j] = start[j]
    for mask in range(1, full):
        for j in range(n):
            here = best[mask, j]
            if not (mask >> j) & 1 or here == np.inf:
                continue
            for k in range(n):
                if (mask >> k) & 1:
                    continue
                nxt = mask | (1 << k)
                cost = here + dist[j + 1, k + 1]
                if cost < best[nxt, k]:
                    best[nxt, k] = cost
                    came[nxt, k] = j
    return best, came


@nb.njit(cache=True)
def open_tour(dist: NDArray[np.float64]) -> NDArray[np.int64]:
    """The shortest path from node 0 through every other node of ``dist`` ((n + 1, n + 1), n ≤ 16),
    ending anywhere: the stops after node 0 (0-based among them), in order."""
    n = dist.shape[0] - 1
    best, came = _paths_through_all(dist, dist[0, 1:].copy())
    mask = (1 << n) - 1
    last = int(np.argmin(best[mask]))
    order = np.empty(n, np.int64)
    for i in range(n - 1, -1, -1):
        order[i] = last
        previous = came[mask, last]
        mask ^= 1 << last
        last = previous
    return order


def first_stop_costs(dist: NDArray[np.float64]) -> NDArray[np.float64]:
    """For each stop k (node k + 1 of a symmetric ``dist``, n ≤ 16), the length of the shortest
    path from node 0 through every other node that visits k first: ``dist[0, k + 1]`` plus the
    shortest path from k through the rest (by symmetry, the shortest one through all that ends at k)."""
    n = dist.shape[0] - 1
    best, _ = _paths_through_all(dist, np.zeros(n))
    return np.asarray(dist[0, 1:] + best[(1 << n) - 1], np.float64)


def costs_to_stops(
    costmap: Costmap, start: tuple[int, int], goals: NDArray[np.int64], robot_radius: float, want: int
) -> NDArray[np.float64]:
    """Planner path costs (m) from ``start`` (the robot's cell; from where it sets out when it stands
    too close to a wall, :meth:`~frontier_rl.core.navigation.costmap.Costmap.set_out`) to each of
    ``goals`` (row, col cells): exact on a map searched cell by cell; on a map searched on blocks
    (:func:`block_factor` > 1, for a robot of ``robot_radius`` m), block estimates for the ``want``
    cheapest and inf for the rest, so that the work is bounded by their distance, not by the map."""
    grid = costmap.grid
    goals = np.asarray(goals, np.int64).reshape(-1, 2)
    if block_factor(grid.shape, grid.resolution, robot_radius) == 1:
        return costmap.costs_from(
            start, lambda cell: (path_costs(costmap, np.array([cell], np.int64), goals)[0], True)
        )[0]
    flat = goals[:, 0] * grid.width + goals[:, 1]
    return costmap.costs_from(
        start,
        lambda cell: group_path_costs(costmap, cell, flat, np.arange(len(goals)), len(goals), 0, robot_radius, want),
    )[0]


def stop_costs(
    costmap: Costmap,
    start: tuple[int, int],
    goals: NDArray[np.int64],
    robot_radius: float,
    from_start: NDArray[np.float64] | None = None,
) -> NDArray[np.float64]:
    """Planner path costs (m) between ``start`` and the ``goals`` (row, col cells), as the
    symmetric (n + 1, n + 1) matrix the tours above take: ``start`` is node 0, and a pair with no
    path costs :data:`UNREACHABLE_M`. ``from_start``, the costs from ``start`` to the goals when
    the caller has them (:func:`costs_to_stops`), saves that search. Exact on a map searched cell
    by cell; on blocks (as :func:`costs_to_stops`), one block search per goal to the goals after it."""
    goals = np.asarray(goals, np.int64).reshape(-1, 2)
    n, grid = len(goals), costmap.grid
    dist = np.zeros((n + 1, n + 1))
    dist[0, 1:] = costs_to_stops(costmap, start, goals, robot_radius, n) if from_start is None else from_start
    if block_factor(grid.shape, grid.resolution, robot_radius) == 1:
        dist[1:, 1:] = path_costs(costmap, goals)  # symmetric: each pair's from the earlier goal
    else:
        flat = goals[:, 0] * grid.width + goals[:, 1]
        for i in range(n - 1):
            later = n - 1 - i
            source = (int(goals[i, 0]), int(goals[i, 1]))
            dist[i + 1, i + 2 :] = group_path_costs(
                costmap, source, flat[i + 1 :], np.arange(later), later, 0, robot_radius
            )[0]
        dist[1:, 1:] += dist[1:, 1:].T
    dist[1:, 0] = dist[0, 1:]
    dist[~np.isfinite(dist)] = UNREACHABLE_M
    return dist


def open_path_length(order: NDArray[np.int64], dist: NDArray[np.float64]) -> float:
    """Length of the open path visiting ``order`` (node 0 first)."""
    return float(dist[order[:-1], order[1:]].sum())


@nb.njit(cache=True)
def two_opt(order: NDArray[np.int64], dist: NDArray[np.float64]) -> NDArray[np.int64]:
    """2-opt on an open path with fixed first node and free end (``dist`` symmetric): reverse
    ``order[i:j + 1]`` while that shortens the path (first improvement, until none does)."""
    tour = order.copy()
    n = tour.shape[0]
    improved = True
    while improved:
        improved = False
        for i in range(1, n - 1):
            for j in range(i + 1, n):
                a, b, c = tour[i - 1], tour[i], tour[j]
                old = dist[a, b]
                new = dist[a, c]
                if j + 1 < n:
                    e = tour[j + 1]
                    old += dist[c, e]
                    new += dist[b, e]
                if new < old - 1e-9:
                    tour[i : j + 1] = tour[i : j + 1][::-1].copy()
                    improved = True
    return tour
