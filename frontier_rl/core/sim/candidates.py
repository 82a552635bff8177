"""What a decision chooses from: the current map, its costmap, the cells the robot can reach and
the frontiers it may drive to."""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum

import numpy as np
from numpy.typing import NDArray

from frontier_rl.core.frontiers.blacklist import AUDIT_BUDGET, Blacklist
from frontier_rl.core.frontiers.detection import Frontiers, detect_frontiers
from frontier_rl.core.navigation.astar import SearchScratch
from frontier_rl.core.navigation.costmap import Costmap
from frontier_rl.core.navigation.inflation import InflationMemory
from frontier_rl.core.navigation.thin_walls import Recovery, recovery_costmap
from frontier_rl.core.sim.config import SimConfig, drop_cells_at
from frontier_rl.core.world.grid import CellState, OccupancyGrid
from frontier_rl.core.world.robot import Pose

Discs = tuple[NDArray[np.float64], float]
"""Other robots to see as walls: centres (k, 2) (m) and their radius (m)."""


def with_robots_as_walls(grid: OccupancyGrid, robots: Discs) -> OccupancyGrid:
    """A copy of ``grid`` with every cell whose centre lies within a robot's disc occupied: what a
    costmap whose obstacle layer sees them would hold (inflated like any wall, and blocking the
    view of a frontier's goal)."""
    centres, radius = robots
    data = grid.data.copy()
    for x, y in centres:
        rows, cols, cx, cy = grid.centres_near(float(x), float(y), radius)
        data[rows, cols][np.hypot(cx[None, :] - x, cy[:, None] - y) <= radius] = CellState.OCCUPIED
    return OccupancyGrid(data, grid.resolution, grid.origin)


class Look(Enum):
    """What a decision's frontiers are for (:mod:`frontier_rl.core.sim.looks`)."""

    NONE = "none"
    """Frontiers to drive to, as the thesis's explorer has them."""
    SMALL = "small"
    """Last looks at clusters the size filter drops (a gap in a thin wall, a window)."""
    BLIND = "blind"
    """A last look at clusters the size filter drops where no floor was seen beyond any (until one
    pays, :func:`~frontier_rl.core.sim.looks.blind_looks`)."""
    UNKNOWN_LEFT = "unknown_left"
    """Last looks at clusters the size filter drops that open onto the unknown a frontier left
    opens onto, before the robot gives it up (:func:`~frontier_rl.core.sim.looks.looks_into_unknown_left`):
    each a visit, whatever it maps."""
    GIVEN_UP = "given_up"
    """Last looks at frontiers given up after their tries, from another place."""


@dataclass(frozen=True)
class Candidates:
    """The frontiers a decision chooses from, and what they were found on.

    Attributes:
        grid: the robot's map (cropped to the seen area, with a margin).
        costmap: the navigator's costmap of ``grid``.
        reachable: the known free cells of ``grid`` the robot can reach.
        frontiers: the reachable frontiers that are not blacklisted.
        recovery: the costmap they were found on: the normal one, or the narrow-passage recovery's
            at one of its levels (:mod:`frontier_rl.core.navigation.thin_walls`).
        looks: whether the frontiers are last looks, and at what (:mod:`frontier_rl.core.sim.looks`):
            clusters each with its goal at the viewpoint that sees most of the unknown beyond it.
    """

    grid: OccupancyGrid
    costmap: Costmap
    reachable: NDArray[np.bool_]
    frontiers: Frontiers
    recovery: Recovery = Recovery.NONE
    looks: Look = Look.NONE


def reachable_frontiers(
    grid: OccupancyGrid,
    pose: Pose,
    config: SimConfig,
    min_cells: int | None = None,
    scratch: SearchScratch | None = None,
    recovery: Recovery = Recovery.NONE,
    felt: NDArray[np.bool_] | None = None,
    memory: InflationMemory | None = None,
    avoid: Discs | None = None,
    trail: NDArray[np.bool_] | None = None,
) -> tuple[Costmap, NDArray[np.bool_], Frontiers]:
    """The navigator's costmap of ``grid`` (its searches using ``scratch``, its inflation updating
    ``memory``'s when there is one: not on the narrow-passage recovery's), the known free cells
    the robot at ``pose`` can reach, and the frontier clusters larger than ``min_cells`` (default
    ``config.min_frontier_cells``; cells of 0.05 m on coarser maps, :func:`drop_cells_at`) that
    touch them: what a decision chooses from, before any blacklist. With a ``recovery`` level, the
    costmap is that of the narrow-passage recovery: the map's walls thinned by a cell except at
    ``felt`` (the walls the robot touched, a mask of ``grid``'s shape; none by default), for a
    slimmer robot, open along its ``trail`` (:func:`~frontier_rl.core.navigation.thin_walls.recovery_costmap`).
    With ``avoid``, the teammates the robot gives way to are walls (:func:`with_robots_as_walls`;
    ``memory`` is then left as it was)."""
    if avoid is not None and len(avoid[0]):
        grid, memory = with_robots_as_walls(grid, avoid), None
    costmap, reachable = reachable_cells(grid, pose, config, scratch, recovery, felt, memory, trail)
    cells = drop_cells_at(config.min_frontier_cells if min_cells is None else min_cells, grid.resolution)
    # a goal farther from its frontier than the map update reaches would map none of it
    reach = min(config.frontier_goal_reach, config.mapping_range)
    frontiers = detect_frontiers(grid, pose, reachable, cells, config.frontier_segment_length, reach)
    return costmap, reachable, frontiers


def reachable_cells(
    grid: OccupancyGrid,
    pose: Pose,
    config: SimConfig,
    scratch: SearchScratch | None = None,
    recovery: Recovery = Recovery.NONE,
    felt: NDArray[np.bool_] | None = None,
    memory: InflationMemory | None = None,
    trail: NDArray[np.bool_] | None = None,
) -> tuple[Costmap, NDArray[np.bool_]]:
    """:func:`reachable_frontiers`' costmap of ``grid`` and the known free cells the robot at
    ``pose`` can reach on it, without the frontiers."""
    if recovery is Recovery.NONE:
        costmap = Costmap.build(grid, config.robot, config.navigation, scratch, memory)
        if felt is not None:
            costmap = costmap.with_felt_walls(felt, config.robot.radius)
        return costmap, costmap.reachable_known(grid.world_to_cell(pose.x, pose.y))
    touched = np.zeros(grid.shape, np.bool_) if felt is None else felt
    costmap = recovery_costmap(grid, touched, config.robot, config.navigation, recovery, scratch, trail)
    return costmap, costmap.reachable_known(grid.world_to_cell(pose.x, pose.y)) & (grid.data == CellState.FREE)


def find_candidates(
    grid: OccupancyGrid,
    pose: Pose,
    config: SimConfig,
    blacklist: Blacklist,
    map_state: NDArray[np.int8],
    scratch: SearchScratch | None = None,
    recovery: Recovery = Recovery.NONE,
    felt: NDArray[np.bool_] | None = None,
    memory: InflationMemory | None = None,
    avoid: Discs | None = None,
    trail: NDArray[np.bool_] | None = None,
) -> Candidates:
    """The candidates on ``grid`` for a robot at ``pose``: on the normal costmap, or on the
    narrow-passage recovery's at level ``recovery``, which thins every wall but those ``felt`` (the
    walls the robot touched, in ``grid``'s frame). Goals the ``blacklist`` blocks are left out
    (refreshed against the robot's whole map ``map_state`` first); when that would leave none, the
    goals that may be retried are lifted once, so that the episode never ends with a frontier it
    gave up on after a single failure, and then those still within the audit's budget
    (:data:`~frontier_rl.core.frontiers.blacklist.AUDIT_BUDGET`); last, a frontier blocked only
    because its goal lies near a neighbour's failed one gets the tries its own history leaves it.
    ``scratch`` and ``memory`` are the robot's, kept from map to map; ``avoid``, the teammates it
    gives way to (:func:`reachable_frontiers`)."""
    costmap, reachable, frontiers = reachable_frontiers(
        grid, pose, config, scratch=scratch, recovery=recovery, felt=felt, memory=memory, avoid=avoid, trail=trail
    )
    if blacklist.entries and len(frontiers):
        blacklist.refresh(map_state)
        goals = frontiers.goals
        kept = frontiers.subset(~blacklist.blocked(goals))
        if len(kept) == 0:
            blacklist.retry()
            kept = frontiers.subset(~blacklist.blocked(goals))
        if len(kept) == 0:  # the audit: goals the map has a way to get as many tries again
            blacklist.retry(AUDIT_BUDGET * blacklist.max_failures)
            kept = frontiers.subset(~blacklist.blocked(goals))
        if len(kept) == 0:  # blocked only by a neighbour's goal: the tries its own history leaves it
            kept = frontiers.subset(_with_tries_left(frontiers, grid, blacklist))
        frontiers = kept
    return Candidates(grid, costmap, reachable, frontiers, recovery)


def _with_tries_left(frontiers: Frontiers, grid: OccupancyGrid, blacklist: Blacklist) -> NDArray[np.int64]:
    """The frontiers whose own history leaves them a try: no entry whose goal lies near their cells
    or whose failed frontiers touch them (:meth:`~frontier_rl.core.frontiers.blacklist.Blacklist.history_of`)
    is unrevealable or has used up the audit's budget. They are blocked only because their goal
    lies near a neighbour's failed one (a viewpoint two frontiers share). A failure of one joins
    that neighbour's history or its own, so each such frontier's tries stay within the budget."""
    budget = AUDIT_BUDGET * blacklist.max_failures
    histories = [blacklist.history_of(grid.cells_to_world(frontiers.cells_of(i))) for i in range(len(frontiers))]
    return np.asarray(
        [i for i, (count, unrevealable) in enumerate(histories) if count < budget and not unrevealable], np.int64
    )
