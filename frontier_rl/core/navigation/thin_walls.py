"""Walls a cell thinner than the map shows: the map for the narrow-passage recovery.

Range noise makes about half the returns of a wall fall a little short, into the free cell in
front of it, and a hit outweighs a miss in the log-odds update (as in Gmapping and OctoMap), so a
mapped wall is about one cell thicker than the true one on each side the LiDAR saw, and a passage
about two cells narrower. A gap the robot fits through by a few centimetres is closed on its map.
Measured on the final maps of episodes, the robot's walls stand a median of one cell (0.05 m on
0.05 m cells, 0.08-0.10 m on 0.1 m cells) nearer than the true ones, and 7-16 % of the cells where
the normal costmap lets the robot stand on the true map are lost on its own.
When the normal costmap leaves no frontier to go to, the simulator plans once more on a map whose
walls have their outer layer peeled (:func:`thin_walls`), for a robot half a cell slimmer, and
when that leaves none either, a whole cell slimmer (:class:`Recovery`, :func:`recovery_robot`);
the robot's collision check on the true map still holds it back where the gap really is too
narrow, and the wall cells it touches are kept from then on.
"""

from __future__ import annotations

import dataclasses
from enum import IntEnum

import numpy as np
from numpy.typing import NDArray

from frontier_rl.core.navigation.astar import SearchScratch
from frontier_rl.core.navigation.config import NavigationConfig
from frontier_rl.core.navigation.costmap import Costmap
from frontier_rl.core.world.grid import FREE_I8, OCCUPIED_I8, OccupancyGrid
from frontier_rl.core.world.robot import RobotConfig


class Recovery(IntEnum):
    """The costmap a decision's candidates were found on, each tried only when the one before
    leaves no frontier: the normal one, then the narrow-passage recovery's, planned half a cell
    and then a whole cell slimmer (:func:`recovery_robot`)."""

    NONE = 0
    HALF_CELL = 1
    WHOLE_CELL = 2


def thin_walls(state: NDArray[np.int8], felt: NDArray[np.bool_] | None = None) -> NDArray[np.int8]:
    """A copy of ``state`` in which every occupied cell that faces a free cell (4-neighbour), with
    an occupied cell right behind it and no free cell right behind that, is free: each wall loses
    the layer it grew on every side it was seen from, and a wall never loses its last cell, nor a
    wall two cells thick one of them (it may be one true cell seen from either side). Cells set
    in ``felt`` (walls the robot touched, same shape) are kept."""
    occupied = state == OCCUPIED_I8
    free = np.pad(state == FREE_I8, 2)
    wall = np.pad(occupied, 2)
    peel = np.zeros_like(occupied)
    rows, cols = state.shape
    for dr, dc in ((-1, 0), (1, 0), (0, -1), (0, 1)):
        in_front = free[2 + dr : 2 + dr + rows, 2 + dc : 2 + dc + cols]
        behind = wall[2 - dr : 2 - dr + rows, 2 - dc : 2 - dc + cols]
        beyond_free = free[2 - 2 * dr : 2 - 2 * dr + rows, 2 - 2 * dc : 2 - 2 * dc + cols]
        peel |= in_front & behind & ~beyond_free
    peel &= occupied
    if felt is not None:
        peel &= ~felt
    out = state.copy()
    out[peel] = FREE_I8
    return out


def recovery_costmap(
    grid: OccupancyGrid,
    felt: NDArray[np.bool_],
    robot: RobotConfig,
    navigation: NavigationConfig,
    level: Recovery,
    scratch: SearchScratch | None = None,
    trail: NDArray[np.bool_] | None = None,
) -> Costmap:
    """The narrow-passage recovery's costmap of the robot's map ``grid`` at ``level``: its walls
    thinned (:func:`thin_walls`) for a robot half a cell or a cell slimmer (:func:`recovery_robot`),
    open along the robot's ``trail`` (the cells its centre crossed, 4-connected, ``grid``'s shape:
    the way it came is a way back, however its map has grown since), except round the walls the
    robot touched (``felt``, ``grid``'s shape), whose every cell closer than the robot's radius stays
    blocked, as the collision check on the true map found them."""
    thinned = OccupancyGrid(thin_walls(grid.data, felt), grid.resolution, grid.origin)
    costmap = Costmap.build(thinned, recovery_robot(robot, grid.resolution, level), navigation, scratch)
    if trail is not None and trail.any():
        costmap = costmap.with_cells_opened(trail & (grid.data == FREE_I8))
    return costmap.with_felt_walls(felt, robot.radius)


def recovery_robot(robot: RobotConfig, resolution: float, level: Recovery) -> RobotConfig:
    """``robot`` as the narrow-passage recovery at ``level`` plans for it: half a cell of
    ``resolution`` (m) slimmer per level, never thinner than a quarter of a cell.

    The normal costmap keeps the robot's centre a radius from a wall's surface; the collision check
    on the true map asks a radius from a wall cell's centre, half a cell less. Where the peel cannot
    find every cell a wall grew by (a wall grown along a diagonal, a chair leg seen from every side,
    a speck beside a wall), a robot that drove into a cluttered corner can find itself walled in on
    its own map with room to move on the true map. Planned with the collision check's own margin
    (``HALF_CELL``), the gaps open by the half cell the map grew into them; as a last resort
    (``WHOLE_CELL``), by the whole cell it is measured to grow. Where a gap is still too tight on the
    true map the collision check stops the robot and the leg is given up like any other. (The whole
    cell as the only level reopened the 0.1 m SLAM maps as well, but sent robots into gaps they
    bumped in far more often: 276 aborted legs in one episode.)"""
    slimmer = 0.5 * int(level) * resolution
    return dataclasses.replace(robot, radius=max(robot.radius - slimmer, 0.25 * resolution))
