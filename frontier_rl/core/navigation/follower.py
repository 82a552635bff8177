"""The path follower and path checks.

The follower drives a differential-drive robot along a planned path under its speed limits,
turning in place when the heading error is large, so turning costs time; the costmap and the
A* planner are in :mod:`frontier_rl.core.navigation.costmap`.
"""

from __future__ import annotations

import math
from enum import IntEnum
from typing import NamedTuple

import numba as nb
import numpy as np
from numpy.typing import NDArray

from frontier_rl.core.navigation.config import NavigationConfig
from frontier_rl.core.world.grid import OCCUPIED_I8
from frontier_rl.core.world.raycast import FASTMATH
from frontier_rl.core.world.robot import RobotConfig


class FollowerParams(NamedTuple):
    """The path follower's settings, as the compiled follower takes them (a tuple numba reads by
    field name)."""

    max_linear_speed: float
    """m/s."""
    max_angular_speed: float
    """rad/s."""
    turn_in_place_angle: float
    """Heading errors above this (rad) are turned on the spot."""
    heading_gain: float
    """Angular speed per radian of heading error (1/s)."""
    lookahead: float
    """Distance (m) of the point on the path the robot steers at."""
    goal_tolerance: float
    """The goal is reached within this distance (m)."""
    control_dt: float
    """The control step (s)."""
    radius: float
    """The robot's radius (m): a move closer than this to a wall's cell centre is refused."""

    @classmethod
    def of(cls, robot: RobotConfig, navigation: NavigationConfig) -> FollowerParams:
        """The settings of ``robot`` under ``navigation``."""
        return cls(
            robot.max_linear_speed,
            robot.max_angular_speed,
            robot.turn_in_place_angle,
            navigation.heading_gain,
            navigation.lookahead,
            navigation.goal_tolerance,
            navigation.control_dt,
            robot.radius,
        )


class FollowStatus(IntEnum):
    """How :func:`follow_path` stopped."""

    DRIVING = 0  # still on the way: the duration is over, or the scan gate opened
    REACHED = 1  # within the goal tolerance (the time used is exact)
    BLOCKED = 2  # a wall is in the way (the robot waits out the tick)
    BLOCKED_BY_ROBOT = 3  # another robot is in the way, and no wall (the robot waits out the tick)


# the compiled follower returns plain ints
_DRIVING = int(FollowStatus.DRIVING)
_REACHED = int(FollowStatus.REACHED)
_BLOCKED = int(FollowStatus.BLOCKED)
_BLOCKED_BY_ROBOT = int(FollowStatus.BLOCKED_BY_ROBOT)


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
            if 0 <= r < rows and 0 <= c < cols and state[r, c] == OCCUPIED_I8:
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


_CENTRED = 0.25
"""A careful robot this close (cells) to its nearest waypoint stands on it."""
_BACK_SEARCH_LOOKAHEADS = 4.0
"""How far back along the path (in lookaheads of path length) the careful follower looks for the
waypoint nearest to the robot: far enough to find where it stands on a path that winds around a
corner within the lookahead, short enough never to send it back around a loop it has driven."""


@nb.njit(cache=True, inline="always")
def _nearest_waypoint(
    path_x: NDArray[np.float64], path_y: NDArray[np.float64], index: int, x: float, y: float, lookahead: float
) -> int:
    """The waypoint nearest to (x, y) among those up to ``index`` within :data:`_BACK_SEARCH_LOOKAHEADS`
    lookaheads (m) of path before it (the earlier one on a tie).

    The nearest, not the first local minimum searching back: a path that turns around a wall
    corner within the lookahead comes nearer, goes away and comes nearer again, and the first
    minimum then lies past the corner, straight through the wall."""
    near, best = index, math.hypot(path_x[index] - x, path_y[index] - y)
    window = _BACK_SEARCH_LOOKAHEADS * lookahead
    travelled = 0.0
    k = index
    while k > 0 and travelled <= window:
        travelled += math.hypot(path_x[k] - path_x[k - 1], path_y[k] - path_y[k - 1])
        k -= 1
        gap = math.hypot(path_x[k] - x, path_y[k] - y)
        if gap <= best:
            near, best = k, gap
    return near


@nb.njit(cache=True, inline="always")
def _careful_target(
    path_x: NDArray[np.float64],
    path_y: NDArray[np.float64],
    index: int,
    x: float,
    y: float,
    lookahead: float,
    resolution: float,
    careful: NDArray[np.bool_],
) -> tuple[int, int, bool]:
    """The waypoint a careful robot at (x, y) (m) steers at: the one after its nearest, or the
    nearest itself while ``careful[1]`` (cleared once it stands on it, when ``careful[2]`` is set).
    Returns the target, the nearest waypoint and whether the robot stands off its centre (m, cells
    of ``resolution``)."""
    near = _nearest_waypoint(path_x, path_y, index, x, y, lookahead)
    off_centre = math.hypot(path_x[near] - x, path_y[near] - y) > _CENTRED * resolution
    if careful[1] and not off_centre:
        careful[1] = False
        careful[2] = True
    return (near if careful[1] else min(near + 1, path_x.shape[0] - 1)), near, off_centre


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


@nb.njit(cache=True, inline="always")
def _same_cell(x0: float, y0: float, x1: float, y1: float, origin_x: float, origin_y: float, resolution: float) -> bool:
    """Whether the points (x0, y0) and (x1, y1) (m) lie in one cell of the grid."""
    return math.floor((x0 - origin_x) / resolution) == math.floor((x1 - origin_x) / resolution) and math.floor(
        (y0 - origin_y) / resolution
    ) == math.floor((y1 - origin_y) / resolution)


@nb.njit(cache=True, inline="always")
def _cuts_a_corner(
    x: float,
    y: float,
    nx: float,
    ny: float,
    clearance: NDArray[np.float64],
    origin_x: float,
    origin_y: float,
    resolution: float,
    radius: float,
) -> bool:
    """Whether a step from (x, y) to (nx, ny) (m) crosses into the diagonal cell past a corner
    whose two cells beside both are closer than ``radius`` to a wall: the robot would pass through
    one of them, as the planner, which never cuts a corner, knows."""
    col, row = math.floor((x - origin_x) / resolution), math.floor((y - origin_y) / resolution)
    ncol, nrow = math.floor((nx - origin_x) / resolution), math.floor((ny - origin_y) / resolution)
    if col == ncol or row == nrow:
        return False
    rows, cols = clearance.shape
    beside_a = 0 <= row < rows and 0 <= ncol < cols and clearance[int(row), int(ncol)] >= radius
    beside_b = 0 <= nrow < rows and 0 <= col < cols and clearance[int(nrow), int(col)] >= radius
    return not (beside_a or beside_b)


@nb.njit(cache=True, inline="always")
def _deeper_into_a_mate(x: float, y: float, nx: float, ny: float, mates: NDArray[np.float64], gap: float) -> bool:
    """Whether moving from (x, y) to (nx, ny) (m) puts the robot centre closer than ``gap`` (m) to
    one of ``mates`` ((k, 2) centres, m), and closer to it than before: robots are discs that
    collide exactly, and one already in contact may still move off."""
    for k in range(mates.shape[0]):
        after = math.hypot(nx - mates[k, 0], ny - mates[k, 1])
        if after < gap and after < math.hypot(x - mates[k, 0], y - mates[k, 1]):
            return True
    return False


@nb.njit(cache=True, inline="always")
def _moved_on(
    careful: NDArray[np.bool_],
    x: float,
    y: float,
    nx: float,
    ny: float,
    origin_x: float,
    origin_y: float,
    resolution: float,
) -> None:
    """A step from (x, y) into another cell (nx, ny) (m) clears the careful robot's third flag:
    it has left the waypoint it stepped back onto."""
    if careful[2] and not _same_cell(x, y, nx, ny, origin_x, origin_y, resolution):
        careful[2] = False


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
    params: FollowerParams,
    clearance: NDArray[np.float64],
    mates: NDArray[np.float64],
    mate_gap: float,
    origin_x: float,
    origin_y: float,
    resolution: float,
    gate: NDArray[np.float64],
    careful: NDArray[np.bool_],
) -> tuple[float, float, float, int, float, float, int]:
    """Drive along the path for up to ``duration`` (s), in LiDAR ticks.

    ``params``: the follower's settings. ``clearance`` is the true distance (m) from each cell to the nearest
    wall: a move that would put the robot centre closer than its radius is refused (collision),
    and so is one that takes it deeper within ``mate_gap`` (m) of one of ``mates`` ((k, 2) centres
    of other robots, m; (0, 2) alone).
    ``gate`` = (tick, x0, y0, theta0, linear, angular): the drive also stops at the first tick
    boundary (every ``tick`` s) where the robot is ``linear`` m from (x0, y0) or has turned
    ``angular`` rad from theta0, the moment the mapper wants a new scan. ``careful``
    (:func:`careful_flags`, kept by the caller for the whole path): the first switches from
    steering at the lookahead point to following the waypoints one by one, set the first time the
    lookahead cuts a corner into a wall; the second steers back to the nearest waypoint before the
    next, set when the way to the next from off its centre is walled; the third is set once the
    robot stands on that waypoint again, until it enters another cell: walled a second time
    from there, the way is too tight (BLOCKED), where stepping back again would circle for ever.

    Returns (x, y, theta, index, distance driven (m), time used (s), status), the status a
    :class:`FollowStatus`.
    """
    v_max, w_max, turn_angle = params.max_linear_speed, params.max_angular_speed, params.turn_in_place_angle
    k_w, lookahead, tol = params.heading_gain, params.lookahead, params.goal_tolerance
    h, radius = params.control_dt, params.radius
    tick, gate_x, gate_y, gate_theta, linear, angular = gate[0], gate[1], gate[2], gate[3], gate[4], gate[5]
    n = path_x.shape[0]
    elapsed = 0.0
    driven = 0.0
    next_tick = tick
    while elapsed < duration - 1e-9:
        if elapsed >= next_tick - 1e-9:
            turned = abs((theta - gate_theta + math.pi) % (2.0 * math.pi) - math.pi)
            if math.hypot(x - gate_x, y - gate_y) >= linear or turned >= angular:
                return x, y, theta, index, driven, elapsed, _DRIVING
            next_tick += tick
        to_goal = math.hypot(path_x[n - 1] - x, path_y[n - 1] - y)
        if to_goal <= tol:
            return x, y, theta, n - 1, driven, elapsed, _REACHED
        while index < n - 1 and math.hypot(path_x[index] - x, path_y[index] - y) < lookahead:
            index += 1
        target, near, off_centre = index, index, False
        if careful[0]:
            target, near, off_centre = _careful_target(path_x, path_y, index, x, y, lookahead, resolution, careful)
        err = math.atan2(path_y[target] - y, path_x[target] - x) - theta
        err = (err + math.pi) % (2.0 * math.pi) - math.pi
        step = min(h, next_tick - elapsed, duration - elapsed)
        if abs(err) > turn_angle:
            theta, used = _turn(theta, err, step, w_max)
            elapsed += used
            continue
        nx, ny, new_theta = _drive_step(x, y, theta, err, step, to_goal, v_max, w_max, k_w)
        wall = not _clear(nx, ny, clearance, origin_x, origin_y, resolution, radius) or _cuts_a_corner(
            x, y, nx, ny, clearance, origin_x, origin_y, resolution, radius
        )
        if wall or _deeper_into_a_mate(x, y, nx, ny, mates, mate_gap):
            if careful[0]:
                if abs(err) > _ALIGNED:
                    # Face the waypoint on the spot first (a turn never collides): in a slot one
                    # cell wide, driving on while turning would keep leaving it.
                    theta, used = _turn(theta, err, step, w_max)
                    elapsed += used
                    continue
                cut = not _same_cell(nx, ny, path_x[target], path_y[target], origin_x, origin_y, resolution)
                if wall and cut and not careful[1] and not careful[2] and off_centre and target != near:
                    # The straight line to the next waypoint cuts the corner of a cell the robot
                    # may not enter (it stands at its cell's edge): its own waypoint first.
                    careful[1] = True
                    continue
                return x, y, theta, index, driven, min(next_tick, duration), _BLOCKED if wall else _BLOCKED_BY_ROBOT
            # Steering at the lookahead point cuts corners; in a tight spot follow the waypoints
            # one by one from now on, which keeps the robot on the planned cells.
            careful[0] = True
            continue
        _moved_on(careful, x, y, nx, ny, origin_x, origin_y, resolution)
        driven += math.hypot(nx - x, ny - y)
        x, y, theta = nx, ny, new_theta
        elapsed += step
    return x, y, theta, index, driven, elapsed, _DRIVING


def careful_flags() -> NDArray[np.bool_]:
    """The careful follower's three flags for a new path, all clear (see :func:`follow_path`)."""
    return np.zeros(3, np.bool_)
