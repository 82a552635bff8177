"""What an episode leaves unexplored: the frontiers of the robot's map that are not candidates,
each with the unseen free space beside it (its unknown 8-neighbours that are free in the true world)
and behind it (the unseen free region those open onto). They decide between ``explored`` and
``unreachable`` (:func:`~frontier_rl.core.sim.episode_log.completion_reason`) by whether one
leaves space (:func:`~frontier_rl.core.sim.episode_log.leaves_space`)."""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np
from numpy.typing import NDArray
from scipy import ndimage

from frontier_rl.core.frontiers.blacklist import Blacklist
from frontier_rl.core.frontiers.detection import Frontiers, detect_frontiers
from frontier_rl.core.frontiers.fringe import labels_beside, unknown_beside
from frontier_rl.core.navigation.thin_walls import Recovery
from frontier_rl.core.sim.candidates import Candidates, reachable_frontiers
from frontier_rl.core.sim.config import UNSEEN_ROOM_M2, SimConfig
from frontier_rl.core.sim.episode_log import leaves_space
from frontier_rl.core.sim.look_views import look_promise_cells, segments_opened_areas, unknown_regions
from frontier_rl.core.sim.metrics import FrontierLeft
from frontier_rl.core.world.grid import FREE_I8, CellState, OccupancyGrid
from frontier_rl.core.world.robot import Pose


@dataclass(frozen=True)
class UnseenRegions:
    """The space a map has left unseen: 4-connected regions of cells unknown in the map and free
    in the true world (whose free cells are 4-connected, as the robot's planner moves).

    Attributes:
        labels: each cell's region, 0 for none (the map's shape).
        sizes: each region's cells, by label (``sizes[0]`` counts the other cells).
        explorable: each region's cells that lie in the world's explorable space, by label (0 for
            the other cells, and for every region when the explorable space is not known).
    """

    labels: NDArray[np.int32]
    sizes: NDArray[np.int64]
    explorable: NDArray[np.int64]

    @classmethod
    def of(
        cls, state: NDArray[np.int8], truth: NDArray[np.int8], explorable: NDArray[np.bool_] | None = None
    ) -> UnseenRegions:
        """The regions of the map ``state`` against the true world ``truth`` and its explorable
        space ``explorable`` (all the same shape; None: a robot's, which has no true map)."""
        labels, count = ndimage.label((state == CellState.UNKNOWN) & (truth == CellState.FREE))
        flat = labels.ravel()
        sizes = np.bincount(flat, minlength=count + 1)
        if explorable is None:
            seeable = np.zeros(count + 1, np.int64)
        else:
            seeable = np.bincount(flat, weights=explorable.ravel(), minlength=count + 1).astype(np.int64)
            seeable[0] = 0
        return cls(np.asarray(labels, np.int32), sizes, seeable)

    def beside(self, rows: NDArray[np.int64], cols: NDArray[np.int64]) -> NDArray[np.int64]:
        """The labels of the regions that touch (8-neighbours) one of the given cells, each once."""
        return labels_beside(self.labels, rows, cols)


@dataclass(frozen=True)
class _MapAgainstTruth:
    """A crop of the robot's map beside the same cells of the true world: what a frontier left
    leaves unseen, and whether the audit found a path to it. What each answer needs is computed
    for the first frontier that asks: an office episode ends with none left, and the audit's
    costmaps took almost a hundredth of its CPU time.

    Attributes:
        grid: the robot's map (a crop; ``top``, ``left`` its first cell in the world's grid).
        truth_grid: the true world.
        map_state: the robot's whole map (the world's shape).
        pose: the robot's pose (m).
        felt: the walls the robot touched (the world's shape).
        trail: the cells its centre crossed (the world's shape); None: not known.
        explorable: the world's explorable space (the world's shape); None: not known.
        blacklist: the robot's failed goals: each frontier's history, and the views it had.
        config: the simulation's settings.
    """

    grid: OccupancyGrid
    top: int
    left: int
    truth_grid: OccupancyGrid
    map_state: NDArray[np.int8]
    pose: Pose
    felt: NDArray[np.bool_]
    trail: NDArray[np.bool_] | None
    explorable: NDArray[np.bool_] | None
    blacklist: Blacklist
    config: SimConfig

    @property
    def _crop(self) -> tuple[slice, slice]:
        """``grid``'s cells in the world's grid."""
        return slice(self.top, self.top + self.grid.height), slice(self.left, self.left + self.grid.width)

    def in_world(self, flat: NDArray[np.int64]) -> NDArray[np.int64]:
        """The flat indices (row-major) in the world's grid of ``grid``'s cells ``flat`` (its flat indices)."""
        rows, cols = np.divmod(flat, self.grid.width)
        return np.asarray((rows + self.top) * self.truth_grid.width + cols + self.left, np.int64)

    @cached_property
    def truth(self) -> NDArray[np.int8]:
        """The true world's cells under ``grid``."""
        return self.truth_grid.data[self._crop]

    @cached_property
    def beside(self) -> NDArray[np.int8]:
        """``grid``'s cells, free where the robot's whole map knows them (unseen in both)."""
        return np.where(self.map_state[self._crop] == CellState.UNKNOWN, self.grid.data, FREE_I8)

    @cached_property
    def regions(self) -> UnseenRegions:
        """The unseen free regions of the world."""
        return UnseenRegions.of(self.map_state, self.truth_grid.data, self.explorable)

    @cached_property
    def audit(self) -> Audit:
        """Where the audit found paths (:func:`audit`)."""
        trail = None if self.trail is None else self.trail[self._crop]
        return audit(self.grid, self.pose, self.config, self.felt[self._crop], trail)

    @cached_property
    def unknown(self) -> tuple[NDArray[np.int32], NDArray[np.float64]]:
        """The labels of ``grid``'s unknown regions and their areas (m²), for the looks a frontier
        left with a path could have had (:func:`~frontier_rl.core.sim.look_views.look_promise_cells`)."""
        return unknown_regions(self.grid)

    @cached_property
    def views_left(self) -> NDArray[np.bool_]:
        """The cells the audit reaches (``audit.reachable``) but those within the blacklist's
        radius of a goal reached and scanned from (:meth:`~frontier_rl.core.frontiers.blacklist.Blacklist.views_had`):
        where a look at a frontier left could still be had (computed for the first that asks)."""
        reachable = self.audit.reachable
        cells = np.argwhere(reachable)
        had = self.blacklist.views_had(self.grid.cells_to_world(cells))
        left = reachable.copy()
        left[cells[had, 0], cells[had, 1]] = False
        return left

    def behind(self, cells: NDArray[np.int64]) -> NDArray[np.int64]:
        """The labels of the unseen free regions behind a frontier of ``cells`` (rows, cols of ``grid``)."""
        return self.regions.beside(cells[:, 0] + self.top, cells[:, 1] + self.left)

    def roomy(self, frontiers: Frontiers) -> NDArray[np.bool_]:
        """(n,) whether more than :data:`~frontier_rl.core.sim.config.UNSEEN_ROOM_M2` of unseen
        free space lies behind each of ``frontiers`` (of ``grid``), for all at once: an office
        episode ends with a few dozen specks, nothing behind them."""
        unseen = (self.regions.labels, self.regions.sizes.astype(np.float64))
        counts = segments_opened_areas(self.in_world(frontiers.flat_cells), frontiers.spans, unseen)
        res = self.grid.resolution
        return np.asarray(counts * res * res > UNSEEN_ROOM_M2)  # counts * res * res as behind_m2 has it

    def behind_m2(self, regions: NDArray[np.int64]) -> float:
        """The unseen free area (m²) of ``regions`` (labels)."""
        res = self.grid.resolution
        return int(self.regions.sizes[regions].sum()) * res * res

    def frontier_left(self, frontiers: Frontiers, i: int, behind: NDArray[np.int64]) -> FrontierLeft:
        """Frontier ``i`` of ``frontiers`` as left by the episode, with the unseen regions ``behind``
        it (labels)."""
        cells, res, width = frontiers.cells_of(i), self.grid.resolution, self.grid.width
        behind_m2 = self.behind_m2(behind)
        failures, unrevealable = self.blacklist.history_of(self.grid.cells_to_world(cells))
        unknown, unseen = unknown_beside(self.beside, cells[:, 0], cells[:, 1], self.truth)
        in_world = self.in_world(unseen)
        levels = self.audit.levels[cells[:, 0] * width + cells[:, 1]]
        has_path = bool((levels >= 0).any())
        speck = self.config.speck_cells(res)
        if has_path and not unrevealable:  # could a look from anywhere it can go reveal more than a speck?
            promise = look_promise_cells(self.grid, cells, self.views_left, self.config, self.unknown)
            unrevealable = promise <= speck
        x, y = (float(v) for v in frontiers.centers[i])
        return FrontierLeft(
            x=x,
            y=y,
            cells=int(frontiers.sizes[i]),
            unknown_cells=unknown,
            unseen_free_cells=unseen.size,
            unknown_m2=unseen.size * res * res,
            failures=failures,
            unseen_behind_m2=behind_m2,
            unseen_cells=in_world,
            has_path=has_path,
            path_on_map=bool((levels == Recovery.NONE).any()),
            unrevealable=unrevealable,
            leaves_space=leaves_space(unseen.size, behind_m2, speck),
            explorable_behind={int(r): float(self.regions.explorable[r]) * res * res for r in behind},
        )


def frontiers_left(
    cand: Candidates,
    truth_grid: OccupancyGrid,
    pose: Pose,
    config: SimConfig,
    blacklist: Blacklist,
    map_state: NDArray[np.int8],
    felt: NDArray[np.bool_],
    trail: NDArray[np.bool_] | None = None,
    explorable: NDArray[np.bool_] | None = None,
) -> tuple[FrontierLeft, ...]:
    """The frontiers of ``cand``'s map that are not candidates (blacklisted after failed attempts,
    with no reachable cell that sees them, or no larger than the drop size), with the unseen
    space beside and behind each (free cells read from ``truth_grid``, the world; ``map_state`` is
    the robot's whole map, ``felt`` the walls it touched, ``trail`` the cells it crossed and
    ``explorable`` the world's explorable space, the world's shape; None: not known), and the audit:
    whether the map has a path to each, and on which costmap (:func:`audit`); one with a path
    whose best look from any cell the robot can reach, but where it has had one (a goal reached in
    vain), would reveal no more than a speck of its unknown is unrevealable, as one reached twice
    in vain is. A cluster of at most ``config.speck_cells`` cells is a speck and left out, unless
    more than :data:`UNSEEN_ROOM_M2` of unseen free space lies behind it: a room seen only through
    a slot is not a speck."""
    grid = cand.grid
    top, left_col = truth_grid.world_to_cell(*grid.cell_to_world(0, 0))
    against = _MapAgainstTruth(
        grid=grid,
        top=top,
        left=left_col,
        truth_grid=truth_grid,
        map_state=map_state,
        pose=pose,
        felt=felt,
        trail=trail,
        explorable=explorable,
        blacklist=blacklist,
        config=config,
    )
    candidate_cells = np.zeros(grid.shape[0] * grid.shape[1], np.bool_)
    for start, end in cand.frontiers.spans:
        candidate_cells[cand.frontiers.flat_cells[start:end]] = True
    left = []
    for specks in (False, True):
        frontiers = _frontiers(grid, pose, config, specks)
        if specks:  # left out unless a room's worth lies behind
            frontiers = frontiers.subset(against.roomy(frontiers))
        for i in range(len(frontiers)):
            cells = frontiers.cells_of(i)
            if candidate_cells[cells[:, 0] * grid.width + cells[:, 1]].any():
                continue
            left.append(against.frontier_left(frontiers, i, against.behind(cells)))
    return tuple(left)


@dataclass(frozen=True)
class Audit:
    """Where the robot's final map has paths, planned afresh (a new costmap, no blacklist).

    Attributes:
        levels: per flat cell of the map, the lowest costmap level (a
            :class:`~frontier_rl.core.navigation.thin_walls.Recovery` value; -1: none) on which the
            robot could drive to a frontier through that cell.
        reachable: the cells it can reach on some level (the map's shape).
    """

    levels: NDArray[np.int8]
    reachable: NDArray[np.bool_]


def audit(
    grid: OccupancyGrid,
    pose: Pose,
    config: SimConfig,
    felt: NDArray[np.bool_],
    trail: NDArray[np.bool_] | None = None,
) -> Audit:
    """The audit before an episode gives up: where the robot at ``pose`` could drive to a frontier
    on its map ``grid`` as it is now, planned afresh (a new costmap, no blacklist), on the normal
    costmap or a level of the narrow-passage recovery's, whose walls are thinned (``felt``: the
    walls it touched; ``trail``: the cells it crossed; ``grid``'s shape). A frontier left with such
    a cell was given up on after its failed attempts, not for want of a way; on the normal
    costmap, through walls as mapped."""
    levels = np.full(grid.height * grid.width, -1, np.int8)
    reachable = np.zeros(grid.shape, np.bool_)
    for level in reversed(Recovery):  # the lowest level last: it is the one kept
        _, reach, frontiers = reachable_frontiers(grid, pose, config, recovery=level, felt=felt, trail=trail)
        reachable |= reach
        for start, end in frontiers.spans:
            levels[frontiers.flat_cells[start:end]] = level
    return Audit(levels, reachable)


def _frontiers(grid: OccupancyGrid, pose: Pose, config: SimConfig, specks: bool) -> Frontiers:
    """The map's frontier clusters larger than ``config.speck_cells`` (on ``grid``'s cells), split
    into segments as the candidates are; or, with ``specks``, the clusters of at most that many cells, whole."""
    speck = config.speck_cells(grid.resolution)
    if not specks:
        return detect_frontiers(grid, pose, None, speck, config.frontier_segment_length)
    every = detect_frontiers(grid, pose, None, 0)
    return every.subset(np.flatnonzero(every.sizes <= speck))
