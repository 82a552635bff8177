"""The paths a leg drives: planned on the candidates' costmap (round teammates in the way, when
there is a way round), and checked against the robot's map as it grows."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from frontier_rl.core.navigation.costmap import ESCAPE_RADIUS_M, nearest_cell
from frontier_rl.core.navigation.follower import path_blocked
from frontier_rl.core.navigation.thin_walls import thin_walls
from frontier_rl.core.sim.candidates import Candidates
from frontier_rl.core.sim.config import SimConfig
from frontier_rl.core.sim.teammates import Teammates
from frontier_rl.core.sim.trail import opened_on_trail
from frontier_rl.core.world.grid import OccupancyGrid
from frontier_rl.core.world.robot import Pose


def plan_path(
    cand: Candidates, pose: Pose, goal_cell: tuple[int, int], mates: Teammates, config: SimConfig
) -> NDArray[np.float64] | None:
    """A world-frame path (n, 2) (m) from ``pose`` to ``goal_cell`` of ``cand.grid``, or None. It
    keeps ``teammate_margin`` off the robots within ``teammate_range`` when a path that does exists."""
    start = cand.grid.world_to_cell(pose.x, pose.y)
    cells = cand.costmap.plan(start, goal_cell)
    if len(cells) == 0:
        return None
    xy = cand.grid.cells_to_world(cells)
    nav = config.navigation
    here = (pose.x, pose.y)
    close = mates.positions[mates.distances(here) <= nav.teammate_range]
    if len(close):  # around nearby robots in the way, if there is a way round
        keep_off = mates.radius + config.robot.radius + nav.teammate_margin
        gap = np.hypot(xy[:, None, 0] - close[None, :, 0], xy[:, None, 1] - close[None, :, 1])
        goal_xy = cand.grid.cell_to_world(*goal_cell)
        if gap.min() <= keep_off and not mates.within(keep_off, here, goal_xy):
            detour = cand.costmap.with_discs_blocked(close, keep_off).plan(start, goal_cell)
            if len(detour):
                xy = cand.grid.cells_to_world(detour)
    xy[-1] = cand.grid.cell_to_world(*goal_cell)
    return clear_of_teammates(xy, mates)


def clear_of_teammates(xy: NDArray[np.float64], mates: Teammates) -> NDArray[np.float64]:
    """``xy`` (n, 2) (m) without its first points that lie closer to a teammate than the robots
    collide (the centre of the cell of a robot in contact may): the follower would refuse to
    drive to them, and the robot would stand until the leg was given up. The goal stays."""
    if len(mates) == 0:
        return xy
    gaps = np.hypot(xy[:, None, 0] - mates.positions[None, :, 0], xy[:, None, 1] - mates.positions[None, :, 1])
    inside = gaps.min(axis=1) < mates.collision_gap
    first = int(np.argmin(inside)) if not inside.all() else len(xy) - 1
    return xy[first:]


def map_blocks_path(
    state: NDArray[np.int8],
    path_cells: NDArray[np.int64],
    footprint: NDArray[np.int64],
    felt: NDArray[np.bool_] | None = None,
    opened: NDArray[np.bool_] | None = None,
) -> bool:
    """Whether the map ``state`` puts a wall within the robot's ``footprint`` (cell offsets) of a
    cell of ``path_cells`` ((n, 2) map cells). With ``felt`` (the walls the robot touched), the map
    is first thinned around the path as the narrow-passage recovery planned it
    (:func:`~frontier_rl.core.navigation.thin_walls.thin_walls`); the path cells ``opened`` ((n,)
    mask; :func:`~frontier_rl.core.sim.trail.opened_on_trail`) are not checked."""
    rows, cols = path_cells[:, 0], path_cells[:, 1]
    if felt is not None:
        reach = int(np.abs(footprint).max()) + 2  # the peel looks two cells beyond a cell
        r0, c0 = max(int(rows.min()) - reach, 0), max(int(cols.min()) - reach, 0)
        r1, c1 = int(rows.max()) + reach + 1, int(cols.max()) + reach + 1
        state = thin_walls(state[r0:r1, c0:c1], felt[r0:r1, c0:c1])
        rows, cols = rows - r0, cols - c0
    if opened is not None:
        rows, cols = rows[~opened], cols[~opened]
    return path_blocked(state, rows, cols, 0, footprint)


def recovery_blocks_path(
    state: NDArray[np.int8],
    path_cells: NDArray[np.int64],
    footprint: NDArray[np.int64],
    felt: NDArray[np.bool_],
    trail: NDArray[np.bool_],
    keep_out: NDArray[np.bool_],
) -> bool:
    """:func:`map_blocks_path` for a path the narrow-passage recovery planned: the map thinned except
    at the ``felt`` walls, and the cells of the robot's ``trail`` its costmap opens left unchecked
    (:func:`~frontier_rl.core.sim.trail.opened_on_trail`, ``keep_out`` round the felt walls)."""
    opened = opened_on_trail(path_cells, trail, state, felt, keep_out)
    return map_blocks_path(state, path_cells, footprint, felt, opened)


def replan_path(
    cand: Candidates, pose: Pose, goal: tuple[float, float], mates: Teammates, config: SimConfig
) -> NDArray[np.float64] | None:
    """A world-frame path (n, 2) (m) from ``pose`` to the cell of ``goal`` (m) a replan aims at
    (:func:`passable_goal_cell`, :func:`plan_path`), or None."""
    cell = passable_goal_cell(cand, goal)
    return None if cell is None else plan_path(cand, pose, cell, mates, config)


def replan_round_teammates(
    cand: Candidates, pose: Pose, goal: tuple[float, float], mates: Teammates
) -> NDArray[np.float64] | None:
    """:func:`replan_path`'s path, but one that keeps out of the teammates in contact with the
    robot (:func:`plan_round_teammates`), or None."""
    cell = passable_goal_cell(cand, goal)
    return None if cell is None else plan_round_teammates(cand, pose, cell, mates)


def point_goal_cell(g: OccupancyGrid, reachable: NDArray[np.bool_], x: float, y: float) -> tuple[int, int] | None:
    """The ``reachable`` cell of ``g`` nearest to world point (x, y) (m), a point outside the grid
    taken at its edge; None if no cell is reachable."""
    (x0, y0), (width, height) = g.origin, g.size_m
    row, col = g.world_to_cell(min(max(x, x0), x0 + width), min(max(y, y0), y0 + height))  # no 1e308 cell
    row, col = min(max(row, 0), g.height - 1), min(max(col, 0), g.width - 1)
    return nearest_cell(reachable, (row, col), max_radius=int(math.ceil(math.hypot(*g.shape))))


def path_to_follow(path: NDArray[np.float64], pose: Pose, resolution: float) -> NDArray[np.float64]:
    """``path`` ((n, 2), m) from its point nearest the robot at ``pose`` on, as Nav2's controllers
    prune a path they are given, with points at most half a cell (``resolution``, m) apart along
    its segments: a path of a few points crosses the cells between them."""
    path = path[int(np.argmin(np.hypot(path[:, 0] - pose.x, path[:, 1] - pose.y))) :]
    pieces = np.maximum(np.ceil(np.hypot(*np.diff(path, axis=0).T) / (resolution / 2)), 1).astype(np.int64)
    steps = [
        a + np.arange(1, k + 1)[:, None] / k * (b - a) for a, b, k in zip(path[:-1], path[1:], pieces, strict=True)
    ]
    return np.concatenate([path[:1], *steps])


def cells_beyond(
    path: NDArray[np.float64], cells: NDArray[np.int64], pose: Pose, radius: float = ESCAPE_RADIUS_M
) -> NDArray[np.int64]:
    """The ``cells`` ((n, 2)) of ``path``'s points ((n, 2), m) farther than ``radius`` (m; the
    planner's escape radius) from the robot at ``pose``: a robot too close to a wall may leave it,
    as the planner lets it."""
    return cells[np.hypot(path[:, 0] - pose.x, path[:, 1] - pose.y) > radius]


def passable_goal_cell(cand: Candidates, goal: tuple[float, float]) -> tuple[int, int] | None:
    """The cell of ``cand.grid`` a replan to ``goal`` (m) aims at: the goal's own cell when the
    costmap lets the robot stand there, else the nearest one that does within 0.5 m, else None."""
    g = cand.grid
    row, col = g.world_to_cell(*goal)
    passable = cand.costmap.traversable
    if g.in_bounds(row, col) and passable[row, col]:
        return row, col
    return nearest_cell(passable, (row, col), max_radius=int(round(0.5 / g.resolution)))


def plan_round_teammates(
    cand: Candidates, pose: Pose, goal_cell: tuple[int, int], mates: Teammates
) -> NDArray[np.float64] | None:
    """A world-frame path (n, 2) (m) from ``pose`` to ``goal_cell`` of ``cand.grid`` that keeps out
    of the teammates in contact with the robot (:meth:`Teammates.in_contact`) by their collision
    gap and half a cell (the path is of grid cells), or None."""
    here = (pose.x, pose.y)
    centres = mates.in_contact(here)
    radius = mates.collision_gap + 0.5 * cand.grid.resolution
    costmap = cand.costmap.with_discs_blocked(centres, radius, here) if len(centres) else cand.costmap
    cells = costmap.plan(cand.grid.world_to_cell(pose.x, pose.y), goal_cell)
    if len(cells) == 0:
        return None
    xy = cand.grid.cells_to_world(cells)
    xy[-1] = cand.grid.cell_to_world(*goal_cell)
    return clear_of_teammates(xy, mates)
