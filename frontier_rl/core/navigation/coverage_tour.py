"""A full-knowledge coverage tour: viewpoints whose scans cover the true map, in a short order.

The planner of the ``oracle`` reference method (:class:`~frontier_rl.policies.oracle.OracleTour`).
On the ground truth it

1. takes *candidate viewpoints*: cells the robot can stand on and reach from the start, one per
   ``spacing_m`` × ``spacing_m`` block of the grid (the reachable cell nearest the block centre);
2. computes each candidate's *visibility*: the target cells (:func:`coverage_targets`: the
   explorable cells and the walls around them) that a noise-free 360° scan, cropped at the
   mapping range, would mark, with beams that stop where they only graze a corner
   (:func:`visibility`, a compiled kernel);
3. builds a *cover as a route*, greedily (the start's scan is free): the candidate with the most
   unseen cells per metre of path it adds is inserted where it adds least, until none adds
   ``min_gain_cells`` (:func:`insertion_cover`); path costs are the robot's planner costs on the
   true costmap, by Dijkstra on a bucket queue (:func:`path_costs`);
4. shortens the open route from the start with 2-opt (:func:`two_opt`) and gives each viewpoint
   the cells it adds to the ones before it (its *targets*).

Ranking candidates by gain per metre rather than by gain alone (a plain greedy set cover, then a
nearest-neighbour + 2-opt tour) gave 12 % shorter oracle exploration times on office seeds 0-9
(356 s against 405 s): a set cover puts its viewpoints in the middle of rooms, and the tour then
has to walk into each one.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numba as nb
import numpy as np
from numpy.typing import NDArray

from frontier_rl.core.mapping.mapper import MapperConfig
from frontier_rl.core.navigation.config import NavigationConfig
from frontier_rl.core.navigation.costmap import Costmap
from frontier_rl.core.navigation.path_costs import cost_field, path_costs
from frontier_rl.core.sensing.lidar import LidarConfig
from frontier_rl.core.world.grid import CellState
from frontier_rl.core.world.raycast import FASTMATH, pad_blocked, ray_start
from frontier_rl.core.world.robot import RobotConfig
from frontier_rl.core.world.worlds import World, dilate

_SQRT2 = math.sqrt(2.0)
_FAR = 1e9  # path cost (m) standing in for pairs never searched


@dataclass(frozen=True, eq=False)
class CoverageTour:
    """An ordered coverage tour on a world's grid.

    Attributes:
        viewpoints: (n, 2) viewpoint positions (m, cell centres), in visiting order (the start is
            not one of them: its scan is taken before the first decision).
        cells: (n, 2) the viewpoints' cells (row, col) in the world grid.
        targets: per viewpoint, the (k, 2) world cells (row, col; :func:`coverage_targets`) it is
            meant to reveal: those it sees that neither the start nor an earlier viewpoint sees.
        length_m: planner path cost (m) of the tour from the start.
        coverable: the target cells (:func:`coverage_targets`) some candidate viewpoint sees.
        covered: the target cells the start and the tour's viewpoints see.
    """

    viewpoints: NDArray[np.float64]
    cells: NDArray[np.int64]
    targets: tuple[NDArray[np.int64], ...]
    length_m: float
    coverable: NDArray[np.bool_]
    covered: NDArray[np.bool_]

    def __len__(self) -> int:
        return int(self.viewpoints.shape[0])


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


def _open_tour_length(order: NDArray[np.int64], dist: NDArray[np.float64]) -> float:
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


def insertion_cover(
    costmap: Costmap,
    cand: NDArray[np.int64],
    csr: tuple[NDArray[np.int64], NDArray[np.int32]],
    min_gain: int,
    detour_m: float,
    reach_m: float = math.inf,
) -> tuple[list[int], NDArray[np.float64]]:
    """A cover built as a route: from candidate 0 (the start), repeatedly insert, at its cheapest
    place, the candidate with the most unseen cells per metre the insertion adds (plus
    ``detour_m``), until none adds ``min_gain`` cells. ``csr`` is :func:`visibility` of ``cand``
    on ``costmap``'s grid. Path costs are only searched ``reach_m`` far from each node (on a large
    map a route grows by its neighbourhood), and everywhere once nothing near is left. Returns the
    route (candidate indices) and the symmetric matrix (m) of path costs between its nodes (pairs
    farther apart than searched: a huge cost)."""
    indptr, indices = csr
    covered = np.zeros(costmap.grid.data.size, np.bool_)
    covered[indices[indptr[0] : indptr[1]]] = True
    bound = np.diff(indptr).astype(np.float64)  # upper bounds of the gains: they only shrink
    bound[0] = -1.0
    route = [0]
    rows = [path_costs(costmap, cand[:1], cand, max_m=reach_m)[0]]  # from each route node to every candidate
    while True:
        insert, place = _cheapest_insertion(np.array(rows), route)
        denom = np.maximum(insert, 0.0) + detour_m
        # a candidate no route node has a known path to yet cannot be placed: it waits for the wider search
        reachable = np.isfinite(insert)
        score = np.where((bound >= min_gain) & reachable, bound / denom, -np.inf)
        while True:
            c = int(np.argmax(score))
            if not np.isfinite(score[c]):
                break
            vis = indices[indptr[c] : indptr[c + 1]]
            bound[c] = np.count_nonzero(~covered[vis])
            score[c] = bound[c] / denom[c] if bound[c] >= min_gain and reachable[c] else -np.inf
            if int(np.argmax(score)) == c:
                break
        if not np.isfinite(score[c]):
            if reach_m < math.inf and np.any((bound >= min_gain) & ~np.isfinite(insert)):
                reach_m = math.inf  # cells are left that only far candidates see: search everywhere
                rows = [path_costs(costmap, cand[k : k + 1], cand)[0] for k in route]
                continue
            break
        covered[indices[indptr[c] : indptr[c + 1]]] = True
        bound[c] = -1.0
        route.insert(int(place[c]), c)
        rows.insert(int(place[c]), path_costs(costmap, cand[c : c + 1], cand, max_m=reach_m)[0])
    there = np.array(rows)[:, route]
    back = there.T
    dist = np.where(np.isfinite(there) & np.isfinite(back), 0.5 * (there + back), np.fmin(there, back))
    return route, np.where(np.isfinite(dist), dist, _FAR)


def _cheapest_insertion(costs: NDArray[np.float64], route: list[int]) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """Per candidate, the least path cost (m) its insertion into ``route`` adds, and where it goes
    (the index in the route); ``costs`` holds a row of path costs from each route node."""
    n = costs.shape[1]
    insert = costs[-1].copy()  # after the last node
    place = np.full(n, len(route))
    if len(route) > 1:
        edges = costs[np.arange(len(route) - 1), route[1:]]
        with np.errstate(invalid="ignore"):  # inf - inf where an edge was never searched
            between = costs[:-1] + costs[1:] - edges[:, None]
        between[~np.isfinite(edges)] = np.inf  # no detour is known for an edge of unknown length
        best_between = between.argmin(axis=0)
        better = between[best_between, np.arange(n)] < insert
        insert[better] = between[best_between, np.arange(n)][better]
        place[better] = best_between[better] + 1
    return insert, place


def _drop_weak_viewpoints(
    order: NDArray[np.int64],
    route: list[int],
    csr: tuple[NDArray[np.int64], NDArray[np.int32]],
    dist: NDArray[np.float64],
    min_gain: int,
    n_cells: int,
) -> tuple[NDArray[np.int64], list[NDArray[np.int32]], NDArray[np.bool_]]:
    """What each viewpoint adds to the start and the ones before it on the tour ``order``;
    re-ordering can leave one adding too little: it is dropped and the rest re-ordered. Returns
    the order kept, each viewpoint's new cells (flat indices) and every cell seen."""
    indptr, indices = csr
    while True:
        seen = np.zeros(n_cells, np.bool_)
        targets: list[NDArray[np.int32]] = []
        keep = []
        for pos, k in enumerate(order.tolist()):
            vis = indices[indptr[route[k]] : indptr[route[k] + 1]]
            new = vis[~seen[vis]]
            seen[vis] = True
            if pos == 0 or new.size >= min_gain:
                keep.append(pos)
                targets.append(new)
        if len(keep) == order.size:
            return order, targets, seen
        order = order[keep]
        order = order[two_opt(np.arange(order.size, dtype=np.int64), dist[np.ix_(order, order)])]


def plan_coverage_tour(
    world: World,
    robot: RobotConfig | None = None,
    navigation: NavigationConfig | None = None,
    lidar: LidarConfig | None = None,
    usable_range_m: float | None = None,
    spacing_m: float = 0.5,
    min_gain_cells: int = 10,
    detour_m: float = 3.0,
    margin_cells: float = 1.0,
    graze_cells: int = 3,
    reach_m: float = 15.0,
) -> CoverageTour:
    """The coverage tour of ``world`` from its start (see the module docstring).

    Args:
        world: the ground truth.
        robot, navigation: the robot and the planner of the episode (their defaults if None).
        lidar: its LiDAR; usable_range_m: the mapper's usable range (m; both the defaults if None).
        spacing_m: edge of the blocks that each give one candidate viewpoint (m).
        min_gain_cells: a viewpoint must add at least this many unseen target cells.
        detour_m: added to each insertion's cost in the cover (m), see :func:`insertion_cover`.
        margin_cells, graze_cells: the beams' corner-grazing rule (see :func:`visibility`).
        reach_m: path costs are searched this far around each viewpoint (m), see
            :func:`insertion_cover`.
    """
    lidar = lidar or LidarConfig()
    usable_range_m = MapperConfig().usable_range if usable_range_m is None else usable_range_m
    grid = world.grid
    costmap = Costmap.build(grid, robot or RobotConfig(), navigation or NavigationConfig())
    start = grid.world_to_cell(world.start.x, world.start.y)
    reachable = np.isfinite(cost_field(costmap, start)) & costmap.traversable
    spacing = max(int(round(spacing_m / grid.resolution)), 1)
    cand = np.concatenate((np.array([start], np.int64), candidate_cells(reachable, spacing)))
    indptr, indices = visibility(world, lidar, usable_range_m, cand, None, margin_cells, graze_cells)
    min_gain = max(int(min_gain_cells), 1)
    route, dist = insertion_cover(costmap, cand, (indptr, indices), min_gain, detour_m, reach_m)
    order = two_opt(np.arange(len(route), dtype=np.int64), dist)
    order, targets, seen = _drop_weak_viewpoints(order, route, (indptr, indices), dist, min_gain, grid.data.size)
    tour_cells = cand[np.array(route)[order[1:]]]
    coverable = np.zeros(grid.data.size, np.bool_)
    coverable[indices] = True
    return CoverageTour(
        viewpoints=grid.cells_to_world(tour_cells).reshape(-1, 2),
        cells=tour_cells,
        targets=tuple(np.column_stack(divmod(t, grid.shape[1])).astype(np.int64) for t in targets[1:]),
        length_m=_open_tour_length(order, dist),
        coverable=coverable.reshape(grid.shape),
        covered=seen.reshape(grid.shape),
    )
