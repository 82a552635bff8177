"""What an episode leaves unexplored: the frontiers of the robot's map that are not candidates,
each with the unseen free space beside it (its unknown 8-neighbours that are free in the true world)
and behind it (the unseen free region those open onto). They decide between ``explored`` and
``unreachable`` (:func:`~frontier_rl.core.sim.episode_log.completion_reason`)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy import ndimage

from frontier_rl.core.frontiers.blacklist import Blacklist
from frontier_rl.core.frontiers.detection import Frontiers, detect_frontiers
from frontier_rl.core.frontiers.fringe import NEIGHBOURS_8, unknown_beside
from frontier_rl.core.navigation.thin_walls import Recovery
from frontier_rl.core.sim.candidates import Candidates, reachable_frontiers
from frontier_rl.core.sim.config import UNSEEN_ROOM_M2, SimConfig
from frontier_rl.core.sim.metrics import FrontierLeft
from frontier_rl.core.world.grid import CellState, OccupancyGrid
from frontier_rl.core.world.robot import Pose


@dataclass(frozen=True)
class UnseenRegions:
    """The space a map has left unseen: 4-connected regions of cells unknown in the map and free
    in the true world (whose free cells are 4-connected, as the robot's planner moves).

    Attributes:
        labels: each cell's region, 0 for none (the map's shape).
        sizes: each region's cells, by label (``sizes[0]`` counts the other cells).
    """

    labels: NDArray[np.int32]
    sizes: NDArray[np.int64]

    @classmethod
    def of(cls, state: NDArray[np.int8], truth: NDArray[np.int8]) -> UnseenRegions:
        """The regions of the map ``state`` against the true world ``truth`` (same shape)."""
        labels, count = ndimage.label((state == CellState.UNKNOWN) & (truth == CellState.FREE))
        return cls(np.asarray(labels, np.int32), np.bincount(labels.ravel(), minlength=count + 1))

    def cells_behind(self, rows: NDArray[np.int64], cols: NDArray[np.int64]) -> int:
        """The cells of every region that touches (8-neighbours) one of the given cells, each region once."""
        r = (rows[:, None] + NEIGHBOURS_8[:, 0]).ravel()
        c = (cols[:, None] + NEIGHBOURS_8[:, 1]).ravel()
        inside = (r >= 0) & (r < self.labels.shape[0]) & (c >= 0) & (c < self.labels.shape[1])
        found = np.unique(self.labels[r[inside], c[inside]])
        return int(self.sizes[found[found > 0]].sum())


def frontiers_left(
    cand: Candidates,
    truth_grid: OccupancyGrid,
    pose: Pose,
    config: SimConfig,
    blacklist: Blacklist,
    map_state: NDArray[np.int8],
    felt: NDArray[np.bool_],
    trail: NDArray[np.bool_] | None = None,
) -> tuple[FrontierLeft, ...]:
    """The frontiers of ``cand``'s map that are not candidates (blacklisted after failed attempts,
    with no reachable cell that sees them, or no larger than the drop size), with the unseen
    space beside and behind each (free cells read from ``truth_grid``, the world; ``map_state`` is
    the robot's whole map, ``felt`` the walls it touched and ``trail`` the cells it crossed, the
    world's shape), and the audit:
    whether the map has a path to each (:func:`with_a_path`). A cluster of at most
    ``config.speck_cells`` cells is a speck and left out, unless more than :data:`UNSEEN_ROOM_M2`
    of unseen free space lies behind it: a room seen only through a slot is not a speck."""
    res = cand.grid.resolution
    top, left_col = truth_grid.world_to_cell(*cand.grid.cell_to_world(0, 0))
    crop = (slice(top, top + cand.grid.height), slice(left_col, left_col + cand.grid.width))
    audited = with_a_path(cand.grid, pose, config, felt[crop], None if trail is None else trail[crop])
    truth = truth_grid.data[top : top + cand.grid.height, left_col : left_col + cand.grid.width]
    regions = UnseenRegions.of(map_state, truth_grid.data)
    state = map_state[top : top + cand.grid.height, left_col : left_col + cand.grid.width]
    beside = np.where(state == CellState.UNKNOWN, cand.grid.data, np.int8(CellState.FREE))  # unseen in both
    candidate_cells = np.zeros(cand.grid.shape[0] * cand.grid.shape[1], np.bool_)
    for start, end in cand.frontiers.spans:
        candidate_cells[cand.frontiers.flat_cells[start:end]] = True
    left = []
    for frontiers, specks in ((_frontiers(cand.grid, pose, config, specks=False), False),
                              (_frontiers(cand.grid, pose, config, specks=True), True)):  # fmt: skip
        for i in range(len(frontiers)):
            cells = frontiers.cells_of(i)
            if candidate_cells[cells[:, 0] * cand.grid.width + cells[:, 1]].any():
                continue
            behind_m2 = regions.cells_behind(cells[:, 0] + top, cells[:, 1] + left_col) * res * res
            if specks and behind_m2 <= UNSEEN_ROOM_M2:
                continue
            x, y = (float(v) for v in frontiers.centers[i])
            failures, unrevealable = blacklist.history_of(cand.grid.cells_to_world(cells))
            unknown, unseen = unknown_beside(beside, cells[:, 0], cells[:, 1], truth)
            rows, cols = np.divmod(unseen, cand.grid.width)
            in_world = (rows + top) * truth_grid.width + cols + left_col
            has_path = bool(audited[cells[:, 0] * cand.grid.width + cells[:, 1]].any())
            left.append(FrontierLeft(x, y, int(frontiers.sizes[i]), unknown, unseen.size, unseen.size * res * res,
                                     failures, behind_m2, in_world, has_path, unrevealable))  # fmt: skip
    return tuple(left)


def with_a_path(
    grid: OccupancyGrid,
    pose: Pose,
    config: SimConfig,
    felt: NDArray[np.bool_],
    trail: NDArray[np.bool_] | None = None,
) -> NDArray[np.bool_]:
    """The audit before an episode gives up: the cells (flat, of ``grid``) of every frontier the
    robot at ``pose`` could drive to on its map ``grid`` as it is now, planned afresh (a new
    costmap, no blacklist), on the normal costmap or at a level of the narrow-passage recovery's
    (``felt``: the walls it touched; ``trail``: the cells it crossed; ``grid``'s shape). A frontier
    left with such a cell was given up on after its failed attempts, not for want of a way."""
    found = np.zeros(grid.height * grid.width, np.bool_)
    for level in Recovery:
        _, _, frontiers = reachable_frontiers(grid, pose, config, recovery=level, felt=felt, trail=trail)
        for start, end in frontiers.spans:
            found[frontiers.flat_cells[start:end]] = True
    return found


def _frontiers(grid: OccupancyGrid, pose: Pose, config: SimConfig, specks: bool) -> Frontiers:
    """The map's frontier clusters larger than ``config.speck_cells`` (on ``grid``'s cells), split
    into segments as the candidates are; or, with ``specks``, the clusters of at most that many cells, whole."""
    speck = config.speck_cells(grid.resolution)
    if not specks:
        return detect_frontiers(grid, pose, None, speck, config.frontier_segment_length)
    every = detect_frontiers(grid, pose, None, 0)
    return every.subset(np.flatnonzero(every.sizes <= speck))
