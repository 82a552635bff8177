"""move_base-like navigation settings, the path follower and path checks.

The follower drives a differential-drive robot along a planned path under its speed limits,
turning in place when the heading error is large, so turning costs time; the costmap and the
A* planner are in :mod:`frontier_rl.core.navigation.costmap`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numba as nb
import numpy as np
from numpy.typing import NDArray
from scipy import ndimage

from frontier_rl.core.world.grid import CellState
from frontier_rl.core.world.raycast import FASTMATH
from frontier_rl.errors import ConfigError

_OCCUPIED = np.int8(CellState.OCCUPIED)


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
        progress_distance: the remaining path must shrink by this much (m) to count as progress...
        oscillation_distance: ... or the robot must move this far (m) (move_base's setting).
        max_recoveries: in-place rotations tried when stuck before the goal is aborted.
        blacklist_radius: frontiers whose goal lies this close (m) to a failed goal are skipped
            (until the map around it changes, or it is retried before the episode would end).
        max_goal_failures: a goal that failed this often is given up for good.
        frontier_check_period: how often (s) the goal's frontier is checked for being explored.
        teammate_margin: in a team, paths keep this much room (m) from other robots when they can.
        teammate_range: ... from the robots within this distance (m); farther ones will have moved
            by the time the robot gets there.
        teammate_patience: in a team, a robot blocked by another one for this long (s) in a leg
            squeezes past it for the rest of the leg, instead of both standing for ever (a
            simplification: real teams need a traffic rule for narrow corridors).
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
    oscillation_distance: float = 0.5
    max_recoveries: int = 2
    blacklist_radius: float = 0.25
    max_goal_failures: int = 2
    frontier_check_period: float = 1.0
    teammate_margin: float = 0.1
    teammate_range: float = 1.5
    teammate_patience: float = 5.0

    def __post_init__(self) -> None:
        if not (math.isfinite(self.teammate_margin) and self.teammate_margin >= 0):
            raise ConfigError(f"NavigationConfig.teammate_margin must be >= 0, got {self.teammate_margin!r}")
        for name in ("inflation_radius", "goal_tolerance", "lookahead", "control_dt", "progress_timeout",
                     "teammate_patience", "teammate_range"):  # fmt: skip
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0):
                raise ConfigError(f"NavigationConfig.{name} must be positive, got {value!r}")
        if self.max_goal_failures < 1:
            raise ConfigError(f"NavigationConfig.max_goal_failures must be >= 1, got {self.max_goal_failures!r}")
        if self.max_recoveries < 0:
            raise ConfigError(f"NavigationConfig.max_recoveries must be >= 0, got {self.max_recoveries!r}")


def obstacle_distance(occupied: NDArray[np.bool_], resolution: float) -> NDArray[np.float64]:
    """Distance (m) from each cell centre to the nearest occupied cell centre (``inf`` if none)."""
    if not occupied.any():
        return np.full(occupied.shape, np.inf)
    return np.asarray(ndimage.distance_transform_edt(~occupied), dtype=np.float64) * resolution


@nb.njit(cache=True)
def stamp_discs(
    clearance: NDArray[np.float64],
    true_clearance: NDArray[np.float64],
    blocked_padded: NDArray[np.bool_],
    true_blocked_padded: NDArray[np.bool_],
    boxes: NDArray[np.int64],
    stamped: int,
    xs: NDArray[np.float64],
    ys: NDArray[np.float64],
    occlude: NDArray[np.bool_],
    radius: float,
    reach: int,
    origin_x: float,
    origin_y: float,
    resolution: float,
) -> int:
    """Take back the ``stamped`` discs of ``boxes`` (row0, row1, col0, col1 per disc) from
    ``clearance`` and the LiDAR's ``blocked_padded``, then stamp a disc of ``radius`` (m) at every
    point (xs, ys) (m): ``clearance`` is lowered to the distance (m) from each cell centre to the
    disc, within ``reach`` cells, and, where ``occlude`` is set, the cells whose centre lies in the
    disc stop beams. ``boxes`` is rewritten. Returns the number of discs stamped."""
    rows, cols = clearance.shape
    for k in range(stamped):
        for r in range(boxes[k, 0], boxes[k, 1]):
            for c in range(boxes[k, 2], boxes[k, 3]):
                clearance[r, c] = true_clearance[r, c]
                blocked_padded[r + 1, c + 1] = true_blocked_padded[r + 1, c + 1]
    for k in range(xs.shape[0]):
        row = int(math.floor((ys[k] - origin_y) / resolution))
        col = int(math.floor((xs[k] - origin_x) / resolution))
        r0, r1 = max(row - reach, 0), min(row + reach + 1, rows)
        c0, c1 = max(col - reach, 0), min(col + reach + 1, cols)
        boxes[k, 0], boxes[k, 1], boxes[k, 2], boxes[k, 3] = r0, max(r1, r0), c0, max(c1, c0)
        for r in range(r0, r1):
            cy = origin_y + (r + 0.5) * resolution
            for c in range(c0, c1):
                cx = origin_x + (c + 0.5) * resolution
                d = math.hypot(cx - xs[k], cy - ys[k]) - radius
                if d < clearance[r, c]:
                    clearance[r, c] = d
                if occlude[k] and d <= 0.0:
                    blocked_padded[r + 1, c + 1] = True
    return int(xs.shape[0])


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


@nb.njit(cache=True, inline="always")
def _drive_step(
    x: float,
    y: float,
    theta: float,
    err: float,
    step: float,
    to_goal: float,
    v_max: float,
    w_max: float,
    k_w: float,
) -> tuple[float, float, float]:
    """Pose after ``step`` (s) of driving with heading error ``err`` (rad): unicycle, midpoint rule."""
    omega = max(-w_max, min(w_max, k_w * err))
    v = min(v_max, to_goal / step)
    mid = theta + 0.5 * omega * step
    new_theta = (theta + omega * step + math.pi) % (2.0 * math.pi) - math.pi
    return x + v * step * math.cos(mid), y + v * step * math.sin(mid), new_theta


@nb.njit(cache=True, inline="always")
def _next_waypoint(path_x: NDArray[np.float64], path_y: NDArray[np.float64], index: int, x: float, y: float) -> int:
    """The waypoint right after the one nearest to (x, y), searching back from ``index``."""
    near = index
    while near > 0 and math.hypot(path_x[near - 1] - x, path_y[near - 1] - y) <= math.hypot(
        path_x[near] - x, path_y[near] - y
    ):
        near -= 1
    return int(min(near + 1, path_x.shape[0] - 1))


@nb.njit(cache=True, inline="always")
def _turn(theta: float, err: float, step: float, w_max: float) -> tuple[float, float]:
    """Turn in place toward heading error ``err`` (rad) for at most ``step`` (s): new heading and
    the time used (less than ``step`` when the turn completes)."""
    turn = min(abs(err), w_max * step)
    return theta + (turn if err > 0 else -turn), (turn / w_max if turn < w_max * step else step)


@nb.njit(cache=True, inline="always")
def _clear(
    x: float,
    y: float,
    clearance: NDArray[np.float64],
    origin_x: float,
    origin_y: float,
    resolution: float,
    radius: float,
) -> bool:
    """Whether the robot centre may stand at (x, y) (m): inside the grid, clearance >= radius."""
    col = int(math.floor((x - origin_x) / resolution))
    row = int(math.floor((y - origin_y) / resolution))
    rows, cols = clearance.shape
    return bool(0 <= row < rows and 0 <= col < cols and clearance[row, col] >= radius)


_ALIGNED = 1e-3
"""Heading error (rad) below which a robot blocked by a wall counts as facing its waypoint."""


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
    gate: NDArray[np.float64],
    careful: NDArray[np.bool_],
) -> tuple[float, float, float, int, float, float, int]:
    """Drive along the path for up to ``duration`` (s), in LiDAR ticks.

    ``params`` = (v_max, omega_max, turn_in_place_angle, heading_gain, lookahead, goal_tolerance,
    control_dt, robot_radius). ``clearance`` is the true distance (m) from each cell to the nearest
    wall: a move that would put the robot centre closer than its radius is refused (collision).
    ``gate`` = (tick, x0, y0, theta0, linear, angular): the drive also stops at the first tick
    boundary (every ``tick`` s) where the robot is ``linear`` m from (x0, y0) or has turned
    ``angular`` rad from theta0, the moment the mapper wants a new scan. ``careful`` (one flag,
    kept by the caller for the whole path) switches from steering at the lookahead point to
    following the waypoints one by one; it is set the first time the lookahead cuts a corner into
    a wall.

    Returns (x, y, theta, index, distance driven (m), time used (s), status) with status 0 =
    still driving (duration over, or the gate opened), 1 = goal reached (time used exactly),
    2 = blocked by a wall (the robot waits out the tick).
    """
    v_max, w_max, turn_angle, k_w, lookahead, tol, h, radius = (
        params[0], params[1], params[2], params[3], params[4], params[5], params[6], params[7],
    )  # fmt: skip
    tick, gate_x, gate_y, gate_theta, linear, angular = gate[0], gate[1], gate[2], gate[3], gate[4], gate[5]
    n = path_x.shape[0]
    elapsed = 0.0
    driven = 0.0
    next_tick = tick
    while elapsed < duration - 1e-9:
        if elapsed >= next_tick - 1e-9:
            turned = abs((theta - gate_theta + math.pi) % (2.0 * math.pi) - math.pi)
            if math.hypot(x - gate_x, y - gate_y) >= linear or turned >= angular:
                return x, y, theta, index, driven, elapsed, 0
            next_tick += tick
        to_goal = math.hypot(path_x[n - 1] - x, path_y[n - 1] - y)
        if to_goal <= tol:
            return x, y, theta, n - 1, driven, elapsed, 1
        while index < n - 1 and math.hypot(path_x[index] - x, path_y[index] - y) < lookahead:
            index += 1
        target = _next_waypoint(path_x, path_y, index, x, y) if careful[0] else index
        err = math.atan2(path_y[target] - y, path_x[target] - x) - theta
        err = (err + math.pi) % (2.0 * math.pi) - math.pi
        step = min(h, next_tick - elapsed, duration - elapsed)
        if abs(err) > turn_angle:
            theta, used = _turn(theta, err, step, w_max)
            elapsed += used
            continue
        nx, ny, new_theta = _drive_step(x, y, theta, err, step, to_goal, v_max, w_max, k_w)
        if not _clear(nx, ny, clearance, origin_x, origin_y, resolution, radius):
            if careful[0]:
                if abs(err) > _ALIGNED:
                    # Face the waypoint on the spot first (a turn never collides): in a slot one
                    # cell wide, driving on while turning would keep leaving it.
                    theta, used = _turn(theta, err, step, w_max)
                    elapsed += used
                    continue
                return x, y, theta, index, driven, min(next_tick, duration), 2
            # Steering at the lookahead point cuts corners; in a tight spot follow the waypoints
            # one by one from now on, which keeps the robot on the planned cells.
            careful[0] = True
            continue
        driven += math.hypot(nx - x, ny - y)
        x, y, theta = nx, ny, new_theta
        elapsed += step
    return x, y, theta, index, driven, elapsed, 0
