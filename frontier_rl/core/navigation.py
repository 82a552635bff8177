"""move_base-like navigation: inflated costmap, A* global planner, path follower, path checks.

The planner runs on the robot's current map with unknown cells passable at an extra cost (as
move_base's ``allow_unknown``); the follower drives a differential-drive robot along the path under
its speed limits, turning in place when the heading error is large, so turning costs time.
"""

from __future__ import annotations

import heapq
import math
from dataclasses import dataclass

import numba as nb
import numpy as np
from numpy.typing import NDArray
from scipy import ndimage

from frontier_rl.core.distance import chamfer_distance, flood_fill
from frontier_rl.core.grid import CellState, OccupancyGrid
from frontier_rl.core.raycast import FASTMATH
from frontier_rl.core.robot import RobotConfig
from frontier_rl.errors import ConfigError

_SQRT2 = math.sqrt(2.0)
_OCCUPIED = np.int8(CellState.OCCUPIED)
_UNKNOWN = np.int8(CellState.UNKNOWN)
_STEPS = np.array(
    [(-1, 0, 1.0), (1, 0, 1.0), (0, -1, 1.0), (0, 1, 1.0), (-1, -1, _SQRT2), (-1, 1, _SQRT2), (1, -1, _SQRT2),
     (1, 1, _SQRT2)],
    dtype=np.float64,
)  # fmt: skip


@dataclass(frozen=True)
class NavigationConfig:
    """Costmap, planner and controller settings (TurtleBot3 / move_base / explore_lite flavoured).

    Attributes:
        inflation_radius: distance from obstacles (m) over which the extra cost decays.
        cost_scaling: exponential decay rate of the inflation cost (1/m).
        inflation_cost: extra cost factor of a cell at the robot radius from an obstacle.
        unknown_cost: extra cost factor of an unknown cell (unknown is passable).
        goal_tolerance: distance to the goal (m) at which it counts as reached.
        lookahead: distance (m) of the path point the controller steers toward.
        heading_gain: angular speed per rad of heading error (1/s) while driving.
        control_dt: integration step of the robot motion (s).
        progress_timeout: a goal without progress for this long (s) is aborted and blacklisted.
        progress_distance: the remaining path must shrink by this much (m) to count as progress.
        max_recoveries: in-place rotations tried when stuck before the goal is aborted.
        blacklist_radius: frontiers whose centre lies this close (m) to a blacklisted goal are ignored.
        frontier_check_period: how often (s) the goal's frontier is checked for being explored.
    """

    inflation_radius: float = 0.55
    cost_scaling: float = 5.0
    inflation_cost: float = 3.0
    unknown_cost: float = 1.0
    goal_tolerance: float = 0.15
    lookahead: float = 0.3
    heading_gain: float = 3.0
    control_dt: float = 0.05
    progress_timeout: float = 30.0
    progress_distance: float = 0.1
    max_recoveries: int = 2
    blacklist_radius: float = 0.25
    frontier_check_period: float = 1.0

    def __post_init__(self) -> None:
        for name in ("inflation_radius", "goal_tolerance", "lookahead", "control_dt", "progress_timeout"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0):
                raise ConfigError(f"NavigationConfig.{name} must be positive, got {value!r}")
        if self.max_recoveries < 0:
            raise ConfigError(f"NavigationConfig.max_recoveries must be >= 0, got {self.max_recoveries!r}")


def obstacle_distance(occupied: NDArray[np.bool_], resolution: float) -> NDArray[np.float64]:
    """Distance (m) from each cell centre to the nearest occupied cell centre (``inf`` if none)."""
    if not occupied.any():
        return np.full(occupied.shape, np.inf)
    return np.asarray(ndimage.distance_transform_edt(~occupied), dtype=np.float64) * resolution


@dataclass(frozen=True)
class Costmap:
    """Planning costs on one map.

    Attributes:
        grid: the map.
        traversable: cells the robot centre may occupy (not within the robot radius of a wall).
        penalty: extra cost factor per cell (inflation + unknown), >= 0.
        clearance: distance (m) from each cell centre to the nearest occupied cell centre, by a
            chamfer transform (exact or up to 8 % over), capped just above the inflation radius.
    """

    grid: OccupancyGrid
    traversable: NDArray[np.bool_]
    penalty: NDArray[np.float64]
    clearance: NDArray[np.float64]

    @classmethod
    def build(cls, grid: OccupancyGrid, robot: RobotConfig, config: NavigationConfig) -> Costmap:
        """Inflate the obstacles of ``grid`` for a robot of ``robot.radius``."""
        res = grid.resolution
        clearance, traversable, penalty = _inflate(
            grid.data,
            (robot.radius + 0.5 * res) / res,  # lethal below: cell centre to wall surface, in cells
            config.inflation_radius / res,
            config.cost_scaling * res,
            config.inflation_cost,
            config.unknown_cost,
        )
        clearance *= res
        return cls(grid, traversable, penalty, clearance)

    def reachable_known(self, start: tuple[int, int]) -> NDArray[np.bool_]:
        """Known-free traversable cells connected (8-way) to ``start`` (row, col)."""
        mask = self.traversable & (self.grid.data == CellState.FREE)
        out = np.zeros_like(mask)
        r, c = start
        if not self.grid.in_bounds(r, c):
            return out
        if not mask[r, c]:
            nearest = nearest_cell(mask, start, max_radius=int(round(0.5 / self.grid.resolution)))
            if nearest is None:
                return out
            r, c = nearest
        return flood_fill(mask, r, c)

    def plan(self, start: tuple[int, int], goal: tuple[int, int], escape_radius: float = 0.25) -> NDArray[np.int64]:
        """A* path (cells, (n, 2) rows and columns) from ``start`` to ``goal``; empty if none.

        Cells within ``escape_radius`` (m) of the start may be crossed even if inflated (not if
        occupied), so that a robot that ended up too close to a wall can still leave.
        """
        escape = int(math.ceil(escape_radius / self.grid.resolution))
        passable = self.traversable.copy()
        r0, c0 = max(start[0] - escape, 0), max(start[1] - escape, 0)
        window = passable[r0 : start[0] + escape + 1, c0 : start[1] + escape + 1]
        rows, cols = np.ogrid[r0 : r0 + window.shape[0], c0 : c0 + window.shape[1]]
        near = (rows - start[0]) ** 2 + (cols - start[1]) ** 2 <= escape * escape
        occupied = self.grid.data[r0 : r0 + window.shape[0], c0 : c0 + window.shape[1]] == CellState.OCCUPIED
        window |= near & ~occupied
        if not (self.grid.in_bounds(*goal) and passable[goal]):
            return np.zeros((0, 2), np.int64)
        return astar(passable, self.penalty, start[0], start[1], goal[0], goal[1])


@nb.njit(cache=True)
def _inflate(
    state: NDArray[np.int8],
    lethal_below: float,
    inflation_radius: float,
    cost_scaling: float,
    inflation_cost: float,
    unknown_cost: float,
) -> tuple[NDArray[np.float64], NDArray[np.bool_], NDArray[np.float64]]:
    """Clearance (cells), traversable mask and penalty of a map; lengths in cells, scaling per cell."""
    rows, cols = state.shape
    occupied = np.empty((rows, cols), np.bool_)
    for r in range(rows):
        for c in range(cols):
            occupied[r, c] = state[r, c] == _OCCUPIED
    clearance = chamfer_distance(occupied, inflation_radius + 1.0)
    traversable = np.empty((rows, cols), np.bool_)
    penalty = np.zeros((rows, cols))
    for r in range(rows):
        for c in range(cols):
            d = clearance[r, c]
            traversable[r, c] = d >= lethal_below
            if d < inflation_radius:
                penalty[r, c] = inflation_cost * math.exp(-cost_scaling * max(d - lethal_below, 0.0))
            if state[r, c] == _UNKNOWN:
                penalty[r, c] += unknown_cost
    return clearance, traversable, penalty


def nearest_cell(mask: NDArray[np.bool_], target: tuple[int, int], max_radius: int) -> tuple[int, int] | None:
    """The True cell of ``mask`` nearest to ``target`` (row, col), searched in growing windows
    up to ``max_radius`` cells; None if there is none that close."""
    r, c = target
    radius = 2
    while True:
        r0, c0 = max(r - radius, 0), max(c - radius, 0)
        window = mask[r0 : r + radius + 1, c0 : c + radius + 1]
        hits = np.argwhere(window)
        if hits.size:
            d2 = (hits[:, 0] + r0 - r) ** 2 + (hits[:, 1] + c0 - c) ** 2
            best = int(np.argmin(d2))
            if d2[best] <= radius * radius or radius >= max_radius:
                return int(hits[best, 0] + r0), int(hits[best, 1] + c0)
        if radius >= max_radius:
            return None
        radius = min(radius * 2, max_radius)


@nb.njit(cache=True)
def astar(
    passable: NDArray[np.bool_],
    penalty: NDArray[np.float64],
    start_r: int,
    start_c: int,
    goal_r: int,
    goal_c: int,
) -> NDArray[np.int64]:
    """8-connected A* with octile heuristic; a step costs its length × (1 + penalty of the cell
    entered); diagonal steps may not cut a corner. Returns the (n, 2) cell path, empty if none."""
    rows, cols = passable.shape
    n = rows * cols
    g = np.full(n, np.inf)
    parent = np.full(n, -1, np.int64)
    closed = np.zeros(n, np.bool_)
    start = start_r * cols + start_c
    goal = goal_r * cols + goal_c
    g[start] = 0.0
    heap = [(0.0, start)]
    while heap:
        _, cur = heapq.heappop(heap)
        if closed[cur]:
            continue
        closed[cur] = True
        if cur == goal:
            break
        r = cur // cols
        c = cur % cols
        for k in range(8):
            dr = int(_STEPS[k, 0])
            dc = int(_STEPS[k, 1])
            rr = r + dr
            cc = c + dc
            if rr < 0 or rr >= rows or cc < 0 or cc >= cols or not passable[rr, cc]:
                continue
            if dr != 0 and dc != 0 and not (passable[r, cc] and passable[rr, c]):
                continue
            nxt = rr * cols + cc
            if closed[nxt]:
                continue
            cost = g[cur] + _STEPS[k, 2] * (1.0 + penalty[rr, cc])
            if cost < g[nxt]:
                g[nxt] = cost
                parent[nxt] = cur
                ddr = abs(rr - goal_r)
                ddc = abs(cc - goal_c)
                h = (_SQRT2 - 1.0) * min(ddr, ddc) + max(ddr, ddc)
                heapq.heappush(heap, (cost + h, nxt))
    if not closed[goal]:
        return np.zeros((0, 2), np.int64)
    length = 1
    cur = goal
    while cur != start:
        cur = parent[cur]
        length += 1
    path = np.empty((length, 2), np.int64)
    cur = goal
    for i in range(length - 1, -1, -1):
        path[i, 0] = cur // cols
        path[i, 1] = cur % cols
        cur = parent[cur]
    return path


@nb.njit(cache=True)
def path_blocked(
    state: NDArray[np.int8],
    path_rows: NDArray[np.int64],
    path_cols: NDArray[np.int64],
    first: int,
    offsets: NDArray[np.int64],
) -> bool:
    """Whether any path cell from index ``first`` on has an OCCUPIED cell of ``state`` at one of
    ``offsets`` ((k, 2) row/column offsets covering the robot footprint)."""
    rows, cols = state.shape
    for i in range(first, path_rows.shape[0]):
        for k in range(offsets.shape[0]):
            r = path_rows[i] + offsets[k, 0]
            c = path_cols[i] + offsets[k, 1]
            if 0 <= r < rows and 0 <= c < cols and state[r, c] == _OCCUPIED:
                return True
    return False


def footprint_offsets(radius: float, resolution: float) -> NDArray[np.int64]:
    """Cell offsets (k, 2) whose centres lie within ``radius`` (m) + half a cell of a cell centre."""
    reach = radius / resolution + 0.5
    n = int(math.ceil(reach))
    dr, dc = np.mgrid[-n : n + 1, -n : n + 1]
    keep = dr**2 + dc**2 < reach**2
    return np.column_stack((dr[keep], dc[keep])).astype(np.int64)


@nb.njit(cache=True, fastmath=FASTMATH)
def follow_path(
    path_x: NDArray[np.float64],
    path_y: NDArray[np.float64],
    index: int,
    x: float,
    y: float,
    theta: float,
    duration: float,
    params: NDArray[np.float64],
    clearance: NDArray[np.float64],
    origin_x: float,
    origin_y: float,
    resolution: float,
) -> tuple[float, float, float, int, float, float, int]:
    """Drive along the path for up to ``duration`` (s).

    ``params`` = (v_max, omega_max, turn_in_place_angle, heading_gain, lookahead, goal_tolerance,
    control_dt, robot_radius). ``clearance`` is the true distance (m) from each cell to the nearest
    wall: a move that would put the robot centre closer than its radius is refused (collision).

    Returns (x, y, theta, index, distance driven (m), time used (s), status) with status 0 =
    still driving, 1 = goal reached, 2 = blocked by a wall.
    """
    v_max, w_max, turn_angle, k_w, lookahead, tol, h, radius = (
        params[0], params[1], params[2], params[3], params[4], params[5], params[6], params[7],
    )  # fmt: skip
    n = path_x.shape[0]
    rows, cols = clearance.shape
    elapsed = 0.0
    driven = 0.0
    while elapsed < duration - 1e-9:
        to_goal = math.hypot(path_x[n - 1] - x, path_y[n - 1] - y)
        if to_goal <= tol:
            return x, y, theta, n - 1, driven, elapsed, 1
        while index < n - 1 and math.hypot(path_x[index] - x, path_y[index] - y) < lookahead:
            index += 1
        err = math.atan2(path_y[index] - y, path_x[index] - x) - theta
        err = (err + math.pi) % (2.0 * math.pi) - math.pi
        step = min(h, duration - elapsed)
        if abs(err) > turn_angle:
            turn = min(abs(err), w_max * step)
            theta += turn if err > 0 else -turn
            elapsed += turn / w_max if turn < w_max * step else step
            continue
        omega = max(-w_max, min(w_max, k_w * err))
        v = min(v_max, to_goal / step)
        mid = theta + 0.5 * omega * step
        nx = x + v * step * math.cos(mid)
        ny = y + v * step * math.sin(mid)
        col = int(math.floor((nx - origin_x) / resolution))
        row = int(math.floor((ny - origin_y) / resolution))
        if row < 0 or row >= rows or col < 0 or col >= cols or clearance[row, col] < radius:
            return x, y, theta, index, driven, elapsed, 2
        driven += math.hypot(nx - x, ny - y)
        x, y = nx, ny
        theta = (theta + omega * step + math.pi) % (2.0 * math.pi) - math.pi
        elapsed += step
    return x, y, theta, index, driven, elapsed, 0
